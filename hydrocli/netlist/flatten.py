"""A machine written with includes and template instances, as one flat document.

Tools that EDIT a machine component by component (the diagnosis adds a hose between a valve
and its chamber, re-types a valve, frees a parameter on a log scale) need every component as
a mapping of its own in the main document. A template instance's components exist only after
expansion (``outer.valve`` of a ``jib_circuit`` instance) and an included file's components
live in another file, so such edits have nowhere to go. :func:`flat_doc` writes the machine
the loader sees: includes merged (the including file's entries win), every template instance
expanded into top-level components named ``instance.component`` with their overrides applied
and their inner nodes renamed (``outer.p1``), the templates and includes dropped. The machine
it describes is the same one: same components, parameters, nodes, inputs, outputs and
initial values (tested on the knuckle-boom crane).
"""
from __future__ import annotations

import copy

from ruamel.yaml.comments import CommentedMap

from ..errors import ProblemCollector
from .loader import merged_sections
from .model import Netlist
from .templates import expand_templates


def is_flat(net: Netlist) -> bool:
    """No includes and no templates: every component is written in the main document."""
    doc = net.doc
    return doc is None or (not doc.get("include") and not doc.get("templates"))


def flat_doc(net: Netlist) -> CommentedMap:
    """``net``'s document with its includes merged and its template instances expanded (a copy;
    ``net`` must have loaded without problems)."""
    doc = net.doc
    sections = merged_sections(doc, net.file)
    flat = CommentedMap()
    for key in ("name", "description", "notes"):
        if key in doc:
            flat[key] = copy.deepcopy(doc[key])
    for key, value in sections.items():
        if key in ("templates", "components"):
            continue
        if isinstance(value, dict):
            flat[key] = CommentedMap((k, copy.deepcopy(v[0])) for k, v in value.items())
        else:
            flat[key] = copy.deepcopy(value)
    comps = CommentedMap()
    for name, src in expand_templates(sections.get("components"), sections.get("templates"), ProblemCollector()).items():
        comps[name] = copy.deepcopy(src.cmap)
    flat["components"] = comps
    return flat
