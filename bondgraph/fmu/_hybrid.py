r"""FMUs of switched models: the mode table, event indicators and the mode change (private).

:func:`build_switched_fmu` is what :func:`bondgraph.fmu.build_fmu` calls for a
:class:`~bondgraph.hybrid.SwitchedModel`.  The C code is
:func:`bondgraph.codegen.generate_switched_c` (one mode-independent state:
the stored quantities, then the integrated signals; per reachable mode its
right-hand side, outputs, guards and re-initialisation), the FMI layers and
core are those of every FMU, and ``bg_fmu_events.h`` (:data:`EVENTS`) adds
the switching:

* the FMU state holds the index of the current mode and one offset per
  guard; event indicator ``j`` is guard ``j`` of the current mode plus its
  offset (``guard_tol`` when the mode was entered with that guard at or
  below zero, as in :func:`bondgraph.hybrid.simulate`; else 0);
* leaving initialization chooses the consistent initial mode (every switch
  with a guard free, fewest flips from the built state) and re-initialises
  the state;
* in event mode (``fmi2NewDiscreteStates``, ``fmi3UpdateDiscreteStates``) the
  switches whose indicators are at or below zero flip; the stored quantities are
  first put back on the current mode's constraint (what the importer's
  integration of a dependent quantity drifted), then the new mode is chosen
  as :func:`bondgraph.hybrid.simulate` chooses it (the diodes free and
  checked; no energy lost if possible, then fewest flips) and the state is
  re-initialised -- ``valuesOfContinuousStatesChanged`` is then true.  No
  consistent mode is a sliding mode: the call fails naming the switch and
  the time; so do more than 100 mode changes at one instant, and one switch
  changing 20 times within 1e-6 of the run (the importer's start to stop
  time; without a stop time, 1e-6 of ``max(1, |t|)`` seconds): chattering,
  as :func:`bondgraph.hybrid.simulate` reports it;
* Co-Simulation steps with the fixed RK4 step (``rk4_step``), checks the
  indicators after every step, and locates a sign change by bisection of
  the RK4 step to the rounding of the time (about 1e-15 relative), then
  changes the mode there and continues: events inside a communication step
  are handled, one per RK4 step at least; a gate that rises and falls again
  within one RK4 step is missed (choose ``step`` below the shortest pulse).

The FMU's states are the stored quantities of every storage element (also
those in derivative causality in some mode: ``p_J2`` of a locked clutch) and
the integrated signals; set their start values by those names.
"""

from __future__ import annotations

import json
from typing import Any, Optional

from ..codegen import CodegenError, generate_switched_c
from ..parameters import ParameterValues
from ._build import (FMUError, compile_library, library_suffix, platform_folder, standard_headers,
                     token_for, zip_archive)
from ._c_core import CORE, config_header
from ._plan import STEP_NAME, Plan, Unknown, Variable, _Names, fmi_name, identifier_for

__all__ = ["build_switched_fmu", "EVENTS"]

#: default of ``guard_tol``: a guard is consistent while >= -guard_tol (as ``hybrid.simulate``)
GUARD_TOL = 1e-9

