"""Templates (sub-circuits): a group of components written once and instantiated many times.

```yaml
templates:
  jib_circuit:
    ports: [P, T, rod, base, cmd]          # the template's external nodes
    components:
      valve: {type: valve_4_3, ports: {P: P, T: T, A: a, B: b, cmd: cmd}}
      cyl:   {type: cylinder, ports: {A: a, B: b, rod: rod, body: base}}
components:
  outer:
    template: jib_circuit
    ports: {P: supply, T: tank, rod: outer_tip, base: ground, cmd: u_outer}
    valve.Kv: "40 L/min/bar^0.5"           # overrides, by inner component.parameter
```
expands to components ``outer.valve`` and ``outer.cyl`` with inner nodes ``outer.a``,
``outer.b``; ``ground`` stays the global reference.
"""
from __future__ import annotations

import copy

from ..components.registry import suggest
from ..errors import ProblemCollector
from . import yamldoc as Y

INSTANCE_KEYS = ("template", "ports", "description")
GLOBAL_NODES = ("ground",)


def expand_templates(components, templates, errs: ProblemCollector, depth: int = 0) -> dict:
    """{name: (component map, file, yaml path)} with every template instance flattened."""
    out: dict = {}
    if not isinstance(components, dict):
        return out
    tdefs = templates if isinstance(templates, dict) else {}
    for name, (cmap, parent, file) in components.items():
        ypath = f"components.{name}"
        if Y.is_map(cmap) and "template" in cmap:
            _expand_one(str(name), cmap, file, ypath, tdefs, errs, out, depth)
        else:
            out[str(name)] = (cmap, file, ypath)
    return out


def _expand_one(inst, cmap, file, ypath, tdefs, errs, out, depth) -> None:
    tname = str(cmap["template"])
    if depth > 8:
        errs.add(f"templates nested too deeply at '{inst}'", Y.node_loc(cmap, file, ypath),
                 "a template must not instantiate itself")
        return
    if tname not in tdefs:
        errs.add(f"unknown template '{tname}'{suggest(tname, tdefs)}", Y.value_loc(cmap, "template", file, ypath),
                 "define it under 'templates:'")
        return
    tdef, _, tfile = tdefs[tname]
    if not Y.is_map(tdef) or not Y.is_map(tdef.get("components")):
        errs.add(f"template '{tname}' needs 'ports:' (a list) and 'components:' (a mapping)",
                 Y.node_loc(tdef, tfile, f"templates.{tname}"))
        return
    external = [str(p) for p in (tdef.get("ports") or [])]
    pmap = cmap.get("ports") or {}
    for p in pmap:
        if str(p) not in external:
            errs.add(f"template '{tname}' has no port '{p}'{suggest(str(p), external)}",
                     Y.key_loc(pmap, p, file, f"{ypath}.ports.{p}"), f"its ports: {', '.join(external)}")
    for p in external:
        if p not in pmap:
            errs.add(f"port '{p}' of template instance '{inst}' is not connected", Y.node_loc(cmap, file, ypath),
                     f"add '{p}: <node>' under ports")

    def rename(node: str) -> str:
        if node in pmap:
            return str(pmap[node])
        if node in GLOBAL_NODES:
            return node
        return f"{inst}.{node}"

    overrides = {}
    for k, v in cmap.items():
        if k in INSTANCE_KEYS:
            continue
        inner, _, pname = str(k).rpartition(".")
        if not inner:
            errs.add(f"'{k}' in template instance '{inst}' must be written <component>.<parameter>",
                     Y.key_loc(cmap, k, file, f"{ypath}.{k}"), "e.g. valve.Kv: 1e-6")
            continue
        overrides.setdefault(inner, []).append((pname, v, k))
    inner_comps = tdef["components"]
    for inner in overrides:
        if inner not in inner_comps:
            errs.add(f"template '{tname}' has no component '{inner}'{suggest(inner, inner_comps)}",
                     Y.key_loc(cmap, overrides[inner][0][2], file, ypath))
    nested = {}
    for cname, cdef in inner_comps.items():
        if not Y.is_map(cdef):
            errs.add(f"component '{cname}' of template '{tname}' must be a mapping",
                     Y.key_loc(inner_comps, cname, tfile))
            continue
        clone = copy.deepcopy(cdef)
        ports = clone.get("ports")
        if Y.is_map(ports):
            for port in list(ports):
                if isinstance(ports[port], str):
                    ports[port] = rename(ports[port])
        if Y.is_map(clone.get("ports")) and "template" in clone:
            pass
        for pname, v, _ in overrides.get(str(cname), []):
            clone[pname] = v
        full = f"{inst}.{cname}"
        nested[full] = (clone, None, tfile)
    out.update(expand_templates(nested, tdefs, errs, depth + 1))
