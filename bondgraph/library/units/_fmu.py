"""FMUs whose modelDescription carries the units of their variables.

:func:`model_units` (:mod:`bondgraph.library.units.signals`) gives the
dimension of every state, input, output and unit-carrying parameter of a
derived model; :func:`fmu_with_units` adds the
``unit`` attribute of each such variable (and of each state derivative) to
an FMU's ``modelDescription.xml``, with the ``UnitDefinitions`` (SI base-unit
exponents) FMI 2.0 and 3.0 define; :func:`export_fmu_with_units` does both
around :func:`bondgraph.fmu.build_fmu`.

Examples
--------
>>> import bondgraph as bg, sympy.physics.units as u
>>> g = bg.BondGraph("mass")
>>> g.add(bg.Se("F"), bg.I("m")); _ = g.connect("F", "m")
>>> model = bg.derive(g, outputs={"v": bg.flow("m")})
>>> {k: text(d) for k, d in model_units(model, g, {"m": 2 * u.kilogram},
...                                     domains={"F": "translation"}).items()}
{'p_m': 'kilogram*meter/second', 'F': 'newton', 'v': 'meter/second', 'm': 'kilogram'}
"""

from __future__ import annotations

import io
import os
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path
from typing import Any, Mapping, Optional, Union

import sympy

from ...graph import BondGraph
from ...model import Model

from ._dims import Dim, text
from .signals import model_units

__all__ = ["model_units", "fmu_with_units", "export_fmu_with_units"]

_BASE_ATTR = ("kg", "m", "s", "A", "K", "mol", "cd")


def _unit_definition(parent: ET.Element, name: str, d: Dim) -> bool:
    exps = d[:-1]
    if any(not sympy.Integer(x) == x for x in exps):
        return False          # FMI base-unit exponents are integers
    unit = ET.SubElement(parent, "Unit", {"name": name})
    attrs = {a: str(int(x)) for a, x in zip(_BASE_ATTR, exps) if x != 0}
    ET.SubElement(unit, "BaseUnit", attrs)
    return True


def fmu_with_units(data: bytes, dims: Mapping[str, Dim]) -> bytes:
    """The FMU archive ``data`` with ``unit`` attributes for the variables named in ``dims``.

    A state derivative ``der(x)`` gets the unit of ``x`` per second.  Every
    other file of the archive is copied unchanged (the instantiation token
    does not cover the ``unit`` attributes).
    """
    src = zipfile.ZipFile(io.BytesIO(data))
    root = ET.fromstring(src.read("modelDescription.xml"))
    fmi2 = root.get("fmiVersion", "").startswith("2")
    want: dict[str, Dim] = dict(dims)
    for name, d in dims.items():
        want[f"der({name})"] = tuple(x - (1 if i == 2 else 0) for i, x in enumerate(d))
    names: dict[str, Dim] = {}
    variables = root.find("ModelVariables")
    for var in (variables if variables is not None else []):
        name = var.get("name", "")
        if name in want:
            target = var.find("Real") if fmi2 else var
            if target is not None:
                names[text(want[name])] = want[name]
                target.set("unit", text(want[name]))
    if names:
        defs = ET.Element("UnitDefinitions")
        kept = [n for n, d in sorted(names.items()) if _unit_definition(defs, n, d)]
        for var in (variables if variables is not None else []):
            target = var.find("Real") if fmi2 else var
            if target is not None and target.get("unit") not in (None, *kept):
                del target.attrib["unit"]
        tags = [c.tag for c in root]
        at = max((i + 1 for i, t in enumerate(tags) if t in ("ModelExchange", "CoSimulation")),
                 default=0)
        root.insert(at, defs)
    ET.indent(root, space="  ")
    xml = ET.tostring(root, encoding="UTF-8", xml_declaration=True) + b"\n"
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            dst.writestr(info, xml if info.filename == "modelDescription.xml" else src.read(info))
    return out.getvalue()


def export_fmu_with_units(model: Model, path: Union[str, "os.PathLike[str]"], *, graph: BondGraph,
                          values: Mapping[str, Any], domains: Optional[Mapping] = None,
                          fmi: int = 2, kind: str = "both", step: Optional[float] = None,
                          binary: bool = True, cc: Optional[str] = None) -> Path:
    """:func:`bondgraph.fmu.export_fmu` of ``model`` with unit-carrying ``values`` and units.

    ``fmi``, ``kind``, ``step``, ``binary`` and ``cc`` are those of
    :func:`bondgraph.fmu.build_fmu`; ``graph`` and ``domains`` those of
    :func:`bondgraph.library.units.check_units`.  The file is written all or nothing.
    """
    from ..._support.files import atomic_write
    from ...fmu import FMUError, build_fmu
    from .check import si_values

    p = Path(os.fspath(path))
    if p.suffix.lower() != ".fmu":
        raise FMUError(f"FMU output '{p}' must end in .fmu")
    dims = model_units(model, graph, values, domains=domains)
    data = fmu_with_units(build_fmu(model, values=si_values(values), fmi=fmi, kind=kind, step=step,
                                    binary=binary, cc=cc), dims)
    atomic_write(p, lambda fh: fh.write(data), binary=True)
    return p
