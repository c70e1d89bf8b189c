"""Grey-box identification: physical parameters of a bond-graph model fitted to data.

The model's ``A, B, C, D`` are compiled once (:func:`~bondgraph.numeric.compile_plant`)
and evaluated at each trial parameter vector; :func:`scipy.optimize.least_squares`
minimises

* time data (:class:`TimeData`): ``sum_k ||y_k - ŷ_k(p)||^2``, where ``ŷ`` is
  the model's response to the measured input on the sample grid, exact for a
  zero-order-hold (or first-order-hold) input (:func:`simulate_sampled`);
* frequency data (:class:`FrequencyData`, or an
  :class:`~bondgraph.identification.FRFResult`): ``sum_k w_k |H_k - Ĥ(j omega_k; p)|^2``
  with real and imaginary parts as separate residuals.

Free parameters are optimised in the scaled variables ``p / |p_0|`` so that
parameters of very different magnitude (``Jm ~ 1e-7``, ``Rm ~ 1``) are equally
well conditioned.  At the optimum the residual Jacobian ``J`` (with respect to
the physical parameters) gives the usual asymptotic covariance

.. math::

    \\operatorname{cov}(\\hat p) = \\hat\\sigma^2 (J^T J)^{-1}, \\qquad
    \\hat\\sigma^2 = \\frac{\\|r\\|^2}{N_r - n_p},

standard errors (square roots of its diagonal) and 95 % confidence intervals
``p ± t_{0.975, N_r - n_p} se`` (Ljung, *System Identification*, Sec. 9.3).
The intervals are meaningful when the model structure is right and the noise
is white; coloured noise makes them optimistic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping, Sequence, Union

import numpy as np
import scipy.optimize
import scipy.signal
import scipy.stats
from numpy.typing import ArrayLike, NDArray

from ..model import Model
from ..numeric import NumericModel, NumericStateSpace, compile_plant
from ..errors import MissingValueError
from ..numeric.errors import NumericError
from ..parameters import match_values, real_value
from ..numeric.plant import control_labels
from ._validation import IdentificationError, check_positive_float, readonly_copy
from .frf import FRFResult

if TYPE_CHECKING:  # pragma: no cover
    import control

__all__ = ["TimeData", "FrequencyData", "GreyboxResult", "greybox_fit", "simulate_sampled"]

Channels = Union[str, Sequence[str], None]

#: Singular values of the scaled Jacobian below this fraction of the largest one
#: count as zero: the free parameters are then not identifiable from the data.
#: (The central-difference Jacobian is accurate to about 1e-7 relative.)
_RANK_RTOL = 1e-5

#: Relative step of the central differences for the final Jacobian.
_JAC_STEP = 1e-5


def _finite_array(x: ArrayLike, name: str, *, dtype: Any = float, ndim: tuple[int, ...] = (1, 2)
                  ) -> NDArray:
    try:
        arr = np.asarray(x, dtype=dtype)
    except (TypeError, ValueError):
        raise IdentificationError(f"{name}: expected an array of numbers") from None
    if arr.ndim not in ndim:
        raise IdentificationError(
            f"{name}: expected an array with {' or '.join(map(str, ndim))} dimension(s), "
            f"got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr)))
        raise IdentificationError(f"{name}: expected finite values, found {bad} NaN/inf entries")
    return arr


# --------------------------------------------------------------------------- data
@dataclass(frozen=True, eq=False)
class TimeData:
    """Sampled input/output record on a uniform grid.

    Parameters
    ----------
    u : array_like
        Input samples, shape ``(N,)`` or ``(N, m)`` (one column per input).
    y : array_like
        Output samples, shape ``(N,)`` or ``(N, p)`` (one column per output).
    dt : float
        Sample time in seconds.

    Raises
    ------
    IdentificationError
        On NaN/inf samples, mismatched lengths, fewer than 2 samples or
        ``dt <= 0``.

    Examples
    --------
    >>> d = TimeData([0.0, 1.0, 1.0], [0.0, 0.0, 0.5], 0.01)
    >>> d.n_samples, d.u.shape, d.y.shape
    (3, (3, 1), (3, 1))
    >>> TimeData([0.0, float("nan")], [0.0, 0.0], 0.01)
    Traceback (most recent call last):
    ...
    bondgraph.identification._validation.IdentificationError: u: expected finite values, found 1 NaN/inf entries
    """

    u: NDArray[np.float64]
    y: NDArray[np.float64]
    dt: float

    def __post_init__(self) -> None:
        u = _finite_array(self.u, "u")
        y = _finite_array(self.y, "y")
        u = u.reshape(u.shape[0], -1) if u.ndim == 2 else u[:, None]
        y = y.reshape(y.shape[0], -1) if y.ndim == 2 else y[:, None]
        if u.shape[0] != y.shape[0]:
            raise IdentificationError(
                f"y: expected the same number of samples as u ({u.shape[0]}), got {y.shape[0]}")
        if u.shape[0] < 2:
            raise IdentificationError(f"u: expected at least 2 samples, got {u.shape[0]}")
        object.__setattr__(self, "u", readonly_copy(u))
        object.__setattr__(self, "y", readonly_copy(y))
        object.__setattr__(self, "dt", check_positive_float(self.dt, "dt"))

    @property
    def n_samples(self) -> int:
        """Number of samples ``N``."""
        return int(self.u.shape[0])

    @property
    def time(self) -> NDArray[np.float64]:
        """Sample times ``k dt``."""
        return np.arange(self.n_samples, dtype=np.float64) * float(self.dt)


@dataclass(frozen=True, eq=False)
class FrequencyData:
    """Complex frequency-response samples of one input/output channel.

    Parameters
    ----------
    omega : array_like
        Angular frequencies in rad/s, ``> 0`` and distinct.
    response : array_like of complex
        ``H(j omega_k)``.
    weights : array_like, optional
        Non-negative weights of the squared errors (e.g. the coherence).

    Examples
    --------
    >>> d = FrequencyData([1.0, 2.0], [1 + 0j, 0.5 - 0.5j])
    >>> d.weights
    array([1., 1.])
    """

    omega: NDArray[np.float64]
    response: NDArray[np.complex128]
    weights: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        w = _finite_array(self.omega, "omega", ndim=(1,))
        h = _finite_array(self.response, "response", dtype=complex, ndim=(1,))
        if h.shape != w.shape:
            raise IdentificationError(
                f"response: expected the same length as omega ({w.size}), got {h.size}")
        if w.size < 1:
            raise IdentificationError("omega: expected at least 1 frequency, got 0")
        if np.any(w <= 0):
            raise IdentificationError("omega: expected angular frequencies > 0 rad/s")
        if np.unique(w).size != w.size:
            raise IdentificationError("omega: expected distinct frequencies")
        if self.weights is None:
            wt = np.ones(w.size)
        else:
            wt = _finite_array(self.weights, "weights", ndim=(1,))
            if wt.shape != w.shape:
                raise IdentificationError(
                    f"weights: expected the same length as omega ({w.size}), got {wt.size}")
            if np.any(wt < 0) or not np.any(wt > 0):
                raise IdentificationError("weights: expected non-negative values, not all zero")
        object.__setattr__(self, "omega", readonly_copy(w))
        object.__setattr__(self, "response", readonly_copy(h, complex))
        object.__setattr__(self, "weights", readonly_copy(wt))

    @classmethod
    def from_frf(cls, frf: FRFResult, *, fmin: float | None = None, fmax: float | None = None,
                 estimator: str = "h1", coherence_weights: bool = True) -> "FrequencyData":
        """Frequency data from a Welch FRF estimate, within ``[fmin, fmax]`` Hz.

        Bins at 0 Hz and bins where the estimate is undefined (NaN) are dropped.

        Parameters
        ----------
        frf : FRFResult
        fmin, fmax : float, optional
            Band in Hz (inclusive).
        estimator : {"h1", "h2"}
        coherence_weights : bool
            Weight each bin by its coherence (default) or equally.

        Examples
        --------
        >>> import numpy as np
        >>> from bondgraph.identification import estimate_frf
        >>> x = np.random.default_rng(1).standard_normal(2048)
        >>> d = FrequencyData.from_frf(estimate_frf(x, 3.0 * x, fs=100.0, nperseg=128), fmax=10.0)
        >>> d.omega.size, bool(np.allclose(d.response, 3.0))
        (12, True)
        """
        if not isinstance(frf, FRFResult):
            raise IdentificationError(f"frf: expected an FRFResult, got {type(frf).__name__}")
        if estimator not in ("h1", "h2"):
            raise IdentificationError(f"estimator: expected 'h1' or 'h2', got {estimator!r}")
        f = frf.frequencies
        h = frf.h1 if estimator == "h1" else frf.h2
        keep = (f > 0) & np.isfinite(h)
        if fmin is not None:
            keep &= f >= float(fmin)
        if fmax is not None:
            keep &= f <= float(fmax)
        if not np.any(keep):
            raise IdentificationError(
                f"fmin, fmax: no usable FRF bin in [{fmin}, {fmax}] Hz")
        wt = frf.coherence[keep] if coherence_weights else None
        return cls(2 * np.pi * f[keep], h[keep], wt)


# --------------------------------------------------------------------------- simulation
def _as_plant(plant: Any) -> NumericStateSpace:
    if isinstance(plant, NumericStateSpace):
        return plant
    try:
        import control
    except ImportError:  # pragma: no cover
        control = None
    if control is not None and isinstance(plant, control.StateSpace):
        if plant.dt not in (0, None):
            raise IdentificationError("plant: expected a continuous-time system (dt = 0)")
        return NumericStateSpace(plant.A, plant.B, plant.C, plant.D,
                                 tuple(plant.state_labels), tuple(plant.input_labels),
                                 tuple(plant.output_labels))
    raise IdentificationError(
        f"plant: expected a NumericStateSpace or a continuous control.StateSpace, "
        f"got {type(plant).__name__}")


def _channel_indices(which: Channels, names: tuple[str, ...], what: str) -> tuple[list[int], bool]:
    """Indices of the named channels and whether a single name (not a list) was given."""
    if which is None:
        return list(range(len(names))), len(names) == 1
    single = isinstance(which, str)
    wanted = [which] if single else list(which)
    if not wanted:
        raise IdentificationError(f"{what}: expected at least one name")
    labels = control_labels(names)
    out = []
    for name in wanted:
        if not isinstance(name, str):
            raise IdentificationError(f"{what}: expected names (str), got {name!r}")
        if name in names:
            out.append(names.index(name))
        elif name in labels:
            out.append(labels.index(name))
        else:
            raise IdentificationError(
                f"{what}: unknown {what} {name!r}; the model's {what}s are "
                f"{', '.join(names) or '(none)'}")
    if len(set(out)) != len(out):
        raise IdentificationError(f"{what}: a name is given twice in {wanted!r}")
    return out, single


def _expm(M: NDArray) -> NDArray:
    """Matrix exponential: scaling and squaring with the [6/6] Padé approximant.

    Golub & Van Loan, *Matrix Computations*, Alg. 11.3.1 (``||M / 2^s||_inf <= 1/2``,
    relative error below ``1e-15``).  Written with numpy because
    :func:`scipy.linalg.expm` is slow on tiny matrices when its multithreaded BLAS
    competes for the cores, and the fits call it hundreds of times.
    """
    n = M.shape[0]
    eye = np.eye(n)
    norm = float(np.linalg.norm(M, np.inf))
    s = max(0, int(np.ceil(np.log2(norm / 0.5)))) if norm > 0.5 else 0
    X = M / 2.0**s
    q = 6
    c = 0.5
    Xk = X
    N = eye + c * X
    Dn = eye - c * X
    for k in range(2, q + 1):
        c = c * (q - k + 1) / (k * (2 * q - k + 1))
        Xk = X @ Xk
        N = N + c * Xk
        Dn = Dn + (c if k % 2 == 0 else -c) * Xk
    E = np.linalg.solve(Dn, N)
    for _ in range(s):
        E = E @ E
    return E


def _discretize(A: NDArray, B: NDArray, C: NDArray, D: NDArray, dt: float, method: str
                ) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Exact discretisation for a zero- or first-order-hold input.

    The block-exponential formulas of :func:`scipy.signal.cont2discrete`.
    """
    n, m = B.shape
    if method == "zoh":
        M = np.zeros((n + m, n + m))
        M[:n, :n], M[:n, n:] = A * dt, B * dt
        E = _expm(M)
        return E[:n, :n], E[:n, n:], C, D
    # first-order hold (triangle hold)
    M = np.zeros((n + 2 * m, n + 2 * m))
    M[:n, :n], M[:n, n:n + m] = A * dt, B * dt
    M[n:n + m, n + m:] = np.eye(m)
    E = _expm(M)
    ms11, ms12, ms13 = E[:n, :n], E[:n, n:n + m], E[:n, n + m:]
    return ms11, ms12 - ms13 + ms11 @ ms13, C, D + C @ ms13


