"""The derived model: an immutable record of state equations and outputs.

A :class:`Model` is returned by :func:`bondgraph.derive`.  It keeps the
explicit equations ``x' = f(x, u)`` and ``y = g(x, u)``, the descriptor form
``E(x) x' = F(x, u)`` when derivative causality was present, and the
augmented bond graph it came from.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Optional

import sympy

from ._labels import latex_dot, latex_name, tex
from ._linear import _derivative_orders, _linear_form, _point, _residual  # noqa: F401
from .causality import AugmentedBondGraph
from .errors import NonlinearModelError
from .signals import t as T_SYM
from .statespace import SymbolicStateSpace
from .values import parameter_symbols

if TYPE_CHECKING:
    from .hamiltonian import PortHamiltonian
    from .operating import Equilibrium

__all__ = ["Model"]


@dataclass(frozen=True)
class Model:
    """Symbolic state equations of a bond graph.

    Attributes
    ----------
    name : str
    augmented : AugmentedBondGraph
    states, inputs : tuple of sympy.Symbol
    output_names : tuple of str
    rhs : tuple of sympy.Expr
        ``x' = rhs`` in the order of ``states``.
    output_exprs : tuple of sympy.Expr
    input_derivatives : tuple of sympy.Symbol
        Input derivatives that appear (a flow source driving an inertia
        directly, for instance); such a model has no (A, B) form.
    descriptor : (E, F) or None
        With derivative causality: ``E(x) x' = F(x, u)`` before solving.
    storage_states : int
        How many of the states belong to storage elements (the rest are
        integrators added for displacement or momentum signals).
    integrators : tuple of (str, str)
        The integrator states that were added, each with the signal it
        integrates (``("x", "displacement[m]")``).  A displacement or
        momentum whose flow or effort is a constant combination of state
        derivatives adds none: it is that combination of states (see
        :mod:`bondgraph.integrators`).

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("msd")
    >>> v = bg.One("v")
    >>> g.add(bg.Se("F"), v, bg.I("m"), bg.R("b"), bg.C("k", stiffness="k"))
    >>> for t, h in [("F", v), (v, "m"), (v, "b"), (v, "k")]: _ = g.connect(t, h)
    >>> model = bg.derive(g, outputs={"x": bg.displacement("k")})
    >>> model.state_names, model.input_names, model.output_names
    (('p_m', 'q_k'), ('F',), ('x',))
    >>> [p.name for p in model.parameters]
    ['b', 'k', 'm']
    >>> print(model)
    model 'msd': 2 states, 1 inputs, 1 outputs
      dp_m/dt = F - b*p_m/m - k*q_k
      dq_k/dt = p_m/m
      x = q_k
    """

    name: str
    augmented: AugmentedBondGraph = field(repr=False)
    states: tuple[sympy.Symbol, ...]
    inputs: tuple[sympy.Symbol, ...]
    output_names: tuple[str, ...]
    rhs: tuple[sympy.Expr, ...] = field(repr=False)
    output_exprs: tuple[sympy.Expr, ...] = field(repr=False)
    input_derivatives: tuple[sympy.Symbol, ...] = field(default=(), repr=False)
    descriptor: Optional[tuple] = field(default=None, repr=False)
    storage_states: int = field(default=0, repr=False)
    integrators: tuple[tuple[str, str], ...] = field(default=(), repr=False)
    #: parameter names a model definition declares beyond its elements' (the
    #: defaults of a model file that serves several variants)
    declared_parameters: tuple[str, ...] = field(default=(), repr=False)
    #: results computed once per model (state_space, descriptor_form); not part of equality
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    # ----------------------------------------------------------------- names
    @property
    def state_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.states)

    @property
    def input_names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.inputs)

    @property
    def parameters(self) -> tuple[sympy.Symbol, ...]:
        """Parameter symbols appearing in the equations, sorted by name."""
        known = set(self.states) | set(self.inputs) | set(self.input_derivatives) | {T_SYM}
        syms = set()
        for ex in self.rhs + self.output_exprs:
            syms |= ex.free_symbols
        if self.descriptor is not None:
            syms |= self.descriptor[0].free_symbols
        return tuple(sorted(syms - known, key=lambda s: s.name))

    @property
    def known_parameters(self) -> tuple[str, ...]:
        """Names of every parameter of the model definition, sorted.

        A superset of :attr:`parameters`: it also holds parameters of
        elements whose value does not reach the equations (an inertia in
        derivative causality with no output on it, a parameter that dropped
        out of a linearization).  Values given for these are accepted and
        ignored by every call that takes values (:mod:`bondgraph.parameters`).
        """
        names = {p.name for p in self.parameters} | set(self.declared_parameters)
        elements = self.augmented.flat.elements if self.augmented is not None else ()
        for el in elements:
            names |= {s.name for s in parameter_symbols(el)}
        return tuple(sorted(names))

    @property
    def equations(self) -> tuple[sympy.Eq, ...]:
        r"""``Eq(Derivative(x, t), f)`` for each state, then ``Eq(y, g)``.

        The derivatives are unevaluated (``sympy.latex`` prints
        ``\frac{d}{d t} p_{m}``); :meth:`to_latex` prints the dotted form.

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("mass")
        >>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
        >>> bg.derive(g, outputs={"v": bg.flow("m")}).equations
        (Eq(Derivative(p_m, t), F), Eq(v, p_m/m))
        """
        eqs = [sympy.Eq(sympy.Derivative(s, T_SYM, evaluate=False), r, evaluate=False)
               for s, r in zip(self.states, self.rhs)]
        eqs += [sympy.Eq(sympy.Symbol(n), g, evaluate=False)
                for n, g in zip(self.output_names, self.output_exprs)]
        return tuple(eqs)

    def __str__(self) -> str:
        lines = [f"model {self.name!r}: {len(self.states)} states, {len(self.inputs)} inputs, "
                 f"{len(self.output_names)} outputs"]
        for s, r in zip(self.states, self.rhs):
            lines.append(f"  d{s.name}/dt = {r}")
        for n, g in zip(self.output_names, self.output_exprs):
            lines.append(f"  {n} = {g}")
        return "\n".join(lines)

    # ----------------------------------------------------------------- linear forms
    @property
    def is_linear(self) -> bool:
        """Whether ``rhs`` and outputs are linear in states and inputs."""
        try:
            self.state_space()
        except NonlinearModelError:
            return False
        return True

    def state_space(self) -> SymbolicStateSpace:
        """A, B, C, D of a linear model (sympy ImmutableMatrix), with names.

        Raises
        ------
        NonlinearModelError
            If an equation is not linear in states and inputs, has a constant
            term, depends on time or on input derivatives.

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("rc")
        >>> V, n = bg.Se("V"), bg.One("i")
        >>> g.add(V, n, bg.R("R"), bg.C("C"))
        >>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
        >>> ss = bg.derive(g, outputs={"vC": bg.effort("C")}).state_space()
        >>> ss.A, ss.B, ss.C, ss.D
        (Matrix([[-1/(C*R)]]), Matrix([[1/R]]), Matrix([[1/C]]), Matrix([[0]]))
        """
        if "state_space" not in self._cache:
            x, u = self.states, self.inputs
            A, B = _linear_form(self.rhs, x, u, self, "state equation", "x'")
            C, D = _linear_form(self.output_exprs, x, u, self, "output", "y")
            self._cache["state_space"] = SymbolicStateSpace(
                A, B, C, D, self.state_names, self.input_names, self.output_names,
                known_parameters=self.known_parameters)
        return self._cache["state_space"]

    def _laplace_system(self, descriptor: bool, s: sympy.Symbol, outputs=None):
        """``A, B(s), C, D(s), E`` of the Laplace-transformed equations.

        Input derivatives enter as powers of ``s`` (zero initial conditions):
        ``x' = A x + B0 u + B1 u'`` gives ``B(s) = B0 + s B1``, likewise for
        ``D``.  ``outputs``: indices of the outputs to linearize (default all).
        """
        x, u = self.states, self.inputs
        ud = self.input_derivatives
        orders = _derivative_orders(self) if ud else {}
        outs = range(len(self.output_exprs)) if outputs is None else outputs
        out_exprs = [self.output_exprs[i] for i in outs]
        if descriptor and self.descriptor is not None:
            E, F = self.descriptor
            if E.free_symbols & (set(x) | set(u) | set(ud)):
                raise NonlinearModelError(f"model {self.name!r}: E depends on the states")
            A, B, B1 = _linear_form(F, x, u, self, "state equation", "F", ud)
        else:
            E = None
            A, B, B1 = _linear_form(self.rhs, x, u, self, "state equation", "x'", ud)
        C, D, D1 = _linear_form(out_exprs, x, u, self, "output", "y", ud)

        def with_s(M0, M1):
            if not ud:
                return M0
            M = sympy.Matrix(M0)
            for (i, k), c in M1.todok().items():
                j, order = orders[ud[k]]
                M[i, j] += c * s**order
            return sympy.ImmutableMatrix(M)
        return A, with_s(B, B1), C, with_s(D, D1), E

    def _derivative_form(self):
        """``A, (B0, B1, ..), C, (D0, D1, ..)`` of the explicit equations
        ``x' = A x + sum_k B_k u^(k)``, ``y = C x + sum_k D_k u^(k)``.

        Without input derivatives the tuples have one matrix (``state_space``).
        """
        x, u, ud = self.states, self.inputs, self.input_derivatives
        if not ud:
            ss = self.state_space()
            return ss.A, (ss.B,), ss.C, (ss.D,)
        orders = _derivative_orders(self)
        A, B, B1 = _linear_form(self.rhs, x, u, self, "state equation", "x'", ud)
        C, D, D1 = _linear_form(self.output_exprs, x, u, self, "output", "y", ud)
        top = max(k for _, k in orders.values())

        def split(M0, M1):
            mats = [M0] + [sympy.zeros(*M0.shape) for _ in range(top)]
            for (i, c), val in M1.todok().items():
                j, k = orders[ud[c]]
                mats[k][i, j] += val
            return (M0,) + tuple(sympy.ImmutableSparseMatrix(M) for M in mats[1:])
        return A, split(B, B1), C, split(D, D1)

    def transfer_function(self, input=None, output=None, *, descriptor: bool | None = None,
                          **options):
        """Symbolic ``G(s)`` from one input to one output (see :mod:`bondgraph.tf`).

        Models with derivative causality use their descriptor form
        ``E x' = A x + B u`` (``det(sE - A)`` and its minors; ``E`` is never
        inverted) unless ``descriptor=False``.  ``options`` go to
        :func:`bondgraph.tf.transfer_function` (``normalize=``, ``cancel=``, ...).

        Input derivatives (a flow source driving an inertia, for instance) are
        Laplace transformed with zero initial conditions:
        ``x' = A x + B u + B1 u'``, ``y = C x + D u + D1 u'`` give
        ``G(s) = C (sE - A)^-1 (B + s B1) + D + s D1``, improper when ``D1``
        (or ``C`` meeting ``B1``) makes the numerator degree exceed the
        denominator's.  Only the chosen output is linearized: another output
        that is nonlinear or improper does not matter.

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("rc")
        >>> V, n = bg.Se("V"), bg.One("i")
        >>> g.add(V, n, bg.R("R"), bg.C("C"))
        >>> _ = g.connect(V, n); _ = g.connect(n, "R"); _ = g.connect(n, "C")
        >>> model = bg.derive(g, outputs={"vC": bg.effort("C")})
        >>> model.transfer_function("V", "vC", normalize="leading-one-denominator").expr
        1/(C*R*s + 1)

        A velocity source driving a mass and a damper: the force it must
        deliver is ``(m s + b) v``, an improper transfer function.

        >>> g = bg.BondGraph("shaker")
        >>> g.add(bg.Sf("v"), bg.One("j"), bg.I("m"), bg.R("b"))
        >>> for t, h in [("v", "j"), ("j", "m"), ("j", "b")]: _ = g.connect(t, h)
        >>> G = bg.derive(g, outputs={"F": bg.effort(1)}).transfer_function("v", "F")
        >>> G.expr, G.is_proper
        (b + m*s, False)
        """
        from .tf import transfer_function
        from .tf.symbolic import _resolve

        use_e = self.descriptor is not None if descriptor is None else descriptor
        s = options.pop("s", None) or sympy.Symbol("s")
        i = _resolve(output, self.output_names, "output")
        A, B, C, D, E = self._laplace_system(use_e, s, [i])
        G = transfer_function(A, B, C, D, E=E, input=input, output=0,
                              input_names=self.input_names,
                              output_names=(self.output_names[i],), s=s, **options)
        return dataclasses.replace(G, known_parameters=self.known_parameters)

    def transfer_matrix(self, **options):
        """All input/output transfer functions over one denominator (see :mod:`bondgraph.tf`).

        Input derivatives are handled as in :meth:`transfer_function`: an
        entry that involves one may be improper, the others are unchanged.
        """
        from .tf import transfer_matrix

        s = options.pop("s", None) or sympy.Symbol("s")
        A, B, C, D, E = self._laplace_system(self.descriptor is not None, s)
        G = transfer_matrix(A, B, C, D, E=E, input_names=self.input_names,
                            output_names=self.output_names, s=s, **options)
        return dataclasses.replace(G, known_parameters=self.known_parameters)

    def to_latex(self, *, matrices: bool = False) -> str:
        r"""The model as a paper prints it: ``\dot{p}_{m} &= ...`` lines, then the outputs.

        Parameters
        ----------
        matrices : bool
            Append the ``A, B, C, D`` (or descriptor) form of a linear model.

        Returns
        -------
        str
            An ``aligned`` environment (without ``$$``), ready for an
            ``equation`` environment; names printed by the package's one
            LaTeX naming helper (sub-model paths upright).

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("rc")
        >>> g.add(bg.Se("V"), bg.One("i"), bg.R("R"), bg.C("C"))
        >>> for t, h in [("V", "i"), ("i", "R"), ("i", "C")]: _ = g.connect(t, h)
        >>> print(bg.derive(g, outputs={"vC": bg.effort("C")}).to_latex())
        \begin{aligned}
        \dot{q}_{C} &= \frac{V - \frac{q_{C}}{C}}{R} \\
        vC &= \frac{q_{C}}{C}
        \end{aligned}
        """
        body = _equations_latex(self)[len(r"$$\begin{aligned}"):-len(r"\end{aligned}$$")]
        text = "\\begin{aligned}\n" + body.replace(" \\\\ ", " \\\\\n") + "\n\\end{aligned}"
        if matrices:
            form = self.descriptor_form() if self.descriptor is not None else self.state_space()
            text += "\n" + form.to_latex()
        return text

    def _repr_latex_(self) -> str:
        return _equations_latex(self)

    def equilibrium(self, values, inputs=None, *, guess=None, fixed=None, tol: float = 1e-10,
                    exact: bool = True) -> "Equilibrium":
        """Operating point ``f(x0, u0) = 0`` at numeric parameter values (trim).

        See :func:`bondgraph.operating.equilibrium`: exact (sympy) for small
        polynomial systems, else :func:`scipy.optimize.root` from ``guess``;
        the point must be isolated (``fixed=`` holds states no equation
        determines).  Pass the result to :meth:`linearize` for the plant there.

        Examples
        --------
        >>> import bondgraph as bg, sympy
        >>> m, g_, l = sympy.symbols("m g l", positive=True)
        >>> g = bg.BondGraph("pendulum")
        >>> w = bg.One("w")
        >>> g.add(bg.Se("T"), w, bg.I("J"), bg.R("b"), bg.C("grav", law=m*g_*l*sympy.sin(bg.q)))
        >>> for t, h in [("T", w), (w, "J"), (w, "b"), (w, "grav")]: _ = g.connect(t, h)
        >>> vals = {"m": 1.0, "g": 9.81, "l": 0.5, "J": 0.25, "b": 0.1}
        >>> eq = bg.derive(g).equilibrium(vals, {"T": 0.0}, guess={"q_grav": 3.0})
        >>> round(eq.states["q_grav"], 12)        # hanging up: theta = pi
        3.14159265359
        """
        from .operating import equilibrium

        return equilibrium(self, values, inputs, guess=guess, fixed=fixed, tol=tol, exact=exact)

    def linearize(self, x0=None, u0=None, *, values=None, equilibrium: bool = True,
                  tol: float = 1e-9):
        """Linearize about an operating point ``(x0, u0)`` by symbolic Jacobians.

        With numeric parameter ``values`` (or an :class:`~bondgraph.operating.Equilibrium`
        as ``x0``, which carries its inputs and values) the result is a numeric
        plant: a :class:`~bondgraph.numeric.NumericStateSpace` with names, ready
        for ``.to_control()``.

        Parameters
        ----------
        x0, u0 : mapping of state / input name (or symbol) to value, or an Equilibrium
            Every state and input needs a value (numbers or sympy expressions).
        values : mapping of parameter name to number, optional
            Parameter values: the result is then numeric.
        equilibrium : bool
            When True (default), ``f(x0, u0)`` must vanish; otherwise the
            linearization about a non-equilibrium point is returned (the
            constant drift ``f(x0, u0)`` is then dropped).
        tol : float
            Tolerance of the equilibrium check for floating-point values
            (``0.0``, ``math.pi``).  Each residual ``f_i(x0, u0)`` is split
            into terms ``c * (product of parameters)`` with a numeric ``c``;
            the terms with the same parameter product are summed, and a sum
            whose parts hold a float passes when
            ``|sum| <= tol * max(1, sum of |parts|)`` (absolute below 1,
            relative above).  Exact parts (integers, rationals, ``sympy.pi``)
            must simplify to exactly zero.  ``tol=0`` asks for exact zeros.

        Returns
        -------
        SymbolicStateSpace or NumericStateSpace
            In deviation variables ``x - x0``, ``u - u0``; numeric when values
            are given.

        Examples
        --------
        >>> import bondgraph as bg, sympy
        >>> m, g_, l = sympy.symbols("m g l", positive=True)
        >>> g = bg.BondGraph("pendulum")
        >>> w = bg.One("w")
        >>> g.add(bg.Se("T"), w, bg.I("J"), bg.C("grav", law=m*g_*l*sympy.sin(bg.q)))
        >>> for t, h in [("T", w), (w, "J"), (w, "grav")]: _ = g.connect(t, h)
        >>> lin = bg.derive(g).linearize({"p_J": 0, "q_grav": 0}, {"T": 0})
        >>> lin.A
        Matrix([
        [  0, -g*l*m],
        [1/J,      0]])
        """
        from .operating import Equilibrium, linear_plant

        if isinstance(x0, Equilibrium) or values is not None:
            if values is None:
                values = dict(x0.values)
            return linear_plant(self, x0, u0, values, tol=max(tol, 1e-9))
        x, u = self.states, self.inputs
        point = {**_point(self, x0, x, "state"), **_point(self, u0, u, "input")}
        bad = set(self.input_derivatives) | {T_SYM}
        for ex in self.rhs + self.output_exprs:
            if ex.free_symbols & bad:
                raise NonlinearModelError(
                    f"model {self.name!r} depends on {', '.join(map(str, ex.free_symbols & bad))}; "
                    "it cannot be linearized to a constant (A, B)")
        if equilibrium:
            if isinstance(tol, bool) or not isinstance(tol, (int, float)) or not tol >= 0:
                raise NonlinearModelError(f"tol: expected a number >= 0, got {tol!r}")
            for s_, r in zip(x, self.rhs):
                val = _residual(r, point, tol)
                if val is not None:
                    raise NonlinearModelError(
                        f"model {self.name!r}: the operating point is not an equilibrium: "
                        f"d{s_.name}/dt = {val} there (tol={tol:g}); pass equilibrium=False "
                        "to linearize about a non-equilibrium point")

        def jac(exprs, wrt):
            return sympy.ImmutableMatrix(len(exprs), len(wrt), lambda i, j: sympy.simplify(
                sympy.diff(exprs[i], wrt[j]).xreplace(point)))
        return SymbolicStateSpace(jac(self.rhs, x), jac(self.rhs, u), jac(self.output_exprs, x),
                                  jac(self.output_exprs, u), self.state_names, self.input_names,
                                  self.output_names, known_parameters=self.known_parameters)

    def port_hamiltonian(self) -> "PortHamiltonian":
        """Port-Hamiltonian form ``x' = (J - R) grad H + (G - P) u``,
        ``y = (G + P)^T grad H + (S - N) u`` (see :mod:`bondgraph.hamiltonian`).

        Raises
        ------
        PortHamiltonianError
            Naming the element that has no such form (a nonlinear or modulated
            R, a prescribed source, nonlinear storage in derivative causality).

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("msd")
        >>> g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.R("b"), bg.C("c"))
        >>> for t, h in [("F", "v"), ("v", "m"), ("v", "b"), ("v", "c")]: _ = g.connect(t, h)
        >>> ph = bg.derive(g).port_hamiltonian()
        >>> ph.J, ph.R
        (Matrix([
        [0, -1],
        [1,  0]]), Matrix([
        [b, 0],
        [0, 0]]))
        """
        from .hamiltonian import port_hamiltonian

        return port_hamiltonian(self)

    def energy(self) -> sympy.Expr:
        """Stored energy ``H`` of every storage element, in the storage states.

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("lc")
        >>> g.add(bg.One("i"), bg.I("L"), bg.C("C"))
        >>> _ = g.connect("i", "L"); _ = g.connect("i", "C")
        >>> bg.derive(g).energy()
        p_L**2/(2*L) + q_C**2/(2*C)
        """
        from .hamiltonian import energy

        return energy(self)

    def descriptor_form(self) -> SymbolicStateSpace:
        """``E x' = A x + B u`` as derived, before eliminating dependent storage.

        Without derivative causality ``E`` is the identity.  Computed once per model.
        """
        if "descriptor_form" not in self._cache:
            self._cache["descriptor_form"] = self._descriptor_form()
        return self._cache["descriptor_form"]

    def _descriptor_form(self) -> SymbolicStateSpace:
        if self.descriptor is None:
            ss = self.state_space()
            return SymbolicStateSpace(ss.A, ss.B, ss.C, ss.D, ss.state_names,
                                      ss.input_names, ss.output_names,
                                      sympy.ImmutableMatrix(sympy.eye(len(self.states))),
                                      known_parameters=self.known_parameters)
        E, F = self.descriptor
        x, u = self.states, self.inputs
        A, B = _linear_form(F, x, u, self, "state equation", "F")
        C, D = _linear_form(self.output_exprs, x, u, self, "output", "y")
        if E.free_symbols & (set(x) | set(u)):
            raise NonlinearModelError(f"model {self.name!r}: E depends on the states")
        return SymbolicStateSpace(A, B, C, D, self.state_names, self.input_names,
                                  self.output_names, E, known_parameters=self.known_parameters)


def _equations_latex(model: Model) -> str:
    r"""``\dot x = f`` and ``y = g`` lines as a LaTeX aligned block."""
    rows = [r"%s &= %s" % (latex_dot(s.name), tex(r)) for s, r in zip(model.states, model.rhs)]
    rows += [r"%s &= %s" % (latex_name(n), tex(g))
             for n, g in zip(model.output_names, model.output_exprs)]
    return r"$$\begin{aligned}" + r" \\ ".join(rows) + r"\end{aligned}$$"