EVENTS = r"""/* bg_fmu_events.h -- the mode changes of a switched bondgraph FMU; do not edit.
 * Included by bg_fmu_core.h when BG_SWITCHED is 1. */
#ifndef BG_FMU_EVENTS_H
#define BG_FMU_EVENTS_H

#define BG_GALLOC BG_ALLOC(BG_NZ)

/* guard j of the current mode at (t, x), plus its offset */
static void bg_sw_indicators(bg_instance *c, double t, const double *x, double *z)
{
    int j;
    BG_SW_GUARDS(c->d.sw_mode, t, x, c->d.u, c->d.p, z);
    for (j = 0; j < BG_NZ; ++j) z[j] += c->d.sw_off[j];
}

/* the switches whose indicators are at or below zero (a root CVode finds may be exactly 0; a
 * mode is never entered with an indicator at or below zero: see bg_sw_offsets) */
static unsigned long bg_sw_fired(bg_instance *c, double t, const double *x)
{
    double z[BG_GALLOC];
    unsigned long fired = 0;
    int j;
    bg_sw_indicators(c, t, x, z);
    for (j = 0; j < BG_NZ; ++j)
        if (z[j] <= 0.0) fired |= 1UL << BG_SW_GUARD_SWITCH[j];
    return fired;
}

/* entering a mode: a guard at or below zero fires only at -guard_tol */
static void bg_sw_offsets(bg_instance *c)
{
    double g[BG_GALLOC];
    int j;
    BG_SW_GUARDS(c->d.sw_mode, c->d.time, c->d.x, c->d.u, c->d.p, g);
    for (j = 0; j < BG_NZ; ++j) c->d.sw_off[j] = g[j] <= 0.0 ? BG_GUARD_TOL : 0.0;
}

static int bg_indicator(bg_instance *c, unsigned int k, double *value)
{
    double z[BG_GALLOC];
    bg_sw_indicators(c, c->d.time, c->d.x, z);
    *value = z[k];
    return BG_OK;
}

static int bg_event_indicators(bg_instance *c, double *z, size_t nz)
{
    if (bg_count(c, nz, BG_NZ, "event indicators") != BG_OK) return BG_ERROR;
    if (nz > 0) bg_sw_indicators(c, c->d.time, c->d.x, z);
    return BG_OK;
}

static void bg_sw_name(unsigned long mask, char *out, size_t size)
{
    int i;
    for (i = 0; i < BG_SW_NSW; ++i)
        if ((mask >> i) & 1UL) { snprintf(out, size, "%s", BG_SW_SWITCH_NAMES[i]); return; }
    snprintf(out, size, "?");
}

/* the mode from the switch states `proposed`, the `free` ones chosen; x re-initialised */
static int bg_sw_change(bg_instance *c, unsigned long proposed, unsigned long free_mask,
                        unsigned long trigger)
{
    double loss = 0.0;
    char name[64], message[256];
    int mode = BG_SW_SELECT(proposed, free_mask, free_mask, BG_GUARD_TOL, c->d.time, c->d.x, c->d.u,
                            c->d.p, &loss);
    if (mode < 0 && !trigger) {
        snprintf(message, sizeof message, "no consistent initial mode at t = %.17g: every combination "
                 "of the switches' states violates a guard (check the states' start values)", c->d.time);
        bg_fail(c, message);
        return BG_ERROR;
    }
    if (mode < 0) {
        bg_sw_name(trigger, name, sizeof name);
        snprintf(message, sizeof message, "switch %.60s has no consistent state at t = %.17g: every "
                 "mode violates a diode's guard (a sliding mode: it would flip at every step)", name,
                 c->d.time);
        bg_fail(c, message);
        return BG_ERROR;
    }
    c->d.sw_mode = mode;
    bg_sw_offsets(c);
    bg_changed(c);
    return BG_OK;
}

/* one switch firing BG_CHATTER_COUNT times within the window (1e-6 of the run, else of
 * max(1, |t|) s) is a sliding mode: an error naming it, never an endless run */
static int bg_sw_chatters(bg_instance *c, unsigned long fired)
{
    double window = c->sw_window > 0.0 ? c->sw_window : 1e-6 * (fabs(c->d.time) > 1.0 ? fabs(c->d.time) : 1.0);
    char name[64], message[320];
    int j;
    for (j = 0; j < BG_NZ; ++j) {
        long n;
        double oldest;
        if (!((fired >> BG_SW_GUARD_SWITCH[j]) & 1UL)) continue;
        n = c->sw_fired[j]++;
        c->sw_recent[j][n % BG_CHATTER_COUNT] = c->d.time;
        if (n + 1 < BG_CHATTER_COUNT) continue;
        oldest = c->sw_recent[j][(n + 1) % BG_CHATTER_COUNT];
        if (c->d.time >= oldest && c->d.time - oldest <= window) {
            bg_sw_name(1UL << BG_SW_GUARD_SWITCH[j], name, sizeof name);
            snprintf(message, sizeof message, "switch %.60s chatters: %d mode changes within %.3g s up "
                     "to t = %.17g (a sliding mode: its guard is driven to zero from both sides); add "
                     "the dynamics that decide it or a hysteresis in its gate", name, BG_CHATTER_COUNT,
                     c->d.time - oldest, c->d.time);
            bg_fail(c, message);
            return BG_ERROR;
        }
    }
    return BG_OK;
}

static int bg_event_start(bg_instance *c)
{
    if (!bg_all_finite(c->d.x, BG_NX)) {
        bg_fail(c, "a state's start value is not finite");
        return BG_ERROR;
    }
    return bg_sw_change(c, BG_SW_INITIAL_ON, BG_SW_GUARDED, 0);
}

static int bg_event_update(bg_instance *c, int *changed)
{
    double xs[BG_ALLOC(BG_NX)];
    char name[64], message[256];
    unsigned long fired = bg_sw_fired(c, c->d.time, c->d.x);
    *changed = 0;
    if (!fired) return BG_OK;
    if (c->d.time == c->sw_event_time) {
        if (++c->sw_event_count > 100) {
            bg_sw_name(fired, name, sizeof name);
            snprintf(message, sizeof message, "switch %.60s chatters: more than 100 mode changes at "
                     "t = %.17g", name, c->d.time);
            bg_fail(c, message);
            return BG_ERROR;
        }
    } else {
        c->sw_event_time = c->d.time;
        c->sw_event_count = 1;
    }
    if (bg_sw_chatters(c, fired) != BG_OK) return BG_ERROR;
    /* back onto the current mode's constraint, then the change */
    BG_SW_ENTER(c->d.sw_mode, c->d.time, c->d.x, c->d.u, c->d.p, xs);
    if (BG_NX > 0) memcpy(c->d.x, xs, sizeof xs);
    if (bg_sw_change(c, BG_SW_MODE_ON[c->d.sw_mode] ^ fired, BG_SW_SELF_SWITCHED, fired) != BG_OK)
        return BG_ERROR;
    *changed = 1;
    return BG_OK;
}

/* Co-Simulation from t to t + H in `steps` equal RK4 steps, through the events */
static int bg_sw_steps(bg_instance *c, double t, double H, long steps)
{
    double x0[BG_ALLOC(BG_NX)], xt[BG_ALLOC(BG_NX)];
    double end = t + H, a = t, hk = steps > 0 ? H / (double)steps : 0.0;
    long events = 0;
    int changed;
    while (steps > 0 && end - a > 4e-16 * (1.0 + fabs(end))) {
        double b = a + hk < end ? a + hk : end, lo = 0.0, hi = b - a;
        int it;
        memcpy(x0, c->d.x, sizeof x0);
        if (BG_NX > 0) BG_STEP_RK4(c->d.sw_mode, a, b - a, c->d.x, c->d.u, c->d.p);
        if (!bg_sw_fired(c, b, c->d.x)) { a = b; continue; }
        /* the first instant in (a, b] at which an indicator is negative: bisection of the step */
        for (it = 0; it < 200 && hi - lo > 2e-16 * (fabs(a) + hi); ++it) {
            double mid = 0.5 * (lo + hi);
            memcpy(xt, x0, sizeof xt);
            if (BG_NX > 0) BG_STEP_RK4(c->d.sw_mode, a, mid, xt, c->d.u, c->d.p);
            if (bg_sw_fired(c, a + mid, xt)) hi = mid; else lo = mid;
        }
        memcpy(c->d.x, x0, sizeof x0);
        if (BG_NX > 0) BG_STEP_RK4(c->d.sw_mode, a, hi, c->d.x, c->d.u, c->d.p);
        a += hi;
        c->d.time = a;
        if (bg_event_update(c, &changed) != BG_OK) return BG_ERROR;
        if (++events > 1000000L) {
            bg_fail(c, "more than 1e6 events in one communication step");
            return BG_ERROR;
        }
    }
    return BG_OK;
}

#endif /* BG_FMU_EVENTS_H */
"""