def _powers_times(Ad: NDArray, G: NDArray, count: int) -> NDArray:
    """Stack ``Ad**j @ G`` for ``j = 0 .. count-1`` by doubling, shape ``(count, n, k)``."""
    blocks = G[None]
    P = Ad
    while blocks.shape[0] < count:
        blocks = np.concatenate((blocks, P @ blocks), axis=0)
        P = P @ P
    return blocks[:count]


def _dlsim(Ad: NDArray, Bd: NDArray, Cd: NDArray, Dd: NDArray, u: NDArray,
           x0: NDArray | None) -> NDArray:
    """``x_{k+1} = Ad x_k + Bd u_k``, ``y_k = Cd x_k + Dd u_k``; ``u (N, m)`` -> ``y (N, p)``.

    The Markov parameters ``Cd Ad^j Bd`` are built by doubling and convolved
    with the input by FFT: exact up to rounding, for any ``Ad`` (Jordan
    blocks, integrators), and vectorised.
    """
    N = u.shape[0]
    n, p, m = Ad.shape[0], Cd.shape[0], Bd.shape[1]
    y = u @ Dd.T
    if n == 0 or (N < 2 and x0 is None):
        return y
    G = Bd if x0 is None else np.column_stack((Bd, x0))
    stack = Cd @ _powers_times(Ad, G, N)                       # (N, p, m[+1]): Cd Ad^j G
    for i in range(p):
        for j in range(m):
            h = stack[: N - 1, i, j]
            if np.any(h):
                y[1:, i] += scipy.signal.fftconvolve(h, u[:, j])[: N - 1]
    if x0 is not None:
        y += stack[:, :, m]
    return y


