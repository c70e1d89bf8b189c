"""Newton's method in generated code: implicit models ``0 = g(t, x, z, u, p)`` (private).

An implicit model (:mod:`bondgraph.equations.implicit`) keeps algebraic
unknowns ``z`` with residuals ``0 = g(t, x, z, u, p)``.  The generated C,
Python and MATLAB code solves them at every evaluation of ``f`` and ``h`` by
the same algorithm, written once per language from the constants here:

1. start from the caller's ``z`` (the last solution: a warm start);
2. at most :data:`MAX_ITERATIONS` Newton steps ``dz = -(dg/dz)^-1 g`` with
   the analytic Jacobian (generated and CSE'd like the equations), solved by
   Gaussian elimination with partial pivoting;
3. damped: the step is halved (at most :data:`HALVINGS` times) until the
   largest ``|g_i|`` decreases;
4. converged when ``g = 0`` exactly; or when a full step with every
   ``|dz_i| <= STEP_RTOL |z_i| + REF_RTOL zref_i`` (``zref_i``: the largest
   ``|z_i|`` of the start and the iterates, so that an unknown whose root is
   0 still converges to its rounding noise) has cut the largest ``|g_i|`` below
   ``DROP`` times its value at the start (quadratic convergence: a small
   step alone proves nothing where ``dg/dz`` is huge, as in a diode's loop
   in reverse bias); or when such a small step no longer decreases ``|g|``
   (the rounding floor; the step is not taken); or, when no halving
   decreases ``|g|``, if every ``|dz_i|`` is below ``FLOOR_RTOL zref_i``.
   Otherwise the solve fails;
5. a singular ``dg/dz`` (an orifice ``f |f|`` at ``f = 0``) moves every
   ``z_i`` by ``KICK (1 + |z_i|)``, at most :data:`KICKS` times;
6. a failure from a non-zero start is retried once from ``z = 0`` (the
   warm start may lie in another basin or outside a law's domain); when
   that fails too, ``z`` keeps its start value and the call reports a
   status (C: a non-zero return, its text from ``NAME_status_message``;
   Python: ``AlgebraicSolveError``; MATLAB: ``error``) naming the algebraic
   unknowns and what they are.  Nothing is computed from an unsolved ``z``.

Examples
--------
>>> import textwrap
>>> print(textwrap.fill(failure_text("diode", ("f_D",), ("the flow of R:D",), NOT_FINITE), 72))
model 'diode': Newton's method found no solution of 0 = g(x, z, u) for
the algebraic unknowns f_D (the flow of R:D): a residual or dg/dz is not
finite (a law evaluated outside its domain)
"""

from __future__ import annotations

from typing import Sequence

__all__ = ["MAX_ITERATIONS", "HALVINGS", "STEP_RTOL", "REF_RTOL", "DROP", "FLOOR_RTOL", "KICK", "KICKS", "OK",
           "NOT_FINITE", "SINGULAR", "NO_DECREASE", "NO_CONVERGENCE", "REASONS",
           "failure_text"]

#: Newton steps per attempt: a warm start needs 1 to 3; a cold start of a diode written
#: f = Is (exp(e/Vt) - 1) in a loop about one per Vt of forward voltage (e/Vt up to 709)
MAX_ITERATIONS = 500
#: halvings of a step before the line search gives up
HALVINGS = 40
#: converged when every step component is below this fraction of its unknown
STEP_RTOL = 1e-12
#: ... plus this fraction of the unknown's largest size in the solve (its start included)
REF_RTOL = 1e-15
#: reduction of the largest residual that confirms convergence after a small step
DROP = 1e-6
#: accepted without a decrease when the step is below this fraction of the largest unknown
FLOOR_RTOL = 1e-9
#: relative move of the unknowns when dg/dz is singular, and how many such moves
KICK, KICKS = 1e-3, 4

#: status codes of the generated solvers
OK, NOT_FINITE, SINGULAR, NO_DECREASE, NO_CONVERGENCE = 0, 1, 2, 3, 4
#: what each failure status means
REASONS = {
    NOT_FINITE: "a residual or dg/dz is not finite (a law evaluated outside its domain)",
    SINGULAR: "dg/dz is singular (the unknowns are not determined there)",
    NO_DECREASE: "the residual does not decrease along the Newton step (the loop may have no "
                 "solution there, e.g. a law saturating below the imposed value)",
    NO_CONVERGENCE: f"no convergence in {MAX_ITERATIONS} iterations",
}


def failure_text(model_name: str, names: Sequence[str], origins: Sequence[str], status: int) -> str:
    """The message of a failed solve (raw text: each generator escapes it for its target)."""
    unknowns = ", ".join(f"{n} ({o})" for n, o in zip(names, origins))
    return (f"model {model_name!r}: Newton's method found no solution of 0 = g(x, z, u) for the "
            f"algebraic unknowns {unknowns}: {REASONS[status]}")
