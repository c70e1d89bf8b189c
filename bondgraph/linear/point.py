"""The operating point a linear form was taken about: ``x0``, ``u0``, ``y0`` with names.

A model with constant sources (gravity, an ambient temperature, a bias
voltage) or with equations nonlinear in its inputs has its linear forms --
state space, transfer functions, numeric plants -- in deviations ``x - x0``,
``u - u0``, ``y - y0`` about an equilibrium ``f(x0, u0) = 0``.  Each such
result carries the :class:`OperatingPoint` in its ``operating_point``
attribute; :attr:`OperatingPoint.note` says it in words, and the exports
(:mod:`bondgraph.export`) store it.

Examples
--------
>>> import sympy
>>> W, k = sympy.symbols("W k", positive=True)
>>> op = OperatingPoint({"p_m": sympy.S.Zero, "q_k": -W / k}, {"F": sympy.S.Zero},
...                     {"x": -W / k}, how="exact: the linear equations A x0 = -(B u0 + c)")
>>> op.symbolic
True
>>> print(op.note)
deviations about the operating point x0: p_m = 0, q_k = -W/k; u0: F = 0; y0: x = -W/k
>>> op.subs({"W": 9.81, "k": 100.0}).states["q_k"]
-0.0981
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Mapping, Optional, Sequence

import numpy as np
import sympy

from ..errors import BondGraphError, NonlinearModelError
from ..parameters import ParameterValues, exact_value, match_values

__all__ = ["OperatingPoint", "OperatingPointError"]


class OperatingPointError(NonlinearModelError):
    """No operating point to linearize about: none, several, or not solvable symbolically."""


def _value(v: Any) -> Any:
    """A float stays a float; anything else becomes a sympy expression."""
    if isinstance(v, (float, np.floating)):
        return float(v)
    if isinstance(v, (int, np.integer)) and not isinstance(v, bool):
        return sympy.Integer(int(v))
    return sympy.sympify(v, strict=True)


@dataclass(frozen=True)
class OperatingPoint:
    """An equilibrium ``f(x0, u0) = 0`` and the outputs there, by signal name.

    Attributes
    ----------
    states, inputs, outputs : mapping of name to value
        ``x0``, ``u0``, ``y0``: sympy expressions (a symbolic point, such as
        ``q_k = -W/k`` or ``Vg0*d0``) or floats (a numeric point).
    units : mapping of name to str
        The unit of each signal that has one (empty when the model declares none).
    how : str
        How the point was found (an exact linear solve, sympy's solver, the
        numeric search of :func:`bondgraph.linear.equilibrium`).
    equilibrium : Equilibrium or None
        The numeric search's full result (residual, stability) when it found the point.
    """

    states: Mapping[str, Any]
    inputs: Mapping[str, Any]
    outputs: Mapping[str, Any] = field(default_factory=dict)
    units: Mapping[str, str] = field(default_factory=dict, repr=False)
    how: str = field(default="", repr=False)
    equilibrium: Optional[Any] = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("states", "inputs", "outputs"):
            given = getattr(self, name)
            if not isinstance(given, Mapping):
                raise BondGraphError(f"OperatingPoint {name}: expected a mapping of signal "
                                     f"names to values, got {type(given).__name__}")
            object.__setattr__(self, name, MappingProxyType(
                {str(k): _value(v) for k, v in given.items()}))
        object.__setattr__(self, "units", MappingProxyType(
            {str(k): str(v) for k, v in dict(self.units).items()}))

    @property
    def symbolic(self) -> bool:
        """Whether a value is a sympy expression with symbols (not a number)."""
        return any(isinstance(v, sympy.Basic) and v.free_symbols
                   for part in (self.states, self.inputs, self.outputs) for v in part.values())

    @property
    def note(self) -> str:
        """The point in words (what the CLI prints)."""
        def part(label, values):
            if not values:
                return f"{label}: ({self.how or 'none'})" if label == "x0" and self.how \
                    and not self.states else f"{label}: (none)"
            return f"{label}: " + ", ".join(
                f"{n} = {_text(v)}" + (f" {self.units[n]}" if n in self.units else "")
                for n, v in values.items())
        return "deviations about the operating point " + "; ".join(
            part(label, values) for label, values in
            (("x0", self.states), ("u0", self.inputs), ("y0", self.outputs)))

    def __str__(self) -> str:
        return self.note

    def subs(self, values: ParameterValues) -> "OperatingPoint":
        """The point at parameter values: floats where every symbol has a value.

        Raises
        ------
        ParameterValueError
            A name that is no symbol of the point, or a value that is not a
            finite real number.
        """
        syms = sorted({s for part in (self.states, self.inputs, self.outputs)
                       for v in part.values() if isinstance(v, sympy.Basic)
                       for s in v.free_symbols}, key=lambda s: s.name)
        given = match_values(syms, values, known=tuple(str(k) for k in dict(values)),
                             partial=True)
        sub = {p: exact_value(v, p.name) for p, v in given.items()}

        def ev(v):
            if not isinstance(v, sympy.Basic):
                return v
            out = v.xreplace(sub)
            return float(out) if out.is_number and out.is_real is not False else out
        return OperatingPoint({k: ev(v) for k, v in self.states.items()},
                              {k: ev(v) for k, v in self.inputs.items()},
                              {k: ev(v) for k, v in self.outputs.items()}, self.units,
                              self.how, self.equilibrium)

    def vectors(self, state_names: Sequence[str], input_names: Sequence[str],
                output_names: Sequence[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``x0, u0, y0`` as float arrays in the given orders (for a numeric plant's files).

        Raises
        ------
        BondGraphError
            A name the point does not hold, or a value that is still symbolic.
        """
        out = []
        for label, part, names in (("x0", self.states, state_names),
                                   ("u0", self.inputs, input_names),
                                   ("y0", self.outputs, output_names)):
            row = []
            for n in names:
                if n not in part:
                    raise BondGraphError(f"operating point {label} has no value for {n!r}")
                try:
                    row.append(float(part[n]))
                except TypeError:
                    raise BondGraphError(f"operating point {label}: {n} = {part[n]} is "
                                         "symbolic; give parameter values (subs)") from None
            out.append(np.array(row, dtype=float))
        return out[0], out[1], out[2]


def _text(v: Any) -> str:
    return f"{v:.6g}" if isinstance(v, float) else str(v)
