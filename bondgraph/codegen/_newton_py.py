"""Python text of an implicit model's Newton solver (private; see :mod:`._newton`, :mod:`.python`).

The generated module of an implicit model adds::

    ALGEBRAIC_NAMES, ALGEBRAIC_ORIGINS    # tuples of str: the unknowns z and what they are
    residuals(t, x, u, p, z)              # -> g, len(ALGEBRAIC_NAMES) floats (0 = g)
    jacobian(t, x, u, p, z)               # -> dg/dz, row-major
    solve_algebraic(t, x, u, p, z0=None)  # -> z; from z0, else the last solution
    class AlgebraicSolveError(ArithmeticError)

``derivatives`` and ``outputs`` call ``solve_algebraic`` first (warm-started
from the module's last solution) and raise ``AlgebraicSolveError``, naming
the unknowns, the time and the state, when it fails.
"""

from __future__ import annotations

from . import _newton as nw
from ._common import PreparedModel

__all__ = ["RESERVED", "solver_lines"]

#: names the generated solver uses at module level or as arguments
RESERVED = frozenset(["z", "residuals", "jacobian", "solve_algebraic", "AlgebraicSolveError",
                      "ALGEBRAIC_NAMES", "ALGEBRAIC_ORIGINS", "NZ", "_Z", "_FAILURE", "_newton",
                      "_lu_solve", "_maxabs", "_eval", "z0"])


def _str_tuple(names) -> str:
    items = [ascii(n) for n in names]
    return "(" + ", ".join(items) + ("," if len(items) == 1 else "") + ")"


