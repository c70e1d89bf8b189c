"""The result of a grey-box fit: :class:`GreyboxResult` (estimates, statistics, plant).

The fit (:func:`~bondgraph.identification.greybox_fit`) fills it: estimates
with standard errors and 95 % confidence intervals from the residual Jacobian
at the optimum, residuals, NRMSE fit per output and the plant at the estimate.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np
from numpy.typing import NDArray

from ..numeric import NumericStateSpace

__all__ = ["GreyboxResult"]


@dataclass(frozen=True, eq=False)
class GreyboxResult:
    """Result of :func:`~bondgraph.identification.greybox_fit` (read-only).

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
        Residual evaluations by the optimiser (those of its finite-difference
        Jacobians not counted).
    cost : float
        ``0.5 ||r_w||^2`` at the estimate.

    Examples
    --------
    A mass with viscous friction, ``v/F = 1/(m s + b)``, ``b`` fitted to its
    exact frequency response:

    >>> import numpy as np, bondgraph as bg
    >>> from bondgraph.identification import FrequencyData, greybox_fit
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