def simulate_sampled(plant: NumericStateSpace | "control.StateSpace", u: ArrayLike, dt: float,
                     *, input: Channels = None, output: Channels = None, method: str = "zoh",
                     x0: ArrayLike | None = None) -> NDArray[np.float64]:
    """Response of a continuous linear plant to a sampled input, on the sample grid.

    The plant is discretised exactly for the chosen input hold (the
    block-exponential formulas of :func:`scipy.signal.cont2discrete`) and
    simulated by FFT convolution with its Markov parameters ``C A_d^k B_d``
    (built by doubling), which handles integrators and repeated poles.

    Parameters
    ----------
    plant : NumericStateSpace or control.StateSpace
        Continuous-time plant.
    u : array_like
        Input samples, ``(N,)`` for one input or ``(N, m)`` for the ``m``
        inputs selected by ``input``.
    dt : float
        Sample time in seconds.
    input : str or sequence of str, optional
        Inputs driven by the columns of ``u`` (others are held at zero).
        Default: all inputs.
    output : str or sequence of str, optional
        Outputs to return.  Default: all outputs.
    method : {"zoh", "foh"}
        ``"zoh"``: the input is held constant between samples (a DAC);
        ``"foh"``: it is linear between samples.
    x0 : array_like, optional
        Initial state (default zero).

    Returns
    -------
    numpy.ndarray
        Shape ``(N,)`` when a single output is selected by name or the plant
        has one output, otherwise ``(N, p)``.

    Examples
    --------
    A unit step into ``1/(s + 1)`` sampled at 0.5 s, against ``1 - exp(-t)``:

    >>> import numpy as np
    >>> G = NumericStateSpace([[-1.0]], [[1.0]], [[1.0]], [[0.0]], ("x",), ("u",), ("y",))
    >>> y = simulate_sampled(G, np.ones(4), 0.5)
    >>> bool(np.allclose(y, 1 - np.exp(-0.5 * np.arange(4))))
    True
    """
    ss = _as_plant(plant)
    dt = check_positive_float(dt, "dt")
    if method not in ("zoh", "foh"):
        raise IdentificationError(f"method: expected 'zoh' or 'foh', got {method!r}")
    ins, _ = _channel_indices(input, ss.input_names, "input")
    outs, single = _channel_indices(output, ss.output_names, "output")
    u_arr = _finite_array(u, "u")
    u_arr = u_arr[:, None] if u_arr.ndim == 1 else u_arr
    if u_arr.shape[1] != len(ins):
        raise IdentificationError(
            f"u: expected {len(ins)} column(s), one per input "
            f"({', '.join(ss.input_names[i] for i in ins)}), got {u_arr.shape[1]}")
    if u_arr.shape[0] < 1:
        raise IdentificationError("u: expected at least 1 sample, got 0")
    x0_arr = None
    if x0 is not None:
        x0_arr = _finite_array(x0, "x0", ndim=(1,))
        if x0_arr.size != ss.nstates:
            raise IdentificationError(
                f"x0: expected {ss.nstates} initial states, got {x0_arr.size}")
    B = ss.B[:, ins]
    D = ss.D[np.ix_(outs, ins)]
    C = ss.C[outs]
    Ad, Bd, Cd, Dd = _discretize(ss.A, B, C, D, dt, method)
    if method == "foh" and x0_arr is not None:
        raise IdentificationError("x0: only supported with method='zoh'")
    y = _dlsim(Ad, Bd, Cd, Dd, u_arr, x0_arr)
    return y[:, 0] if single or (output is None and len(outs) == 1) else y