def solver_lines(pm: PreparedModel, function) -> list[str]:
    """Module text of the solver; ``function(name, exprs, doc, args)`` writes a function."""
    nz = len(pm.algebraic_ids)
    failures = ", ".join(
        f"{code}: {ascii(nw.failure_text(pm.name, pm.algebraic_names, pm.algebraic_origin, code))}"
        for code in nw.REASONS)
    out = [f"ALGEBRAIC_NAMES = {_str_tuple(pm.algebraic_names)}",
           f"ALGEBRAIC_ORIGINS = {_str_tuple(pm.algebraic_origin)}",
           f"NZ = {nz}",
           f"_FAILURE = {{{failures}}}",
           "_Z = [0.0] * NZ      # the warm start: the last solution", "", "",
           "class AlgebraicSolveError(ArithmeticError):",
           '    """Newton\'s method found no solution of 0 = g(x, z, u) (the message says where)."""',
           "", ""]
    out += function("residuals", pm.residuals, "Residuals g of 0 = g(t, x, z, u, p).",
                    "t, x, u, p, z")
    out += ["", ""]
    out += function("jacobian", pm.jacobian, "dg/dz, row-major.", "t, x, u, p, z")
    out += ["", "", f'''def _maxabs(v):
    """Largest |v_i|; inf when one is not finite."""
    m = 0.0
    for a in v:
        if not math.isfinite(a):
            return math.inf
        m = max(m, abs(a))
    return m


def _lu_solve(a, b):
    """a^-1 b by Gaussian elimination with partial pivoting (a row-major); None if singular."""
    n = len(b)
    a = [a[i * n:(i + 1) * n] for i in range(n)]
    b = list(b)
    for k in range(n):
        r = max(range(k, n), key=lambda i: abs(a[i][k]))
        if a[r][k] == 0.0:
            return None
        a[k], a[r], b[k], b[r] = a[r], a[k], b[r], b[k]
        for i in range(k + 1, n):
            m = a[i][k] / a[k][k]
            for j in range(k, n):
                a[i][j] -= m * a[k][j]
            b[i] -= m * b[k]
    for k in range(n - 1, -1, -1):
        b[k] = (b[k] - sum(a[k][j] * b[j] for j in range(k + 1, n))) / a[k][k]
    return None if _maxabs(b) == math.inf else b


def _eval(fn, t, x, u, p, z):
    """fn(t, x, u, p, z), with math's domain and range errors as a non-finite value."""
    try:
        return fn(t, x, u, p, z)
    except (ValueError, OverflowError, ZeroDivisionError):
        return [math.nan]


def _newton(t, x, u, p, z):
    """(status, z): damped Newton from z (see bondgraph.codegen._newton)."""
    g = _eval(residuals, t, x, u, p, z)
    norm = start = _maxabs(g)
    zref = [abs(v) for v in z]      # each unknown's size so far
    if norm == math.inf:
        return {nw.NOT_FINITE}, z
    kicks = 0
    for _ in range({nw.MAX_ITERATIONS}):
        if norm == 0.0:
            return {nw.OK}, z
        jac = _eval(jacobian, t, x, u, p, z)
        if _maxabs(jac) == math.inf:
            return {nw.NOT_FINITE}, z
        dz = _lu_solve(jac, [-v for v in g])
        if dz is None:
            if kicks >= {nw.KICKS}:
                return {nw.SINGULAR}, z
            kicks += 1
            z = [v + {nw.KICK!r} * (1.0 + abs(v)) for v in z]
            g = _eval(residuals, t, x, u, p, z)
            norm = _maxabs(g)
            if norm == math.inf:
                return {nw.NOT_FINITE}, z
            continue
        small = all(abs(d) <= {nw.STEP_RTOL!r} * abs(v) + {nw.REF_RTOL!r} * r for d, v, r in zip(dz, z, zref))
        alpha = 1.0
        for k in range({nw.HALVINGS}):
            zt = [v + alpha * d for v, d in zip(z, dz)]
            gt = _eval(residuals, t, x, u, p, zt)
            trial = _maxabs(gt)
            if trial < norm:
                break
            if small:
                return {nw.OK}, z          # at the rounding floor
            alpha *= 0.5
        else:
            ok = all(abs(d) <= {nw.FLOOR_RTOL!r} * r for d, r in zip(dz, zref))
            return ({nw.OK} if ok else {nw.NO_DECREASE}), z
        z, g, norm = zt, gt, trial
        zref = [max(r, abs(v)) for r, v in zip(zref, z)]
        if small and k == 0 and norm <= {nw.DROP!r} * start:
            return {nw.OK}, z
    return {nw.NO_CONVERGENCE}, z


def solve_algebraic(t, x, u, p, z0=None):
    """The algebraic unknowns z (order of ALGEBRAIC_NAMES) solving 0 = g(t, x, z, u, p).

    Newton's method from z0, else from the last solution (kept by the module); retried
    from z = 0 when that fails.  Raises AlgebraicSolveError naming the unknowns, t and x.
    """
    for what, given, names in (("x", x, STATE_NAMES), ("u", u, INPUT_NAMES),
                               ("p", p, PARAMETER_NAMES), ("z0", _Z if z0 is None else z0, ALGEBRAIC_NAMES)):
        if not hasattr(given, "keys") and len(given) != len(names):
            raise ValueError(f"{{what}} has {{len(given)}} values; expected {{len(names)}} ({{names}})")
    begin = [float(v) for v in (_Z if z0 is None else z0)]
    status, z = _newton(t, x, u, p, list(begin))
    if status and any(v != 0.0 for v in begin):
        status, z = _newton(t, x, u, p, [0.0] * NZ)
    if status:
        where = ", ".join(f"{{n}} = {{float(v)!r}}" for n, v in zip(STATE_NAMES, x))
        inputs = ", ".join(f"{{n}} = {{float(v)!r}}" for n, v in zip(INPUT_NAMES, u))
        raise AlgebraicSolveError(f"{{_FAILURE[status]}}; at t = {{float(t)!r}}"
                                  + (f", {{where}}" if where else "")
                                  + (f", inputs {{inputs}}" if inputs else ""))
    _Z[:] = z
    return z''']
    return out
