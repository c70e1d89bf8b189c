"""Plots of numeric plants: Bode, pole-zero, step and impulse responses, FRF overlays.

Every function returns a new :class:`matplotlib.figure.Figure` (no pyplot,
no global state), so they work on any backend, in notebooks (a Figure shows
itself) and in tests; save one with ``fig.savefig("bode.png")``.  Responses
are computed with python-control.

A *system* is a python-control LTI system (``TransferFunction``,
``StateSpace``, ...), a ``(num, den)`` tuple of polynomial coefficients in
``s`` (highest power first), or -- for frequency plots only -- a callable
``H(s)`` evaluated at ``s = j*omega``.

Examples
--------
>>> import control
>>> from bondgraph.drawing.plots import bode
>>> fig = bode(control.tf([1], [1, 1]))
>>> [ax.get_ylabel() for ax in fig.axes]
['Magnitude [dB]', 'Phase [deg]']
"""

from __future__ import annotations

from typing import Callable, Optional, Sequence, Union

import control
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike, NDArray

from ..errors import BondGraphError

__all__ = ["PlotError", "bode", "pole_zero", "step", "impulse", "frf_overlay"]

SystemLike = Union[control.LTI, tuple, Callable[[NDArray[np.complex128]], ArrayLike]]


class PlotError(BondGraphError, ValueError):
    """A plot was asked of something it cannot show (a MIMO system, bad data)."""


# ---------------------------------------------------------------- helpers
def _is_pair(obj) -> bool:
    """A ``(num, den)`` tuple of coefficient sequences."""
    if not isinstance(obj, tuple) or len(obj) != 2:
        return False
    if any(isinstance(x, control.LTI) or callable(x) for x in obj):
        return False
    try:
        return all(np.asarray(x, dtype=float).ndim <= 1 for x in obj)
    except (TypeError, ValueError):
        return False


def _systems(systems) -> list:
    if isinstance(systems, control.LTI) or callable(systems) or _is_pair(systems):
        return [systems]
    if isinstance(systems, (list, tuple)):
        if not systems:
            raise PlotError("no system to plot: got an empty sequence")
        return list(systems)
    raise PlotError(
        "expected a python-control system, a (num, den) tuple or a callable H(s); got "
        f"{type(systems).__name__} {systems!r}"
    )


def _lti(sys, what: str, *, siso: bool = True) -> control.LTI:
    if _is_pair(sys):
        num, den = sys
        sys = control.tf(np.atleast_1d(np.asarray(num, dtype=float)),
                         np.atleast_1d(np.asarray(den, dtype=float)))
    if not isinstance(sys, control.LTI):
        raise PlotError(
            f"{what} needs a python-control system or a (num, den) tuple; got "
            f"{type(sys).__name__} {sys!r}"
        )
    if siso and not sys.issiso():
        raise PlotError(
            f"{what} draws single-input single-output systems; this one has "
            f"{sys.ninputs} inputs and {sys.noutputs} outputs: select a channel, e.g. sys[0, 0]"
        )
    return sys


def _response(sys, omega: NDArray[np.float64], what: str) -> NDArray[np.complex128]:
    """Complex frequency response at ``omega`` [rad/s] of a system or callable."""
    if callable(sys) and not isinstance(sys, control.LTI):
        s = 1j * omega
        try:
            H = np.asarray(sys(s), dtype=complex)
        except TypeError:
            H = np.array([complex(sys(x)) for x in s])
        if H.shape != omega.shape:
            H = np.broadcast_to(H, omega.shape).astype(complex)
        return H
    lti = _lti(sys, what)
    H = control.frequency_response(lti, omega).complex
    return np.asarray(H, dtype=complex).reshape(omega.shape)


