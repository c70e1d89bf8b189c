"""The FMU's variables: names, value references, causality, start values and dependencies (private).

One :class:`Plan` serves both FMI versions: the variables are listed in
value-reference order (time, states, derivatives, inputs, outputs,
parameters, the Co-Simulation step), which is also their order in the
model description, so the FMI 2 index of a variable is its value reference
plus one.

Names: a model's states, inputs and parameters keep their names (the model
guarantees they are distinct); an output named like one of them gets the
suffix ``_2`` (``_3``...) unless it *is* that state (an integrator state
named after its output, ``theta``), in which case the one variable is the
state and the output (causality ``output``).  FMI's flat naming convention
forbids carriage returns, line feeds and tabs in a name, and XML 1.0 cannot
carry other control characters, so those are written as visible escapes
(``\\n``, ``\\x01``...); the variable's description then gives the model's
name as a JSON string.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from typing import Iterable, Optional, Sequence

import sympy

from ..model import Model
from ..signals import t as T_SYM
from ._defaults import Experiment, RunDefaults

__all__ = ["Variable", "Plan", "make_plan", "fmi_name", "xml_text", "STEP_NAME"]

#: name of the Co-Simulation step parameter (``_2``... if the model has one of that name)
STEP_NAME = "rk4_step"

# characters XML 1.0 cannot carry (the C0 controls but tab, LF, CR; lone surrogates; U+FFFE/F)
_XML_BAD = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")
# ... and the ones FMI's flat naming convention forbids in a name on top of them
_NAME_BAD = re.compile("[\x00-\x1f\ud800-\udfff\ufffe\uffff]")
_NAMED = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}


def _escape(match: "re.Match[str]") -> str:
    ch = match.group(0)
    code = ord(ch)
    return _NAMED.get(ch) or (f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}")


def xml_text(text: str) -> str:
    r"""``text`` with the characters XML 1.0 cannot hold written as visible escapes.

    Examples
    --------
    >>> xml_text("a\x01b\tc")
    'a\\x01b\tc'
    """
    return _XML_BAD.sub(_escape, text)


def fmi_name(text: str) -> str:
    r"""A valid FMI variable name (flat naming convention) for a model's name.

    A name that needs no change is returned as it is; otherwise backslashes
    are doubled and the forbidden characters escaped.

    Examples
    --------
    >>> fmi_name("motor.Ra"), fmi_name('a"<&]]>'), fmi_name("a\\b\nc")
    ('motor.Ra', 'a"<&]]>', 'a\\\\b\\nc')
    """
    if not _NAME_BAD.search(text):
        return text
    return _NAME_BAD.sub(_escape, text.replace("\\", "\\\\"))


@dataclass(frozen=True)
class Variable:
    """One FMI variable.

    ``kind`` is ``time``, ``state``, ``derivative``, ``input``, ``output``,
    ``parameter`` or ``step``; ``index`` is the position in the C array of
    that kind (``x``, ``u``, ``y``, ``p``; 0 for time and the step).
    ``derivative_of`` is the value reference of the state a derivative
    belongs to.  ``output_index`` is the output's position for a state that
    is also an output.
    """

    name: str
    vr: int
    kind: str
    index: int
    causality: str
    variability: str
    initial: Optional[str]
    start: Optional[float]
    description: str
    derivative_of: Optional[int] = None
    output_index: Optional[int] = None
    nominal: Optional[float] = None


@dataclass(frozen=True)
class Unknown:
    """A ModelStructure entry: the unknown's value reference, its dependencies and their kinds."""

    vr: int
    dependencies: tuple[int, ...]
    kinds: Optional[tuple[str, ...]] = None


@dataclass(frozen=True)
class Plan:
    """Everything the model description and the C layer need to agree on."""

    model_name: str
    identifier: str
    variables: tuple[Variable, ...]
    outputs: tuple[Unknown, ...]
    derivatives: tuple[Unknown, ...]
    initial_unknowns: tuple[Unknown, ...]
    parameters: tuple[float, ...]
    step: Optional[float]
    me: bool
    cs: bool
    n_states: int = 0
    n_inputs: int = 0
    n_outputs: int = 0
    experiment: Optional[Experiment] = None
    nominals: tuple[float, ...] = ()
    #: event indicators (switched models): value reference and dependencies of each
    indicators: tuple[Unknown, ...] = ()
    n_algebraic: int = 0

    def of_kind(self, kind: str) -> list[Variable]:
        """The variables of one kind, in value-reference order."""
        return [v for v in self.variables if v.kind == kind]


