"""What a study varies, and how it samples: parameter ranges and designs.

A parameter of a study is given as

* bounds ``(lo, hi)`` -- a **tuple** of two finite numbers, ``lo < hi``:
  uniform between them;
* a frozen ``scipy.stats`` distribution (``scipy.stats.norm(2.6, 0.1)``):
  sampled through its quantile function ``ppf``;
* explicit values -- a **list** (or 1-D array, or range) of finite numbers:
  each equally likely (a grid takes every one).

Designs: ``"sobol"``, ``"lhs"`` (Latin hypercube) and ``"halton"`` are the
scrambled ``scipy.stats.qmc`` engines, ``"random"`` is independent uniform
draws, ``"grid"`` a full factorial, and an array of shape ``(N, d)`` in the
unit hypercube is used as given.  Every design except the grid draws points
in ``[0, 1)^d`` and maps them through the parameters' ranges.

Examples
--------
>>> import scipy.stats
>>> specs = parameter_specs({"m": (1.0, 2.0), "k": [10.0, 20.0, 40.0], "b": scipy.stats.norm(0.5, 0.1)})
>>> [s.kind for s in specs]
['bounds', 'values', 'distribution']
>>> X, name = design_points(specs, "sobol", 8, seed=1)
>>> X.shape, name, bool((X[:, 0] >= 1.0).all() and (X[:, 0] <= 2.0).all())
((8, 3), 'sobol', True)
>>> sorted(set(X[:, 1].tolist())) <= [10.0, 20.0, 40.0]
True
>>> design_points(parameter_specs({"m": (1.0, 2.0), "k": [1.0, 2.0]}), "grid", 4, seed=0)[0]
array([[1., 1.],
       [1., 2.],
       [2., 1.],
       [2., 2.]])
"""

from __future__ import annotations

import inspect
import math
import numbers
import warnings
from dataclasses import dataclass
from typing import Any, Mapping, Optional, Sequence, Union

import numpy as np

from ..parameters import parameter_name
from .deps import StudyError

__all__ = ["ParameterSpec", "parameter_specs", "design_points", "DESIGNS", "DEFAULT_N",
           "GRID_POINTS", "Design"]

#: designs by name
DESIGNS = ("sobol", "lhs", "halton", "grid", "random")
#: samples when ``n`` is not given (a power of two: Sobol points keep their balance)
DEFAULT_N = 1024
#: grid points per continuous parameter when ``n`` is not given
GRID_POINTS = 11

Design = Union[str, np.ndarray]

_TINY = np.finfo(float).tiny
_BELOW_ONE = np.nextafter(1.0, 0.0)