# --------------------------------------------------------------------------- result
@dataclass(frozen=True, eq=False)
class GreyboxResult:
    """Result of :func:`greybox_fit` (read-only).

    Attributes
    ----------
    names : tuple of str
        The free parameters, in the order of :attr:`covariance`.
    estimates : mapping of str to float
        Estimated value of each free parameter.
    std_errors : mapping of str to float
        Standard errors ``sqrt(diag(covariance))`` (NaN if not identifiable).
    confidence_intervals : mapping of str to (float, float)
        95 % intervals ``estimate ± t_{0.975, dof} se``.
    covariance : numpy.ndarray
        ``sigma^2 (J^T J)^{-1}`` in physical units, shape ``(n_free, n_free)``.
    parameters : mapping of str to float
        Every model parameter: the fixed values and the estimates (ready for
        ``compile_plant(model).plant(result.parameters)``).
    initial : mapping of str to float
        Starting values of the free parameters.
    residuals : numpy.ndarray
        ``data - model`` at the estimate: ``(N, p)`` real for time data,
        ``(K,)`` complex (unweighted) for frequency data.
    fit_percent : numpy.ndarray
        NRMSE fit ``100 (1 - ||r|| / ||data - mean(data)||)`` per output.
    noise_variance : float
        ``sigma^2 = ||r_w||^2 / dof`` (weighted residuals for frequency data).
    dof : int
        Residual degrees of freedom ``N_r - n_free``.
    rank : int
        Numerical rank of the Jacobian in the scaled parameters (``< n_free``:
        the free parameters are not identifiable together from these data, and
        the covariance, standard errors and intervals are NaN).
    kind : str
        ``"time"`` or ``"frequency"``.
    input_names, output_names : tuple of str
        The channels fitted.
    plant : NumericStateSpace
        The model at the estimate.
    success : bool
    message : str
    nfev : int
        Residual evaluations by the optimiser.
    cost : float
        ``0.5 ||r_w||^2`` at the estimate.

    Examples
    --------
    A mass with viscous friction, ``v/F = 1/(m s + b)``, ``b`` fitted to its
    exact frequency response:

    >>> import numpy as np, bondgraph as bg
    >>> g = bg.BondGraph("md")
    >>> g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"))
    >>> for a, b in [("F", "v"), ("v", "m"), ("v", "b")]: _ = g.connect(a, b)
    >>> model = bg.derive(g, outputs={"vel": bg.flow("m")})
    >>> w = np.linspace(0.1, 10.0, 30)
    >>> r = greybox_fit(model, FrequencyData(w, 1.0 / (2.0j * w + 0.5)), free=["b"],
    ...                 values={"m": 2.0}, initial={"b": 1.0})
    >>> r.names, r.kind, r.dof, r.rank, r.success, r.output_names
    (('b',), 'frequency', 59, 1, True, ('vel',))
    >>> round(r.estimates["b"], 8), round(r.parameters["m"], 8), np.round(r.fit_percent, 4)
    (0.5, 2.0, array([100.]))
    """

    names: tuple[str, ...]
    estimates: Mapping[str, float]
    std_errors: Mapping[str, float]
    confidence_intervals: Mapping[str, tuple[float, float]]
    covariance: NDArray[np.float64]
    parameters: Mapping[str, float]
    initial: Mapping[str, float]
    residuals: NDArray
    fit_percent: NDArray[np.float64]
    noise_variance: float
    dof: int
    rank: int
    kind: str
    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    plant: NumericStateSpace
    success: bool
    message: str
    nfev: int
    cost: float

    @property
    def correlation(self) -> NDArray[np.float64]:
        """Correlation matrix of the estimates."""
        s = np.sqrt(np.diag(self.covariance))
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.covariance / np.outer(s, s)

    def relative_std(self, name: str) -> float:
        """Standard error of ``name`` relative to its estimate."""
        return abs(self.std_errors[name] / self.estimates[name])

    def table(self, truth: Mapping[str, float] | None = None) -> str:
        """Plain-text table of estimates, standard errors and 95 % intervals.

        Parameters
        ----------
        truth : mapping, optional
            True values to compare with (adds "true" and "error %" columns).
        """
        head = f"{'parameter':<14}{'initial':>12}{'estimate':>13}{'std err':>11}{'95% CI':>31}"
        if truth is not None:
            head += f"{'true':>12}{'error %':>9}"
        rows = [head]
        for n in self.names:
            lo, hi = self.confidence_intervals[n]
            row = (f"{n:<14}{self.initial[n]:>12.4g}{self.estimates[n]:>13.6g}"
                   f"{self.std_errors[n]:>11.2g}{'[' + f'{lo:.6g}, {hi:.6g}' + ']':>31}")
            if truth is not None and n in truth:
                err = 100 * (self.estimates[n] - truth[n]) / truth[n]
                row += f"{truth[n]:>12.4g}{err:>9.3f}"
            rows.append(row)
        return "\n".join(rows)

    def __repr__(self) -> str:
        est = ", ".join(f"{n}={self.estimates[n]:.4g}±{self.std_errors[n]:.2g}" for n in self.names)
        fits = ", ".join(f"{f:.1f}" for f in self.fit_percent)
        return f"GreyboxResult({self.kind}: {est}; fit {fits} %)"