class _Names:
    """Hands out distinct names: a taken name gets ``_2``, ``_3``..."""

    def __init__(self) -> None:
        self.taken: set[str] = set()

    def claim(self, wanted: str) -> str:
        name, k = wanted, 2
        while name in self.taken:
            name, k = f"{wanted}_{k}", k + 1
        self.taken.add(name)
        return name


def _described(what: str, model_name: str, fmi: str) -> str:
    """A variable's description; names an escaped name in full, as a JSON string."""
    return what if model_name == fmi else f"{what}; model name {json.dumps(model_name)}"


def _kind_of(expr: sympy.Expr, known: sympy.Symbol, varying: set) -> str:
    """FMI dependency kind of ``expr`` on ``known``: constant, tunable (parameters) or dependent."""
    try:
        slope = sympy.diff(expr, known)
    except Exception:           # pragma: no cover - sympy cannot differentiate a law
        return "dependent"
    free = slope.free_symbols
    if free & varying:
        return "dependent"
    return "tunable" if free else "constant"


def identifier_for(name: str) -> str:
    """The ``modelIdentifier`` (a C identifier, the binary's file name) for a model name.

    Examples
    --------
    >>> identifier_for("srv02"), identifier_for("9 lives"), identifier_for("")
    ('srv02', 'm_9_lives', 'model')
    """
    ident = re.sub(r"[^A-Za-z0-9_]", "_", name).strip("_") or "model"
    if not ident[0].isalpha():
        ident = "m_" + ident
    return ident[:60]


def make_plan(model: Model, parameters: Sequence[float], *, step: Optional[float],
              me: bool, cs: bool, identifier: str, defaults: Optional[RunDefaults] = None) -> Plan:
    """Lay out the FMU's variables for ``model`` (parameter values in ``model.parameters`` order).

    ``defaults`` (from :func:`~bondgraph.fmu._defaults.run_defaults`) gives the
    states' nominal values and the default experiment.
    """
    nominals = defaults.nominals if defaults is not None else (1.0,) * len(model.states)
    names = _Names()
    states, inputs, params = model.states, model.inputs, model.parameters
    # the model's own names first: they are what users set start values by
    state_names = [names.claim(fmi_name(s.name)) for s in states]
    input_names = [names.claim(fmi_name(s.name)) for s in inputs]
    param_names = [names.claim(fmi_name(s.name)) for s in params]
    # an output that is exactly the state of its name is that state
    merged: dict[int, int] = {}
    for j, (oname, expr) in enumerate(zip(model.output_names, model.output_exprs)):
        for i, s in enumerate(states):
            if s.name == oname and expr == s and i not in merged.values():
                merged[j] = i
    output_names = {j: names.claim(fmi_name(n)) for j, n in enumerate(model.output_names) if j not in merged}
    time_name = names.claim("time")
    der_names = [names.claim(f"der({n})") for n in state_names]
    step_name = names.claim(STEP_NAME) if cs else None

    n, m = len(states), len(inputs)
    variables: list[Variable] = [Variable(time_name, 0, "time", 0, "independent", "continuous", None, None,
                                          "independent variable (time)")]
    output_of_state = {i: j for j, i in merged.items()}
    for i, s in enumerate(states):
        as_output = output_of_state.get(i)
        variables.append(Variable(
            state_names[i], len(variables), "state", i,
            "output" if as_output is not None else "local", "continuous", "exact", 0.0,
            _described("state" + (" and output" if as_output is not None else ""), s.name, state_names[i]),
            output_index=as_output, nominal=float(nominals[i])))
    first_state = 1
    for i, s in enumerate(states):
        variables.append(Variable(der_names[i], len(variables), "derivative", i, "local", "continuous",
                                  "calculated", None, f"time derivative of state {i + 1}",
                                  derivative_of=first_state + i))
    for k, s in enumerate(inputs):
        variables.append(Variable(input_names[k], len(variables), "input", k, "input", "continuous", None,
                                  0.0, _described("input", s.name, input_names[k])))
    for j, oname in enumerate(model.output_names):
        if j in output_names:
            variables.append(Variable(output_names[j], len(variables), "output", j, "output", "continuous",
                                      "calculated", None, _described("output", oname, output_names[j])))
    for k, s in enumerate(params):
        variables.append(Variable(param_names[k], len(variables), "parameter", k, "parameter", "tunable",
                                  "exact", float(parameters[k]), _described("parameter", s.name, param_names[k])))
    if cs:
        assert step_name is not None and step is not None
        variables.append(Variable(step_name, len(variables), "step", 0, "parameter", "tunable", "exact",
                                  float(step), "Co-Simulation: largest internal RK4 step (s); each "
                                  "communication step is split into equal steps no longer than this"))

    vr_of: dict[sympy.Symbol, int] = {}
    for v in variables:
        if v.kind == "state":
            vr_of[states[v.index]] = v.vr
        elif v.kind == "input":
            vr_of[inputs[v.index]] = v.vr
        elif v.kind == "parameter":
            vr_of[params[v.index]] = v.vr
    z_syms = set(model.algebraic)
    varying = set(states) | set(inputs) | {T_SYM} | z_syms
    # an implicit model: what the algebraic unknowns z depend on (every residual, conservatively)
    through_z: set = set().union(*(r.free_symbols for r in model.residuals)) - z_syms

    def unknown(vr: int, expr: sympy.Expr, knowns: Iterable[sympy.Symbol], kinds: bool) -> Unknown:
        free = expr.free_symbols
        implicit = free | through_z if free & z_syms else free
        used = sorted((s for s in implicit & set(knowns)), key=lambda s: vr_of[s])
        deps = tuple(vr_of[s] for s in used)
        via_z = through_z if free & z_syms else set()
        return Unknown(vr, deps, tuple("dependent" if s in via_z else _kind_of(expr, s, varying)
                                       for s in used) if kinds else None)

    runtime = set(states) | set(inputs)
    at_init = runtime | set(params)
    outs, ders, inits = [], [], []
    for v in variables:
        if v.kind == "state" and v.output_index is not None:
            outs.append(Unknown(v.vr, ()))          # the output is the state itself
        elif v.kind == "output":
            expr = model.output_exprs[v.index]
            outs.append(unknown(v.vr, expr, runtime, True))
            inits.append(unknown(v.vr, expr, at_init, False))
        elif v.kind == "derivative":
            expr = model.rhs[v.index]
            ders.append(unknown(v.vr, expr, runtime, True))
            inits.append(unknown(v.vr, expr, at_init, False))
    inits.sort(key=lambda u: u.vr)
    return Plan(model.name, identifier, tuple(variables), tuple(outs), tuple(ders), tuple(inits),
                tuple(float(p) for p in parameters), step, me, cs, n, m, len(model.output_names),
                defaults.experiment if defaults is not None else None, tuple(float(v) for v in nominals),
                n_algebraic=len(model.algebraic))


