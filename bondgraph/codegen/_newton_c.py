"""C text of an implicit model's Newton solver (private; see :mod:`._newton` and :mod:`.c`).

For a prefix ``NAME`` the header of an implicit model declares, besides the
sizes and names of :mod:`bondgraph.codegen.c`::

    #define NAME_NZ                                     /* algebraic unknowns */
    #define NAME_NEWTON_OK 0  (NOT_FINITE 1, SINGULAR 2, NO_DECREASE 3, NO_CONVERGENCE 4)
    extern const char *const NAME_algebraic_names[];   /* NZ names, then NULL */
    extern const char *const NAME_algebraic_origins[]; /* what each unknown is */
    void NAME_residuals(t, x, u, p, const double *z, double *g);      /* 0 = g */
    void NAME_jacobian(t, x, u, p, const double *z, double *jac);     /* dg/dz, row-major */
    int NAME_solve(t, x, u, p, double *z);          /* z: start in, solution out */
    const char *NAME_status_message(int status);
    int NAME_derivatives(t, x, u, p, double *z, double *xdot);
    int NAME_outputs(t, x, u, p, double *z, double *y);
    int NAME_step_euler(double t, double h, double *x, const double *u, const double *p, double *z);
    int NAME_step_rk4(double t, double h, double *x, const double *u, const double *p, double *z);

Every ``int`` function returns ``NAME_NEWTON_OK`` (0) or the failure status;
on failure ``z`` keeps its start value, ``xdot`` and ``y`` are filled with
``NAN`` and the step functions leave ``x`` unchanged.  ``z`` is the caller's
warm start: keep one array per simulated system and pass it to every call.
"""

from __future__ import annotations

from . import _newton as nw
from ._common import PreparedModel

__all__ = ["reserved_names", "header_lines", "source_lines", "c_signatures"]

_ARGS = "double t, const double *x, const double *u, const double *p"


def reserved_names(prefix: str) -> set[str]:
    """Identifiers the generated solver uses: model symbols must not take them."""
    up = prefix.upper()
    funcs = ("residuals", "jacobian", "solve", "newton", "lu_solve", "maxabs", "status_message",
             "derivatives", "outputs", "step_euler", "step_rk4", "algebraic_names",
             "algebraic_origins")
    macros = ("NZ", "NZ_ALLOC", "NEWTON_OK", "NEWTON_NOT_FINITE", "NEWTON_SINGULAR",
              "NEWTON_NO_DECREASE", "NEWTON_NO_CONVERGENCE")
    return ({f"{prefix}_{f}" for f in funcs} | {f"{up}_{m}" for m in macros}
            | {"z", "g", "jac", "status", "i"})


def c_signatures(prefix: str) -> dict[str, str]:
    """The signatures of an implicit model's functions (without ``;``)."""
    return {
        "residuals": f"void {prefix}_residuals({_ARGS}, const double *z, double *g)",
        "jacobian": f"void {prefix}_jacobian({_ARGS}, const double *z, double *jac)",
        "solve": f"int {prefix}_solve({_ARGS}, double *z)",
        "status_message": f"const char *{prefix}_status_message(int status)",
        "derivatives": f"int {prefix}_derivatives({_ARGS}, double *z, double *xdot)",
        "outputs": f"int {prefix}_outputs({_ARGS}, double *z, double *y)",
        "step_euler": f"int {prefix}_step_euler(double t, double h, double *x, const double *u, "
                      "const double *p, double *z)",
        "step_rk4": f"int {prefix}_step_rk4(double t, double h, double *x, const double *u, "
                    "const double *p, double *z)",
    }


def header_lines(pm: PreparedModel, prefix: str) -> list[str]:
    """Macros and declarations an implicit model's header adds."""
    up = prefix.upper()
    sig = c_signatures(prefix)
    return ["", f"/* implicit model: {len(pm.algebraic_ids)} algebraic unknowns z, solved by Newton's",
            " * method at every call (z: the caller's warm start, kept between calls) */",
            f"#define {up}_NZ {len(pm.algebraic_ids)}",
            f"#define {up}_NEWTON_OK {nw.OK}", f"#define {up}_NEWTON_NOT_FINITE {nw.NOT_FINITE}",
            f"#define {up}_NEWTON_SINGULAR {nw.SINGULAR}",
            f"#define {up}_NEWTON_NO_DECREASE {nw.NO_DECREASE}",
            f"#define {up}_NEWTON_NO_CONVERGENCE {nw.NO_CONVERGENCE}",
            f"extern const char *const {prefix}_algebraic_names[];",
            f"extern const char *const {prefix}_algebraic_origins[];",
            sig["residuals"] + ";", sig["jacobian"] + ";", sig["solve"] + ";",
            sig["status_message"] + ";"]


