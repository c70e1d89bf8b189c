"""State-space averaging of a PWM-switched model over one switching period.

A converter switching periodically between an *active* mode (for the fraction
``d`` of each period) and a *passive* mode (for ``1 - d``), with the same
states in both (continuous conduction), has the averaged model

    x' = d f_active(x, u) + (1 - d) f_passive(x, u),
    y  = d g_active(x, u) + (1 - d) g_passive(x, u),

valid when the period is short against the model's time constants
(Middlebrook and Cuk's state-space averaging).  It is returned as an ordinary
:class:`~bondgraph.Model` with the duty cycle ``d`` as one more input, so
``equilibrium``, ``linearize`` and ``transfer_function`` give the
duty-to-output transfer functions of buck, boost and buck-boost converters.

Examples
--------
A buck converter: the averaged duty-to-output transfer function is
``Vin/(L C s^2 + (L/R) s + 1)``.

>>> import bondgraph as bg, sympy
>>> from bondgraph.hybrid import Mode, SwitchedModel
>>> from bondgraph.hybrid.library import buck
>>> sm = SwitchedModel(buck(), outputs={"v": bg.effort("C")})
>>> avg = sm.average("d", active=Mode(on={"S"}, off={"D"}), passive=Mode(on={"D"}, off={"S"}))
>>> avg.input_names, avg.rhs
(('d',), (Vin*d - q_C/C, p_L/L - q_C/(C*R)))
>>> sympy.factor(avg.transfer_function("d", "v").expr)
R*Vin/(C*L*R*s**2 + L*s + R)

With the source voltage an input too (``inputs=("Vin",)``), ``d Vin`` makes the
averaged model nonlinear in its inputs: its transfer functions are taken
about the operating point, by default the symbolic one at ``d = d0``,
``Vin = Vin0`` (control-to-output and line-to-output from one model):

>>> avg2 = sm.average("d", active=Mode(on={"S"}, off={"D"}), passive=Mode(on={"D"}, off={"S"}),
...                   inputs=("Vin",))
>>> G = avg2.transfer_function("Vin", "v")
>>> sympy.factor(G.expr)
R*d0/(C*L*R*s**2 + L*s + R)
>>> print(G.operating_point.note)
deviations about the operating point x0: p_L = L*Vin0*d0/R, q_C = C*Vin0*d0; u0: Vin = Vin0, d = d0; y0: v = Vin0*d0
"""

from __future__ import annotations

import dataclasses
from typing import Mapping, Optional, Sequence, Union

import sympy

from ..elements import Se, Sf
from ..errors import OutputError
from ..model import Model
from .errors import ModeError
from .modes import Mode, ModeSet

__all__ = ["average"]

ModeLike = Union[Mode, Mapping]


def average(sm: ModeSet, duty: Union[str, sympy.Symbol], active: ModeLike, passive: ModeLike,
            *, name: Optional[str] = None, inputs: Sequence[str] = ()) -> Model:
    """The state-space average of two modes of ``sm`` weighted by the duty cycle.

    Parameters
    ----------
    sm : SwitchedModel
    duty : str or sympy.Symbol
        The duty-cycle input (``"d"``): the fraction of the period in ``active``.
    active, passive : Mode or mapping with keys ``'on'`` and ``'off'``
        The two modes; switches not named keep their built state.
    name : str, optional
        The averaged model's name (default ``'<name>_avg'``).
    inputs : sequence of str, optional
        Constant sources (``Se("Vin", value=Vin)``) made inputs named after
        the element, so that the line-to-output transfer function comes from
        the same averaged model as the control-to-output one.

    Returns
    -------
    Model
        Inputs: those of the modes, then ``duty``.  Its ``augmented`` graph is
        the active mode's.

    Raises
    ------
    ModeError
        The two modes do not have the same states (discontinuous conduction:
        a storage element changes causality), or the duty name clashes.
    """
    if inputs:
        sm = _with_inputs(sm, inputs)
    a, p = (_mode(sm, m) for m in (active, passive))
    ma, mp = sm.derived(a).user, sm.derived(p).user
    if ma.states != mp.states:
        raise ModeError(
            f"cannot average modes ({a}) and ({p}) of model {sm.name!r}: their states differ "
            f"({', '.join(ma.state_names) or 'none'} vs {', '.join(mp.state_names) or 'none'}); "
            "the state-space average needs continuous conduction (no storage element in "
            f"derivative causality in one mode only: {', '.join(sm.causality_changes) or '-'})")
    d = sympy.Symbol(duty, real=True) if isinstance(duty, str) else duty
    if not isinstance(d, sympy.Symbol) or not d.name.isidentifier():
        raise ModeError(f"duty must be an identifier or a sympy Symbol; got {duty!r}")
    taken = {s.name for s in ma.states + ma.inputs + mp.inputs} | {s.name for s in ma.parameters}
    if d.name in taken:
        raise ModeError(f"duty name {d.name!r} is already a state, input or parameter of "
                        f"model {sm.name!r}; choose another")
    if ma.output_names != mp.output_names:   # pragma: no cover - same SwitchedModel outputs
        raise OutputError("the two modes have different outputs")
    inputs = tuple(dict.fromkeys(ma.inputs + mp.inputs)) + (d,)
    rhs = tuple(sympy.expand(d * fa + (1 - d) * fp) for fa, fp in zip(ma.rhs, mp.rhs))
    outs = tuple(sympy.expand(d * ya + (1 - d) * yp) for ya, yp in zip(ma.output_exprs, mp.output_exprs))
    derivs = tuple(dict.fromkeys(ma.input_derivatives + mp.input_derivatives))
    return dataclasses.replace(ma, name=name or f"{sm.name}_avg", inputs=inputs, rhs=rhs,
                               output_exprs=outs, input_derivatives=derivs, descriptor=None)


def _with_inputs(sm: ModeSet, names: Sequence[str]) -> ModeSet:
    """``sm`` rebuilt with the constant sources ``names`` made inputs (their value dropped)."""
    if isinstance(names, str) or not all(isinstance(n, str) for n in names):
        raise ModeError(f"inputs: expected a sequence of source names, got {names!r}")
    by_name = {el.name: el for el in sm.flat.elements}
    swap = {}
    for n in names:
        el = by_name.get(n)
        if not isinstance(el, (Se, Sf)):
            raise ModeError(f"inputs: {n!r} is not a source (Se or Sf) of model {sm.name!r}; "
                            "its sources are "
                            f"{', '.join(e.name for e in sm.flat.elements if isinstance(e, (Se, Sf))) or 'none'}")
        if el.value is None:
            raise ModeError(f"inputs: {el.label()} is already an input")
        if el.modulated:
            raise ModeError(f"inputs: {el.label()} is modulated (value={el.value}); only a "
                            "constant source can be made an input")
        swap[n] = dataclasses.replace(el, value=None)
    flat = dataclasses.replace(sm.flat, elements=tuple(swap.get(el.name, el)
                                                       for el in sm.flat.elements))
    return type(sm)(flat, sm.user_outputs)


def _mode(sm: ModeSet, m: ModeLike) -> Mode:
    if isinstance(m, Mode):
        return sm.mode_of(m.on, m.off)
    if isinstance(m, Mapping) and set(m) <= {"on", "off"}:
        return sm.mode_of(m.get("on", ()), m.get("off", ()))
    raise ModeError(f"a mode must be a bondgraph.hybrid.Mode or a mapping with keys 'on' and "
                    f"'off'; got {m!r}")
