"""What a study measures: metrics of a numeric plant, built in or your own.

A metric maps a :class:`~bondgraph.numeric.NumericStateSpace` to one or more
numbers, each a column of the study's table.  The built-in metrics, by name:

============== ============================== =========================================
name           columns                        definition
============== ============================== =========================================
max_real       ``max_real``                   largest real part of the eigenvalues of A
min_damping    ``min_damping``                smallest damping ratio ``-Re p / |p|`` of
                                              the poles, poles at the origin left out
dc_gain        ``dc_gain``                    ``H(0)`` of one channel (nan: A singular)
peak_gain      ``peak_gain``,                 largest ``|H(jw)|`` of one channel and its
               ``peak_frequency``             frequency (rad/s), see :class:`PeakGain`
bandwidth      ``bandwidth``                  first frequency (rad/s) where ``|H|`` drops
                                              3 dB below ``|H(0)|`` (python-control's
                                              definition: nan for an infinite DC gain,
                                              inf if it never drops)
overshoot      ``overshoot``                  step overshoot, percent (python-control
                                              ``step_info``)
settling_time  ``settling_time``              2 % settling time of the step response (s)
step           ``overshoot``,                 both from one step response
               ``settling_time``
============== ============================== =========================================

The first five are vectorised: a study evaluates them on a whole chunk of
plants at once (batched eigenvalues and frequency responses of
:class:`~bondgraph.numeric.BatchStateSpace`); the step metrics and your own
functions run plant by plant.  Channel metrics take ``input=`` and
``output=`` (needed only when the plant has several): ``dc_gain(output="y")``.

Your own metric is a function of a ``NumericStateSpace`` returning a number
(column named after the function), or a mapping of column names to such
functions.  For a process pool it must be importable (a module-level
function); Dask also sends lambdas.

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("msd")
>>> F, v = bg.Se("F"), bg.One("v")
>>> g.add(F, v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
>>> for tail, head in [(F, v), (v, "m"), (v, "b"), (v, "k")]: _ = g.connect(tail, head)
>>> plant = bg.compile_plant(bg.derive(g, outputs={"x": bg.displacement("k")})).plant(
...     {"m": 1.0, "b": 0.4, "k": 4.0})
>>> [round(float(v), 6) for v in MinDamping().bind((), ()).plant(plant)]      # 0.4/(2*sqrt(4))
[0.1]
>>> [float(v) for v in DCGain().bind(plant.input_names, plant.output_names).plant(plant)]
[0.25]
"""

from __future__ import annotations

import dataclasses
import difflib
import numbers
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any, Callable, Mapping, Optional, Sequence

import numpy as np

from ..numeric import ChannelResponse, channel_response, sorted_eigenvalues
from ..numeric.batch import dense_stacks
from .deps import StudyError

__all__ = ["Metric", "MaxReal", "MinDamping", "DCGain", "PeakGain", "Bandwidth", "StepInfo",
           "FunctionMetric", "BUILTIN", "resolve_metrics", "max_real", "min_damping", "dc_gain",
           "peak_gain", "bandwidth", "overshoot", "settling_time", "step"]

#: relative size below which a pole counts as at the origin (an integrator: no damping ratio)
ZERO_POLE = 1e-9


class Metric:
    """Base of the metrics: ``columns`` and ``plant(ss)``; vectorised ones also ``stack``.

    ``stack(plants)`` takes anything with stacked ``A, B, C, D`` and
    ``D_derivatives`` (a :class:`~bondgraph.numeric.BatchStateSpace`) and
    returns one array of ``P`` values per column.
    """

    name: str = "metric"
    columns: tuple[str, ...] = ()
    vectorised: bool = False

    def bind(self, input_names: Sequence[str], output_names: Sequence[str]) -> "Metric":
        """This metric checked against (and fixed to) a plant's signal names."""
        return self

    def stack(self, plants: Any) -> tuple[np.ndarray, ...]:
        raise NotImplementedError

    def plant(self, ss: Any) -> tuple[float, ...]:
        """The metric's values for one plant (the vectorised code on a stack of one)."""
        ss = dense_stacks(ss, what=f"metric {self.name}")
        one = SimpleNamespace(A=ss.A[None], B=ss.B[None], C=ss.C[None], D=ss.D[None],
                              D_derivatives=tuple(M[None] for M in ss.D_derivatives))
        return tuple(float(v[0]) for v in self.stack(one))