def source_lines(pm: PreparedModel, prefix: str, body, c_string, names_array) -> list[str]:
    """The solver's C: name arrays, residuals, Jacobian, Newton, status messages.

    ``body(exprs, out, where)`` gives the lines of a function body computing
    ``exprs`` into ``out`` (:func:`bondgraph.codegen.c._function_body`).
    """
    up = prefix.upper()
    sig = c_signatures(prefix)
    nz = f"{up}_NZ"
    where = f"model {pm.name!r}"
    src = [names_array(prefix, "algebraic", pm.algebraic_names),
           f"const char *const {prefix}_algebraic_origins[] = {{"
           + "".join(c_string(o) + ", " for o in pm.algebraic_origin) + "NULL};", "",
           sig["residuals"], "{"] + body(pm.residuals, "g", f"{where}, residuals") + ["}", "",
           sig["jacobian"], "{"] + body(pm.jacobian, "jac", f"{where}, Jacobian dg/dz") + ["}", ""]
    src += [
        "/* largest |v[i]|; HUGE_VAL when one is not finite */",
        f"static double {prefix}_maxabs(const double *v, int n)",
        "{",
        "    double m = 0.0;",
        "    int i;",
        "    for (i = 0; i < n; ++i) {",
        "        if (!isfinite(v[i])) return HUGE_VAL;",
        "        if (fabs(v[i]) > m) m = fabs(v[i]);",
        "    }",
        "    return m;",
        "}",
        "",
        "/* a <- LU of a (row-major n x n), b <- a^-1 b; partial pivoting; 1 if singular */",
        f"static int {prefix}_lu_solve(double *a, double *b, int n)",
        "{",
        "    int i, j, k, r;",
        "    double tmp;",
        "    for (k = 0; k < n; ++k) {",
        "        r = k;",
        "        for (i = k + 1; i < n; ++i)",
        "            if (fabs(a[i * n + k]) > fabs(a[r * n + k])) r = i;",
        "        if (a[r * n + k] == 0.0) return 1;",
        "        if (r != k) {",
        "            for (j = 0; j < n; ++j) {",
        "                tmp = a[k * n + j]; a[k * n + j] = a[r * n + j]; a[r * n + j] = tmp;",
        "            }",
        "            tmp = b[k]; b[k] = b[r]; b[r] = tmp;",
        "        }",
        "        for (i = k + 1; i < n; ++i) {",
        "            tmp = a[i * n + k] / a[k * n + k];",
        "            for (j = k; j < n; ++j) a[i * n + j] -= tmp * a[k * n + j];",
        "            b[i] -= tmp * b[k];",
        "        }",
        "    }",
        "    for (k = n - 1; k >= 0; --k) {",
        "        for (j = k + 1; j < n; ++j) b[k] -= a[k * n + j] * b[j];",
        "        b[k] /= a[k * n + k];",
        "    }",
        f"    return {prefix}_maxabs(b, n) == HUGE_VAL;",
        "}",
        "",
        "/* damped Newton from z (see bondgraph.codegen._newton); z holds the last iterate */",
        f"static int {prefix}_newton({_ARGS}, double *z)",
        "{",
        f"    double g[{nz}], gt[{nz}], jac[{nz} * {nz}], dz[{nz}], zt[{nz}], zref[{nz}];",
        "    double norm, start, trial, alpha;",
        "    int it, k, i, kicks = 0, small;",
        f"    {prefix}_residuals(t, x, u, p, z, g);",
        f"    norm = start = {prefix}_maxabs(g, {nz});",
        f"    for (i = 0; i < {nz}; ++i) zref[i] = fabs(z[i]);   /* each unknown's size so far */",
        f"    if (norm == HUGE_VAL) return {up}_NEWTON_NOT_FINITE;",
        f"    for (it = 0; it < {nw.MAX_ITERATIONS}; ++it) {{",
        f"        if (norm == 0.0) return {up}_NEWTON_OK;",
        f"        {prefix}_jacobian(t, x, u, p, z, jac);",
        f"        if ({prefix}_maxabs(jac, {nz} * {nz}) == HUGE_VAL) return {up}_NEWTON_NOT_FINITE;",
        f"        for (i = 0; i < {nz}; ++i) dz[i] = -g[i];",
        f"        if ({prefix}_lu_solve(jac, dz, {nz})) {{",
        f"            if (kicks++ >= {nw.KICKS}) return {up}_NEWTON_SINGULAR;",
        f"            for (i = 0; i < {nz}; ++i) z[i] += {nw.KICK!r} * (1.0 + fabs(z[i]));",
        f"            {prefix}_residuals(t, x, u, p, z, g);",
        f"            norm = {prefix}_maxabs(g, {nz});",
        f"            if (norm == HUGE_VAL) return {up}_NEWTON_NOT_FINITE;",
        "            continue;",
        "        }",
        "        small = 1;",
        f"        for (i = 0; i < {nz}; ++i)",
        f"            if (!(fabs(dz[i]) <= {nw.STEP_RTOL!r} * fabs(z[i]) + {nw.REF_RTOL!r} * zref[i])) small = 0;",
        "        alpha = 1.0;",
        f"        for (k = 0; k < {nw.HALVINGS}; ++k) {{",
        f"            for (i = 0; i < {nz}; ++i) zt[i] = z[i] + alpha * dz[i];",
        f"            {prefix}_residuals(t, x, u, p, zt, gt);",
        f"            trial = {prefix}_maxabs(gt, {nz});",
            "            if (trial < norm) break;",
        f"            if (small) return {up}_NEWTON_OK;      /* at the rounding floor */",
        "            alpha *= 0.5;",
        "        }",
        f"        if (k == {nw.HALVINGS}) {{",
        f"            for (i = 0; i < {nz}; ++i)",
        f"                if (!(fabs(dz[i]) <= {nw.FLOOR_RTOL!r} * zref[i])) return {up}_NEWTON_NO_DECREASE;",
        f"            return {up}_NEWTON_OK;",
        "        }",
        f"        for (i = 0; i < {nz}; ++i) {{",
        "            z[i] = zt[i]; g[i] = gt[i];",
        "            if (fabs(z[i]) > zref[i]) zref[i] = fabs(z[i]);",
        "        }",
        "        norm = trial;",
        f"        if (small && k == 0 && norm <= {nw.DROP!r} * start) return {up}_NEWTON_OK;",
        "    }",
        f"    return {up}_NEWTON_NO_CONVERGENCE;",
        "}",
        "",
        sig["solve"],
        "{",
        f"    double z0[{nz}];",
        "    int i, status, nonzero = 0;",
        f"    for (i = 0; i < {nz}; ++i) {{",
        "        z0[i] = z[i];",
        "        if (z[i] != 0.0) nonzero = 1;",
        "    }",
        f"    status = {prefix}_newton(t, x, u, p, z);",
        f"    if (status != {up}_NEWTON_OK && nonzero) {{   /* the warm start failed: from z = 0 */",
        f"        for (i = 0; i < {nz}; ++i) z[i] = 0.0;",
        f"        status = {prefix}_newton(t, x, u, p, z);",
        "    }",
        f"    if (status != {up}_NEWTON_OK)",
        f"        for (i = 0; i < {nz}; ++i) z[i] = z0[i];",
        "    return status;",
        "}",
        "",
        sig["status_message"],
        "{",
        "    switch (status) {",
        f"    case {up}_NEWTON_OK: return \"converged\";"]
    for code, macro in ((nw.NOT_FINITE, "NOT_FINITE"), (nw.SINGULAR, "SINGULAR"),
                        (nw.NO_DECREASE, "NO_DECREASE"), (nw.NO_CONVERGENCE, "NO_CONVERGENCE")):
        text = nw.failure_text(pm.name, pm.algebraic_names, pm.algebraic_origin, code)
        src.append(f"    case {up}_NEWTON_{macro}: return {c_string(text)};")
    src += ["    default: return \"unknown status\";", "    }", "}", ""]
    return src