def _default_omega(systems: Sequence) -> NDArray[np.float64]:
    """Two decades around the poles and zeros of the LTI systems (1e-2..1e3 otherwise)."""
    mags: list[float] = []
    nyquist = np.inf
    for sys in systems:
        if callable(sys) and not isinstance(sys, control.LTI):
            continue
        lti = _lti(sys, "bode")
        roots = np.concatenate([np.atleast_1d(control.poles(lti)),
                                np.atleast_1d(control.zeros(lti))])
        if lti.isdtime(strict=True):
            dt = float(lti.dt) if lti.dt is not True else 1.0
            nyquist = min(nyquist, np.pi / dt * (1 - 1e-9))
            with np.errstate(divide="ignore"):
                roots = np.log(roots.astype(complex)) / dt
        mags.extend(abs(r) for r in roots if np.isfinite(r) and abs(r) > 1e-12)
    if mags:
        lo = 10.0 ** (np.floor(np.log10(min(mags))) - 1)
        hi = 10.0 ** (np.ceil(np.log10(max(mags))) + 1)
    else:
        lo, hi = 1e-2, 1e3
    hi = min(hi, nyquist)
    lo = min(lo, hi / 100)
    return np.logspace(np.log10(lo), np.log10(hi), 500)


def _phase_deg(H: NDArray[np.complex128]) -> NDArray[np.float64]:
    return np.degrees(np.unwrap(np.angle(H)))


def _db(H: NDArray[np.complex128]) -> NDArray[np.float64]:
    with np.errstate(divide="ignore"):
        return 20.0 * np.log10(np.abs(H))


# ---------------------------------------------------------------- frequency plots
def bode(systems: Union[SystemLike, Sequence[SystemLike]], *,
         omega: Optional[ArrayLike] = None, hz: bool = False,
         labels: Optional[Sequence[str]] = None, title: Optional[str] = None) -> Figure:
    """Bode diagram (magnitude in dB, phase in degrees) of one or several systems.

    Parameters
    ----------
    systems : system or list of systems
        python-control systems, ``(num, den)`` tuples or callables ``H(s)``
        (SISO); several go in a list.
    omega : array_like, optional
        Frequencies in rad/s (also with ``hz=True``); by default 500 points
        from a decade below the slowest to a decade above the fastest pole
        or zero.
    hz : bool
        Label the frequency axis in Hz (``omega / 2 pi``) instead of rad/s.
    labels : sequence of str, optional
        Legend entries, one per system.
    title : str, optional

    Returns
    -------
    Figure
        Two axes (magnitude, phase), one line per system in each.

    Examples
    --------
    >>> import control, numpy as np
    >>> fig = bode([control.tf([1], [1, 1]), ([1], [1, 2, 1])], omega=np.array([0.1, 1.0, 10.0]),
    ...            labels=["first order", "second order"])
    >>> mag = fig.axes[0].lines[0].get_ydata()
    >>> round(float(mag[1]), 2)
    -3.01
    """
    syss = _systems(systems)
    if labels is not None and len(labels) != len(syss):
        raise PlotError(f"bode: {len(syss)} systems but {len(labels)} labels; "
                        "give one label per system")
    w = _default_omega(syss) if omega is None else np.asarray(omega, dtype=float).ravel()
    if w.size == 0 or np.any(w <= 0):
        raise PlotError("bode: omega must hold positive frequencies in rad/s")
    x = w / (2 * np.pi) if hz else w
    fig = Figure(figsize=(6.4, 5.2), layout="constrained")
    ax_mag, ax_ph = fig.subplots(2, 1, sharex=True)
    for k, sys in enumerate(syss):
        H = _response(sys, w, "bode")
        label = labels[k] if labels is not None else (f"system {k + 1}" if len(syss) > 1 else None)
        ax_mag.semilogx(x, _db(H), label=label)
        ax_ph.semilogx(x, _phase_deg(H), label=label)
    ax_mag.set_ylabel("Magnitude [dB]")
    ax_ph.set_ylabel("Phase [deg]")
    ax_ph.set_xlabel("Frequency [Hz]" if hz else "Frequency [rad/s]")
    for ax in (ax_mag, ax_ph):
        ax.grid(True, which="both", alpha=0.3)
    if labels is not None or len(syss) > 1:
        ax_mag.legend(loc="best")
    if title:
        fig.suptitle(title)
    return fig


