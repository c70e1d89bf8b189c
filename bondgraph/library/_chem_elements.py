"""Chemical elements: the species ``Ce``, the reaction ``Re``, chemostats and flowstats.

The chemical domain of bond graphs (Oster, Perelson and Katchalsky, *Nature*
229, 1971; Gawthrop and Crampin, *Proc. R. Soc. A* 470, 2014): the effort is
the chemical potential ``mu`` (J/mol), the flow a molar flow (mol/s).

* :class:`Ce` -- a species: a capacitor storing the amount ``q`` (mol) with
  ``mu = R T ln(K q)``;
* :class:`Re` -- a reaction: a resistive two-port with the Marcelin--de Donder
  law ``v = r (exp(A_f/RT) - exp(A_r/RT))``, ``A_f`` the forward affinity
  (effort of the bond into it) and ``A_r`` the reverse affinity (effort of
  the bond out of it).  With ``Ce`` species on both sides it is mass action,
  ``v = r (prod (K_s q_s)^n_s - prod (K_p q_p)^n_p)``;
* :class:`Chemostat` -- a species held at a fixed amount: an effort source
  ``mu = R T ln(K x)``;
* :class:`Flowstat` -- a species whose net molar flow is prescribed: a flow
  source.

Each answers the element protocol (:mod:`bondgraph.protocol`) itself: the
causality, derivation and drawing modules know nothing of chemistry.

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph.library.chemical import Ce, Re
>>> A = Ce("A")
>>> A.forward()
R_gas*T*log(q*K_A)
>>> Re("r1").label(), Re("r1").bonds
('Re:r1', (2, 2))
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from typing import ClassVar, Optional, cast

import sympy

from ..elements import C, Se, Sf
from ..errors import ParameterError
from ..elements.protocol import Element, rename
from ._twoport import ConductanceTwoPort, positive_parameter as _positive
from ..signals import Signal, e as E_VAR, q as Q_VAR
from .._support.sympify import ParameterLike, nonzero, to_expr
from ..elements.rules import rule

__all__ = ["Ce", "Re", "Chemostat", "Flowstat", "GAS_CONSTANT", "FARADAY", "R_GAS", "TEMPERATURE"]

#: the molar gas constant, J/(mol K) (CODATA 2018, exact)
GAS_CONSTANT = 8.314462618
#: the Faraday constant, C/mol (CODATA 2018, exact)
FARADAY = 96485.33212
#: the default symbol of the gas constant in chemical laws (give its value with the others)
R_GAS = sympy.Symbol("R_gas", positive=True)
#: the default symbol of the temperature in chemical laws
TEMPERATURE = sympy.Symbol("T", positive=True)


def _whole_log_powers(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` with each ``c*log(...)`` term whose float ``c`` is a whole number within
    rounding given the integer ``c``.

    ``A/RT`` of species ``mu = RT ln(K q)`` with a numeric ``RT`` leaves
    ``1.0*log(q)`` (``RT/RT`` in floats), and ``exp`` of it ``q**1.0``; the
    quotient is exactly the stoichiometric coefficient, so it is given as one.

    Examples
    --------
    >>> q = sympy.Symbol("q", positive=True)
    >>> rt = sympy.Float(8.314) * 310
    >>> sympy.exp(_whole_log_powers(sympy.expand(sympy.expand_log(2 * rt * sympy.log(q) / rt))))
    q**2
    """
    def whole(term: sympy.Expr) -> sympy.Expr:
        c, rest = term.as_coeff_Mul()
        if isinstance(c, sympy.Float) and rest.has(sympy.log):
            n = round(float(c))
            if n != 0 and abs(float(c) - n) <= 8 * sys.float_info.epsilon * abs(n):
                return sympy.Integer(n) * rest
        return term
    return sympy.Add(*[whole(t) for t in sympy.Add.make_args(expr)])


def _rt(el) -> sympy.Expr:
    owner = f"{el.kind}:{el.name}"
    return (_positive(el.gas_constant, R_GAS, owner=owner, what="gas_constant") *
            _positive(el.temperature, TEMPERATURE, owner=owner, what="temperature"))


def _thermo_rules(el) -> tuple:
    """The gas constant and the (absolute) temperature of a chemical law: positive."""
    owner = f"{el.kind}:{el.name}"
    return (rule(_positive(el.gas_constant, R_GAS, owner=owner, what="gas_constant"),
                 "gas constant R_gas", opt_out=False) +
            rule(_positive(el.temperature, TEMPERATURE, owner=owner, what="temperature"),
                 "absolute temperature", opt_out=False))


