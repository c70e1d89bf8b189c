"""The façade: :class:`Model`, the derived record with its verbs, and :func:`derive`.

A :class:`Model` is the frozen :class:`~bondgraph.equations.StateEquations`
record (state equations, outputs, the augmented bond graph they came from)
with the methods a user reaches for.  Each method is a few lines calling down
into the stage that owns the work:

=========================  ==============================================
method                     stage
=========================  ==============================================
``state_space``,           :mod:`bondgraph.linear` (linear forms, cached)
``descriptor_form``,
``transfer_function``,
``transfer_matrix``,
``linearize`` (symbolic)
``equilibrium``            :mod:`bondgraph.linear.operating`
``linearize`` (numeric)    :func:`bondgraph.numeric.linear_plant`
``port_hamiltonian``,      :mod:`bondgraph.hamiltonian`
``energy``
``to_latex``               :mod:`bondgraph.linear.latex`
=========================  ==============================================
"""

from __future__ import annotations

from typing import Union, cast

import sympy

from .causality import AugmentedBondGraph
from .equations import StateEquations, derive_equations
from .equations.derive import OutputSpec
from .graph import BondGraph
from .hamiltonian import PortHamiltonian, energy, port_hamiltonian
from . import linear
from .linear import Equilibrium, OperatingPoint, SymbolicStateSpace
from .linear.latex import equations_latex, model_latex

__all__ = ["Model", "derive"]