def _switched_config(prefix: str, sp: Any, guard_tol: float) -> list[str]:
    guarded = 0
    for i in sp.guard_switch:
        guarded |= 1 << i
    initial = sp.mode_on.index(sp.initial_on) if sp.initial_on in sp.mode_on else 0
    return ["#define BG_SWITCHED 1", f"#define BG_NZ {len(sp.guard_switch)}",
            f"#define BG_INITIAL_MODE {initial}", f"#define BG_GUARD_TOL {guard_tol!r}",
            f"#define BG_SW_NSW {len(sp.switches)}",
            f"#define BG_SW_INITIAL_ON {sp.initial_on}UL", f"#define BG_SW_GUARDED {guarded}UL",
            f"#define BG_SW_SELF_SWITCHED {sp.self_switched}UL",
            f"#define BG_SW_SELECT {prefix}_select", f"#define BG_SW_GUARDS {prefix}_guards",
            f"#define BG_SW_ENTER {prefix}_enter", f"#define BG_SW_MODE_ON {prefix}_mode_on",
            f"#define BG_SW_GUARD_SWITCH {prefix}_guard_switch",
            f"#define BG_SW_SWITCH_NAMES {prefix}_switch_names",
            f"#define BG_DERIVATIVES {prefix}_derivatives", f"#define BG_OUTPUTS {prefix}_outputs",
            f"#define BG_STEP_RK4 {prefix}_step_rk4"]


