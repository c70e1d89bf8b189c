"""The frozen record of a derived model: state equations, outputs, where they came from.

:class:`StateEquations` is what :func:`~bondgraph.equations.derive_equations`
returns and what every later stage reads (linear forms, transfer functions,
numeric plants, the port-Hamiltonian form).  It holds data and the names
derived from it, nothing else: the verbs live in those stages, and
:class:`bondgraph.Model` is this record with the verbs attached.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import sympy

from .._support.sympify import parameter_symbols
from ..causality import AugmentedBondGraph
from ..signals import t as T_SYM

__all__ = ["StateEquations"]


@dataclass(frozen=True)
class StateEquations:
    """Symbolic state equations ``x' = f(x, u)``, outputs ``y = g(x, u)``, and their origin.

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
        :mod:`bondgraph.equations.integrators`).
    declared_parameters : tuple of str
        Parameter names a model definition declares beyond its elements'.
    algebraic : tuple of sympy.Symbol
        Algebraic unknowns ``z`` of an implicit model: the variables of a
        nonlinear algebraic loop, and the outputs of laws with no closed-form
        inverse, that no symbolic solve could eliminate.  ``rhs`` and
        ``output_exprs`` may then hold them: ``x' = f(x, z, u)``,
        ``y = h(x, z, u)``.  Empty for an explicit model.
    residuals : tuple of sympy.Expr
        ``0 = g(x, z, u)``, one per algebraic unknown.
    algebraic_origin : tuple of str
        For each algebraic unknown, what it is (``"the flow of R:D (its
        effort law has no closed-form inverse)"``), for messages.

    Examples
    --------
    >>> from bondgraph import examples
    >>> from bondgraph.equations import derive_equations
    >>> eqs = derive_equations(examples.mass_spring_damper())
    >>> eqs.state_names, eqs.input_names, [p.name for p in eqs.parameters]
    (('p_m', 'q_k'), ('F',), ['b', 'k', 'm'])
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
    #: implicit part: algebraic unknowns z and residuals 0 = g(x, z, u)
    algebraic: tuple[sympy.Symbol, ...] = field(default=(), repr=False)
    residuals: tuple[sympy.Expr, ...] = field(default=(), repr=False)
    algebraic_origin: tuple[str, ...] = field(default=(), repr=False)
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
        got = self._cache.get("parameters")      # frozen record: walk the equations once
        if got is not None:
            return got
        known = (set(self.states) | set(self.inputs) | set(self.input_derivatives) | {T_SYM}
                 | set(self.algebraic))
        syms = set()
        for ex in self.rhs + self.output_exprs + self.residuals:
            syms |= ex.free_symbols
        if self.descriptor is not None:
            syms |= self.descriptor[0].free_symbols
        got = self._cache["parameters"] = tuple(sorted(syms - known, key=lambda s: s.name))
        return got

    @property
    def algebraic_names(self) -> tuple[str, ...]:
        return tuple(z.name for z in self.algebraic)

    @property
    def is_implicit(self) -> bool:
        """Whether the model keeps algebraic unknowns ``z`` with residuals ``0 = g(x, z, u)``."""
        return bool(self.algebraic)

    @property
    def known_parameters(self) -> tuple[str, ...]:
        """Names of every parameter of the model definition, sorted.

        A superset of :attr:`parameters`: it also holds parameters of
        elements whose value does not reach the equations (an inertia in
        derivative causality with no output on it, a parameter that dropped
        out of a linearization).  Values given for these are accepted and
        ignored by every call that takes values (:mod:`bondgraph.parameters`).
        """
        got = self._cache.get("known_parameters")
        if got is not None:
            return got
        names = {p.name for p in self.parameters} | set(self.declared_parameters)
        elements = self.augmented.flat.elements if self.augmented is not None else ()
        for el in elements:
            names |= {s.name for s in parameter_symbols(el)}
        got = self._cache["known_parameters"] = tuple(sorted(names))
        return got

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
        eqs += [sympy.Eq(sympy.Integer(0), g, evaluate=False) for g in self.residuals]
        eqs += [sympy.Eq(sympy.Symbol(n), g, evaluate=False)
                for n, g in zip(self.output_names, self.output_exprs)]
        return tuple(eqs)

    def __str__(self) -> str:
        lines = [f"model {self.name!r}: {len(self.states)} states, {len(self.inputs)} inputs, "
                 f"{len(self.output_names)} outputs"]
        if self.algebraic:
            lines[0] += (f", {len(self.algebraic)} algebraic unknowns "
                         f"({', '.join(self.algebraic_names)})")
        for s, r in zip(self.states, self.rhs):
            lines.append(f"  d{s.name}/dt = {r}")
        for g in self.residuals:
            lines.append(f"  0 = {g}")
        for n, g in zip(self.output_names, self.output_exprs):
            lines.append(f"  {n} = {g}")
        return "\n".join(lines)

