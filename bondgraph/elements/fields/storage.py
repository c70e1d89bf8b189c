"""Storage fields: :class:`IField`, :class:`CField`, :class:`ICField` (conventions in :mod:`bondgraph.elements.fields`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar, Optional, Sequence

import sympy

from .algebra import FieldError, field_matrix, inverse, partial_solve, solve_law
from .base import Field, law_function, field_variables
from ..protocol import DERIVATIVE, INTEGRAL, STORAGE, Choice, LocalVariables
from ...signals import LawVariable, displacement, momentum

__all__ = ["StorageField", "IField", "CField", "ICField"]


@dataclass(frozen=True, eq=False)
class StorageField(Field):
    """Base of the storage fields: I-like and C-like ports, a quadratic or general energy.

    Attributes
    ----------
    matrix : ImmutableMatrix or None
        The linear law; with ``form == 'hessian'`` ``z = matrix x``, with
        ``form == 'inverse'`` ``x = matrix z`` (mass or compliance).
    energy : sympy.Expr or None
        ``H`` in the field's own variables (:attr:`variables`).
    """

    matrix: Optional[sympy.ImmutableMatrix] = field(default=None, init=False)
    form: str = field(default="hessian", init=False, repr=False)
    #: what the matrix is called in messages ('mass matrix', ...)
    matrix_name: str = field(default="matrix", init=False, repr=False)
    energy: Optional[sympy.Expr] = field(default=None, init=False)
    variables: tuple = field(default=(), init=False, repr=False)
    drawing_role: ClassVar[str] = "storage"

    def _setup(self, kinds: str, *, matrix=None, form: str = "hessian", what: str = "matrix",
               energy=None, variables=None) -> None:
        owner = self.label()
        given = [x is not None for x in (matrix, energy)]
        if sum(given) != 1:
            raise FieldError(f"{owner}: give either a matrix or energy=, "
                             f"{'not both' if all(given) else 'one of them'}")
        n = len(kinds) if kinds else None
        prefixes = kinds.replace("I", "p").replace("C", "q") if kinds else None
        if matrix is not None:
            M = field_matrix(matrix, owner=owner, what=what, ports=n)
            kinds = kinds or self.default_kind * M.rows
            object.__setattr__(self, "matrix", M)
            object.__setattr__(self, "form", form)
            object.__setattr__(self, "matrix_name", what)
            own = tuple(LawVariable(f"{'p' if k == 'I' else 'q'}{i + 1}")
                        for i, k in enumerate(kinds))
        else:
            size = n if n is not None else len(tuple(variables or ()))
            kinds = kinds or self.default_kind * size
            prefixes = kinds.replace("I", "p").replace("C", "q")
            own, vs = field_variables(energy, variables, n, owner=owner, prefixes=prefixes,
                                 what="energy")
            H = law_function(energy, vs, own, owner=owner, what="energy")
            object.__setattr__(self, "energy", H)
            hess = sympy.hessian(H, own)
            if not hess.free_symbols & set(own):      # quadratic: the linear (exact) path
                object.__setattr__(self, "matrix", field_matrix(hess, owner=owner,
                                                                what="Hessian of the energy"))
                object.__setattr__(self, "matrix_name", "Hessian of the energy")
        object.__setattr__(self, "port_kinds", kinds)
        object.__setattr__(self, "variables", own)

    default_kind: ClassVar[str] = "I"

    # ------------------------------------------------------------ causality
    def _integral(self, port: int) -> bool:
        """Whether integral causality receives effort on ``port`` (an I port)."""
        return self.port_kinds[port] == "I"

    def _sides(self, effort_in: Sequence[bool]) -> tuple[list[int], list[int]]:
        """(integral ports, derivative ports)."""
        a = [p for p in range(self.ports) if effort_in[p] == self._integral(p)]
        return a, [p for p in range(self.ports) if p not in a]

    def causal_choices(self, prefer_derivative: bool) -> Sequence[Choice]:
        how = "derivative" if prefer_derivative else "integral"
        return tuple(Choice(p, self._integral(p) != prefer_derivative,
                            f"{how} causality of {self.label()} port {p + 1}", STORAGE)
                     for p in range(self.ports))

    def causal_class(self, effort_in: Sequence[bool], free: Sequence[bool]) -> Optional[str]:
        return DERIVATIVE if self._sides(effort_in)[1] else INTEGRAL

    def output_dependencies(self, effort_in: Sequence[bool],
                            causality: Optional[str]) -> Sequence[Sequence[int]]:
        dep = tuple(self._sides(effort_in)[1])
        return tuple(dep for _ in range(self.ports))

    # ------------------------------------------------------------ names
    def _name(self, port: int) -> str:
        return f"{'p' if self._integral(port) else 'q'}_{self.name}_{port + 1}"

    def state_names(self, effort_in: Sequence[bool]) -> tuple[str, ...]:
        return tuple(self._name(p) for p in self._sides(effort_in)[0])

    def derivative_ports(self, effort_in: Sequence[bool]) -> tuple[int, ...]:
        return tuple(self._sides(effort_in)[1])

    def stored_names(self, effort_in: Sequence[bool]) -> tuple[str, ...]:
        return tuple(self._name(p) for p in self._sides(effort_in)[1])

    def port_energy_variable(self, variable: str, port: int,
                             effort_in: Sequence[bool]) -> Optional[int]:
        """Index in (states + stored quantities) of the port's momentum or displacement."""
        k = self._port(variable, port)
        if variable != ("momentum" if self._integral(k) else "displacement"):
            return None
        a, b = self._sides(effort_in)
        return a.index(k) if k in a else len(a) + b.index(k)

    # ------------------------------------------------------------ relations
    def _solve(self, local: LocalVariables) -> tuple[list, list]:
        """(x, z) on every port from the states (integral ports) and the inputs (others)."""
        effort_in = [local.effort_in(p) for p in range(self.ports)]
        a, b = self._sides(effort_in)
        x_a = dict(zip(a, local.states))
        z_b = {p: (local.sign(p) * local.input(p) if self._integral(p) else local.input(p))
               for p in b}
        if self.matrix is not None and self.form == "inverse":    # x = A z
            z, x = partial_solve(self.matrix, z_b, x_a, owner=self.label(),
                                 what=getattr(self, "matrix_name", "matrix"))
            return x, z
        if self.matrix is not None:                                # z = Q x
            return partial_solve(self.matrix, x_a, z_b, owner=self.label(),
                                 what=getattr(self, "matrix_name", "matrix"))
        own = self.variables
        grad = [sympy.diff(self.energy, v) for v in own]
        known = {own[p]: x_a[p] for p in a}
        x = [x_a.get(p) for p in range(self.ports)]
        if b:
            sol = solve_law([grad[p].xreplace(known) - z_b[p] for p in b], [own[p] for p in b],
                            owner=self.label(), ports=[p + 1 for p in b],
                            what="derivative causality")
            for p in b:
                x[p] = sol[own[p]]
        full = dict(zip(own, x))
        z = [z_b[p] if p in z_b else grad[p].xreplace(full) for p in range(self.ports)]
        return x, z

    def output(self, local: LocalVariables, port: int) -> sympy.Expr:
        z = self._solve(local)[1][port]
        return local.sign(port) * z if self._integral(port) else z   # the I port's bond flow

    def state_derivatives(self, local: LocalVariables) -> tuple[sympy.Expr, ...]:
        a = self._sides([local.effort_in(p) for p in range(self.ports)])[0]
        return tuple(local.input(p) if self._integral(p) else local.sign(p) * local.input(p)
                     for p in a)

    def stored(self, local: LocalVariables) -> tuple[sympy.Expr, ...]:
        b = self._sides([local.effort_in(p) for p in range(self.ports)])[1]
        x = self._solve(local)[0]
        return tuple(x[p] for p in b)

    def derivative_output(self, local: LocalVariables, port: int,
                          rates: Sequence[sympy.Expr]) -> sympy.Expr:
        b = self._sides([local.effort_in(p) for p in range(self.ports)])[1]
        rate = rates[b.index(port)]
        return rate if self._integral(port) else local.sign(port) * rate

    # ------------------------------------------------------------ energy
    def energy_signals(self) -> tuple:
        return tuple((momentum if self._integral(p) else displacement)(self.name, port=p + 1)
                     for p in range(self.ports))

    def stored_energy(self, quantities: Sequence[sympy.Expr]) -> sympy.Expr:
        x = sympy.Matrix(list(quantities))
        if self.energy is not None:
            return self.energy.xreplace(dict(zip(self.variables, quantities)))
        assert self.matrix is not None
        Q = inverse(self.matrix) if self.form == "inverse" else self.matrix
        return sympy.expand((x.T * Q * x)[0, 0] / 2) if not Q.free_symbols else \
            (x.T * Q * x)[0, 0] / 2

    def energy_hessian_inverse(self) -> Optional[sympy.ImmutableMatrix]:
        if self.matrix is not None and self.energy is None:
            return self.matrix if self.form == "inverse" else None
        return None

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        if dependent and self.matrix is None:
            return (f"{self.label()} is in derivative causality with the nonlinear energy "
                    f"{self.energy}; the reduced form needs a linear (matrix) field there")
        return None