def _number(value: Any, what: str) -> float:
    """A finite real number, or :class:`StudyError` naming ``what``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise StudyError(f"{what} must be a finite real number; got {type(value).__name__} {value!r}")
    out = float(value)
    if not math.isfinite(out):
        raise StudyError(f"{what} must be a finite real number; got {out!r}")
    return out


@dataclass(frozen=True)
class ParameterSpec:
    """One varied parameter: its name and range (see the module docstring).

    Attributes
    ----------
    name : str
    kind : {"bounds", "distribution", "values"}
    lo, hi : float
        Bounds (``kind == "bounds"``).
    dist : scipy.stats frozen distribution or None
    values : tuple of float
        Explicit values (``kind == "values"``).
    """

    name: str
    kind: str
    lo: float = math.nan
    hi: float = math.nan
    dist: Any = None
    values: tuple[float, ...] = ()

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        """Map points ``u`` of ``[0, 1]`` to parameter values."""
        u = np.asarray(u, dtype=float)
        if self.kind == "bounds":
            return self.lo + u * (self.hi - self.lo)
        if self.kind == "values":
            idx = np.minimum((u * len(self.values)).astype(int), len(self.values) - 1)
            return np.asarray(self.values)[idx]
        return np.asarray(self.dist.ppf(np.clip(u, _TINY, _BELOW_ONE)), dtype=float)

    def grid(self, k: int) -> np.ndarray:
        """Grid points: ``k`` from ``lo`` to ``hi``, the ``k`` mid-quantiles, or every value."""
        if self.kind == "bounds":
            return np.linspace(self.lo, self.hi, k)
        if self.kind == "values":
            return np.asarray(self.values)
        return self.from_unit((np.arange(k) + 0.5) / k)

    def describe(self) -> dict:
        """The range as JSON-ready data (kept in a study's ``df.attrs``)."""
        if self.kind == "bounds":
            return {"bounds": [self.lo, self.hi]}
        if self.kind == "values":
            return {"values": list(self.values)}
        dist = self.dist
        args = ", ".join([repr(a) for a in dist.args] + [f"{k}={v!r}" for k, v in dist.kwds.items()])
        return {"distribution": f"{dist.dist.name}({args})"}


def _spec(name: str, given: Any) -> ParameterSpec:
    where = f"study parameter {name!r}"
    if isinstance(given, tuple):
        if len(given) != 2:
            raise StudyError(f"{where}: bounds must be a tuple (lo, hi) of two numbers; got "
                             f"{len(given)} values (give explicit values as a list)")
        lo, hi = (_number(v, f"{where}: bound") for v in given)
        if not lo < hi:
            raise StudyError(f"{where}: bounds (lo, hi) need lo < hi; got ({lo:g}, {hi:g})")
        return ParameterSpec(name, "bounds", lo=lo, hi=hi)
    if hasattr(given, "ppf") and hasattr(given, "dist"):
        return ParameterSpec(name, "distribution", dist=given)
    if isinstance(given, (list, range, np.ndarray)):
        arr = np.asarray(given)
        if arr.ndim != 1 or arr.size == 0:
            raise StudyError(f"{where}: explicit values must be a non-empty 1-D list; got shape "
                             f"{arr.shape}")
        values = tuple(_number(v.item() if isinstance(v, np.generic) else v, f"{where}: value")
                       for v in arr.tolist())
        return ParameterSpec(name, "values", values=values)
    raise StudyError(f"{where} must be bounds (lo, hi) as a tuple, a frozen scipy.stats "
                     f"distribution, or a list of values; got {type(given).__name__} {given!r}")


def parameter_specs(parameters: Mapping[Any, Any]) -> list[ParameterSpec]:
    """Check a study's ``parameters`` mapping (name or Symbol to range), in the order given.

    Raises
    ------
    StudyError
        Not a mapping, empty, a name given twice, or a bad range (the message
        names the parameter).
    """
    if not isinstance(parameters, Mapping):
        raise StudyError("parameters must map names to bounds (lo, hi), distributions or value "
                         f"lists; got {type(parameters).__name__}")
    if not parameters:
        raise StudyError("parameters must name at least one parameter to vary")
    specs, seen = [], set()
    for key, given in parameters.items():
        try:
            name = parameter_name(key)
        except ValueError as exc:
            raise StudyError(str(exc)) from None
        if name in seen:
            raise StudyError(f"study parameter {name!r} is given twice (as a name and as a Symbol)")
        seen.add(name)
        specs.append(_spec(name, given))
    return specs


def _engine(cls, d: int, rng: np.random.Generator):
    if "rng" in inspect.signature(cls).parameters:       # scipy >= 1.15
        return cls(d, scramble=True, rng=rng)
    return cls(d, scramble=True, seed=rng)               # pragma: no cover - older scipy


def unit_points(design: str, d: int, n: int, seed: int) -> np.ndarray:
    """``n`` points of ``[0, 1)^d`` from a named (non-grid) design."""
    from scipy.stats import qmc

    rng = np.random.default_rng(seed)
    if design == "random":
        return rng.random((n, d))
    cls = {"sobol": qmc.Sobol, "lhs": qmc.LatinHypercube, "halton": qmc.Halton}[design]
    with warnings.catch_warnings():      # Sobol: n not a power of two keeps most of its balance
        warnings.filterwarnings("ignore", message="The balance properties of Sobol")
        return _engine(cls, d, rng).random(n)


def _grid(specs: Sequence[ParameterSpec], n: Optional[int]) -> np.ndarray:
    continuous = [s for s in specs if s.kind != "values"]
    fixed = math.prod(len(s.values) for s in specs if s.kind == "values")
    if n is None:
        k = GRID_POINTS
    else:
        k = max(2, int(math.floor((n / fixed) ** (1.0 / len(continuous)) + 1e-9))) if continuous else 0
    axes = [s.grid(k) for s in specs]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.column_stack([m.ravel() for m in mesh])


def design_points(specs: Sequence[ParameterSpec], design: Design, n: Optional[int],
                  seed: int) -> tuple[np.ndarray, str]:
    """Parameter values ``(N, d)`` (columns as ``specs``) and the design's name.

    Parameters
    ----------
    specs : sequence of ParameterSpec
    design : str or array
        A name of :data:`DESIGNS`, or ``(N, d)`` points of the unit hypercube.
    n : int or None
        Samples (default :data:`DEFAULT_N`); for ``"grid"`` the largest number
        of grid points wanted (at least 2 per continuous parameter; default
        :data:`GRID_POINTS` per continuous parameter); explicit values are
        all taken.
    seed : int

    Raises
    ------
    StudyError
        An unknown design, a bad ``n``, or an array of the wrong shape or
        outside the unit hypercube.
    """
    d = len(specs)
    if n is not None and (isinstance(n, (bool, np.bool_)) or not isinstance(n, numbers.Integral)
                          or n < 1):
        raise StudyError(f"n must be a positive integer; got {n!r}")
    if isinstance(design, str):
        if design == "grid":
            return _grid(specs, None if n is None else int(n)), "grid"
        if design not in DESIGNS:
            import difflib

            near = difflib.get_close_matches(design.lower(), DESIGNS, n=1)
            raise StudyError(f"unknown design {design!r}" + (f" (did you mean {near[0]!r}?)" if near else "")
                             + f"; designs are {', '.join(DESIGNS)}, or an (N, d) array of unit-"
                             "hypercube points")
        unit = unit_points(design, d, DEFAULT_N if n is None else int(n), seed)
        name = design
    else:
        unit = np.asarray(design)
        if unit.dtype.kind not in "fiu" or unit.ndim != 2 or unit.shape[1] != d:
            raise StudyError(f"a design array must be numbers of shape (N, {d}), one column per "
                             f"varied parameter; got {unit.dtype} of shape {unit.shape}")
        unit = unit.astype(float)
        if not np.all((unit >= 0.0) & (unit <= 1.0)):
            raise StudyError("a design array holds points of the unit hypercube [0, 1]^d; "
                             f"got values from {np.nanmin(unit):g} to {np.nanmax(unit):g}")
        if n is not None and n != unit.shape[0]:
            raise StudyError(f"n = {n} but the design array has {unit.shape[0]} rows")
        name = "array"
    return np.column_stack([s.from_unit(unit[:, j]) for j, s in enumerate(specs)]), name
