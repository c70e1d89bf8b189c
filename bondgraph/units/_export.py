"""``.mat`` and JSON plants that carry the units of their states, inputs and outputs.

The formats are those of :mod:`bondgraph.export`, with three more ``.mat``
variables (``state_units``, ``input_units``, ``output_units``: cell arrays of
unit texts, ``''`` where unknown) and the optional JSON key ``"units"``
(signal name -> unit text), which :func:`bondgraph.export.load_json` accepts.

Examples
--------
>>> import tempfile, os, scipy.io
>>> from bondgraph.numeric import NumericStateSpace
>>> from bondgraph.units._dims import unit_dims
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

from typing import Mapping, Sequence

from ..export import ExportError, _cell, _check_exportable, _check_plant, _json_text, _mat_dict, to_json_dict
from .._support.files import PathLike, atomic_write
from ..numeric import NumericStateSpace
from ._dims import Dim, text

__all__ = ["export_mat_with_units", "export_json_with_units"]


def _texts(names: Sequence[str], dims: Mapping[str, Dim]) -> list[str]:
    return [text(dims[n]) if n in dims else "" for n in names]


def export_mat_with_units(plant: NumericStateSpace, path: PathLike, dims: Mapping[str, Dim]) -> None:
    """:func:`bondgraph.export.export_mat` plus the units of the plant's signals.

    ``dims`` is :func:`bondgraph.units.model_units`'s mapping.
    """
    _check_exportable(plant)
    import scipy.io

    p = _check_plant(plant)
    data = _mat_dict(p)
    data["state_units"] = _cell(_texts(p.state_names, dims))
    data["input_units"] = _cell(_texts(p.input_names, dims))
    data["output_units"] = _cell(_texts(p.output_names, dims))
    atomic_write(path, lambda fh: scipy.io.savemat(fh, data, format="5", long_field_names=False,
                                                   do_compression=False, oned_as="row"))


def export_json_with_units(plant: NumericStateSpace, path: PathLike,
                           dims: Mapping[str, Dim]) -> None:
    """:func:`bondgraph.export.export_json` with the ``"units"`` key."""
    _check_exportable(plant)
    doc = to_json_dict(plant)
    names = [*doc["states"], *doc["inputs"], *doc["outputs"]]
    doc["units"] = {n: text(dims[n]) for n in names if n in dims}
    try:
        body = _json_text(doc)
    except ValueError as exc:        # NaN or infinity: JSON cannot hold them
        raise ExportError(f"cannot write '{path}': {exc}", path=str(path)) from exc
    atomic_write(path, lambda fh: fh.write(body), binary=False)