def default_step(model: Model, parameters: Sequence[float]) -> float:
    """The default Co-Simulation RK4 step: 0.05 over the Jacobian's spectral radius at rest.

    The Jacobian of ``x' = f(t, x, u)`` is taken by finite differences at
    ``t = 0``, ``x = 0``, ``u = 0`` with the given parameter values; ``h
    |lambda|max = 0.05`` keeps RK4's error per unit time of the fastest mode
    near ``|lambda| (h |lambda|)^4 / 120``, about 5e-8 ``|lambda|`` relative.
    The step is rounded down to 1, 2 or 5 times a power of ten and kept
    within [1e-7, 1e-3] s; 1e-3 s when the Jacobian cannot be evaluated
    (a law singular at rest).
    """
    import numpy as np

    from ..numeric import compile_dynamics

    n = len(model.states)
    try:
        dyn = compile_dynamics(model)
        p = np.asarray(parameters, dtype=float)
        u = np.zeros(len(model.inputs))
        x0 = np.zeros(n)
        f0 = dyn.derivatives(0.0, x0, u, p)
        jac = np.empty((n, n))
        for i in range(n):
            dx = np.zeros(n)
            dx[i] = 1e-6
            jac[:, i] = (dyn.derivatives(0.0, x0 + dx, u, p) - dyn.derivatives(0.0, x0 - dx, u, p)) / 2e-6
        radius = float(np.max(np.abs(np.linalg.eigvals(jac)))) if n else 0.0
        if not (np.all(np.isfinite(f0)) and math.isfinite(radius)):
            return 1e-3
    except Exception:
        return 1e-3
    if radius <= 0.0:
        return 1e-3
    raw = min(1e-3, max(1e-7, 0.05 / radius))
    exponent = math.floor(math.log10(raw))
    for mantissa in (5.0, 2.0, 1.0):
        value = mantissa * 10.0 ** exponent
        if value <= raw * (1 + 1e-12):
            return float(f"{value:.1e}")
    return float(f"{10.0 ** exponent:.1e}")  # pragma: no cover