class Model(StateEquations):
    """Symbolic state equations of a bond graph.

    The fields (``states``, ``inputs``, ``rhs``, ``output_exprs``, ``descriptor``, ...)
    are those of the record, :class:`~bondgraph.equations.StateEquations`,
    documented there once; this class adds the verbs, each calling its stage.

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

    __slots__ = ()

    # ----------------------------------------------------------------- linear forms
    @property
    def is_linear(self) -> bool:
        """Whether ``rhs`` and outputs are linear in states and inputs."""
        return linear.is_linear(self)

    def state_space(self, *, at=None) -> SymbolicStateSpace:
        """A, B, C, D of a linear model (sympy ImmutableMatrix), with names.

        A model with constant sources (gravity, an ambient temperature), or
        linear in its states but not in its inputs, gives its matrices in
        deviations ``x - x0``, ``u - u0``, ``y - y0`` about its equilibrium,
        held in the result's ``operating_point`` (see :meth:`operating_point`;
        inputs without a value there are the symbols ``<input>0``).

        Parameters
        ----------
        at : mapping or OperatingPoint, optional
            The point to take the form about: input values (``{"F": 0}``),
            states too if wanted (the others are solved), or an
            :class:`~bondgraph.linear.OperatingPoint`.  Needed for a model
            nonlinear in its states.

        Raises
        ------
        NonlinearModelError
            If an equation is not linear in the states (and no ``at``), depends
            on time or on input derivatives; an
            :class:`~bondgraph.linear.OperatingPointError` when the point is not
            isolated (a conserved total to fix) or not solvable.

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
        return linear.state_space(self, at=at)

    def descriptor_form(self) -> SymbolicStateSpace:
        """``E x' = A x + B u`` as derived, before eliminating dependent storage.

        Without derivative causality ``E`` is the identity.  Computed once per model.
        """
        return linear.descriptor_form(self)

    def transfer_function(self, input=None, output=None, *, descriptor: bool | None = None,
                          at=None, **options):
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

        A model with constant sources, or nonlinear in its inputs but linear
        in its states (an averaged converter, ``d Vg``), gives ``G`` from
        ``u - u0`` to ``y - y0`` about its equilibrium, in
        ``G.operating_point`` (``at=`` chooses the point, as for
        :meth:`state_space`).

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
        return linear.transfer_function(self, input, output, descriptor=descriptor, at=at,
                                        **options)

    def transfer_matrix(self, *, at=None, **options):
        """All input/output transfer functions over one denominator (see :mod:`bondgraph.tf`).

        Input derivatives are handled as in :meth:`transfer_function`: an
        entry that involves one may be improper, the others are unchanged.
        Constant sources and ``at=`` as in :meth:`transfer_function`.
        """
        return linear.transfer_matrix(self, at=at, **options)

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
        return model_latex(self, matrices=matrices)

    def _repr_latex_(self) -> str:
        return equations_latex(self)

    # ----------------------------------------------------------------- operating points
    def equilibrium(self, values, inputs=None, *, guess=None, fixed=None, tol: float = 1e-10,
                    exact: bool = True, totals=None) -> Equilibrium:
        """Operating point ``f(x0, u0) = 0`` at numeric parameter values (trim).

        See :func:`bondgraph.linear.operating.equilibrium`: exact (sympy) for small
        polynomial systems, else :func:`scipy.optimize.root` from ``guess``;
        the point must be isolated (``fixed=`` holds states no equation
        determines; ``totals=`` fixes the totals of conserved quantities, as
        for :meth:`operating_point`).  Pass the result to :meth:`linearize` for
        the plant there.

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
        return linear.equilibrium(self, values, inputs, guess=guess, fixed=fixed, tol=tol,
                                  exact=exact, totals=totals)

    def operating_point(self, inputs=None, *, values=None, totals=None, guess=None,
                        fixed=None, tol: float = 1e-10) -> "OperatingPoint":
        """The equilibrium the linear forms are taken about: ``x0``, ``u0`` and ``y0``.

        Without ``values`` it is symbolic
        (:func:`bondgraph.linear.offsets.symbolic_operating_point`: an exact
        linear solve when the state equations are linear in the states at
        ``u0``, sympy's solver for small polynomial ones); with numeric
        ``values`` it is the numeric search of :meth:`equilibrium`, and
        ``guess``/``fixed`` go to it.

        Parameters
        ----------
        inputs : mapping of input name to value, optional
            ``u0``.  Symbolic: inputs not given are the symbols ``<input>0``;
            numeric: 0.
        values : mapping of parameter name to number, optional
        totals : mapping, optional
            The totals of conserved quantities (a chemical moiety, a floating
            charge), which leave the equilibrium free otherwise: a key is a
            state name, a tuple of state names (their sum) or a sympy
            expression linear in the states, e.g. ``{("q_E", "q_C"): E_T}``.

        Returns
        -------
        OperatingPoint

        Examples
        --------
        >>> import bondgraph as bg
        >>> g = bg.BondGraph("rc")
        >>> g.add(bg.Se("V"), bg.One("i"), bg.R("R"), bg.C("C"))
        >>> for t, h in [("V", "i"), ("i", "R"), ("i", "C")]: _ = g.connect(t, h)
        >>> model = bg.derive(g, outputs={"vC": bg.effort("C")})
        >>> print(model.operating_point().note)
        deviations about the operating point x0: q_C = C*V0; u0: V = V0; y0: vC = V0
        >>> model.operating_point({"V": 2.0}, values={"R": 1.0, "C": 0.5}).states["q_C"]
        1.0
        """
        if values is None:
            if guess is not None or fixed is not None:
                raise linear.OperatingPointError(
                    f"model {self.name!r}: guess= and fixed= steer the numeric search; give "
                    "values= with them")
            return linear.symbolic_operating_point(self, inputs, totals=totals)
        eq = self.equilibrium(values, inputs, guess=guess, fixed=fixed, tol=tol, totals=totals)
        return linear.numeric_operating_point(self, eq)

    def linearize(self, x0=None, u0=None, *, values=None, equilibrium: bool = True,
                  tol: float = 1e-9):
        """Linearize about an operating point ``(x0, u0)`` by symbolic Jacobians.

        With numeric parameter ``values`` (or an :class:`~bondgraph.linear.operating.Equilibrium`
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

        Without ``x0`` the point is the equilibrium at ``u0``: solved exactly
        (inputs not in ``u0`` are the symbols ``<input>0``), or, with
        ``values``, found by :meth:`equilibrium` (inputs not given are 0).

        Returns
        -------
        SymbolicStateSpace or NumericStateSpace
            In deviation variables ``x - x0``, ``u - u0``; numeric when values
            are given.  Its ``operating_point`` holds ``x0``, ``u0``, ``y0``.

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
        if isinstance(x0, Equilibrium) or values is not None:
            if values is None:
                values = dict(x0.values)
            if x0 is None:
                x0, u0 = self.equilibrium(values, u0, tol=min(tol, 1e-10)), None
            from .numeric import linear_plant     # scipy only when a numeric plant is asked for

            return linear_plant(self, x0, u0, values, tol=max(tol, 1e-9), equilibrium=equilibrium)
        return linear.linearize(self, x0, u0, equilibrium=equilibrium, tol=tol)

    # ----------------------------------------------------------------- energy
    def port_hamiltonian(self) -> PortHamiltonian:
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
        return energy(self)


def derive(graph: Union[BondGraph, AugmentedBondGraph], outputs: OutputSpec = None) -> Model:
    """Derive explicit state equations (and outputs) from a bond graph.

    Parameters
    ----------
    graph : BondGraph or AugmentedBondGraph
        Causality is assigned (by SCAP) when a plain graph is given.
    outputs : mapping of str to expression, optional
        Named outputs: expressions of signals such as ``bg.flow("J")``,
        ``bg.displacement("J")`` or ``L*bg.displacement("hub") + ...``.

    Returns
    -------
    Model
        States, inputs, ``rhs`` (x' = f(x, u)), outputs and, when derivative
        causality is present, the descriptor form (see
        :func:`bondgraph.equations.derive_equations`).

    Raises
    ------
    OutputError
        An output names no element or bond, or is not an expression.
    AlgebraicLoopError
        A loop that is not linear in its unknowns.

    Examples
    --------
    >>> import bondgraph as bg
    >>> g = bg.BondGraph("dc_motor")
    >>> V, ia, w = bg.Se("V"), bg.One("ia"), bg.One("w")
    >>> g.add(V, ia, w, bg.R("Ra"), bg.I("La"), bg.GY("K"), bg.I("J"), bg.R("b"))
    >>> for tail, head in [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")]:
    ...     _ = g.connect(tail, head)
    >>> model = bg.derive(g, outputs={"omega": bg.flow("J"), "theta": bg.displacement("J")})
    >>> model.state_names
    ('p_La', 'p_J', 'theta')
    >>> model.rhs
    (V - Ra*p_La/La - K*p_J/J, K*p_La/La - b*p_J/J, p_J/J)
    """
    return cast(Model, derive_equations(graph, outputs, record=Model))
