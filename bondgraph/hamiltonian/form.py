"""The port-Hamiltonian form of derived equations (see :mod:`bondgraph.hamiltonian`)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Optional, Sequence

import numpy as np
import sympy

from .._support.labels import latex_name, tex
from ..errors import NonlinearModelError
from ..equations import StateEquations
from ..linear import state_space
from ..parameters import ParameterValues, exact_value, match_values, real_value
from .parts import (PortHamiltonianError, check_elements, column_of,
                                 collocated_outputs, sum_energy, input_derivative_error, input_matrix,
                                 coefficient_matrix, hessian_inverse, block_hessian_inverse, cancel_entries, nonconservative_elements,
                                 rederive, storage_elements, stored_quantities, stored_signals)

__all__ = ["PortHamiltonian", "PortHamiltonianError", "port_hamiltonian", "energy"]

Matrix = sympy.ImmutableMatrix   # constructor shorthand; annotations spell it out


@dataclass(frozen=True)
class PortHamiltonian:
    r"""``x' = (J - R) grad H + (G - P) u``, ``y = (G + P)^T grad H + (S - N) u``.

    Returned by :func:`port_hamiltonian`; see :mod:`bondgraph.hamiltonian`
    for the conventions, the method and what is refused.

    Attributes
    ----------
    name : str
    states : tuple of sympy.Symbol
        The storage states (``p_<I>``, ``q_<C>``) of the model, in its order.
    inputs : tuple of sympy.Symbol
    H : sympy.Expr
        Stored energy, a function of ``states``.
    gradient : tuple of sympy.Expr
        ``grad H``: the co-energy variables (flow of each I, effort of each C,
        or their effective combination with derivative causality).
    J : ImmutableMatrix
        Skew-symmetric interconnection (junctions, TF, GY).
    R : ImmutableMatrix
        Symmetric dissipation (R elements), positive semi-definite for a
        passive model.
    G, P : ImmutableMatrix
        Input matrices, ``n x m``; ``P`` is zero without feedthrough.
    S, N : ImmutableMatrix
        Feedthrough, ``m x m``, symmetric and skew-symmetric; ``D = S - N``.
    Q : ImmutableMatrix or None
        The Hessian of ``H`` when ``H`` is quadratic (linear storage), so
        ``grad H = Q x``; None for nonlinear storage.
    output_names : tuple of str
        The collocated outputs, one per input: ``f_<Se>`` (flow out of an
        effort source), ``e_<Sf>`` (effort at a flow source).
    nonconservative : tuple of str
        Labels of TF/GY elements with an efficiency other than 1.
    known_parameters : tuple of str
        Parameter names of the model definition (for :meth:`subs`).
    """

    name: str
    states: tuple[sympy.Symbol, ...]
    inputs: tuple[sympy.Symbol, ...]
    H: sympy.Expr
    gradient: tuple[sympy.Expr, ...]
    J: sympy.ImmutableMatrix
    R: sympy.ImmutableMatrix
    G: sympy.ImmutableMatrix
    P: sympy.ImmutableMatrix
    S: sympy.ImmutableMatrix
    N: sympy.ImmutableMatrix
    Q: Optional[sympy.ImmutableMatrix]
    output_names: tuple[str, ...]
    nonconservative: tuple[str, ...] = ()
    known_parameters: tuple[str, ...] = field(default=(), compare=False, repr=False)

    # ----------------------------------------------------------------- names
    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.states)

    @property
    def input_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.inputs)

    @property
    def D(self) -> sympy.ImmutableMatrix:
        """Feedthrough ``S - N`` of the collocated outputs."""
        return Matrix(self.S - self.N)

    @property
    def W(self) -> sympy.ImmutableMatrix:
        """``[[R, P], [P^T, S]]``: positive semi-definite for a passive model."""
        return Matrix(sympy.BlockMatrix([[self.R, self.P], [self.P.T, self.S]]).as_explicit())

    @property
    def parameters(self) -> tuple[sympy.Symbol, ...]:
        """Parameter symbols of ``H`` and the matrices, sorted by name."""
        syms: set = set(self.H.free_symbols)
        for mat in self._matrices():
            syms |= mat.free_symbols
        return tuple(sorted(syms - set(self.states) - set(self.inputs), key=lambda s: s.name))

    def _matrices(self) -> tuple[sympy.ImmutableMatrix, ...]:
        return (self.J, self.R, self.G, self.P, self.S, self.N) + \
            ((self.Q,) if self.Q is not None else ())

    # ----------------------------------------------------------------- equations
    def rhs(self) -> tuple[sympy.Expr, ...]:
        """``(J - R) grad H + (G - P) u``, rebuilt; equal to the model's storage ``rhs``.

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("rc")
        >>> V, n = bg.Se("V"), bg.One("i")
        >>> g.add(V, n, bg.R("R"), bg.C("C"))
        >>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
        >>> ph = port_hamiltonian(bg.derive(g))
        >>> ph.rhs(), ph.outputs()
        ((V/R - q_C/(C*R),), (V/R - q_C/(C*R),))

        The source meets the resistor directly: a feedthrough, ``G = 0``,
        ``P = -1/R``, ``S = 1/R``.

        >>> ph.G, ph.P, ph.S
        (Matrix([[0]]), Matrix([[-1/R]]), Matrix([[1/R]]))
        """
        z, u = column_of(self.gradient), column_of(self.inputs)
        return tuple((self.J - self.R) * z + (self.G - self.P) * u)

    def outputs(self) -> tuple[sympy.Expr, ...]:
        """The collocated outputs ``(G + P)^T grad H + (S - N) u`` (see :attr:`output_names`)."""
        z, u = column_of(self.gradient), column_of(self.inputs)
        return tuple((self.G + self.P).T * z + self.D * u)

    def dissipation(self) -> sympy.Expr:
        """``w^T W w`` with ``w = (grad H, u)``: the power the R elements dissipate."""
        w = column_of(self.gradient + tuple(self.inputs))
        return sympy.expand((w.T * self.W * w)[0, 0])

    def supplied_power(self) -> sympy.Expr:
        """``y^T u``: the power the sources deliver."""
        return sympy.expand(sum((y * u for y, u in zip(self.outputs(), self.inputs)),
                                sympy.Integer(0)))

    # ----------------------------------------------------------------- values
    def subs(self, values: ParameterValues | None = None, *,
             partial: bool = True) -> "PortHamiltonian":
        """Substitute parameter values (exactly) in ``H`` and every matrix.

        The policy of :mod:`bondgraph.parameters`: names or Symbols as keys,
        unknown names refused listing the valid ones, floats read as the
        rational of their decimal representation.

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("m")
        >>> g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"))
        >>> for t, h in [("F", "v"), ("v", "m"), ("v", "b")]: _ = g.connect(t, h)
        >>> port_hamiltonian(bg.derive(g)).subs({"m": 2, "b": 0.5}).H
        p_m**2/4
        """
        given = match_values(self.parameters, values, known=self.known_parameters,
                             partial=partial, where=f"port-Hamiltonian form of {self.name!r}: ")
        sub = {p: exact_value(v, p.name) for p, v in given.items()}

        def f(mat: Optional[sympy.ImmutableMatrix]) -> Optional[sympy.ImmutableMatrix]:
            return None if mat is None else Matrix(mat.xreplace(sub))
        return dataclasses.replace(
            self, H=self.H.xreplace(sub), gradient=tuple(g.xreplace(sub) for g in self.gradient),
            J=f(self.J), R=f(self.R), G=f(self.G), P=f(self.P), S=f(self.S), N=f(self.N),
            Q=f(self.Q))

    def numeric(self, values: ParameterValues) -> dict[str, np.ndarray]:
        """Float arrays ``J, R, G, P, S, N`` (and ``Q`` for quadratic ``H``).

        Every parameter needs a value.  The arrays fit pymor's
        ``PHLTIModel.from_matrices(J, R, G, P=P, S=S, N=N, Q=Q)``.
        """
        ph = self.subs(values, partial=False)
        names = ("J", "R", "G", "P", "S", "N") + (("Q",) if ph.Q is not None else ())
        out = {}
        for label in names:
            mat = getattr(ph, label)
            out[label] = np.array([[real_value(v, f"{label}[{i},{j}]") for j, v in
                                    enumerate(mat.row(i))] for i in range(mat.rows)],
                                  dtype=float).reshape(mat.shape)
        return out

    def is_passive(self, values: ParameterValues, *, tol: float = 1e-12) -> bool:
        """Whether ``W = [[R, P], [P^T, S]]`` is positive semi-definite at ``values``.

        Eigenvalues down to ``-tol * max(1, |W|)`` count as zero.  ``J`` and
        ``N`` are skew-symmetric by construction.
        """
        m = self.numeric(values)
        W = np.block([[m["R"], m["P"]], [m["P"].T, m["S"]]])
        if W.size == 0:
            return True
        scale = max(1.0, float(np.abs(W).max()))
        return bool(np.linalg.eigvalsh((W + W.T) / 2).min() >= -tol * scale)

    # ----------------------------------------------------------------- printing
    def to_latex(self) -> str:
        r"""``H``, ``grad H`` and the matrices as a LaTeX ``aligned`` block (no ``$$``).

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("m")
        >>> g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"))
        >>> for t, h in [("F", "v"), ("v", "m"), ("v", "b")]: _ = g.connect(t, h)
        >>> print(port_hamiltonian(bg.derive(g)).to_latex())  # doctest: +NORMALIZE_WHITESPACE
        \begin{aligned}\dot{x} &= (J - R)\,\nabla H(x) + G\,u \\ y &= G^{T} \nabla H(x) \\
        x &= \left[\begin{matrix}p_{m}\end{matrix}\right], \quad u = \left[\begin{matrix}F\end{matrix}\right], \quad y = \left[\begin{matrix}f_{F}\end{matrix}\right] \\
        H &= \frac{p_{m}^{2}}{2 m} \\ \nabla H &= \left[\begin{matrix}\frac{p_{m}}{m}\end{matrix}\right] \\
        J &= \left[\begin{matrix}0\end{matrix}\right] \\ R &= \left[\begin{matrix}b\end{matrix}\right] \\
        G &= \left[\begin{matrix}1\end{matrix}\right]\end{aligned}
        """
        feed = any(not m.is_zero_matrix for m in (self.P, self.S, self.N))
        gu = r"(G - P)\,u" if feed else r"G\,u"
        y = r"(G + P)^{T} \nabla H(x) + (S - N)\,u" if feed else r"G^{T} \nabla H(x)"

        def col(names: Sequence[str]) -> str:
            return r"\left[\begin{matrix}" + r" \\ ".join(latex_name(n) for n in names) + \
                r"\end{matrix}\right]"
        if self.inputs:
            rows = [r"\dot{x} &= (J - R)\,\nabla H(x) + " + gu, r"y &= " + y,
                    rf"x &= {col(self.state_names)}, \quad u = {col(self.input_names)}, "
                    rf"\quad y = {col(self.output_names)}"]
        else:
            rows = [r"\dot{x} &= (J - R)\,\nabla H(x)", rf"x &= {col(self.state_names)}"]
        rows += [rf"H &= {tex(self.H)}", rf"\nabla H &= {tex(column_of(self.gradient))}"]
        shown = ("J", "R") + (("G",) if self.inputs else ()) + (("P", "S", "N") if feed else ())
        for label in shown:
            rows.append(rf"{label} &= {tex(getattr(self, label))}")
        if self.nonconservative:
            rows.append(r"&\text{not power-conserving: " + ", ".join(self.nonconservative) + "}")
        return r"\begin{aligned}" + r" \\ ".join(rows) + r"\end{aligned}"

    def _repr_latex_(self) -> str:
        return "$$" + self.to_latex() + "$$"

    def __str__(self) -> str:
        lines = [f"port-Hamiltonian form of {self.name!r}: {len(self.states)} states, "
                 f"{len(self.inputs)} inputs",
                 f"  x = {list(self.state_names)}, u = {list(self.input_names)}, "
                 f"y = {list(self.output_names)}",
                 f"  H = {self.H}",
                 f"  grad H = {list(self.gradient)}"]
        for label in ("J", "R", "G", "P", "S", "N"):
            mat = getattr(self, label)
            if label in "JRG" or not mat.is_zero_matrix:
                lines.append(f"  {label} = {mat.tolist()}")
        if self.nonconservative:
            lines.append(f"  not power-conserving: {', '.join(self.nonconservative)}")
        return "\n".join(lines)


# ===================================================================== API
def energy(model: StateEquations) -> sympy.Expr:
    """The stored energy ``H`` of a model, a function of its storage states.

    Every storage element counts: in integral causality ``H_i = int_0^x phi(s) ds``
    of its law (``p**2/(2 m)``, ``q**2/(2 C)``, ``k q**2/2 + k3 q**4/4``); in
    derivative causality its momentum or displacement is written in the
    remaining states first (an effective inertia).  Unlike
    :func:`port_hamiltonian` this needs no linear R or constant moduli.

    Raises
    ------
    PortHamiltonianError
        A storage law uses signals or time, its integral cannot be found, or a
        storage element in derivative causality stores an input.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("duffing")
    >>> v = bg.One("v")
    >>> g.add(bg.Se("F"), v, bg.I("m"), bg.C("s", law=bg.q + bg.q**3))
    >>> for t, h in [("F", v), (v, "m"), (v, "s")]: _ = g.connect(t, h)
    >>> energy(bg.derive(g))
    q_s**4/4 + q_s**2/2 + p_m**2/(2*m)
    """
    storage, dependent = storage_elements(model, linear_dependent=False)
    aux = rederive(model, stored_signals(dependent)) if dependent else None
    return sum_energy(stored_quantities(storage, dependent, aux))


def port_hamiltonian(model: StateEquations) -> PortHamiltonian:
    """The port-Hamiltonian form of ``model`` (see :mod:`bondgraph.hamiltonian`).

    Parameters
    ----------
    model : StateEquations
        From :func:`bondgraph.derive`: linear R, constant-modulus TF/GY,
        sources that are inputs; storage may be nonlinear (in integral
        causality) and in derivative causality (linear).

    Returns
    -------
    PortHamiltonian

    Raises
    ------
    PortHamiltonianError
        Naming the element that prevents the form (see the module docstring).

    Examples
    --------
    A mass-spring-damper driven by a force ``F``:

    >>> import bondgraph as bg
    >>> g = bg.BondGraph("msd")
    >>> v = bg.One("v")
    >>> g.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    >>> for t, h in [("F", v), (v, "m"), (v, "b"), (v, "k")]: _ = g.connect(t, h)
    >>> ph = port_hamiltonian(bg.derive(g))
    >>> ph.H, ph.gradient
    (k*q_k**2/2 + p_m**2/(2*m), (p_m/m, k*q_k))
    >>> ph.J - ph.R
    Matrix([
    [-b, -1],
    [ 1,  0]])
    >>> ph.rhs()
    (F - b*p_m/m - k*q_k, p_m/m)
    """
    check_elements(model)
    storage, dependent = storage_elements(model, linear_dependent=True)
    # one derivation with the model's own causality: the collocated outputs and
    # the momentum / displacement of storage in derivative causality
    ports, names = collocated_outputs(model)
    aux = rederive(model, {**ports, **stored_signals(dependent)})
    H = sum_energy(stored_quantities(storage, dependent, aux))
    x = tuple(model.states[:model.storage_states])
    u = tuple(model.inputs)
    grad = tuple(sympy.diff(H, xi) for xi in x)
    if dependent:                      # effective combinations: one factored expression each
        grad = tuple(sympy.factor(g) for g in grad)
    if aux.input_derivatives:
        input_derivative_error(model, aux)
    if tuple(aux.states) != x:
        raise PortHamiltonianError(
            f"model {model.name!r}: deriving its augmented graph again gave the states "
            f"{', '.join(aux.state_names)} instead of {', '.join(s.name for s in x)}")
    rows = [aux.output_names.index(k) for k in ports]
    f_x, y_x = aux.rhs, tuple(aux.output_exprs[i] for i in rows)
    hess = sympy.hessian(H, x) if x else sympy.zeros(0, 0)
    quadratic = not (hess.free_symbols & set(x))
    if quadratic:
        try:
            ss = state_space(aux)
            if ss.operating_point is not None:      # a form in deviations is not the model's
                raise NonlinearModelError(
                    "its equations have constant terms or inputs entering nonlinearly; the "
                    "port-Hamiltonian form needs them linear in the states and inputs")
        except NonlinearModelError as exc:
            raise PortHamiltonianError(f"model {model.name!r}: {exc}") from exc
        A, B = ss.A, ss.B
        Cy, Dy = ss.C.extract(rows, list(range(len(x)))), ss.D.extract(rows, list(range(len(u))))
        Qinv = (block_hessian_inverse(storage, x, hess, model) if not dependent else
                hessian_inverse(Matrix(hess), model))
        F, Cz = cancel_entries(A * Qinv), cancel_entries(Cy * Qinv)
    else:
        # nonlinear storage, integral causality only: the Hessian is diagonal, phi_i'(x_i)
        B, Dy = input_matrix(f_x, u, x, model, "state equation"), \
            input_matrix(y_x, u, x, model, "collocated output")
        F = coefficient_matrix(f_x, x, hess, model, "state equation")
        Cz = coefficient_matrix(y_x, x, hess, model, "collocated output")
    ph = PortHamiltonian(
        name=model.name, states=x, inputs=u, H=H, gradient=grad,
        J=cancel_entries((F - F.T) / 2), R=cancel_entries(-(F + F.T) / 2),
        G=cancel_entries((B + Cz.T) / 2), P=cancel_entries((Cz.T - B) / 2),
        S=cancel_entries((Dy + Dy.T) / 2), N=cancel_entries((Dy.T - Dy) / 2),
        Q=Matrix(hess) if quadratic else None, output_names=names,
        nonconservative=nonconservative_elements(model), known_parameters=model.known_parameters)
    verify_form(ph, model)
    return ph


def verify_form(ph: PortHamiltonian, model: StateEquations) -> None:
    """The rebuilt ``x'`` must equal the model's storage ``rhs`` exactly."""
    n = len(ph.states)
    for i, (got, want) in enumerate(zip(ph.rhs(), model.rhs[:n])):
        extra = want.free_symbols & set(model.states[n:])
        if extra:
            raise PortHamiltonianError(
                f"model {model.name!r}: d{ph.states[i].name}/dt depends on the integrator "
                f"state(s) {', '.join(sorted(s.name for s in extra))}, which store no energy")
        diff = sympy.cancel(sympy.together(got - want))
        if diff != 0 and sympy.simplify(diff) != 0:
            raise PortHamiltonianError(
                f"model {model.name!r}: the port-Hamiltonian form does not reproduce "
                f"d{ph.states[i].name}/dt (difference {diff}); please report this model")