def frf_overlay(freq_hz: ArrayLike, H_measured: ArrayLike, coherence: Optional[ArrayLike] = None,
                model_system: Optional[SystemLike] = None, *, measured_label: str = "measured",
                model_label: str = "model", title: Optional[str] = None) -> Figure:
    """Measured frequency response against a model, with the coherence below.

    Parameters
    ----------
    freq_hz : array_like
        Frequencies in Hz of the measurement (non-positive ones, such as the
        0 Hz bin of a Welch estimate, are left out of the log axis).
    H_measured : array_like of complex
        Measured response (e.g. ``estimate_frf(...).h1``).
    coherence : array_like, optional
        Coherence at the same frequencies; adds a third axis.
    model_system : system, optional
        Model evaluated at ``2 pi freq_hz``; its phase is shifted by a
        multiple of 360 deg to start on the measured branch.
    measured_label, model_label : str
        Legend entries.
    title : str, optional

    Returns
    -------
    Figure
        Axes: magnitude [dB], phase [deg] (measured, then model line), and
        coherence when given.

    Examples
    --------
    >>> import control, numpy as np
    >>> f = np.linspace(0.0, 2.0, 41)
    >>> sys = control.tf([1], [1, 1])
    >>> H = 1 / (2j * np.pi * f + 1)
    >>> fig = frf_overlay(f, H, np.ones_like(f), sys)
    >>> len(fig.axes), [len(ax.lines) for ax in fig.axes]
    (3, [2, 2, 1])
    """
    f = np.asarray(freq_hz, dtype=float).ravel()
    H = np.asarray(H_measured, dtype=complex).ravel()
    if H.shape != f.shape:
        raise PlotError(f"frf_overlay: {f.size} frequencies but {H.size} response values; "
                        "expected one value per frequency")
    coh = None
    if coherence is not None:
        coh = np.asarray(coherence, dtype=float).ravel()
        if coh.shape != f.shape:
            raise PlotError(f"frf_overlay: {f.size} frequencies but {coh.size} coherence values; "
                            "expected one value per frequency")
    keep = f > 0
    if not np.any(keep):
        raise PlotError("frf_overlay: no positive frequency to plot")
    f, H = f[keep], H[keep]
    fig = Figure(figsize=(6.4, 6.4 if coh is not None else 5.2), layout="constrained")
    axes = fig.subplots(3 if coh is not None else 2, 1, sharex=True)
    ax_mag, ax_ph = axes[0], axes[1]
    ph_meas = _phase_deg(H)
    ax_mag.semilogx(f, _db(H), ".", ms=3, label=measured_label)
    ax_ph.semilogx(f, ph_meas, ".", ms=3, label=measured_label)
    if model_system is not None:
        Hm = _response(model_system, 2 * np.pi * f, "frf_overlay")
        ph_model = _phase_deg(Hm)
        ph_model += 360.0 * np.round((ph_meas[0] - ph_model[0]) / 360.0)
        ax_mag.semilogx(f, _db(Hm), "-", label=model_label)
        ax_ph.semilogx(f, ph_model, "-", label=model_label)
    ax_mag.set_ylabel("Magnitude [dB]")
    ax_ph.set_ylabel("Phase [deg]")
    if coh is not None:
        ax_c = axes[2]
        ax_c.semilogx(f, coh[keep], "-", color="0.3", label="coherence")
        ax_c.set_ylim(0, 1.05)
        ax_c.set_ylabel("Coherence")
    axes[-1].set_xlabel("Frequency [Hz]")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    ax_mag.legend(loc="best")
    if title:
        fig.suptitle(title)
    return fig


