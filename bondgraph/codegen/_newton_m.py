"""MATLAB / Octave text of an implicit model's Newton solver (private; see :mod:`._newton`).

The function file of an implicit model is ``[xdot, y, z] = NAME(t, x, u, p)``:
it first solves ``0 = g(t, x, z, u, p)`` for the algebraic unknowns ``z``
(``info = NAME()`` lists them in ``info.algebraic`` and what they are in
``info.algebraic_origins``) by Newton's method, warm-started from the last
solution (a ``persistent`` variable), and raises ``error('bondgraph:newton',
...)`` naming the unknowns, the time and the state when it fails.  The
residuals, the Jacobian and the solver are local functions of the file.
"""

from __future__ import annotations

from . import _newton as nw
from ._common import PreparedModel

__all__ = ["RESERVED", "main_lines", "local_functions"]

#: names the generated solver uses
RESERVED = frozenset(["z", "g", "jac", "status", "bg_zlast", "bg_solve", "bg_newton",
                      "bg_residuals", "bg_jacobian", "bg_failure", "bg_maxabs", "bg_where"])


def main_lines(pm: PreparedModel, m_string) -> list[str]:
    """The solve at the top of the main function (after ``p`` became a vector)."""
    nz = len(pm.algebraic_ids)
    states = "; ".join(m_string(n) for n in pm.state_names)
    return ["persistent bg_zlast",
            f"if isempty(bg_zlast), bg_zlast = zeros({nz}, 1); end",
            "[z, status] = bg_solve(t, x, u, p, bg_zlast);",
            "if status ~= 0",
            f"  error('bondgraph:newton', '%s; at t = %.17g%s', bg_failure(status), t, "
            f"bg_where({{{states}}}, x));",
            "end",
            "bg_zlast = z;"]


def local_functions(pm: PreparedModel, unpack, assignments, m_string) -> list[str]:
    """Residuals, Jacobian, Newton and messages as local functions of the file.

    ``unpack(with_z)`` gives the lines naming the array entries;
    ``assignments(exprs, out, where)`` the lines computing ``out``.
    """
    nz = len(pm.algebraic_ids)
    where = f"model {pm.name!r}"
    out = ["", "function g = bg_residuals(t, x, u, p, z)"] + unpack(True)
    out += assignments(pm.residuals, "g", f"{where}, residuals") + ["end", ""]
    out += ["function jac = bg_jacobian(t, x, u, p, z)"] + unpack(True)
    out += assignments(pm.jacobian, "jac", f"{where}, Jacobian dg/dz")
    out += [f"jac = reshape(jac, {nz}, {nz}).';", "end", ""]
    out += ["function m = bg_maxabs(v)",
            "if any(~isfinite(v(:))), m = Inf; else, m = max([0; abs(v(:))]); end",
            "end", "",
            "function text = bg_where(names, x)",
            "text = '';",
            "for k = 1:numel(names)",
            "  text = [text, sprintf(', %s = %.17g', names{k}, x(k))];",
            "end",
            "end", "",
            "function [z, status] = bg_solve(t, x, u, p, z0)",
            "[z, status] = bg_newton(t, x, u, p, z0);",
            "if status ~= 0 && any(z0 ~= 0)",
            f"  [z, status] = bg_newton(t, x, u, p, zeros({nz}, 1));",
            "end",
            "if status ~= 0, z = z0; end",
            "end", "",
            "function [z, status] = bg_newton(t, x, u, p, z)",
            "% damped Newton from z (see bondgraph.codegen._newton)",
            "g = bg_residuals(t, x, u, p, z);",
            "norm0 = bg_maxabs(g);",
            "nrm = norm0;",
            "zref = abs(z);",
            f"status = {nw.NOT_FINITE};",
            "if nrm == Inf, return; end",
            "kicks = 0;",
            f"for it = 1:{nw.MAX_ITERATIONS}",
            f"  if nrm == 0, status = {nw.OK}; return; end",
            "  jac = bg_jacobian(t, x, u, p, z);",
            f"  if bg_maxabs(jac) == Inf, status = {nw.NOT_FINITE}; return; end",
            "  singular = rcond(jac) == 0;",
            "  if ~singular",
            "    ws = warning('off', 'all');",
            "    dz = -(jac \\ g);",
            "    warning(ws);",
            "    singular = bg_maxabs(dz) == Inf;",
            "  end",
            "  if singular",
            f"    if kicks >= {nw.KICKS}, status = {nw.SINGULAR}; return; end",
            "    kicks = kicks + 1;",
            f"    z = z + {nw.KICK!r} * (1 + abs(z));",
            "    g = bg_residuals(t, x, u, p, z);",
            "    nrm = bg_maxabs(g);",
            f"    if nrm == Inf, status = {nw.NOT_FINITE}; return; end",
            "    continue;",
            "  end",
            f"  small = all(abs(dz) <= {nw.STEP_RTOL!r} * abs(z) + {nw.REF_RTOL!r} * zref);",
            "  alpha = 1;",
            "  accepted = false;",
            f"  for k = 1:{nw.HALVINGS}",
            "    zt = z + alpha * dz;",
            "    gt = bg_residuals(t, x, u, p, zt);",
            "    trial = bg_maxabs(gt);",
            "    if trial < nrm, accepted = true; break; end",
            f"    if small, status = {nw.OK}; return; end",
            "    alpha = alpha / 2;",
            "  end",
            "  if ~accepted",
            f"    if all(abs(dz) <= {nw.FLOOR_RTOL!r} * zref), status = {nw.OK}; "
            f"else, status = {nw.NO_DECREASE}; end",
            "    return;",
            "  end",
            "  z = zt; g = gt; nrm = trial;",
            "  zref = max(zref, abs(z));",
            f"  if small && k == 1 && nrm <= {nw.DROP!r} * norm0, status = {nw.OK}; return; end",
            "end",
            f"status = {nw.NO_CONVERGENCE};",
            "end", "",
            "function text = bg_failure(status)",
            "switch status"]
    for code in nw.REASONS:
        text = nw.failure_text(pm.name, pm.algebraic_names, pm.algebraic_origin, code)
        out += [f"  case {code}", f"    text = {m_string(text)};"]
    out += ["  otherwise", "    text = 'unknown status';", "end", "end", ""]
    return out