# --------------------------------------------------------------------------- fit
def _compiled(model: Model | NumericModel) -> NumericModel:
    if isinstance(model, NumericModel):
        return model
    if isinstance(model, Model):
        return compile_plant(model)
    raise IdentificationError(
        f"model: expected a bondgraph Model or a NumericModel (compile_plant), "
        f"got {type(model).__name__}")


def _name_map(values: Mapping | None, what: str) -> dict[str, float]:
    if values is None:
        return {}
    if not isinstance(values, Mapping):
        raise IdentificationError(f"{what}: expected a mapping of parameter name to value")
    out = {}
    for k, v in values.items():
        name = k if isinstance(k, str) else getattr(k, "name", None)
        if not isinstance(name, str):
            raise IdentificationError(f"{what}: expected parameter names as keys, got {k!r}")
        try:
            val = float(v)
        except (TypeError, ValueError):
            raise IdentificationError(f"{what}: {name!r} must be a real number, got {v!r}") from None
        if not math.isfinite(val):
            raise IdentificationError(f"{what}: {name!r} must be finite, got {val!r}")
        out[name] = val
    return out


def _unknown(names, known: set[str], what: str) -> None:
    bad = sorted(n for n in names if n not in known)
    if bad:
        raise IdentificationError(
            f"{what}: unknown parameter(s) {', '.join(bad)}; the model's parameters are "
            f"{', '.join(sorted(known))}")


