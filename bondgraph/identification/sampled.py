"""Exact sampled response of a continuous linear plant to a held input.

The simulation half of grey-box identification: the plant is discretised
exactly for a zero- or first-order-hold input (the block-exponential
formulas of :func:`scipy.signal.cont2discrete`, on a numpy Padé exponential,
:func:`_expm`, that stays fast when the cores are busy; see
``bench/greybox_numerics.py``), and the discrete system is simulated by FFT
convolution with its Markov parameters ``C A_d^k B_d``, built by doubling.

Examples
--------
>>> import numpy as np
>>> from bondgraph.numeric import NumericStateSpace
>>> G = NumericStateSpace([[0.0]], [[1.0]], [[1.0]], [[0.0]], ("p",), ("F",), ("p",))
>>> simulate_sampled(G, np.arange(4.0), 1.0, method="foh")    # p = t^2 / 2
array([0. , 0.5, 2. , 4.5])
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence, Union

import numpy as np
import scipy.signal
from numpy.typing import ArrayLike, NDArray

from ..numeric import NumericStateSpace
from ..numeric.plant import control_labels
from ._validation import IdentificationError, check_positive_float, finite_array

if TYPE_CHECKING:  # pragma: no cover
    import control

__all__ = ["simulate_sampled"]

#: Input, output selection: one name, several names or ``None`` (all).
Channels = Union[str, Sequence[str], None]


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

    Golub & Van Loan, *Matrix Computations*, Alg. 11.3.1 (``||M / 2^s||_inf <= 1/2``).
    Kept instead of :func:`scipy.linalg.expm` (and so instead of
    :func:`scipy.signal.cont2discrete`, which calls it) because of
    ``bench/greybox_numerics.py``: scipy's Padé solve goes through LAPACK
    ``getrs``, which OpenBLAS runs multithreaded even for 3 x 3 matrices
    (OpenBLAS issues #1886, #4387).  With the cores busy (tests in parallel,
    several fits at once) a call then waits for a scheduler time slice:
    ``--busy 2`` on 2 cores measures a median of 8 ms a call for the SRV-02
    hold matrix against 0.07 ms for this function, and time-domain fits 2 to 4
    times slower (the 80-fit Monte Carlo test of ``tests/identification/test_greybox.py``
    took 14-33 s instead of 3 s on the shared machine).  numpy's ``solve``
    (LAPACK ``gesv``) stays single threaded at these sizes.  The accuracy is
    ample: within ``1e-13`` relative of a 50-digit mpmath reference on the
    SRV-02 and FLEXCAM hold matrices (scipy: ``1e-16`` to ``1e-13``).  On idle
    cores, or with ``OPENBLAS_NUM_THREADS=1``, scipy's is faster (about 15
    against 60 microseconds a call), a negligible part of a fit either way.

    Examples
    --------
    >>> bool(np.allclose(_expm(np.array([[0.0, 1.0], [-1.0, 0.0]])),
    ...                  [[np.cos(1), np.sin(1)], [-np.sin(1), np.cos(1)]], rtol=0, atol=1e-15))
    True
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
    """Exact discretisation for a zero- (``"zoh"``) or first-order-hold (``"foh"``) input.

    The block-exponential formulas of :func:`scipy.signal.cont2discrete`
    (``[[A, B], [0, 0]] dt``; first-order hold: with a third, ramp block), on
    :func:`_expm` (see there why not scipy's).

    Examples
    --------
    >>> Ad, Bd, Cd, Dd = _discretize(np.zeros((1, 1)), np.ones((1, 1)), np.ones((1, 1)),
    ...                              np.zeros((1, 1)), 0.5, "foh")
    >>> Ad, Bd, Dd                                  # integrator, input linear in between
    (array([[1.]]), array([[0.5]]), array([[0.25]]))
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


#: the working memory :func:`simulate_sampled` may use (Markov parameters and FFTs; 1 GiB)
MAX_WORK_BYTES = 2**30


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
    u_arr = finite_array(u, "u")
    u_arr = u_arr[:, None] if u_arr.ndim == 1 else u_arr
    if u_arr.shape[1] != len(ins):
        raise IdentificationError(
            f"u: expected {len(ins)} column(s), one per input "
            f"({', '.join(ss.input_names[i] for i in ins)}), got {u_arr.shape[1]}")
    if u_arr.shape[0] < 1:
        raise IdentificationError("u: expected at least 1 sample, got 0")
    n, m, p = ss.nstates, len(ins), len(outs)
    work = 8 * u_arr.shape[0] * ((n + p) * (m + 1) + p + 8)
    if work > MAX_WORK_BYTES:
        raise IdentificationError(
            f"u: {u_arr.shape[0]:,} samples would need about {work / 2**30:.1f} GiB of working "
            f"memory ({n} states, {m} inputs, {p} outputs), more than the "
            f"{MAX_WORK_BYTES / 2**30:.0f} GiB budget (bondgraph.identification.sampled."
            "MAX_WORK_BYTES); simulate the record in pieces, each starting from the state "
            "the previous one ends in (x0=)")
    x0_arr = None
    if x0 is not None:
        x0_arr = finite_array(x0, "x0", ndim=(1,))
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
