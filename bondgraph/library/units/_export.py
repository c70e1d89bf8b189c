"""``.mat`` and JSON plants that carry the units of their states, inputs and outputs.

The formats are those of :mod:`bondgraph.export` with its ``units=``
option: three more ``.mat`` variables (``state_units``, ``input_units``,
``output_units``: cell arrays of unit texts, ``''`` where unknown) and the
optional JSON key ``"units"`` (signal name -> unit text), which
:func:`bondgraph.export.load_json` accepts.

Examples
--------
>>> import tempfile, os, scipy.io
>>> from bondgraph.numeric import NumericStateSpace
>>> from bondgraph.library.units._dims import unit_dims
>>> import sympy.physics.units as u
>>> ss = NumericStateSpace([[-1.0]], [[1.0]], [[1.0]], [[0.0]], ("q",), ("V",), ("vC",), {}, "rc")
>>> dims = {"q": unit_dims(u.coulomb), "V": unit_dims(u.volt), "vC": unit_dims(u.volt)}
>>> with tempfile.TemporaryDirectory() as d:
...     export_mat_with_units(ss, os.path.join(d, "rc.mat"), dims)
...     m = scipy.io.loadmat(os.path.join(d, "rc.mat"))
>>> str(m["state_units"][0, 0][0]), str(m["output_units"][0, 0][0])
('coulomb', 'volt')
"""

from __future__ import annotations

from typing import Mapping

from ..._support.files import PathLike
from ...export import export_json, export_mat
from ...numeric import NumericStateSpace
from ._dims import Dim, text

__all__ = ["export_mat_with_units", "export_json_with_units"]


def export_mat_with_units(plant: NumericStateSpace, path: PathLike, dims: Mapping[str, Dim]) -> None:
    """:func:`bondgraph.export.export_mat` with the units of ``dims``
    (:func:`bondgraph.library.units.model_units`'s mapping)."""
    export_mat(plant, path, units={n: text(d) for n, d in dims.items()})


def export_json_with_units(plant: NumericStateSpace, path: PathLike,
                           dims: Mapping[str, Dim]) -> None:
    """:func:`bondgraph.export.export_json` with the ``"units"`` key."""
    export_json(plant, path, units={n: text(d) for n, d in dims.items()})
