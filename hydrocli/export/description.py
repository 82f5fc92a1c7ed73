"""modelDescription.xml for FMI 2.0 (model exchange and/or co-simulation) and FMI 3.0
(co-simulation), from an :class:`~hydrocli.export.variables.FmuLayout`.

FMI 2.0 §2.2 (ModelVariables, ModelStructure: Outputs, Derivatives, InitialUnknowns with
1-based indices into ModelVariables); FMI 3.0 §2.4 (Float64 variables, dependencies by
value reference). Numbers are written with ``repr`` so start values survive bit-exactly.
"""
from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from datetime import datetime, timezone

from .unitdefs import UnitTable
from .variables import FmuLayout, FmuVariable

_IDENT = r"[A-Za-z_][A-Za-z0-9_]*(\[[0-9]+(,[0-9]+)*\])?"
_STRUCTURED = re.compile(rf"^(der\()?{_IDENT}(\.{_IDENT})*\)?$")


@dataclass
class FmuInfo:
    model_name: str
    identifier: str
    guid: str
    description: str
    kinds: tuple[str, ...]          # ("cs",), ("me",) or ("me", "cs")
    tool: str
    rtol: float
    stop_time: float
    source_files: tuple[str, ...]


def _num(v: float) -> str:
    return repr(float(v))


def naming_convention(layout: FmuLayout) -> str:
    """"structured" when every name follows FMI's structured grammar, else "flat"."""
    return "structured" if all(_STRUCTURED.match(v.name) for v in layout.variables) else "flat"


def _unit_definitions(root: ET.Element, table: UnitTable) -> None:
    if not table.by_key:
        return
    ud = ET.SubElement(root, "UnitDefinitions")
    for d in sorted(table.by_key.values(), key=lambda d: d.name):
        u = ET.SubElement(ud, "Unit", name=d.name)
        if d.exponents is not None:
            ET.SubElement(u, "BaseUnit", {k: str(v) for k, v in d.exponents.items()})
        for name, (factor, offset) in sorted(d.display.items()):
            if name == d.name:
                continue
            attrs = {"name": name, "factor": _num(factor)}
            if offset:
                attrs["offset"] = _num(offset)
            ET.SubElement(u, "DisplayUnit", attrs)


def _units(layout: FmuLayout) -> tuple[UnitTable, dict[int, tuple[str, str | None]]]:
    table = UnitTable()
    keys = {v.vr: table.add(v.unit, v.display_unit) for v in layout.variables}
    out = {}
    for v in layout.variables:
        k = keys[v.vr]
        unit = table.resolve(k) if k != "" else ""
        out[v.vr] = (unit, v.display_unit if table.has_display(k, v.display_unit) and v.display_unit != unit else None)
    return table, out


def _type_attrs(v: FmuVariable, unit: str, display: str | None) -> dict[str, str]:
    a: dict[str, str] = {}
    if unit:
        a["unit"] = unit
    if display:
        a["displayUnit"] = display
    if v.start is not None:
        a["start"] = _num(v.start)
    if v.min is not None:
        a["min"] = _num(v.min)
    if v.max is not None:
        a["max"] = _num(v.max)
    if v.nominal is not None and v.nominal > 0:
        a["nominal"] = _num(v.nominal)
    return a


def _root_attrs(info: FmuInfo, layout: FmuLayout, version: str) -> dict[str, str]:
    a = {"fmiVersion": version, "modelName": info.model_name,
         ("instantiationToken" if version.startswith("3") else "guid"): info.guid,
         "description": info.description, "generationTool": info.tool,
         "generationDateAndTime": datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
         "variableNamingConvention": naming_convention(layout)}
    if version == "2.0":
        a["numberOfEventIndicators"] = "0"
    return a


def _common_tail(root: ET.Element, info: FmuInfo) -> None:
    cats = ET.SubElement(root, "LogCategories")
    for name, text in (("logStatusError", "errors (model guard messages, solver failures)"),
                       ("logStatusWarning", "warnings")):
        ET.SubElement(cats, "Category", name=name, description=text)
    ET.SubElement(root, "DefaultExperiment", startTime="0.0", stopTime=_num(info.stop_time),
                  tolerance=_num(info.rtol))


