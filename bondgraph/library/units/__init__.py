"""Physical domains and units: bond domains, unit-carrying values, a dimensional check.

Units are those of :mod:`sympy.physics.units` (not pint): the package's
parameters and constitutive laws are already sympy expressions, so the
dimensional check walks the very relations derivation uses, with no second
representation of the model and no new dependency; pint is made for numeric
arrays, which this check never needs.  Numbers carrying units are converted
to SI floats once (:func:`si_values`) and the rest of the pipeline stays
unit-free, so models without units work unchanged.

* Each bond gets a domain (:data:`DOMAINS`: effort and flow units),
  inferred by :func:`bond_domains` from elements that fix their own
  (chemical species, thermal elements), from library components' ports,
  and from the ``domains`` a user names, and propagated through everything
  but a ``TF``/``GY``/``RS`` (which may change domain: their moduli carry
  the ratio of units).
* :func:`check_units` evaluates every constitutive relation of the graph
  with each bond variable, state and input replaced by its dimension and
  each parameter by the unit of its value, and refuses the first relation
  whose dimension is wrong, naming the element, the parameter and both units.
  Relations touching a bond of unknown domain or a parameter given without
  units are not checked (they are counted in the report).
* :func:`model_units` gives the units of a derived model's states, inputs and
  outputs, :func:`plant_with_units` a numeric plant carrying them (kept by
  ``to_control()`` and the ``.mat``/JSON exports), :func:`fmu_with_units` an
  FMU whose modelDescription has them; a
  :class:`~bondgraph.modelfile.ModelDefinition` with unit-carrying parameters
  hands them to its plants and to the command line's tables and exports.

Examples
--------
>>> import bondgraph as bg, sympy.physics.units as u
>>> g = bg.BondGraph("msd")
>>> g.add(bg.Se("F"), bg.One("v"), bg.I("m"), bg.C("k", stiffness="k"), bg.R("b"))
>>> for t, h in [("F", "v"), ("v", "m"), ("v", "k"), ("v", "b")]: _ = g.connect(t, h)
>>> values = {"m": 2 * u.kilogram, "k": 3 * u.newton / u.millimeter,
...           "b": 4 * u.newton * u.second / u.meter}
>>> check_units(g, values, domains={"F": "translation"}).checked
8
>>> si_values(values)
{'m': 2.0, 'k': 3000.0, 'b': 4.0}
>>> check_units(g, dict(values, b=4 * u.newton / u.meter), domains={"F": "translation"})
Traceback (most recent call last):
...
bondgraph.library.units.check.UnitError: R:b, parameter b: its value has the unit newton/meter (newton/meter), but its translation bond 4 needs newton*second/meter (effort newton, flow meter/second)
"""

from .check import (DOMAINS, Domain, UnitError, UnitReport, bond_domains, check_units, si_values,
                    signal_units)
from ._fmu import export_fmu_with_units, fmu_with_units
from .signals import model_units, plant_with_units, ratio_text, unit_dims, unit_text
from ._export import export_json_with_units, export_mat_with_units

__all__ = ["Domain", "DOMAINS", "UnitError", "UnitReport", "bond_domains", "check_units",
           "si_values", "signal_units", "model_units", "plant_with_units", "unit_text",
           "ratio_text", "unit_dims", "fmu_with_units", "export_fmu_with_units",
           "export_mat_with_units", "export_json_with_units"]
