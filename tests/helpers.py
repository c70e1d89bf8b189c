"""Test helpers: independent checks of derived models.

The transfer function is formed here with plain sympy on small matrices
(``C adj(sI - A) B / det(sI - A) + D``) and compared with a hand-derived
closed form at random parameter values and random complex frequencies.
"""

from __future__ import annotations

import numpy as np
import sympy

s = sympy.Symbol("s")


def tf_of(model, inp: str, out: str) -> sympy.Expr:
    ss = model.state_space()
    i = ss.input_names.index(inp)
    o = ss.output_names.index(out)
    n = ss.nstates
    M = s * sympy.eye(n) - sympy.Matrix(ss.A)
    num = (sympy.Matrix(ss.C)[o, :] * M.adjugate() * sympy.Matrix(ss.B)[:, i])[0, 0]
    return num / M.det() + ss.D[o, i]


def assert_same_tf(G: sympy.Expr, expected: sympy.Expr, *, trials: int = 4, rtol: float = 1e-9, seed: int = 0):
    rng = np.random.default_rng(seed)
    syms = sorted((G.free_symbols | expected.free_symbols) - {s}, key=lambda x: x.name)
    fg = sympy.lambdify([s] + syms, G, "numpy")
    fe = sympy.lambdify([s] + syms, expected, "numpy")
    for _ in range(trials):
        vals = rng.uniform(0.5, 2.0, len(syms))
        sv = complex(rng.uniform(-1, 1), rng.uniform(0.5, 3))
        a, b = complex(fg(sv, *vals)), complex(fe(sv, *vals))
        assert abs(a - b) <= rtol * max(abs(b), 1e-300), (G, expected, a, b)


def connect_all(g, pairs):
    for tail, head in pairs:
        g.connect(tail, head)
    return g
