"""Value checks of a switched model: every equation, output, guard and the stored energy
finite with the given values (naming the element whose parameter is zero), and every
declared switching period a finite positive number.

The simulation (:mod:`bondgraph.hybrid.events`) and the switched code generators
(:mod:`bondgraph.codegen`) refuse a model with these messages.

Examples
--------
>>> import sympy
>>> from bondgraph.hybrid import SwitchedModel, library
>>> sm = SwitchedModel(library.rectifier())
>>> fulls = [sm.derived(m).full for m in sm.modes]
>>> vals = {s: sympy.Float(0 if s.name == "C" else 1) for s in fulls[0].parameters}
>>> print(nonfinite(sm, sm.modes, fulls, vals))
model 'rectifier', mode (D off): the equations are not finite with these values: C:C has C = 0 (a storage parameter or a period must be nonzero)
"""

from __future__ import annotations

import math
from typing import Sequence

import sympy

from .modes import Mode, ModeSet

__all__ = ["nonfinite", "periods"]


_NONFINITE = (sympy.zoo, sympy.nan, sympy.oo, -sympy.oo)


def nonfinite(sm: ModeSet, modes: Sequence[Mode], fulls: Sequence, subs: dict) -> str:
    """Why an equation, output, guard or the stored energy of ``sm`` is not finite with the
    values ``subs`` (naming the element and its parameter that is zero), or ``""``."""
    for mode, full in zip(modes, fulls):
        groups = ([("the equations are", e) for e in full.rhs]
                  + [("the outputs are", e) for e in full.output_exprs])
        for n in sm.switches:
            g = sm.element(n).guard(mode.is_on(n))
            if g is not None:
                groups.append((f"the guard of switch {n!r} is", g))
        for what, expr in groups:
            if sympy.sympify(expr.xreplace(subs), strict=True).has(*_NONFINITE):
                return (f"model {sm.name!r}, mode ({mode}): {what} not finite with these "
                        f"values{_culprits(sm, expr, subs)}")
    _, H = sm.energy()
    if sympy.sympify(H.xreplace(subs), strict=True).has(*_NONFINITE):
        return (f"model {sm.name!r}: the stored energy is not finite with these "
                f"values{_culprits(sm, H, subs)}")
    return ""


def _culprits(sm: ModeSet, expr: sympy.Expr, subs: dict) -> str:
    """``": C:C has C = 0 (...)"`` for the elements whose parameters are zero in ``expr``."""
    from .._support.sympify import parameter_symbols

    zero = {s.name for s in expr.free_symbols if s in subs and float(subs[s]) == 0}
    if not zero:
        zero = {getattr(s, "name", str(s)) for s, v in subs.items() if float(v) == 0}
    found = []
    for el in sm.flat.elements:
        hit = sorted({p.name for p in parameter_symbols(el)} & zero)
        if hit:
            found.append(f"{el.label()} has {', '.join(f'{h} = 0' for h in hit)}")
    for n in sm.switches:
        el = sm.element(n)
        for what in ("gate", "period"):
            ex = getattr(el, what, None)
            hit = sorted({s.name for s in getattr(ex, "free_symbols", ())} & zero)
            if hit and not any(f.startswith(el.label() + " ") for f in found):
                found.append(f"the {what} of switch {n!r} has {', '.join(f'{h} = 0' for h in hit)}")
    if not found:
        return ""
    return ": " + "; ".join(found) + " (a storage parameter or a period must be nonzero)"


def periods(sm: ModeSet, subs: dict) -> tuple[dict, str]:
    """The numeric period of every switch that declares one, and why one is not a finite
    positive number (``""`` when all are)."""
    out: dict[str, float] = {}
    for n in sm.switches:
        p = getattr(sm.element(n), "period", None)
        if p is None:
            continue
        val = p.xreplace(subs)
        try:
            v = float(val)
        except (TypeError, ValueError):
            return out, f"model {sm.name!r}: the period of switch {n!r} is {val}, not a number"
        if not (math.isfinite(v) and v > 0):
            return out, (f"model {sm.name!r}: the period of switch {n!r} ({p} = {v:g}) must be a "
                         "finite positive number")
        out[n] = v
    return out, ""