@dataclass(frozen=True, eq=False)
class IField(StorageField):
    """Inertance field: ``n`` I-like ports, ``p = M f`` or a kinetic energy ``T(p)``.

    Parameters
    ----------
    name : str
    mass : square matrix, optional
        The symmetric positive-definite mass (inertance) matrix ``M``,
        ``n x n`` for ``n`` ports; entries numbers or sympy expressions.
    energy : sympy expression, optional
        Kinetic energy ``T(p_1, ..., p_n)`` (instead of ``mass``); ``f = dT/dp``.
    variables : sequence of sympy.Symbol
        The momenta ``energy`` is written in, one per port.

    Examples
    --------
    >>> import bondgraph as bg
    >>> M = bg.IField("M", [[2, 1], [1, 2]])
    >>> M.ports, M.state_names([True, True]), M.drawing_label()
    (2, ('p_M_1', 'p_M_2'), ('IF', 'M'))
    >>> M.stored_energy(sympy.symbols("a b"))
    a**2/3 - a*b/3 + b**2/3
    """

    mass: object = None
    kind: ClassVar[str] = "IF"

    def __init__(self, name: str, mass: object = None, *, energy: object = None,
                 variables: Optional[Sequence[sympy.Symbol]] = None) -> None:
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "mass", mass)
        self.__post_init__()
        self._setup("", matrix=mass, form="inverse", what="mass matrix", energy=energy,
                    variables=variables)


