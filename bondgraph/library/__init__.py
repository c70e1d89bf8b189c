"""Component libraries: each domain's elements and sub-models with named ports.

Not imported by ``import bondgraph``: import the domain you need, e.g.
``from bondgraph.library import hydraulic``.

* :mod:`~bondgraph.library.chemical` -- ``Ce``, ``Re``, chemostats and
  flowstats, the reaction-network builder, the stoichiometric matrix and the
  conservation laws;
* :mod:`~bondgraph.library.thermal` -- pseudo bond graphs (heat capacity,
  conduction, convection, radiation, sources) and true thermal ones (entropy
  store, conduction with entropy production, the ``RS`` element);
* :mod:`~bondgraph.library.electrical`, :mod:`~bondgraph.library.mechanical`,
  :mod:`~bondgraph.library.hydraulic`, :mod:`~bondgraph.library.electromechanical`
  -- components (:class:`~bondgraph.library._component.Component`) with a
  law, a source, named ports and a drawing label;
* :mod:`~bondgraph.library.catalogue` -- the sub-model check and the
  documentation's catalogue page;
* :mod:`~bondgraph.library.units` -- physical domains of bonds, unit-carrying values,
  the dimensional check, and units in FMU, ``.mat`` and JSON exports.

Examples
--------
>>> from bondgraph.library.catalogue import load_all
>>> "hydraulic.Orifice" in load_all()
True
"""

__all__: list[str] = []