def _rate_constant(value: ParameterLike, *, owner: str, what: str) -> sympy.Expr:
    """A mass-action rate constant: a constant expression, a number not negative (0: the
    step is irreversible)."""
    expr = to_expr(value, owner=owner, what=what)
    if expr is None:
        return sympy.Integer(1)
    if any(isinstance(s, Signal) for s in expr.free_symbols):
        raise ParameterError(f"{owner}: {what} {expr} must be a constant parameter (no signals)")
    if expr.is_number and expr.is_negative:
        raise ParameterError(f"{owner}: {what} must not be negative, got {expr}")
    return expr


@dataclass(frozen=True, eq=False)
class Ce(C):
    """A chemical species: stores the amount ``q`` (mol); ``mu = R T ln(K q)``.

    A capacitor of the chemical domain (Gawthrop and Crampin 2014, Eq. 2.1;
    BondGraphs.jl's ``Ce``).  Its state is ``q_<name>``.

    Parameters
    ----------
    name : str
    K : number, str or sympy expression, optional
        The thermodynamic constant ``exp(mu0/RT)/V`` (1/mol); defaults to the
        positive symbol ``K_<path>``.
    temperature, gas_constant : number, str or sympy expression, optional
        Keyword only; default to the shared symbols ``T`` and ``R_gas``
        (:data:`GAS_CONSTANT` is the value of ``R_gas``).  In mass-action
        networks they cancel out of the equations.

    Examples
    --------
    >>> Ce("A", K=2).forward()
    R_gas*T*log(2*q)
    >>> Ce("A", K=2).backward()
    exp(e/(R_gas*T))/2
    >>> Ce("A").resolved("cell.A").K_value
    K_cell.A
    """

    K: ParameterLike = field(default=None, kw_only=True)
    temperature: ParameterLike = field(default=None, kw_only=True)
    gas_constant: ParameterLike = field(default=None, kw_only=True)
    kind: ClassVar[str] = "Ce"

    def __post_init__(self) -> None:
        if (self.parameter, self.law, self.inverse, self.stiffness) != (None,) * 4:
            raise ParameterError(f"Ce:{self.name}: a species' law is mu = R T ln(K q); give K=, "
                                 "temperature= and gas_constant=, not a parameter or a law")
        self._set_law()
        super().__post_init__()

    @property
    def K_value(self) -> sympy.Expr:
        """``K``, or the default symbol ``K_<name>``."""
        return _positive(self.K, sympy.Symbol(f"K_{self.name}", positive=True),
                         owner=self.label(), what="K")

    def RT(self) -> sympy.Expr:
        """The product ``R T`` of its law."""
        return _rt(self)

    def value_rules(self) -> tuple:
        """``K``, ``R_gas`` and ``T`` positive (``ln(K q)``: no opt-out)."""
        return rule(self.K_value, "thermodynamic constant", opt_out=False) + _thermo_rules(self)

    def _set_law(self) -> None:
        k, rt = self.K_value, self.RT()
        object.__setattr__(self, "law", rt * sympy.log(k * Q_VAR))
        object.__setattr__(self, "inverse", sympy.exp(E_VAR / rt) / k)

    def resolved(self, path: str) -> Element:
        el = cast(Ce, rename(self, path))
        el._set_law()
        return el

    def fixed_domains(self, into) -> dict[int, str]:
        return {0: "chemical"}

    def energy_signals(self) -> tuple:
        return ()        # its free energy is not a storage of the port-Hamiltonian form

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        return (f"{self.label()}: a species' free energy R T (q ln(K q) - q) is defined for "
                "q > 0 only and is not a port-Hamiltonian storage here")

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "species"