def model_function(pm: PreparedModel, prefix: str, which: str, body_lines: list[str],
                   out: str, n_out: str) -> list[str]:
    """``NAME_derivatives`` or ``NAME_outputs`` of an implicit model: solve, then evaluate."""
    up = prefix.upper()
    return [c_signatures(prefix)[which], "{",
            f"    int status = {prefix}_solve(t, x, u, p, z);",
            f"    if (status != {up}_NEWTON_OK) {{",
            "        int i;",
            f"        for (i = 0; i < {n_out}; ++i) {out}[i] = NAN;",
            "        return status;",
            "    }",
            "    {"] + ["    " + ln for ln in body_lines] + ["    }", f"    return {up}_NEWTON_OK;",
                                                         "}", ""]


def step_functions(prefix: str, alloc: str) -> list[str]:
    """Euler and RK4 steps of an implicit model: ``x`` changes only when every stage solved."""
    up = prefix.upper()
    sig = c_signatures(prefix)
    d = f"{prefix}_derivatives"
    chk = "if (status != " + up + "_NEWTON_OK) return status;"
    return [sig["step_euler"], "{",
            f"    double k1[{alloc}];",
            "    int i, status;",
            f"    status = {d}(t, x, u, p, z, k1);",
            f"    {chk}",
            f"    for (i = 0; i < {up}_NX; ++i) x[i] += h * k1[i];",
            f"    return {up}_NEWTON_OK;",
            "}", "",
            sig["step_rk4"], "{",
            f"    double k1[{alloc}], k2[{alloc}], k3[{alloc}], k4[{alloc}];",
            f"    double xt[{alloc}];",
            "    int i, status;",
            f"    status = {d}(t, x, u, p, z, k1);",
            f"    {chk}",
            f"    for (i = 0; i < {up}_NX; ++i) xt[i] = x[i] + 0.5 * h * k1[i];",
            f"    status = {d}(t + 0.5 * h, xt, u, p, z, k2);",
            f"    {chk}",
            f"    for (i = 0; i < {up}_NX; ++i) xt[i] = x[i] + 0.5 * h * k2[i];",
            f"    status = {d}(t + 0.5 * h, xt, u, p, z, k3);",
            f"    {chk}",
            f"    for (i = 0; i < {up}_NX; ++i) xt[i] = x[i] + h * k3[i];",
            f"    status = {d}(t + h, xt, u, p, z, k4);",
            f"    {chk}",
            f"    for (i = 0; i < {up}_NX; ++i)",
            "        x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);",
            f"    return {up}_NEWTON_OK;",
            "}", ""]