def _bounds(free: list[str], bounds: Mapping | None, nm: NumericModel,
            p0: NDArray) -> tuple[NDArray, NDArray]:
    positive = {s.name: bool(s.is_positive) for s in nm.parameters}
    lo = np.array([0.0 if positive[n] else -np.inf for n in free])
    hi = np.full(len(free), np.inf)
    if bounds is not None:
        if not isinstance(bounds, Mapping):
            raise IdentificationError("bounds: expected a mapping of name to (lower, upper)")
        _unknown(bounds, set(free), "bounds (free parameters)")
        for name, pair in bounds.items():
            try:
                a, b = (float(v) for v in pair)
            except (TypeError, ValueError):
                raise IdentificationError(
                    f"bounds: {name!r} expected a pair (lower, upper), got {pair!r}") from None
            if not a < b:
                raise IdentificationError(f"bounds: {name!r} expected lower < upper, got {pair!r}")
            i = free.index(name)
            lo[i], hi[i] = a, b
    outside = [n for n, v, a, b in zip(free, p0, lo, hi) if not a < v < b]
    if outside:
        raise IdentificationError(
            f"initial: {', '.join(outside)} not strictly inside the bounds "
            f"(positive parameters are bounded below by 0)")
    return lo, hi


def greybox_fit(model: Model | NumericModel, data: TimeData | FrequencyData | FRFResult, *,
                free: Sequence[str], values: Mapping[str, float] | None = None,
                initial: Mapping[str, float] | None = None,
                bounds: Mapping[str, tuple[float, float]] | None = None,
                kind: str | None = None, input: Channels = None, output: Channels = None,
                method: str = "zoh", x0: ArrayLike | None = None,
                ftol: float = 1e-10, xtol: float = 1e-10, max_nfev: int | None = None
                ) -> GreyboxResult:
    """Fit free physical parameters of a linear model to time or frequency data.

    Parameters
    ----------
    model : Model or NumericModel
        A linear derived model (:func:`bondgraph.derive`), or its compiled
        form (:func:`~bondgraph.numeric.compile_plant`) to reuse across fits.
    data : TimeData, FrequencyData or FRFResult
        Measurements.  An :class:`FRFResult` is used through
        :meth:`FrequencyData.from_frf` (``H1``, coherence weights).
    free : sequence of str
        Names of the parameters to estimate.
    values : mapping of str to float, optional
        Values of the other parameters, matched by the package-wide policy
        (:mod:`bondgraph.parameters`): every model parameter must be free or
        given a value; names of the model definition that the derived form
        does not use are accepted.  An entry for a free parameter is its
        starting value unless ``initial`` gives one.
    initial : mapping of str to float, optional
        Starting values of free parameters.
    bounds : mapping of str to (float, float), optional
        Bounds of free parameters.  Default ``(0, inf)`` for parameters
        declared positive in the model, unbounded otherwise.
    kind : {"time", "frequency"}, optional
        Checked against the type of ``data`` when given.
    input : str or sequence of str, optional
        Model input(s) driven by the data (time data: one per column of
        ``u``; frequency data: exactly one).  Required when the model has
        several inputs.
    output : str or sequence of str, optional
        Model output(s) measured (time data: one per column of ``y``;
        frequency data: exactly one).  Required when the model has several
        outputs.
    method : {"zoh", "foh"}
        Input hold between samples for time data.
    x0 : array_like, optional
        Known initial state for time data (default zero).
    ftol, xtol : float
        Tolerances of :func:`scipy.optimize.least_squares`.
    max_nfev : int, optional
        Budget of residual evaluations.

    Returns
    -------
    GreyboxResult

    Raises
    ------
    ParameterValueError
        Unknown parameter names (listing the valid ones), parameters neither
        free nor given a value, values that are not finite real numbers.
    IdentificationError
        Unknown channel names, a free parameter without starting value, NaN/inf data, a
        record with no more residuals than free parameters, channel counts
        that do not match the data, or an evaluation of the model that fails.

    Examples
    --------
    A mass-spring-damper, ``1/(m s^2 + b s + k)``, with ``m`` and ``b`` fitted
    to its exact frequency response:

    >>> import numpy as np, bondgraph as bg
    >>> g = bg.BondGraph("msd")
    >>> F, v = bg.Se("F"), bg.One("v")
    >>> g.add(F, v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    >>> for a, b in [(F, v), (v, "m"), (v, "b"), (v, "k")]: _ = g.connect(a, b)
    >>> model = bg.derive(g, outputs={"x": bg.displacement("k")})
    >>> w = np.linspace(0.5, 5.0, 40)
    >>> H = 1.0 / (2.0 * (1j * w) ** 2 + 0.3 * (1j * w) + 8.0)
    >>> r = greybox_fit(model, FrequencyData(w, H), free=["m", "b"],
    ...                 values={"k": 8.0}, initial={"m": 1.0, "b": 1.0})
    >>> round(r.estimates["m"], 8), round(r.estimates["b"], 8)
    (2.0, 0.3)
    """
    nm = _compiled(model)
    known = set(nm.parameter_names)
    if isinstance(free, str):
        free = [free]
    free = list(free)
    if not free:
        raise IdentificationError("free: expected at least one parameter to estimate")
    if len(set(free)) != len(free):
        raise IdentificationError(f"free: a parameter is listed twice in {free!r}")
    _unknown(free, known, "free")
    where = f"model {nm.model.name!r}: "
    given = match_values(nm.parameters, values, known=nm.model.known_parameters, partial=True,
                         where=where)
    fixed_v = {p.name: real_value(v, p.name, where) for p, v in given.items()}
    initial_v = _name_map(initial, "initial")
    _unknown(initial_v, set(free), "initial (free parameters)")
    missing = [n for n in nm.parameter_names if n not in fixed_v and n not in free]
    if missing:
        raise MissingValueError(
            f"{where}values: missing {', '.join(missing)} (every parameter must be free or "
            f"given a value). Valid names: {', '.join(sorted(nm.model.known_parameters))}",
            missing=tuple(missing))
    no_start = [n for n in free if n not in initial_v and n not in fixed_v]
    if no_start:
        raise IdentificationError(f"initial: no starting value for {', '.join(no_start)}")
    p0 = np.array([initial_v.get(n, fixed_v.get(n, 0.0)) for n in free])
    lo, hi = _bounds(free, bounds, nm, p0)
    base = {n: v for n, v in fixed_v.items() if n not in free}

    if isinstance(data, FRFResult):
        data = FrequencyData.from_frf(data)
    tdata: TimeData | None = None
    fdata: FrequencyData | None = None
    if isinstance(data, TimeData):
        data_kind, tdata = "time", data
    elif isinstance(data, FrequencyData):
        data_kind, fdata = "frequency", data
    else:
        raise IdentificationError(
            f"data: expected TimeData, FrequencyData or FRFResult, got {type(data).__name__}")
    if kind is not None and kind != data_kind:
        raise IdentificationError(
            f"kind: expected {data_kind!r} for {type(data).__name__} data, got {kind!r}")

    ins, _ = _channel_indices(input, nm.input_names, "input")
    outs, _ = _channel_indices(output, nm.output_names, "output")
    x0_arr: NDArray | None = None
    sqrt_w: NDArray | None = None
    if tdata is not None:
        n_u, n_y = tdata.u.shape[1], tdata.y.shape[1]
        if input is None and len(ins) != n_u:
            raise IdentificationError(
                f"input: the model has inputs {', '.join(nm.input_names)}; name the "
                f"{n_u} driven by u")
        if output is None and len(outs) != n_y:
            raise IdentificationError(
                f"output: the model has outputs {', '.join(nm.output_names)}; name the "
                f"{n_y} measured in y")
        if len(ins) != n_u:
            raise IdentificationError(
                f"u: expected {len(ins)} column(s) for input(s) "
                f"{', '.join(nm.input_names[i] for i in ins)}, got {n_u}")
        if len(outs) != n_y:
            raise IdentificationError(
                f"y: expected {len(outs)} column(s) for output(s) "
                f"{', '.join(nm.output_names[i] for i in outs)}, got {n_y}")
        if method not in ("zoh", "foh"):
            raise IdentificationError(f"method: expected 'zoh' or 'foh', got {method!r}")
        if x0 is not None:
            x0_arr = _finite_array(x0, "x0", ndim=(1,))
            if x0_arr.size != len(nm.state_names):
                raise IdentificationError(
                    f"x0: expected {len(nm.state_names)} initial states, got {x0_arr.size}")
            if method != "zoh":
                raise IdentificationError("x0: only supported with method='zoh'")
        target = np.asarray(tdata.y)
        n_res = target.size
    else:
        assert fdata is not None
        if len(ins) != 1 or len(outs) != 1:
            raise IdentificationError(
                f"{'input' if len(ins) != 1 else 'output'}: frequency data is one channel; "
                f"name one input and one output (model inputs: {', '.join(nm.input_names)}; "
                f"outputs: {', '.join(nm.output_names)})")
        weights = np.asarray(fdata.weights)
        target = np.asarray(fdata.response)
        sqrt_w = np.sqrt(weights)
        n_res = 2 * int(np.count_nonzero(weights > 0))
    if n_res <= len(free):
        raise IdentificationError(
            f"data: record too short: {n_res} residuals for {len(free)} free parameters "
            f"(need more residuals than parameters)")

    scale = np.where(p0 != 0, np.abs(p0), 1.0)

    def plant_at(p: NDArray) -> NumericStateSpace:
        vals = dict(base)
        vals.update(zip(free, p.tolist()))
        try:
            return nm.plant(vals)
        except NumericError as exc:
            raise IdentificationError(f"model evaluation failed at {vals}: {exc}") from exc

    def predict(p: NDArray) -> NDArray:
        ss = plant_at(p)
        if tdata is not None:
            B, C, D = ss.B[:, ins], ss.C[outs], ss.D[np.ix_(outs, ins)]
            Ad, Bd, Cd, Dd = _discretize(ss.A, B, C, D, tdata.dt, method)
            return _dlsim(Ad, Bd, Cd, Dd, np.asarray(tdata.u), x0_arr)
        assert fdata is not None
        return ss.frequency_response(fdata.omega)[:, outs[0], ins[0]]

    def weighted(diff: NDArray) -> NDArray:
        if sqrt_w is None:
            return diff.ravel()
        d = diff * sqrt_w
        return np.concatenate((d.real, d.imag))

    def fun(x: NDArray) -> NDArray:
        with np.errstate(over="ignore", invalid="ignore"):
            r = weighted(predict(x * scale) - target)
        if not np.all(np.isfinite(r)):
            return np.full(r.shape, 1e150)
        return r

    sol = scipy.optimize.least_squares(fun, p0 / scale, bounds=(lo / scale, hi / scale),
                                       method="trf", ftol=ftol, xtol=xtol, gtol=1e-12,
                                       max_nfev=max_nfev, x_scale=1.0)
    p_hat = sol.x * scale
    model_out = predict(p_hat)
    resid_w = weighted(model_out - target)
    dof = n_res - len(free)
    sigma2 = float(resid_w @ resid_w) / dof
    # Jacobian in the scaled variables x = p / scale (comparable columns), by central
    # differences at the optimum (more accurate than the optimiser's forward ones)
    _, sv, vt = np.linalg.svd(_central_jacobian(fun, sol.x, lo / scale, hi / scale),
                              full_matrices=False)
    rank = int(np.count_nonzero(sv > _RANK_RTOL * sv.max())) if sv.size and sv.max() > 0 else 0
    if rank == len(free):
        cov_x = sigma2 * (vt.T / sv**2) @ vt
        cov = cov_x * np.outer(scale, scale)           # physical units
    else:
        cov = np.full((len(free), len(free)), np.nan)
    se = np.sqrt(np.diag(cov))
    tq = float(scipy.stats.t.ppf(0.975, dof))
    residuals = target - model_out
    if data_kind == "time":
        fits = [_nrmse_fit(target[:, j], model_out[:, j]) for j in range(target.shape[1])]
        in_names = tuple(nm.input_names[i] for i in ins)
    else:
        fits = [_nrmse_fit(target, model_out)]
        in_names = (nm.input_names[ins[0]],)
    all_params = dict(base)
    all_params.update(zip(free, p_hat.tolist()))
    ordered = {n: all_params[n] for n in nm.parameter_names}
    return GreyboxResult(
        names=tuple(free),
        estimates=MappingProxyType(dict(zip(free, p_hat.tolist()))),
        std_errors=MappingProxyType(dict(zip(free, se.tolist()))),
        confidence_intervals=MappingProxyType(
            {n: (float(v - tq * s), float(v + tq * s)) for n, v, s in zip(free, p_hat, se)}),
        covariance=readonly_copy(cov),
        parameters=MappingProxyType(ordered),
        initial=MappingProxyType(dict(zip(free, p0.tolist()))),
        residuals=readonly_copy(residuals, residuals.dtype),
        fit_percent=readonly_copy(fits),
        noise_variance=sigma2, dof=int(dof), rank=rank, kind=data_kind,
        input_names=in_names, output_names=tuple(nm.output_names[i] for i in outs),
        plant=plant_at(p_hat), success=bool(sol.success), message=str(sol.message),
        nfev=int(sol.nfev), cost=float(0.5 * resid_w @ resid_w))


def _central_jacobian(fun: Any, x: NDArray, lo: NDArray, hi: NDArray) -> NDArray:
    """Central-difference Jacobian of ``fun`` at ``x`` (one-sided next to a bound)."""
    f0 = fun(x)
    J = np.empty((f0.size, x.size))
    for i in range(x.size):
        h = _JAC_STEP * max(1.0, abs(float(x[i])))
        up, down = x[i] + h <= hi[i], x[i] - h >= lo[i]
        xp, xm = x.copy(), x.copy()
        if up and down:
            xp[i] += h
            xm[i] -= h
            J[:, i] = (fun(xp) - fun(xm)) / (2 * h)
        elif up:
            xp[i] += h
            J[:, i] = (fun(xp) - f0) / h
        else:
            xm[i] -= h
            J[:, i] = (f0 - fun(xm)) / h
    return J


def _nrmse_fit(y: NDArray, yhat: NDArray) -> float:
    denom = np.linalg.norm(y - y.mean())
    if denom == 0:
        return float("nan")
    return float(100.0 * (1.0 - np.linalg.norm(y - yhat) / denom))