@dataclass(frozen=True, eq=False)
class Re(ConductanceTwoPort):
    """A reaction: a resistive two-port, ``v = r (exp(A_f/RT) - exp(A_r/RT))``.

    The Marcelin--de Donder law (Gawthrop and Crampin 2014, Eq. 2.6;
    BondGraphTools' and BondGraphs.jl's ``Re``).  Port 1 is the bond into the
    reaction (the substrates' side, forward affinity ``A_f``), port 2 the bond
    out of it (the products' side, ``A_r``); the molar flow ``v`` is the same
    on both bonds, in their direction.  The reaction receives both affinities
    (effort on both ports).  With ``mu = RT ln(K q)`` species it is mass
    action: ``v = kf prod q_s^n_s - kr prod q_p^n_p`` with ``kf = r prod K_s^n_s``.

    The *mass-action form* gives the two rate constants instead of ``r``:
    ``v = kf exp(A_f/RT) - kr exp(A_r/RT)``, so with species of ``K = 1``
    ``v = kf prod q_s^n_s - kr prod q_p^n_p`` exactly as a kinetic scheme is
    written.  It obeys detailed balance only when ``kf/kr`` equals the
    reaction's equilibrium constant (with ``K = 1`` species: 1); the
    Marcelin--de Donder form obeys it by construction.

    Parameters
    ----------
    name : str
    r : number, str or sympy expression, optional
        The reaction rate constant (mol/s); defaults to the positive symbol
        ``r_<path>``.
    kf, kr : optional, keyword only
        The mass-action form's forward and reverse rate constants (both, and
        no ``r``).
    temperature, gas_constant : optional, keyword only
        As for :class:`Ce`.

    Examples
    --------
    >>> Re("r1").r_value, Re("r1", r=3).resolved("cell.r1").r_value
    (r_r1, 3)
    >>> Re("r2", kf=2, kr=1).rate(0, 0)
    1
    """

    r: ParameterLike = field(default=None, kw_only=True)
    kf: ParameterLike = field(default=None, kw_only=True)
    kr: ParameterLike = field(default=None, kw_only=True)
    temperature: ParameterLike = field(default=None, kw_only=True)
    gas_constant: ParameterLike = field(default=None, kw_only=True)
    kind: ClassVar[str] = "Re"
    sides: ClassVar[str] = "the substrates' bond into a reaction, the products' bond out of it"
    conflict_hint: ClassVar[str] = (
        " A reaction takes the chemical potential (effort) on both of its bonds: "
        "connect each side to a species 0-junction, a 1-junction of species or a chemostat, "
        "not to a flow source.")

    def __post_init__(self) -> None:
        super().__post_init__()
        if (self.kf is None) != (self.kr is None) or (self.kf is not None and self.r is not None):
            raise ParameterError(f"{self.label()}: give r (Marcelin-de Donder form) or both kf "
                                 "and kr (mass-action form), not a mix")
        kf, kr = self._constants()
        if kf.is_zero and kr.is_zero:
            raise ParameterError(f"{self.label()}: kf and kr are both 0, so the reaction never "
                                 "runs; remove it, or give one of them a positive value (one "
                                 "0 makes an irreversible step)")
        self.RT()      # validate now, at the wrong call

    def _constants(self) -> tuple[sympy.Expr, sympy.Expr]:
        """The forward and reverse coefficients (``r, r`` or ``kf, kr``)."""
        if self.kf is None:
            return self.r_value, self.r_value
        return (_rate_constant(self.kf, owner=self.label(), what="kf"),
                _rate_constant(self.kr, owner=self.label(), what="kr"))

    def value_rules(self) -> tuple:
        """``r`` positive, or ``kf`` and ``kr`` not negative; ``R_gas`` and ``T`` positive."""
        if self.kf is None:
            own = rule(self.r_value, "rate constant r", opt_out=False)
        else:
            kf, kr = self._constants()
            own = (rule(kf, "forward rate constant kf", "nonnegative", opt_out=False) +
                   rule(kr, "reverse rate constant kr", "nonnegative", opt_out=False))
        return own + _thermo_rules(self)

    @property
    def r_value(self) -> sympy.Expr:
        """``r``, or the default symbol ``r_<name>``."""
        return _positive(self.r, sympy.Symbol(f"r_{self.name}", positive=True),
                         owner=self.label(), what="r")

    def RT(self) -> sympy.Expr:
        """The product ``R T`` of its law."""
        return _rt(self)

    def rate(self, forward: sympy.Expr, reverse: sympy.Expr) -> sympy.Expr:
        """The molar flow for the affinities ``forward`` and ``reverse``.

        Examples
        --------
        >>> A = sympy.Symbol("A")
        >>> Re("r1", r=2).rate(A, 0)
        2*exp(A/(R_gas*T)) - 2
        """
        rt = self.RT()
        term = lambda a: sympy.exp(_whole_log_powers(sympy.expand(sympy.expand_log(a / rt,
                                                                                force=False))))
        kf, kr = self._constants()
        if kf == kr:
            return kf * (term(forward) - term(reverse))
        return kf * term(forward) - kr * term(reverse)

    def flows(self, effort_in: sympy.Expr, effort_out: sympy.Expr) -> tuple[sympy.Expr, sympy.Expr]:
        v = self.rate(effort_in, effort_out)
        return v, v

    def hamiltonian_error(self, dependent: bool) -> Optional[str]:
        return (f"{self.label()}: a reaction's law exp(A/RT) is nonlinear; the "
                "port-Hamiltonian form needs linear R elements")

    def fixed_domains(self, into) -> dict[int, str]:
        return {0: "chemical", 1: "chemical"}

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "reaction"