def _poles(plants: Any) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues ``(P, n)`` and a mask of those not at the origin."""
    ev = sorted_eigenvalues(plants.A)
    mag = np.abs(ev)
    scale = np.maximum(1.0, mag.max(axis=-1, initial=0.0))[:, None]
    return ev, mag > ZERO_POLE * scale


@dataclass(frozen=True)
class MaxReal(Metric):
    """Largest real part of the eigenvalues of ``A`` (< 0: asymptotically stable)."""

    name = "max_real"
    columns = ("max_real",)
    vectorised = True

    def stack(self, plants: Any) -> tuple[np.ndarray, ...]:
        ev = sorted_eigenvalues(dense_stacks(plants, what=f"metric {self.name}").A)
        return (ev.real.max(axis=-1, initial=-np.inf) if ev.shape[-1] else np.full(len(ev), np.nan),)


@dataclass(frozen=True)
class MinDamping(Metric):
    """Smallest damping ratio ``zeta = -Re p / |p|`` of the poles.

    A pole at the origin (``|p| <= 1e-9 max(1, max |p|)``: an integrator or a
    rigid-body mode) has no damping ratio and is left out; nan when no pole
    remains.  A stable real pole has ``zeta = 1``, an unstable one ``-1``
    (python-control's ``damp``).
    """

    name = "min_damping"
    columns = ("min_damping",)
    vectorised = True

    def stack(self, plants: Any) -> tuple[np.ndarray, ...]:
        ev, keep = _poles(dense_stacks(plants, what=f"metric {self.name}"))
        with np.errstate(invalid="ignore", divide="ignore"):
            zeta = np.where(keep, -ev.real / np.where(keep, np.abs(ev), 1.0), np.inf)
        out = zeta.min(axis=-1, initial=np.inf)
        return (np.where(np.isinf(out), np.nan, out),)


@dataclass(frozen=True)
class _Channel(Metric):
    """A metric of one input-output channel."""

    input: Optional[str] = None
    output: Optional[str] = None
    _i: int = dataclasses.field(default=-1, repr=False)
    _j: int = dataclasses.field(default=-1, repr=False)

    def bind(self, input_names: Sequence[str], output_names: Sequence[str]) -> "Metric":
        j = _pick(self.name, "input", self.input, tuple(input_names))
        i = _pick(self.name, "output", self.output, tuple(output_names))
        return dataclasses.replace(self, input=input_names[j], output=output_names[i], _i=i, _j=j)

    def _response(self, plants: Any, omega: np.ndarray) -> np.ndarray:
        """``H(jw)`` solved directly (exact at ``w = 0``: nan for a singular ``A``)."""
        with np.errstate(all="ignore"):
            return channel_response(plants.A, plants.B, plants.C, plants.D, plants.D_derivatives,
                                    omega, self._i, self._j)

    def _modal(self, plants: Any) -> ChannelResponse:
        """``H`` of every plant, diagonalised once for the many evaluations of a search."""
        return ChannelResponse(plants.A, plants.B, plants.C, plants.D, plants.D_derivatives,
                               self._i, self._j)

    def _grid(self, plants: Any, points: int) -> np.ndarray:
        """``(P, points)`` frequencies, a decade beyond each plant's poles (not at the origin)."""
        ev, keep = _poles(plants)
        mag = np.abs(ev)
        lo = np.where(keep, mag, np.inf).min(axis=-1, initial=np.inf)
        hi = np.where(keep, mag, 0.0).max(axis=-1, initial=0.0)
        none = ~np.isfinite(lo)
        lo, hi = np.where(none, 1.0, lo), np.where(none, 1.0, hi)
        a, b = np.floor(np.log10(lo)) - 1.0, np.ceil(np.log10(hi)) + 1.0
        return 10.0 ** (a[:, None] + (b - a)[:, None] * np.linspace(0.0, 1.0, points))


def _pick(metric: str, kind: str, name: Optional[str], names: tuple[str, ...]) -> int:
    if name is None:
        if len(names) == 1:
            return 0
        raise StudyError(f"metric {metric}: the plant has {len(names)} {kind}s "
                         f"({', '.join(names) or 'none'}); choose one with {metric}({kind}=...)")
    if name not in names:
        near = difflib.get_close_matches(name, names, n=1)
        raise StudyError(f"metric {metric}: no {kind} named {name!r}"
                         + (f" (did you mean {near[0]!r}?)" if near else "")
                         + f"; {kind}s are {', '.join(names) or '(none)'}")
    return names.index(name)


@dataclass(frozen=True)
class DCGain(_Channel):
    """``H(0)`` of one channel; nan when ``A`` is singular (a pole at the origin)."""

    name = "dc_gain"
    columns = ("dc_gain",)
    vectorised = True

    def stack(self, plants: Any) -> tuple[np.ndarray, ...]:
        plants = dense_stacks(plants, what=f"metric {self.name}")
        return (self._response(plants, np.zeros(1))[:, 0].real,)


@dataclass(frozen=True)
class PeakGain(_Channel):
    """Largest ``|H(jw)|`` of one channel, and its frequency (rad/s).

    Searched over ``w = 0`` and ``points`` log-spaced frequencies from a
    decade below the smallest to a decade above the largest pole magnitude
    (poles at the origin left out) -- or over ``omega`` when given -- then
    refined by a golden-section search between the neighbours of the
    largest grid value.  Frequencies where ``jw`` is a pole are skipped.
    """

    omega: Optional[tuple[float, ...]] = None
    points: int = 100
    name = "peak_gain"
    columns = ("peak_gain", "peak_frequency")
    vectorised = True

    def stack(self, plants: Any) -> tuple[np.ndarray, ...]:
        plants = dense_stacks(plants, what=f"metric {self.name}")
        P = plants.A.shape[0]
        if self.omega is not None:
            w = np.broadcast_to(np.sort(np.asarray(self.omega, dtype=float)), (P, len(self.omega)))
        else:
            w = self._grid(plants, self.points)
        H = self._modal(plants)

        def mag(x: np.ndarray) -> np.ndarray:
            m = np.abs(H(x))
            return np.where(np.isfinite(m), m, -np.inf)

        grid = mag(w)
        if self.omega is None:         # w = 0 too, solved exactly
            zero = np.abs(self._response(plants, np.zeros(1)))
            w = np.concatenate([np.zeros((P, 1)), w], axis=1)
            grid = np.concatenate([np.where(np.isfinite(zero), zero, -np.inf), grid], axis=1)
        k = grid.argmax(axis=1)
        rows = np.arange(P)
        best, where = grid[rows, k], w[rows, k]
        lo = w[rows, np.maximum(k - 1, 0)]
        hi = w[rows, np.minimum(k + 1, w.shape[1] - 1)]
        # golden section on [lo, hi] (the largest grid value's neighbours)
        g = (np.sqrt(5.0) - 1.0) / 2.0
        x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
        f1, f2 = mag(x1[:, None])[:, 0], mag(x2[:, None])[:, 0]
        for _ in range(40):
            left = f1 >= f2
            hi = np.where(left, x2, hi)
            lo = np.where(left, lo, x1)
            x1, x2, f1, f2 = (np.where(left, hi - g * (hi - lo), x2), np.where(left, x1, lo + g * (hi - lo)),
                              np.where(left, np.nan, f2), np.where(left, f1, np.nan))
            fresh = mag(np.where(left, x1, x2)[:, None])[:, 0]
            f1, f2 = np.where(left, fresh, f1), np.where(left, f2, fresh)
        for x, f in ((x1, f1), (x2, f2)):      # not a round-off gain on a flat top (a DC peak)
            better = f > best * (1.0 + 1e-12)
            best, where = np.where(better, f, best), np.where(better, x, where)
        none = np.isneginf(best)
        return np.where(none, np.nan, best), np.where(none, np.nan, where)


@dataclass(frozen=True)
class Bandwidth(_Channel):
    """First frequency (rad/s) where ``|H|`` falls ``dbdrop`` dB below ``|H(0)|``.

    python-control's definition (``control.bandwidth``): nan when the DC
    gain is infinite (``A`` singular), inf when the gain does not drop on a
    grid of ``points`` log-spaced frequencies reaching a decade beyond the
    poles; the crossing is then found by bisection.
    """

    dbdrop: float = -3.0
    points: int = 100
    name = "bandwidth"
    columns = ("bandwidth",)
    vectorised = True

    def stack(self, plants: Any) -> tuple[np.ndarray, ...]:
        plants = dense_stacks(plants, what=f"metric {self.name}")
        P = plants.A.shape[0]
        dc = np.abs(self._response(plants, np.zeros(1))[:, 0])
        level = dc * 10.0 ** (self.dbdrop / 20.0)
        w = self._grid(plants, self.points)
        H = self._modal(plants)
        below = np.abs(H(w)) < level[:, None]
        found = below.any(axis=1)
        k = below.argmax(axis=1)
        rows = np.arange(P)
        hi = w[rows, k]
        lo = np.where(k > 0, w[rows, np.maximum(k - 1, 0)], 0.0)
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            drop = np.abs(H(mid[:, None])[:, 0]) < level
            hi, lo = np.where(drop, mid, hi), np.where(drop, lo, mid)
        out = np.where(found, 0.5 * (lo + hi), np.inf)
        return (np.where(np.isfinite(dc), out, np.nan),)


@dataclass(frozen=True)
class StepInfo(_Channel):
    """Step-response overshoot (percent) and settling time (s) of one channel, plant by plant,
    with python-control's ``step_info`` (``settling``: the settling band, 2 %)."""

    columns: tuple[str, ...] = ("overshoot", "settling_time")
    settling: float = 0.02
    name = "step"

    def plant(self, ss: Any) -> tuple[float, ...]:
        import control

        ss = dense_stacks(ss, what=f"metric {self.name}")
        sys = control.ss(ss.A, ss.B[:, [self._j]], ss.C[[self._i], :], ss.D[[self._i]][:, [self._j]])
        info = control.step_info(sys, SettlingTimeThreshold=self.settling)
        picked = {"overshoot": info["Overshoot"], "settling_time": info["SettlingTime"]}
        return tuple(float(picked[c]) for c in self.columns)


@dataclass(frozen=True)
class FunctionMetric(Metric):
    """Your function of a ``NumericStateSpace``, returning one real number (column ``column``)."""

    func: Callable[[Any], Any]
    column: str = "metric"

    @property
    def columns(self) -> tuple[str, ...]:      # type: ignore[override]
        return (self.column,)

    @property
    def name(self) -> str:                      # type: ignore[override]
        return self.column

    def plant(self, ss: Any) -> tuple[float, ...]:
        value = self.func(ss)
        if isinstance(value, np.ndarray) and value.ndim == 0:
            value = value[()]
        if not isinstance(value, numbers.Real):
            raise StudyError(f"metric {self.column} returned {type(value).__name__} "
                             f"{str(value)[:40]}, not a real number")
        return (float(value),)


def max_real() -> MaxReal:
    """The ``max_real`` metric."""
    return MaxReal()


def min_damping() -> MinDamping:
    """The ``min_damping`` metric."""
    return MinDamping()


def dc_gain(input: Optional[str] = None, output: Optional[str] = None) -> DCGain:
    """The ``dc_gain`` metric of one channel."""
    return DCGain(input=input, output=output)


def peak_gain(input: Optional[str] = None, output: Optional[str] = None, *,
              omega: Optional[Sequence[float]] = None, points: int = 100) -> PeakGain:
    """The ``peak_gain`` / ``peak_frequency`` metric of one channel (see :class:`PeakGain`)."""
    return PeakGain(input=input, output=output,
                    omega=None if omega is None else tuple(float(w) for w in omega), points=points)


def bandwidth(input: Optional[str] = None, output: Optional[str] = None, *,
              dbdrop: float = -3.0) -> Bandwidth:
    """The ``bandwidth`` metric of one channel."""
    return Bandwidth(input=input, output=output, dbdrop=dbdrop)


def overshoot(input: Optional[str] = None, output: Optional[str] = None) -> StepInfo:
    """The step ``overshoot`` (percent) of one channel."""
    return StepInfo(input=input, output=output, columns=("overshoot",))


def settling_time(input: Optional[str] = None, output: Optional[str] = None) -> StepInfo:
    """The step ``settling_time`` of one channel."""
    return StepInfo(input=input, output=output, columns=("settling_time",))


def step(input: Optional[str] = None, output: Optional[str] = None) -> StepInfo:
    """Step ``overshoot`` and ``settling_time`` from one step response."""
    return StepInfo(input=input, output=output)


#: built-in metrics by name: factories taking ``input=`` and ``output=`` where they apply
BUILTIN: dict[str, Callable[..., Metric]] = {
    "max_real": max_real, "min_damping": min_damping, "dc_gain": dc_gain, "peak_gain": peak_gain,
    "bandwidth": bandwidth, "overshoot": overshoot, "settling_time": settling_time, "step": step,
}


def _one(spec: Any, column: Optional[str], channel: Mapping[str, Optional[str]]) -> Metric:
    if isinstance(spec, Metric):
        return spec
    if isinstance(spec, str):
        if spec not in BUILTIN:
            near = difflib.get_close_matches(spec, BUILTIN, n=1)
            raise StudyError(f"unknown metric {spec!r}" + (f" (did you mean {near[0]!r}?)" if near else "")
                             + f"; built-in metrics are {', '.join(BUILTIN)}, or pass a function "
                             "of a NumericStateSpace")
        factory = BUILTIN[spec]
        return factory() if spec in ("max_real", "min_damping") else factory(**channel)
    if callable(spec):
        name = str(column or getattr(spec, "__name__", "metric"))
        return FunctionMetric(spec, "metric" if name == "<lambda>" else name)
    raise StudyError(f"a metric must be a built-in name ({', '.join(BUILTIN)}), a function of a "
                     f"NumericStateSpace, or a mapping of column names to functions; got "
                     f"{type(spec).__name__}")


def resolve_metrics(metric: Any, input_names: Sequence[str], output_names: Sequence[str], *,
                    input: Optional[str] = None, output: Optional[str] = None) -> list[Metric]:
    """The metrics of ``metric`` (a name, function, Metric, mapping or list of them), bound.

    ``input``/``output`` choose the channel of named channel metrics.  Step
    metrics of one channel share one step response.

    Raises
    ------
    StudyError
        An unknown name, an ambiguous or unknown channel, or a column named twice.
    """
    channel = {"input": input, "output": output}
    if isinstance(metric, Mapping):
        items = [(_one(f, str(c), channel) if callable(f) and not isinstance(f, Metric)
                  else _renamed(f, str(c), channel)) for c, f in metric.items()]
    elif isinstance(metric, (list, tuple)):
        if not metric:
            raise StudyError("metric: give at least one metric")
        items = [_one(m, None, channel) for m in metric]
    else:
        items = [_one(metric, None, channel)]
    bound = [m.bind(input_names, output_names) for m in items]
    merged: list[Metric] = []
    for m in bound:        # overshoot + settling_time of one channel: one step response
        twin = next((k for k, o in enumerate(merged) if isinstance(o, StepInfo) and isinstance(m, StepInfo)
                     and (o._i, o._j, o.settling) == (m._i, m._j, m.settling)), None)
        if twin is None:
            merged.append(m)
            continue
        first = merged[twin]
        assert isinstance(first, StepInfo)
        cols = first.columns + tuple(c for c in m.columns if c not in first.columns)
        merged[twin] = dataclasses.replace(first, columns=cols)
    seen: set[str] = set()
    for m in merged:
        for c in m.columns:
            if c in seen:
                raise StudyError(f"metric column {c!r} is asked for twice")
            seen.add(c)
    return merged


def _renamed(spec: Any, column: str, channel: Mapping[str, Optional[str]]) -> Metric:
    m = _one(spec, column, channel)
    if isinstance(m, FunctionMetric):
        return dataclasses.replace(m, column=column)
    raise StudyError(f"metric {column!r}: a mapping of columns takes functions; give built-in "
                     "metrics by name or as a list (their columns are named after them)")
