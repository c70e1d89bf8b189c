"""Library components: sub-models with named ports, a law, a source and a drawing label.

A component is a :class:`~bondgraph.BondGraph` (so it is added to a parent
graph like any sub-model and its ports are connected as ``"name.port"``)
built by its constructor from keyword-only parameters.  Each class states:

* ``domain`` -- ``'electrical'``, ``'translation'``, ``'rotation'``,
  ``'hydraulic'``, ``'thermal'``, ``'thermal (entropy)'``, ``'chemical'`` or
  a pair joined by ``' -> '`` for a two-domain component;
* ``port_names`` and ``port_domains`` -- its ports, in order, and the domain of each;
* ``law`` -- its constitutive law in one line, and ``reference`` -- where
  the law comes from;
* ``symbol`` -- its drawing label (the text of its box in a catalogue).

Two-terminal components follow the iconic-diagram convention: power flows
into port ``a`` (or ``p``) and out of port ``b`` (or ``n``); for the
electrical, hydraulic and pseudo-thermal domains the element sits on a
1-junction (common flow through it, effort difference across it), for the
mechanical domains on a 0-junction (common force, velocity difference).
Connect the nodes of the parent graph (0-junctions of voltages, pressures
and temperatures; 1-junctions of velocities) to its ports.

A parameter not given defaults to the positive symbol ``<name>_<parameter>``
(``o1_Cd``); values are supplied at simulation time like any other.

Every concrete component class is listed in :data:`CATALOGUE`.

Examples
--------
>>> from bondgraph.library.electrical import Resistor
>>> r = Resistor("R1", resistance=10)
>>> r.ports, r.symbol, r.domain
(('p', 'n'), 'R', 'electrical')
"""

from __future__ import annotations

from typing import ClassVar, Mapping

import sympy

from ..elements import Port
from ..errors import ModelStructureError
from ..graph import BondGraph
from .._support.sympify import ParameterLike
from ._twoport import positive_parameter

__all__ = ["Component", "SourceComponent", "CATALOGUE", "components"]

#: every concrete component class, by its qualified name (``'hydraulic.Orifice'``)
CATALOGUE: dict[str, type["Component"]] = {}


class Component(BondGraph):
    """Base of the library's components (see the module docstring).

    Subclasses set the class variables and write :meth:`build`.
    """

    domain: ClassVar[str] = ""
    port_names: tuple[str, ...] = ()
    port_domains: ClassVar[Mapping[str, str]] = {}
    law: ClassVar[str] = ""
    reference: ClassVar[str] = ""
    symbol: ClassVar[str] = ""

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        if "law" in cls.__dict__:
            module = cls.__module__.rsplit(".", 1)[-1]
            CATALOGUE[f"{module}.{cls.__name__}"] = cls

    def __init__(self, name: str) -> None:
        super().__init__(name)
        self.build()
        if self.ports != self.port_names:       # a library bug, caught by its tests
            raise ModelStructureError(f"component {type(self).__name__} {name!r} exposes ports "
                                      f"{self.ports}; its class declares {self.port_names}")

    def build(self) -> None:
        """Add the elements, ports and bonds (called once by the constructor)."""
        raise NotImplementedError

    def param(self, value: ParameterLike, what: str) -> sympy.Expr:
        """A positive parameter, defaulting to the symbol ``<name>_<what>``."""
        return positive_parameter(value, sympy.Symbol(f"{self.name}_{what}", positive=True),
                                  owner=f"{type(self).__name__} {self.name!r}", what=what)


class SourceComponent(Component):
    """Base of the one-port sources: the source ``source(inner, value=value)`` at port ``p``.

    Subclasses set ``source`` (``Se`` or ``Sf``), ``inner`` (the source element's name,
    which names the model's input ``<name>.<inner>`` when no value is given) and the
    catalogue's class variables.

    Examples
    --------
    >>> from bondgraph.library.electrical import VoltageSource
    >>> VoltageSource("vs", value=5)["v"].value, VoltageSource("vs").ports
    (5, ('p',))
    """

    port_names: tuple[str, ...] = ("p",)
    source: ClassVar[type]
    inner: ClassVar[str]

    def __init__(self, name: str, *, value: ParameterLike = None) -> None:
        self._value = value
        super().__init__(name)

    def build(self) -> None:
        self.add(self.source(self.inner, value=self._value), Port("p"))
        self.connect(self.inner, "p")


def components(domain: str = "") -> tuple[type[Component], ...]:
    """The catalogue's component classes, optionally of one domain (its module name).

    Examples
    --------
    >>> import bondgraph.library.mechanical
    >>> "Gear" in [c.__name__ for c in components("mechanical")]
    True
    """
    return tuple(cls for key, cls in CATALOGUE.items() if not domain or
                 key.startswith(domain + "."))
