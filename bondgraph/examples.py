"""Stock bond graphs for examples and doctests (networkx's ``nx.path_graph(5)`` habit).

Each function returns a new, mutable :class:`~bondgraph.BondGraph` with
symbolic parameters named after the elements, so a docstring example starts
with one line and shows only its point.  The README and the user guide keep
the full constructions.

============================  =====================================================================
function                      graph
============================  =====================================================================
:func:`rc`                    ``Se:V`` -> 1 -> ``R:R``, ``C:C`` (series RC)
:func:`rl`                    ``Se:V`` -> 1 -> ``R:R``, ``I:L`` (series RL)
:func:`dc_motor`              ``Se:V`` -> 1 (``R:Ra``, ``I:La``) -> ``GY:K`` -> 1 (``I:J``, ``R:b``)
:func:`mass_spring_damper`    ``Se:F`` -> 1 -> ``I:m``, ``R:b``, ``C:k`` (stiffness ``k``)
:func:`free_mass`             ``Se:F`` -> ``I:m``
============================  =====================================================================

Examples
--------
>>> import bondgraph as bg
>>> from bondgraph import examples
>>> bg.derive(examples.rc()).rhs
((V - q_C/C)/R,)
>>> print(bg.derive(examples.dc_motor(), outputs={"omega": bg.flow("J")}))
model 'dc_motor': 2 states, 1 inputs, 1 outputs
  dp_La/dt = V - Ra*p_La/La - K*p_J/J
  dp_J/dt = K*p_La/La - b*p_J/J
  omega = p_J/J
"""

from __future__ import annotations

from .elements import GY, C, I, One, R, Se
from .graph import BondGraph

__all__ = ["rc", "rl", "dc_motor", "mass_spring_damper", "free_mass"]


def _chain(name: str, elements, bonds) -> BondGraph:
    g = BondGraph(name)
    g.add(*elements)
    for tail, head in bonds:
        g.connect(tail, head)
    return g


def rc() -> BondGraph:
    """Series RC circuit: voltage ``V`` across ``R`` and ``C`` (state ``q_C``).

    >>> sorted(el.name for el in rc().elements)
    ['C', 'R', 'V', 'i']
    """
    return _chain("rc", [Se("V"), One("i"), R("R"), C("C")], [("V", "i"), ("i", "R"), ("i", "C")])


def rl() -> BondGraph:
    """Series RL circuit: voltage ``V`` across ``R`` and ``L`` (state ``p_L``).

    >>> import bondgraph as bg
    >>> bg.derive(rl()).rhs
    (V - R*p_L/L,)
    """
    return _chain("rl", [Se("V"), One("i"), R("R"), I("L")], [("V", "i"), ("i", "R"), ("i", "L")])


def dc_motor() -> BondGraph:
    """Armature ``Ra, La``, torque constant ``K`` (a gyrator), rotor ``J``, friction ``b``.

    >>> import bondgraph as bg
    >>> bg.derive(dc_motor()).state_names
    ('p_La', 'p_J')
    """
    V, ia, w = Se("V"), One("ia"), One("w")
    return _chain("dc_motor", [V, ia, w, R("Ra"), I("La"), GY("K"), I("J"), R("b")],
                  [(V, ia), (ia, "Ra"), (ia, "La"), (ia, "K"), ("K", w), (w, "J"), (w, "b")])


def mass_spring_damper() -> BondGraph:
    """A force ``F`` on a mass ``m`` with a damper ``b`` and a spring of stiffness ``k``.

    >>> import bondgraph as bg
    >>> bg.derive(mass_spring_damper()).rhs
    (F - b*p_m/m - k*q_k, p_m/m)
    """
    v = One("v")
    return _chain("msd", [Se("F"), v, I("m"), R("b"), C("k", stiffness="k")],
                  [("F", v), (v, "m"), (v, "b"), (v, "k")])


def free_mass() -> BondGraph:
    """A force ``F`` on a free mass ``m``.

    >>> import bondgraph as bg
    >>> bg.derive(free_mass(), outputs={"v": bg.flow("m")}).equations
    (Eq(Derivative(p_m, t), F), Eq(v, p_m/m))
    """
    return _chain("mass", [Se("F"), I("m")], [("F", "m")])
