r"""Port-Hamiltonian form of a derived model.

A bond graph in integral causality is a port-Hamiltonian system: the
storage elements give the Hamiltonian ``H(x)`` (the stored energy) and its
gradient, the co-energy variables ``z = grad H`` (the flow of each I, the
effort of each C); the junction structure, transformers and gyrators give a
skew-symmetric ``J``; the R elements give a symmetric positive semi-definite
``R``; the sources give the input matrix ``G``:

.. math::

    \dot x = (J - R)\,\nabla H(x) + (G - P)\,u, \qquad
    y = (G + P)^T \nabla H(x) + (S - N)\,u .

``P``, ``S`` and ``N`` are zero unless a collocated output depends on an
input directly (a feedthrough ``D = S - N``: a source meeting an R element
without storage in between, or two sources joined through a gyrator, which
gives a skew ``N``); the conventions are those
of pymor's ``PHLTIModel`` (``Q`` is the Hessian of a quadratic ``H``), with
``W = [[R, P], [P^T, S]]`` symmetric positive semi-definite and ``N``
skew-symmetric for a passive model.

Outputs
-------
The outputs ``y`` of the port-Hamiltonian form are the *collocated* outputs,
one per input, power-conjugate to it: for an ``Se`` the flow out of the
source, for an ``Sf`` the effort on its bond, so that ``y^T u`` is the power
the sources deliver and

.. math::

    \frac{dH}{dt} = -w^T W w + y^T u, \qquad w = (\nabla H, u) .

They are named ``f_<source>`` and ``e_<source>`` (:attr:`PortHamiltonian.output_names`).
They are *not* the model's own outputs, which may be anything the user asked
for (a displacement, a sensor combination); those stay on the
:class:`~bondgraph.model.Model`.

Method
------
The state equations and collocated outputs are derived (with the model's own
causality) and their coefficients in the co-energy variables are read off:
``x' = F z + B u``, ``y = C_z z + D u`` with ``F = (df/dx) (d^2H/dx^2)^{-1}``.
Then ``J = (F - F^T)/2``, ``R = -(F + F^T)/2``, ``G = (B + C_z^T)/2``,
``P = (C_z^T - B)/2``, ``S = (D + D^T)/2``, ``N = (D^T - D)/2``.  The
rebuilt ``x'`` is checked symbolically against the model's ``rhs``.

The elements say what they store and why they would prevent the form
(:mod:`bondgraph.protocol`, "Energy"): a one-port I or C its ``p`` or ``q``
and ``int phi``; a multiport field (:mod:`bondgraph.fields`) its momenta and
displacements and ``H = p^T M^-1 p / 2`` (``IField``), ``q^T K q / 2``
(``CField``), ``x^T Q x / 2`` (``ICField``) or its energy function; an
``RField`` adds its resistance matrix to ``R``; a source names its collocated
output.  A nonlinear field with a coupled energy is accepted when ``J - R``
comes out constant (``F = (df/dx) (d^2H/dx^2)^{-1}``).

Only the storage states enter: integrator states that a displacement or
momentum output added (``model.integrators``) are not stored energy and are
left out (:attr:`PortHamiltonian.states` is ``model.states[:model.storage_states]``).

Derivative causality
--------------------
Storage elements in derivative causality store energy too: ``H`` is the
energy of *all* storage elements, written in the remaining (independent)
states.  Two inertias ``J1``, ``J2`` rigidly joined give the state ``p_J1``
and ``H = (J1 + J2) p_J1**2 / (2 J1**2)`` -- the energy ``p**2/(2 (J1 + J2))``
of the effective inertia with total momentum ``p = (J1 + J2)/J1 * p_J1``.
The reduced form is then again port-Hamiltonian (with power-conserving
two-ports ``F = E^{-1} F_0 E^{-T}``, a congruence of the descriptor form, so
``R`` stays positive semi-definite), with a non-diagonal ``Q`` in general.
Storage in derivative causality must be linear.

What is refused
---------------
:class:`PortHamiltonianError` (a :class:`~bondgraph.errors.NonlinearModelError`,
hence a :class:`~bondgraph.errors.BondGraphError` and ``ValueError``), naming
the element: nonlinear or modulated R, MTF/MGY, sources with ``value=``
(constant loads, time functions, modulated sources: not ports), storage laws
that use signals or time, storage in derivative causality with a nonlinear
law (a nonlinear field with a port in derivative causality), a nonlinear
``RField``, a storage law whose energy ``sympy.integrate`` cannot find, a
source whose derivative enters (a flow source driving an inertia directly).

Transformers and gyrators with ``efficiency`` other than 1 are accepted and
listed in :attr:`PortHamiltonian.nonconservative`: such a two-port (a
one-quadrant data-sheet model) does not conserve power, so the decomposition
is exact but ``W`` need not be positive semi-definite (see
:meth:`PortHamiltonian.is_passive`; the FLEXCAM model of ``models/`` with the
SRV-02 data-sheet efficiencies is not passive in this sense, and is with
efficiencies 1).

Examples
--------
>>> import bondgraph as bg
>>> g = bg.BondGraph("msd")
>>> v = bg.One("v")
>>> g.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("c"))
>>> for t, h in [("F", v), (v, "m"), (v, "b"), (v, "c")]: _ = g.connect(t, h)
>>> ph = port_hamiltonian(bg.derive(g))
>>> ph.H
p_m**2/(2*m) + q_c**2/(2*c)
>>> ph.J, ph.R, ph.G
(Matrix([
[0, -1],
[1,  0]]), Matrix([
[b, 0],
[0, 0]]), Matrix([
[1],
[0]]))
>>> ph.gradient, ph.output_names, ph.outputs()
((p_m/m, q_c/c), ('f_F',), (p_m/m,))
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Optional, Sequence

import numpy as np
import sympy

from ._labels import latex_name, tex
from .errors import NonlinearModelError
from .model import Model
from .parameters import ParameterValues, exact_value, match_values, real_value
from ._hamiltonian_parts import (PortHamiltonianError, _check_elements, _col,
                                 _collocated, _energy, _input_derivative_error, _input_matrix,
                                 _coefficients, _inverse, _block_inverse, _cancel, _nonconservative,
                                 _rederive, _storage, _stored, _verify, _stored_signals)

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
        z, u = _col(self.gradient), _col(self.inputs)
        return tuple((self.J - self.R) * z + (self.G - self.P) * u)

    def outputs(self) -> tuple[sympy.Expr, ...]:
        """The collocated outputs ``(G + P)^T grad H + (S - N) u`` (see :attr:`output_names`)."""
        z, u = _col(self.gradient), _col(self.inputs)
        return tuple((self.G + self.P).T * z + self.D * u)

    def dissipation(self) -> sympy.Expr:
        """``w^T W w`` with ``w = (grad H, u)``: the power the R elements dissipate."""
        w = _col(self.gradient + tuple(self.inputs))
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
        rows += [rf"H &= {tex(self.H)}", rf"\nabla H &= {tex(_col(self.gradient))}"]
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
def energy(model: Model) -> sympy.Expr:
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
    storage, dependent = _storage(model, linear_dependent=False)
    aux = _rederive(model, _stored_signals(dependent)) if dependent else None
    return _energy(_stored(storage, dependent, aux))


def port_hamiltonian(model: Model) -> PortHamiltonian:
    """The port-Hamiltonian form of ``model`` (see :mod:`bondgraph.hamiltonian`).

    Parameters
    ----------
    model : Model
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
    _check_elements(model)
    storage, dependent = _storage(model, linear_dependent=True)
    # one derivation with the model's own causality: the collocated outputs and
    # the momentum / displacement of storage in derivative causality
    ports, names = _collocated(model)
    aux = _rederive(model, {**ports, **_stored_signals(dependent)})
    H = _energy(_stored(storage, dependent, aux))
    x = tuple(model.states[:model.storage_states])
    u = tuple(model.inputs)
    grad = tuple(sympy.diff(H, xi) for xi in x)
    if dependent:                      # effective combinations: one factored expression each
        grad = tuple(sympy.factor(g) for g in grad)
    if aux.input_derivatives:
        _input_derivative_error(model, aux)
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
            ss = aux.state_space()
        except NonlinearModelError as exc:
            raise PortHamiltonianError(f"model {model.name!r}: {exc}") from exc
        A, B = ss.A, ss.B
        Cy, Dy = ss.C.extract(rows, list(range(len(x)))), ss.D.extract(rows, list(range(len(u))))
        Qinv = (_block_inverse(storage, x, hess, model) if not dependent else
                _inverse(Matrix(hess), model))
        F, Cz = _cancel(A * Qinv), _cancel(Cy * Qinv)
    else:
        # nonlinear storage, integral causality only: the Hessian is diagonal, phi_i'(x_i)
        B, Dy = _input_matrix(f_x, u, x, model, "state equation"), \
            _input_matrix(y_x, u, x, model, "collocated output")
        F = _coefficients(f_x, x, hess, model, "state equation")
        Cz = _coefficients(y_x, x, hess, model, "collocated output")
    ph = PortHamiltonian(
        name=model.name, states=x, inputs=u, H=H, gradient=grad,
        J=_cancel((F - F.T) / 2), R=_cancel(-(F + F.T) / 2),
        G=_cancel((B + Cz.T) / 2), P=_cancel((Cz.T - B) / 2),
        S=_cancel((Dy + Dy.T) / 2), N=_cancel((Dy.T - Dy) / 2),
        Q=Matrix(hess) if quadratic else None, output_names=names,
        nonconservative=_nonconservative(model), known_parameters=model.known_parameters)
    _verify(ph, model)
    return ph