def _deps(exprs, vr_of: dict) -> tuple[int, ...]:
    names: set = set()
    for e in exprs:
        names |= {s.name for s in e.free_symbols}
    return tuple(sorted(vr for name, vr in vr_of.items() if name in names))


def switched_plan(sp: Any, parameters: list[float], *, step: Optional[float], me: bool, cs: bool,
                  identifier: str) -> Plan:
    """The FMU's variables for the prepared switched model ``sp`` (see :mod:`._plan`).

    Value references: time, states, derivatives, inputs, outputs, parameters,
    the Co-Simulation step, then the event indicators (``guard(<switch>)``,
    local: FMI 3 lists them as ``EventIndicator``\\ s).  Dependencies are the
    union over the reachable modes.
    """
    names = _Names()
    state_names = [names.claim(fmi_name(n)) for n in sp.state_names]
    input_names = [names.claim(fmi_name(n)) for n in sp.input_names]
    param_names = [names.claim(fmi_name(n)) for n in sp.parameter_names]
    output_names = [names.claim(fmi_name(n)) for n in sp.output_names]
    time_name = names.claim("time")
    der_names = [names.claim(f"der({n})") for n in state_names]
    step_name = names.claim(STEP_NAME) if cs else None
    ind_names = [names.claim(fmi_name(f"guard({sp.switches[i]})")) for i in sp.guard_switch]
    var: list[Variable] = [Variable(time_name, 0, "time", 0, "independent", "continuous", None, None,
                                    "independent variable (time)")]
    nominals = _nominals(sp, parameters)
    for i, n in enumerate(state_names):
        var.append(Variable(n, len(var), "state", i, "local", "continuous", "exact", 0.0,
                            "stored quantity or integrated signal (every mode)", nominal=nominals[i]))
    for i in range(len(state_names)):
        var.append(Variable(der_names[i], len(var), "derivative", i, "local", "continuous", "calculated",
                            None, f"time derivative of state {i + 1} in the current mode",
                            derivative_of=1 + i))
    for k, n in enumerate(input_names):
        var.append(Variable(n, len(var), "input", k, "input", "continuous", None, 0.0, "input"))
    for j, n in enumerate(output_names):
        var.append(Variable(n, len(var), "output", j, "output", "continuous", "calculated", None,
                            "output (current mode)"))
    for k, n in enumerate(param_names):
        var.append(Variable(n, len(var), "parameter", k, "parameter", "tunable", "exact",
                            float(parameters[k]), "parameter"))
    if cs:
        assert step_name is not None and step is not None
        var.append(Variable(step_name, len(var), "step", 0, "parameter", "tunable", "exact", float(step),
                            "Co-Simulation: largest internal RK4 step (s); events are located "
                            "within each RK4 step"))
    for j, n in enumerate(ind_names):
        var.append(Variable(n, len(var), "indicator", j, "local", "continuous", "calculated", None,
                            f"event indicator: guard of switch {sp.switches[sp.guard_switch[j]]!r} in the "
                            "current mode (>= 0 while consistent)"))
    vr_of = {ident: v.vr for v in var if v.kind == "state" for ident in [sp.state_ids[v.index]]}
    vr_of.update({sp.input_ids[v.index]: v.vr for v in var if v.kind == "input"})
    runtime = dict(vr_of)
    vr_of.update({sp.parameter_ids[v.index]: v.vr for v in var if v.kind == "parameter"})
    outs: list[Unknown] = []
    ders: list[Unknown] = []
    inits: list[Unknown] = []
    inds: list[Unknown] = []
    modes = range(len(sp.modes))
    for v in var:
        if v.kind == "output":
            exprs = [sp.outputs[k][v.index] for k in modes]
        elif v.kind == "derivative":
            exprs = [sp.rhs[k][v.index] for k in modes]
        elif v.kind == "indicator":
            exprs = [sp.guards[k][v.index] for k in modes]
        else:
            continue
        u = Unknown(v.vr, _deps(exprs, runtime))
        {"output": outs, "derivative": ders, "indicator": inds}[v.kind].append(u)
        if v.kind != "indicator":
            inits.append(Unknown(v.vr, _deps(exprs, vr_of)))
    return Plan(sp.name, identifier, tuple(var), tuple(outs), tuple(ders), tuple(inits),
                tuple(float(p) for p in parameters), step, me, cs, len(state_names), len(input_names),
                len(output_names), None, nominals, tuple(inds))


