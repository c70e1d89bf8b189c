"""System identification: PRBS excitation, ARX, FRF estimation, rational fits.

The workflow of the FLEXCAM / multibody papers:

* :func:`prbs` — maximum-length pseudo-random binary excitation;
* :func:`arx` — least-squares ARX(na, nb, nk) models (Barbosa & Góes, Eq. 2),
  with :meth:`ARXResult.to_continuous` (inverse zero-order hold, :func:`d2c_zoh`);
* :func:`estimate_frf` — Welch ``H1``/``H2`` and coherence (Soares et al.,
  Eq. 35); :func:`find_modal_peaks` — resonance peaks in autospectra;
* :func:`fit_rational` — Levy / Sanathanan–Koerner rational fit of FRF data
  (the role of MATLAB ``invfreqs``);
* :func:`greybox_fit` — physical parameters of a bond-graph model fitted to
  time (:class:`TimeData`) or frequency (:class:`FrequencyData`) data, with
  standard errors and confidence intervals; :func:`simulate_sampled` — exact
  sampled response of a plant to a held input.  Grey-box modules, in pipeline
  order: ``data`` (the records) -> ``sampled`` (the model's response) ->
  ``greybox`` (the fit) -> ``greybox_result``.

All invalid arguments raise :class:`IdentificationError` (a ``ValueError``).
"""

from ._validation import IdentificationError
from .arx import ARXResult, arx, fit_percent
from .conversion import d2c_zoh
from .frf import FRFResult, SpectralPeaks, estimate_frf, find_modal_peaks
from .greybox import FrequencyData, GreyboxResult, TimeData, greybox_fit, simulate_sampled
from .prbs import PRBS_MAX_ORDER, PRBS_MIN_ORDER, prbs, prbs_period
from .rational import RationalFit, fit_rational, fit_rational_detailed

__all__ = [
    "IdentificationError",
    "prbs", "prbs_period", "PRBS_MIN_ORDER", "PRBS_MAX_ORDER",
    "ARXResult", "arx", "fit_percent",
    "d2c_zoh",
    "FRFResult", "SpectralPeaks", "estimate_frf", "find_modal_peaks",
    "RationalFit", "fit_rational", "fit_rational_detailed",
    "TimeData", "FrequencyData", "GreyboxResult", "greybox_fit", "simulate_sampled",
]

IdentificationError.__module__ = __name__   # tracebacks name it where users import it