@dataclass(frozen=True, eq=False)
class CField(StorageField):
    """Capacitance field: ``n`` C-like ports, ``e = K q``, ``q = C e`` or ``e = dV/dq``.

    Parameters
    ----------
    name : str
    stiffness : square matrix, optional
        Symmetric positive-definite ``K`` (``e = K q``).
    compliance : square matrix, optional
        Symmetric positive-definite ``C`` (``q = C e``).
    energy : sympy expression, optional
        Potential energy ``V(q_1, ..., q_n)``; ``e = dV/dq``.
    variables : sequence of sympy.Symbol
        The displacements ``energy`` is written in, one per port.

    Examples
    --------
    >>> import bondgraph as bg
    >>> q1, q2 = sympy.symbols("q1 q2")
    >>> V = bg.CField("V", energy=q1**2 / 2 + q2**2 / 2 + q1**2 * q2**2, variables=(q1, q2))
    >>> V.ports, V.state_names([False, False]), V.matrix is None
    (2, ('q_V_1', 'q_V_2'), True)
    """

    stiffness: object = field(default=None, kw_only=True)
    compliance: object = field(default=None, kw_only=True)
    kind: ClassVar[str] = "CF"
    default_kind: ClassVar[str] = "C"

    def __init__(self, name: str, *, stiffness: object = None, compliance: object = None,
                 energy: object = None,
                 variables: Optional[Sequence[sympy.Symbol]] = None) -> None:
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "stiffness", stiffness)
        object.__setattr__(self, "compliance", compliance)
        self.__post_init__()
        if stiffness is not None and compliance is not None:
            raise FieldError(f"{self.label()}: give stiffness= or compliance=, not both")
        if compliance is not None:
            self._setup("", matrix=compliance, form="inverse", what="compliance matrix",
                        energy=energy, variables=variables)
        else:
            self._setup("", matrix=stiffness, what="stiffness matrix", energy=energy,
                        variables=variables)


@dataclass(frozen=True, eq=False)
class ICField(StorageField):
    """Mixed field: I-like and C-like ports, an energy ``H(p, q)`` or its Hessian.

    Parameters
    ----------
    name : str
    kinds : str
        One letter per port, ``'I'`` or ``'C'`` (``"IC"``: port 1 inertial,
        port 2 compliant).
    matrix : square matrix, optional
        The Hessian ``Q`` of a quadratic ``H``: ``z = Q x`` with ``x`` the
        energy variables (``p`` of I ports, ``q`` of C ports) in port order.
    energy : sympy expression, optional
        ``H(x_1, ..., x_n)``; flows ``dH/dp``, efforts ``dH/dq``.
    variables : sequence of sympy.Symbol
        The energy variables ``energy`` is written in, one per port.

    Examples
    --------
    >>> import bondgraph as bg
    >>> p, q = sympy.symbols("p q")
    >>> F = bg.ICField("pend", "IC", energy=p**2 / 2 + q**2 / 2 + p * q / 4, variables=(p, q))
    >>> F.state_names([True, False]), F.matrix
    (('p_pend_1', 'q_pend_2'), Matrix([
    [  1, 1/4],
    [1/4,   1]]))
    """

    kind: ClassVar[str] = "ICF"

    def __init__(self, name: str, kinds: str, *, matrix: object = None, energy: object = None,
                 variables: Optional[Sequence[sympy.Symbol]] = None) -> None:
        object.__setattr__(self, "name", name)
        self.__post_init__()
        if not isinstance(kinds, str) or not kinds or set(kinds) - {"I", "C"}:
            raise FieldError(f"{self.label()}: kinds must be a string of 'I' and 'C', one "
                             f"letter per port (e.g. 'IC'); got {kinds!r}")
        self._setup(kinds, matrix=matrix, what="Hessian", energy=energy, variables=variables)
