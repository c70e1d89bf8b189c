"""Electrical components: effort voltage (V), flow current (A).

Two-terminal components (:class:`Resistor`, :class:`Capacitor`,
:class:`Inductor`) put their element on a 1-junction between ports ``p``
(current in) and ``n`` (current out): the current is common, the voltage
across is ``v_p - v_n``.  In the parent graph the circuit's nodes are
0-junctions; the reference node is a :class:`Ground` (or is left out, the
usual bond-graph simplification).  Laws: Ohm's law and the ideal capacitor
and inductor (Karnopp, Margolis and Rosenberg, *System Dynamics*, 5th ed.,
Ch. 4; 20-sim's and Modelica's ``Electrical.Analog.Basic`` library).

Examples
--------
An RC low-pass, ``v_C/v_s = 1/(R C s + 1)``:

>>> import bondgraph as bg
>>> g = bg.BondGraph("rc")
>>> g.add(VoltageSource("vs"), Resistor("R1", resistance="R"), Capacitor("C1", capacitance="C"),
...       Ground("gnd"), bg.Zero("n1"), bg.Zero("n2"), bg.Zero("n0"))
>>> for t, h in [("vs.p", "n1"), ("n1", "R1.p"), ("R1.n", "n2"), ("n2", "C1.p"), ("C1.n", "n0"),
...              ("n0", "gnd.p")]:
...     _ = g.connect(t, h)
>>> bg.derive(g, outputs={"vC": bg.effort("C1.C")}).transfer_function(normalize="leading-one-denominator").expr
1/(C*R*s + 1)
"""

from __future__ import annotations

from typing import ClassVar

from ..elements import C, I, One, Port, R, Se, Sf, TF
from .._support.sympify import ParameterLike
from ._component import Component, SourceComponent

__all__ = ["Resistor", "Capacitor", "Inductor", "VoltageSource", "CurrentSource", "Ground",
           "Transformer"]

_KMR = "Karnopp, Margolis and Rosenberg, System Dynamics, 5th ed., Ch. 4"


class _TwoTerminal(Component):
    domain: ClassVar[str] = "electrical"
    port_names: tuple[str, ...] = ("p", "n")
    port_domains = {"p": "electrical", "n": "electrical"}
    reference: ClassVar[str] = _KMR

    def __init__(self, name: str, value: ParameterLike, what: str) -> None:
        self._value, self._what = value, what
        super().__init__(name)

    def element(self, value):
        raise NotImplementedError

    def build(self) -> None:
        el = self.element(self.param(self._value, self._what))
        self.add(Port("p"), Port("n"), One("i"), el)
        self.connect("p", "i")
        self.connect("i", "n")
        self.connect("i", el.name)


class Resistor(_TwoTerminal):
    """A resistor, ``v_p - v_n = R i`` (Ohm's law).

    Parameters
    ----------
    name : str
    resistance : optional, keyword only
        ``R`` (ohm); default symbol ``<name>_resistance``.

    Examples
    --------
    >>> Resistor("R1", resistance=10)["R"].parameter
    10
    """

    law = "v_p - v_n = R i"
    symbol = "R"

    def __init__(self, name: str, *, resistance: ParameterLike = None) -> None:
        super().__init__(name, resistance, "resistance")

    def element(self, value):
        return R("R", value)


class Capacitor(_TwoTerminal):
    """A capacitor, ``v_p - v_n = q/C``, ``dq/dt = i``; its state is the charge ``q_<name>.C``.

    Examples
    --------
    >>> Capacitor("C1", capacitance=1e-6).ports
    ('p', 'n')
    """

    law = "v_p - v_n = q / C,  dq/dt = i"
    symbol = "C"

    def __init__(self, name: str, *, capacitance: ParameterLike = None) -> None:
        super().__init__(name, capacitance, "capacitance")

    def element(self, value):
        return C("C", value)


class Inductor(_TwoTerminal):
    """An inductor, ``i = lambda/L``, ``d lambda/dt = v_p - v_n``; state the flux ``p_<name>.L``.

    Examples
    --------
    >>> Inductor("L1", inductance=0.2)["L"].parameter
    0.200000000000000
    """

    law = "i = lambda / L,  d lambda/dt = v_p - v_n"
    symbol = "I"

    def __init__(self, name: str, *, inductance: ParameterLike = None) -> None:
        super().__init__(name, inductance, "inductance")

    def element(self, value):
        return I("L", value)


class VoltageSource(SourceComponent):
    """An ideal voltage source at port ``p``: the input ``v`` (named ``<name>.v`` in the
    model's inputs), or ``value``.

    Examples
    --------
    >>> VoltageSource("vs").ports
    ('p',)
    """

    domain = "electrical"
    port_domains = {"p": "electrical"}
    law = "v = v_s (an effort source)"
    reference = _KMR
    symbol = "Se"
    source = Se
    inner = "v"


class CurrentSource(SourceComponent):
    """An ideal current source out of port ``p``: the input ``i``, or ``value``.

    Examples
    --------
    >>> CurrentSource("src", value=0.1)["i"].value
    0.100000000000000
    """

    domain = "electrical"
    port_domains = {"p": "electrical"}
    law = "i = i_s (a flow source)"
    reference = _KMR
    symbol = "Sf"
    source = Sf
    inner = "i"


class Ground(Component):
    """The reference node: zero voltage at port ``p`` (an ``Se`` of value 0).

    Connect the ground node's 0-junction to ``p`` (the bond pointing into the
    ground), or leave the node out entirely.

    Examples
    --------
    >>> Ground("gnd")["v0"].value
    0
    """

    domain = "electrical"
    port_names = ("p",)
    port_domains = {"p": "electrical"}
    law = "v = 0"
    reference = _KMR
    symbol = "Se:0"

    def build(self) -> None:
        self.add(Se("v0", value=0), Port("p"))
        self.connect("p", "v0")


class Transformer(Component):
    """An ideal transformer of turns ratio ``N = n_a : n_b``: ``v_a = N v_b``, ``i_b = N i_a``.

    Port ``a`` is the primary (power in), ``b`` the secondary (a ``TF`` of
    modulus ``N``; Karnopp et al., Sec. 4.3).

    Examples
    --------
    >>> Transformer("T1", ratio=10)["N"].modulus
    10
    """

    domain = "electrical"
    port_names = ("a", "b")
    port_domains = {"a": "electrical", "b": "electrical"}
    law = "v_a = N v_b,  i_b = N i_a"
    reference = _KMR + ", Sec. 4.3"
    symbol = "TF"

    def __init__(self, name: str, *, ratio: ParameterLike = None) -> None:
        self._ratio = ratio
        super().__init__(name)

    def build(self) -> None:
        self.add(Port("a"), Port("b"), TF("N", self.param(self._ratio, "ratio")))
        self.connect("a", "N")
        self.connect("N", "b")