# ---------------------------------------------------------------- poles and zeros
def pole_zero(system: SystemLike, *, title: Optional[str] = None) -> Figure:
    """Pole-zero map: poles as crosses, zeros as circles.

    The stability boundary is drawn too: the imaginary axis, or the unit
    circle for a discrete-time system.

    Parameters
    ----------
    system : python-control system or (num, den) tuple
    title : str, optional

    Returns
    -------
    Figure
        One axis with the lines ``poles``, ``zeros`` (possibly empty) and
        the stability boundary.

    Examples
    --------
    >>> import control
    >>> fig = pole_zero(control.tf([1, 2], [1, 2, 5]))
    >>> ax = fig.axes[0]
    >>> sorted(ln.get_label().split()[0] for ln in ax.lines)
    ['imaginary', 'poles', 'zeros']
    >>> sorted(ax.lines[0].get_xdata().tolist())
    [-1.0, -1.0]
    """
    lti = _lti(system, "pole_zero", siso=False)
    p = np.atleast_1d(control.poles(lti)).astype(complex)
    z = np.atleast_1d(control.zeros(lti)).astype(complex)
    fig = Figure(figsize=(5.2, 4.8), layout="constrained")
    ax = fig.subplots()
    ax.plot(p.real, p.imag, "x", ms=9, mew=2, color="C3", label=f"poles ({p.size})")
    ax.plot(z.real, z.imag, "o", ms=8, mfc="none", mew=1.5, color="C0", label=f"zeros ({z.size})")
    if lti.isdtime(strict=True):
        t = np.linspace(0, 2 * np.pi, 361)
        ax.plot(np.cos(t), np.sin(t), "--", color="0.6", lw=1, label="unit circle")
        ax.set_aspect("equal", adjustable="datalim")
    else:
        ax.axvline(0.0, color="0.6", lw=1, ls="--", label="imaginary axis")
    ax.set_xlabel("Real")
    ax.set_ylabel("Imaginary")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    if title:
        fig.suptitle(title)
    return fig


# ---------------------------------------------------------------- time responses
def _time_plot(system: SystemLike, T, what: str, title: Optional[str]) -> Figure:
    lti = _lti(system, what, siso=False)
    fn = control.step_response if what == "step" else control.impulse_response
    resp = fn(lti, T=T, squeeze=False)
    t = np.asarray(resp.time)
    y = np.asarray(resp.outputs)   # (outputs, inputs, time)
    ny, nu = y.shape[0], y.shape[1]
    fig = Figure(figsize=(max(4.8, 3.2 * nu), max(3.6, 2.4 * ny)), layout="constrained")
    axes = np.atleast_2d(fig.subplots(ny, nu, sharex=True, squeeze=False))
    in_names = list(getattr(lti, "input_labels", [])) or [f"u[{j}]" for j in range(nu)]
    out_names = list(getattr(lti, "output_labels", [])) or [f"y[{i}]" for i in range(ny)]
    for i in range(ny):
        for j in range(nu):
            ax = axes[i, j]
            ax.plot(t, y[i, j], label=f"{out_names[i]} from {in_names[j]}")
            ax.grid(True, alpha=0.3)
            if ny * nu > 1:
                ax.set_title(f"{in_names[j]} \u2192 {out_names[i]}", fontsize="medium")
            if j == 0:
                ax.set_ylabel(out_names[i] if ny > 1 else "Output")
    for j in range(nu):
        axes[-1, j].set_xlabel("Time [s]")
    fig.suptitle(title or f"{'Step' if what == 'step' else 'Impulse'} response")
    return fig


def step(system: SystemLike, T: Optional[Union[float, ArrayLike]] = None, *,
         title: Optional[str] = None) -> Figure:
    """Step response, one axis per (output, input) pair.

    Parameters
    ----------
    system : python-control system or (num, den) tuple
    T : float or array_like, optional
        Final time, or the time points; chosen from the dynamics by default.
    title : str, optional

    Returns
    -------
    Figure
        ``noutputs x ninputs`` axes with one line each, titled with the
        system's input and output names.

    Examples
    --------
    >>> import control
    >>> fig = step(control.tf([1], [1, 1]), T=5.0)
    >>> y = fig.axes[0].lines[0].get_ydata()
    >>> len(fig.axes), round(float(y[-1]), 2)
    (1, 0.99)
    """
    return _time_plot(system, T, "step", title)


def impulse(system: SystemLike, T: Optional[Union[float, ArrayLike]] = None, *,
            title: Optional[str] = None) -> Figure:
    """Impulse response, one axis per (output, input) pair.

    Parameters
    ----------
    system : python-control system or (num, den) tuple
    T : float or array_like, optional
        Final time, or the time points; chosen from the dynamics by default.
    title : str, optional

    Returns
    -------
    Figure

    Examples
    --------
    >>> fig = impulse(([1], [1, 1]), T=3.0)
    >>> round(float(fig.axes[0].lines[0].get_ydata()[0]), 2)
    1.0
    """
    return _time_plot(system, T, "impulse", title)