def model_description_fmi2(layout: FmuLayout, info: FmuInfo) -> str:
    root = ET.Element("fmiModelDescription", _root_attrs(info, layout, "2.0"))
    flags = {"canGetAndSetFMUstate": "true", "canSerializeFMUstate": "true",
             "providesDirectionalDerivative": "true"}
    if "me" in info.kinds:
        me = ET.SubElement(root, "ModelExchange", modelIdentifier=info.identifier,
                           completedIntegratorStepNotNeeded="true", **flags)
        _source_files(me, info)
    if "cs" in info.kinds:
        cs = ET.SubElement(root, "CoSimulation", modelIdentifier=info.identifier,
                           canHandleVariableCommunicationStepSize="true", canInterpolateInputs="true",
                           maxOutputDerivativeOrder="0", **flags)
        _source_files(cs, info)
    table, units = _units(layout)
    _unit_definitions(root, table)
    _common_tail(root, info)
    mv = ET.SubElement(root, "ModelVariables")
    index = {}
    for k, v in enumerate(layout.variables):
        index[v.vr] = k + 1
        attrs = {"name": v.name, "valueReference": str(v.vr), "causality": v.causality,
                 "variability": v.variability}
        if v.description:
            attrs["description"] = v.description
        if v.initial and v.causality != "input":
            attrs["initial"] = v.initial
        sv = ET.SubElement(mv, "ScalarVariable", attrs)
        ta = _type_attrs(v, *units[v.vr])
        if v.derivative_of is not None:
            ta["derivative"] = str(index[v.derivative_of])
        ET.SubElement(sv, "Real", ta)
    ms = ET.SubElement(root, "ModelStructure")
    for tag, vrs in (("Outputs", layout.outputs), ("Derivatives", layout.derivatives)):
        if vrs:
            el = ET.SubElement(ms, tag)
            for vr in vrs:
                ET.SubElement(el, "Unknown", index=str(index[vr]),
                              dependencies=" ".join(str(index[d]) for d in layout.dependencies[vr]))
    initial = sorted(layout.outputs + layout.derivatives, key=lambda vr: index[vr])
    if initial:
        el = ET.SubElement(ms, "InitialUnknowns")
        for vr in initial:
            ET.SubElement(el, "Unknown", index=str(index[vr]))
    return _text(root)


def _source_files(parent: ET.Element, info: FmuInfo) -> None:
    sf = ET.SubElement(parent, "SourceFiles")
    for f in info.source_files:
        ET.SubElement(sf, "File", name=f)


def model_description_fmi3(layout: FmuLayout, info: FmuInfo) -> str:
    """FMI 3.0 co-simulation (the FMU integrates with its own Rosenbrock solver)."""
    root = ET.Element("fmiModelDescription", _root_attrs(info, layout, "3.0"))
    ET.SubElement(root, "CoSimulation", modelIdentifier=info.identifier,
                  canHandleVariableCommunicationStepSize="true", canGetAndSetFMUState="true",
                  canSerializeFMUState="true", providesDirectionalDerivatives="false",
                  canReturnEarlyAfterIntermediateUpdate="false", hasEventMode="false",
                  providesIntermediateUpdate="false")
    table, units = _units(layout)
    _unit_definitions(root, table)
    _common_tail(root, info)
    mv = ET.SubElement(root, "ModelVariables")
    # FMI 3.0 requires the independent variable
    ET.SubElement(mv, "Float64", name="time", valueReference=str(_time_vr(layout)),
                  causality="independent", variability="continuous", description="simulation time")
    for v in layout.variables:
        attrs = {"name": v.name, "valueReference": str(v.vr), "causality": v.causality,
                 "variability": v.variability}
        if v.description:
            attrs["description"] = v.description
        if v.initial and v.causality != "input":
            attrs["initial"] = v.initial
        attrs.update(_type_attrs(v, *units[v.vr]))
        if v.derivative_of is not None:
            attrs["derivative"] = str(v.derivative_of)
        ET.SubElement(mv, "Float64", attrs)
    ms = ET.SubElement(root, "ModelStructure")
    for vr in layout.outputs:
        ET.SubElement(ms, "Output", valueReference=str(vr),
                      dependencies=" ".join(str(d) for d in layout.dependencies[vr]))
    for vr in layout.derivatives:
        ET.SubElement(ms, "ContinuousStateDerivative", valueReference=str(vr),
                      dependencies=" ".join(str(d) for d in layout.dependencies[vr]))
    for vr in sorted(layout.outputs + layout.derivatives):
        ET.SubElement(ms, "InitialUnknown", valueReference=str(vr))
    return _text(root)


def _time_vr(layout: FmuLayout) -> int:
    return max((v.vr for v in layout.variables), default=-1) + 1


def _text(root: ET.Element) -> str:
    ET.indent(root, space="  ")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
