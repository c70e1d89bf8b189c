"""Pseudo-random binary sequences (maximum-length LFSR sequences).

A PRBS of order ``n`` is the output of an ``n``-bit linear feedback shift
register whose feedback taps form a primitive polynomial over GF(2).  One
period has ``N = 2**n - 1`` bits, ``2**(n-1)`` ones and ``2**(n-1) - 1``
zeros; mapped to levels ``±a`` its circular autocorrelation is ``a**2`` at
lag 0 and ``-a**2/N`` at every other lag, so the power spectrum of one period
is flat at all non-zero DFT bins.  The bits are produced by
:func:`scipy.signal.max_len_seq`, which holds primitive-polynomial taps for
orders 2 to 32.

Holding each bit for ``k`` samples (the *clock divider*) concentrates the
power below roughly ``fs / (2.3 k)``: the spectrum becomes the flat comb
multiplied by ``sinc**2(f k / fs)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.signal import max_len_seq

from ._validation import (IdentificationError, check_finite_float, check_int,
                          check_positive_float)

__all__ = ["prbs", "prbs_period", "PRBS_MIN_ORDER", "PRBS_MAX_ORDER"]

#: Smallest register length accepted by :func:`prbs`.
PRBS_MIN_ORDER = 2
#: Largest register length accepted by :func:`prbs` (taps known to SciPy).
PRBS_MAX_ORDER = 32


def prbs_period(order: int, *, clock_divider: int = 1) -> int:
    """Number of samples in one period of a PRBS.

    Parameters
    ----------
    order : int
        Shift-register length ``n`` (2 to 32).
    clock_divider : int, optional
        Number of samples each bit is held (>= 1).

    Returns
    -------
    int
        ``(2**order - 1) * clock_divider``.

    Examples
    --------
    >>> prbs_period(10)
    1023
    >>> prbs_period(7, clock_divider=4)
    508
    """
    order = check_int(order, "order", minimum=PRBS_MIN_ORDER, maximum=PRBS_MAX_ORDER)
    clock_divider = check_int(clock_divider, "clock_divider", minimum=1)
    return (2**order - 1) * clock_divider


#: the longest sequence :func:`prbs` builds (about 17 bytes a sample while built: ~1.1 GiB)
PRBS_MAX_SAMPLES = 2**26


def prbs(order: int, *, amplitude: float = 1.0, offset: float = 0.0,
         clock_divider: int = 1, periods: int | None = None,
         length: int | None = None, state: ArrayLike | None = None
         ) -> NDArray[np.float64]:
    """Maximum-length pseudo-random binary sequence with levels ``offset ± amplitude``.

    Parameters
    ----------
    order : int
        Shift-register length ``n``; one period has ``2**n - 1`` bits.
        Must lie in ``[2, 32]``.
    amplitude : float, optional
        Half the peak-to-peak swing ``a`` (> 0); register bit 1 maps to
        ``offset + a`` and bit 0 to ``offset - a``.
    offset : float, optional
        Level added to every sample (the mean of one period is
        ``offset + a / N``).
    clock_divider : int, optional
        Number of consecutive samples each bit is held (>= 1).
    periods : int, optional
        Number of whole periods to return (>= 1).  Default 1 unless
        ``length`` is given.  Mutually exclusive with ``length``.
    length : int, optional
        Exact number of samples to return; the sequence repeats
        periodically and the last period may be cut short.
    state : array_like of {0, 1}, optional
        Initial register state of ``order`` bits, not all zero.  Default is
        all ones (the SciPy default).  A different state gives a circular
        shift of the same sequence.

    Returns
    -------
    numpy.ndarray
        The sequence, dtype ``float64``.

    Raises
    ------
    IdentificationError
        If ``order`` is outside ``[2, 32]``, ``amplitude`` is not positive,
        ``clock_divider``/``periods``/``length`` are not positive integers,
        both ``periods`` and ``length`` are given, or ``state`` is invalid.

    Examples
    --------
    >>> prbs(3)
    array([ 1.,  1.,  1., -1.,  1., -1., -1.])
    >>> prbs(2, amplitude=0.5, offset=2.0, clock_divider=2)
    array([2.5, 2.5, 2.5, 2.5, 1.5, 1.5])
    >>> x = prbs(8, periods=2)
    >>> x.size, int(x[:255].sum())
    (510, 1)
    """
    order = check_int(order, "order", minimum=PRBS_MIN_ORDER, maximum=PRBS_MAX_ORDER)
    amplitude = check_positive_float(amplitude, "amplitude")
    offset = check_finite_float(offset, "offset")
    clock_divider = check_int(clock_divider, "clock_divider", minimum=1)
    n_bits_period = 2**order - 1

    if periods is not None and length is not None:
        raise IdentificationError(
            "periods: expected None when length is given (pass one of periods, length)")
    if length is None:
        periods = 1 if periods is None else check_int(periods, "periods", minimum=1)
        length = periods * n_bits_period * clock_divider
    else:
        length = check_int(length, "length", minimum=1)

    if state is not None:
        st = np.asarray(state)
        if st.shape != (order,) or not np.all((st == 0) | (st == 1)) or not np.any(st):
            raise IdentificationError(
                f"state: expected {order} bits of 0/1, not all zero, got {state!r}")
        state = st.astype(np.int8)

    if length > PRBS_MAX_SAMPLES:      # refused before allocating (prbs(32) needed 32 GiB)
        raise IdentificationError(
            f"length: the sequence would have {length:,} samples ({length * 17 / 2**30:.3g} GiB while "
            f"built), more than the {PRBS_MAX_SAMPLES:,} prbs() builds; pass length= (a part of "
            f"the period) or a lower order (order {order} has a period of {n_bits_period:,} bits)")
    n_bits = -(-length // clock_divider)  # ceil division
    bits, _ = max_len_seq(order, state=state, length=n_bits)
    levels = offset + amplitude * (2.0 * bits.astype(np.float64) - 1.0)
    return np.repeat(levels, clock_divider)[:length]
