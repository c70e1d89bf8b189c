"""``modelDescription.xml`` (FMI 2.0 and 3.0) and ``buildDescription.xml`` (FMI 3.0), private.

Built with :mod:`xml.etree.ElementTree`: names reach the XML only as
attribute values, which ElementTree escapes (``"``, ``<``, ``&``, ``>``,
newlines); what XML cannot hold at all was escaped by the plan
(:func:`~bondgraph.fmu._plan.xml_text`, :func:`~bondgraph.fmu._plan.fmi_name`).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Optional, Sequence

from ._plan import Plan, Unknown, Variable, xml_text

__all__ = ["model_description", "build_description"]


def _num(value: float) -> str:
    return repr(float(value))


def _tree(root: ET.Element) -> bytes:
    ET.indent(root, space="  ")
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True) + b"\n"


def _root(plan: Plan, fmi: int, token: str, generator: str) -> ET.Element:
    attrs = {"fmiVersion": "2.0" if fmi == 2 else "3.0",
             "modelName": xml_text(plan.model_name),
             ("guid" if fmi == 2 else "instantiationToken"): token,
             "description": xml_text(f"bond-graph model {plan.model_name}: {plan.n_states} states, "
                                     f"{plan.n_inputs} inputs, {plan.n_outputs} outputs"),
             "generationTool": generator,
             "variableNamingConvention": "flat"}
    if fmi == 2:
        attrs["numberOfEventIndicators"] = str(len(plan.indicators))
    return ET.Element("fmiModelDescription", attrs)


def _interfaces(root: ET.Element, plan: Plan, fmi: int, sources: Sequence[str]) -> None:
    state = "FMUstate" if fmi == 2 else "FMUState"
    common = {"modelIdentifier": plan.identifier, f"canGetAndSet{state}": "true",
              f"canSerialize{state}": "true"}
    if fmi == 2:
        common["canNotUseMemoryManagementFunctions"] = "true"
    specific = {"ModelExchange": {"completedIntegratorStepNotNeeded": "true"} if fmi == 2
                else {"needsCompletedIntegratorStep": "false"},
                "CoSimulation": {"canHandleVariableCommunicationStepSize": "true"}}
    for tag, wanted in (("ModelExchange", plan.me), ("CoSimulation", plan.cs)):
        if not wanted:
            continue
        el = ET.SubElement(root, tag, {**common, **specific[tag]})
        if fmi == 2:   # FMI 3 lists the sources in sources/buildDescription.xml
            files = ET.SubElement(el, "SourceFiles")
            for name in sources:
                ET.SubElement(files, "File", {"name": name})
    cats = ET.SubElement(root, "LogCategories")
    ET.SubElement(cats, "Category", {"name": "logStatusError", "description": "errors"})
    ET.SubElement(cats, "Category", {"name": "logAll", "description": "every message"})
    if plan.experiment is not None:
        e = plan.experiment
        ET.SubElement(root, "DefaultExperiment", {"startTime": _num(e.start), "stopTime": _num(e.stop),
                                                  "tolerance": _num(e.tolerance), "stepSize": _num(e.step)})


def _attributes(v: Variable, fmi: int) -> dict[str, str]:
    attrs = {"name": v.name, "valueReference": str(v.vr), "description": xml_text(v.description),
             "causality": v.causality, "variability": v.variability}
    if v.initial is not None and v.causality != "input":
        attrs["initial"] = v.initial
    return attrs


def _type_attributes(v: Variable, fmi: int) -> dict[str, str]:
    out = {}
    if v.start is not None:
        out["start"] = _num(v.start)
    if v.nominal is not None:
        out["nominal"] = _num(v.nominal)
    if v.derivative_of is not None:
        out["derivative"] = str(v.derivative_of + 1 if fmi == 2 else v.derivative_of)
    return out


def _variables(root: ET.Element, plan: Plan, fmi: int) -> None:
    box = ET.SubElement(root, "ModelVariables")
    for v in plan.variables:
        if fmi == 2:
            sv = ET.SubElement(box, "ScalarVariable", _attributes(v, fmi))
            ET.SubElement(sv, "Real", _type_attributes(v, fmi))
        else:
            ET.SubElement(box, "Float64", {**_attributes(v, fmi), **_type_attributes(v, fmi)})


def _unknown(parent: ET.Element, tag: str, u: Unknown, fmi: int) -> None:
    # FMI 2 names variables by index (value reference + 1), FMI 3 by value reference
    shift = 1 if fmi == 2 else 0
    attrs = {"index" if fmi == 2 else "valueReference": str(u.vr + shift),
             "dependencies": " ".join(str(d + shift) for d in u.dependencies)}
    if u.kinds is not None and u.dependencies:
        attrs["dependenciesKind"] = " ".join(u.kinds)
    ET.SubElement(parent, tag, attrs)


def _structure(root: ET.Element, plan: Plan, fmi: int) -> None:
    box = ET.SubElement(root, "ModelStructure")
    groups: tuple[tuple[str, str, tuple[Unknown, ...]], ...] = (
        ("Outputs", "Output", plan.outputs), ("Derivatives", "ContinuousStateDerivative", plan.derivatives),
        ("InitialUnknowns", "InitialUnknown", plan.initial_unknowns))
    if fmi == 3:    # FMI 2 counts its event indicators in numberOfEventIndicators only
        groups += (("EventIndicators", "EventIndicator", plan.indicators),)
    for group, tag3, unknowns in groups:
        if fmi == 2:
            if unknowns:
                parent = ET.SubElement(box, group)
                for u in unknowns:
                    _unknown(parent, "Unknown", u, fmi)
        else:
            for u in unknowns:
                _unknown(box, tag3, u, fmi)


def model_description(plan: Plan, fmi: int, token: str, generator: str,
                      sources: Sequence[str] = ()) -> bytes:
    """The ``modelDescription.xml`` bytes (UTF-8) of an FMI ``fmi`` (2 or 3) FMU."""
    root = _root(plan, fmi, token, generator)
    _interfaces(root, plan, fmi, sources)
    _variables(root, plan, fmi)
    _structure(root, plan, fmi)
    return _tree(root)


def build_description(identifier: str, sources: Sequence[str],
                      definitions: Optional[dict[str, str]] = None) -> bytes:
    """FMI 3's ``sources/buildDescription.xml``: one C99 source-file set."""
    root = ET.Element("fmiBuildDescription", {"fmiVersion": "3.0"})
    config = ET.SubElement(root, "BuildConfiguration", {"modelIdentifier": identifier})
    files = ET.SubElement(config, "SourceFileSet", {"language": "C99"})
    for name in sources:
        ET.SubElement(files, "SourceFile", {"name": name})
    for key, value in (definitions or {}).items():
        ET.SubElement(files, "PreprocessorDefinition", {"name": key, "value": value})
    return _tree(root)