def _nominals(sp: Any, parameters: list[float]) -> tuple[float, ...]:
    """Each state's nominal: a stored quantity ``q_i`` holding a unit of energy alone,
    ``sqrt(2 / Q_ii)`` (``Q`` the energy Hessian at rest, 3 significant digits:
    ``sqrt(2 C)`` for a capacitor, ``sqrt(2 m)`` for a mass); 1 for the integrated
    signals and where the Hessian gives no positive number."""
    import math

    import sympy

    subs = {sympy.Symbol(i, real=True): sympy.Float(v) for i, v in zip(sp.parameter_ids, parameters)}
    rest = {sympy.Symbol(i, real=True): sympy.Integer(0) for i in sp.state_ids}
    out = []
    for ident in sp.state_ids:
        s = sympy.Symbol(ident, real=True)
        try:
            qii = float(sympy.diff(sp.energy, s, 2).xreplace(subs).xreplace(rest))
        except (TypeError, ValueError):
            qii = float("nan")
        out.append(float(f"{math.sqrt(2.0 / qii):.3g}") if math.isfinite(qii) and qii > 0 else 1.0)
    return tuple(out)


def _plan_bytes(plan: Plan) -> bytes:
    return json.dumps([plan.model_name, plan.identifier, [list(v.__dict__.values()) for v in plan.variables],
                       plan.me, plan.cs, [list(u.__dict__.values()) for u in plan.indicators]],
                      default=str).encode("utf-8")


