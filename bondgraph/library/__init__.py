"""Component libraries: domains' elements and sub-models with named ports.

Not imported by ``import bondgraph``: import the domain you need,
``from bondgraph.library import chemical``.

* :mod:`~bondgraph.library.chemical` -- ``Ce``, ``Re``, chemostats, the
  reaction-network builder, stoichiometric matrix and conservation laws.
"""

__all__: list[str] = []