@dataclass(frozen=True, eq=False)
class Chemostat(Se):
    """A species held at the amount ``x``: an effort source ``mu = R T ln(K x)``.

    Parameters
    ----------
    name : str
    K : optional
        As for :class:`Ce` (default symbol ``K_<path>``).
    amount : number, str or sympy expression, optional
        The fixed amount ``x`` (mol); a function of time :data:`bondgraph.t`
        is allowed.  Defaults to the positive symbol ``x_<path>``.
    temperature, gas_constant : optional, keyword only

    Examples
    --------
    >>> Chemostat("S", K=1, amount=2).value
    R_gas*T*log(2)
    >>> Chemostat("S").label()          # BondGraphs.jl's name for a chemostat
    'SCe:S'
    """

    K: ParameterLike = field(default=None, kw_only=True)
    amount: ParameterLike = field(default=None, kw_only=True)
    temperature: ParameterLike = field(default=None, kw_only=True)
    gas_constant: ParameterLike = field(default=None, kw_only=True)
    kind: ClassVar[str] = "SCe"

    def __post_init__(self) -> None:
        object.__setattr__(self, "value", self._potential(self.name))
        super().__post_init__()

    @property
    def K_value(self) -> sympy.Expr:
        """``K``, or the default symbol ``K_<name>``."""
        return _positive(self.K, sympy.Symbol(f"K_{self.name}", positive=True),
                         owner=f"Ce:{self.name} (chemostat)", what="K")

    def value_rules(self) -> tuple:
        """``K`` positive, the amount not negative, ``R_gas`` and ``T`` positive."""
        path = self.name
        k = _positive(self.K, sympy.Symbol(f"K_{path}", positive=True),
                      owner=f"Ce:{path} (chemostat)", what="K")
        x = to_expr(self.amount, owner=f"Ce:{path} (chemostat)", what="amount")
        if x is None:
            x = sympy.Symbol(f"x_{path}", positive=True)
        return (rule(k, "thermodynamic constant", opt_out=False) +
                rule(x, "amount", "nonnegative", opt_out=False) + _thermo_rules(self))

    def _potential(self, path: str) -> sympy.Expr:
        owner = f"Ce:{self.name} (chemostat)"
        k = _positive(self.K, sympy.Symbol(f"K_{path}", positive=True), owner=owner, what="K")
        x = nonzero(to_expr(self.amount, owner=owner, what="amount"), owner=owner, what="amount")
        if x is None:
            x = sympy.Symbol(f"x_{path}", positive=True)
        elif any(isinstance(s, Signal) for s in x.free_symbols):
            raise ParameterError(f"{owner}: amount {x} must be a parameter or a function of time")
        return _rt(self) * sympy.log(k * x)

    def resolved(self, path: str) -> Element:
        el = rename(self, path)
        object.__setattr__(el, "value", self._potential(path))
        return el

    def fixed_domains(self, into) -> dict[int, str]:
        return {0: "chemical"}

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "chemostat"


@dataclass(frozen=True, eq=False)
class Flowstat(Sf):
    """A species whose net molar flow is prescribed (mol/s): a flow source.

    With no ``value`` the flow is a model input named after the element.

    Examples
    --------
    >>> Flowstat("Cl", value=0).label(), Flowstat("Cl").drawing_label()
    ('SfCe:Cl', ('SfCe:Cl', 'flowstat'))
    """

    kind: ClassVar[str] = "SfCe"

    def fixed_domains(self, into) -> dict[int, str]:
        return {0: "chemical"}

    def drawing_label(self) -> tuple[str, str]:
        return self.label(), "flowstat"