def _default_step(sm: Any, values: dict) -> float:
    """The Co-Simulation step: :func:`bondgraph.fmu.default_step` of every mode, the smallest."""
    from ..numeric.resolve import resolve_parameters
    from ._plan import default_step

    steps = [1e-3]
    for mode in sm.reachable_modes:
        model = sm.derived(mode).user
        if model.states:
            vals = resolve_parameters(model.parameters, values, model=model.name,
                                      known=list(values))
            steps.append(default_step(model, [float(v) for v in vals]))
    return min(steps)


def build_switched_fmu(sm: Any, *, version: int, me: bool, cs: bool,
                       values: Optional[ParameterValues], step: Optional[float], binary: bool,
                       cc: Optional[str], guard_tol: float = GUARD_TOL) -> bytes:
    """The bytes of the ``.fmu`` archive of switched model ``sm`` (see the module docstring).

    Raises
    ------
    FMUError
        A mode that cannot be exported (its re-initialisation is not a linear
        map: the message names the mode's switches; input derivatives), a
        bad ``guard_tol``, and what :func:`bondgraph.fmu.build_fmu` raises.
    """
    from .. import __version__
    from ._c_fmi2 import FMI2_LAYER
    from ._c_fmi3 import FMI3_LAYER
    from ._xml import build_description, model_description

    if isinstance(guard_tol, bool) or not isinstance(guard_tol, (int, float)) or not 0 < guard_tol < 1:
        raise FMUError(f"guard_tol must be a number in (0, 1) (the FMU's hysteresis at a mode "
                       f"change); got {guard_tol!r}")
    if values is not None and not hasattr(values, "items"):
        raise FMUError(f"values must be a mapping of parameter name to number; got {type(values).__name__}")
    headers = standard_headers(version)
    identifier = identifier_for(sm.name)
    prefix = f"{identifier}_model"
    try:
        code = generate_switched_c(sm, name=prefix, defaults=dict(values or {}), header_file=f"{prefix}.h")
    except CodegenError as exc:
        raise FMUError(f"switched model {sm.name!r} cannot be an FMU: {exc}") from exc
    sp = code.prepared
    parameters = [float(v) for v in (sp.defaults or ())]
    by_name = dict(zip(sp.parameter_names, parameters))
    h = (float(step) if step is not None else _default_step(sm, by_name)) if cs else None
    plan = switched_plan(sp, parameters, step=h, me=me, cs=cs, identifier=identifier)
    layer_name = f"fmi{version}Functions.c"
    layer = FMI2_LAYER if version == 2 else FMI3_LAYER
    c_files = [f"{prefix}.c", layer_name]
    token = token_for(str(version).encode(), _plan_bytes(plan), code.source.encode(), layer.encode(),
                      CORE.encode(), EVENTS.encode(), repr(float(guard_tol)).encode())
    config = config_header(plan, prefix, f"{prefix}.h", token,
                           switched=_switched_config(prefix, sp, float(guard_tol)))
    sources: dict[str, bytes] = {
        f"{prefix}.c": code.source.encode("utf-8"), f"{prefix}.h": code.header.encode("utf-8"),
        "bg_fmu_config.h": config.encode("utf-8"), "bg_fmu_core.h": CORE.encode("utf-8"),
        "bg_fmu_events.h": EVENTS.encode("utf-8"), layer_name: layer.encode("utf-8"), **headers}
    if version == 3:
        sources["buildDescription.xml"] = build_description(identifier, c_files)
    files = {"modelDescription.xml": model_description(plan, version, token, f"bondgraph {__version__}",
                                                       c_files)}
    files.update({f"sources/{name}": data for name, data in sorted(sources.items())})
    if binary:
        lib = identifier + library_suffix()
        c_sources = {k: v for k, v in sources.items() if not k.endswith(".xml")}
        files[f"binaries/{platform_folder(version)}/{lib}"] = compile_library(c_sources, c_files, lib, cc=cc)
    return zip_archive(files)
