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
from dataclasses import dataclass, field

from ..suggest import suggest
from ..errors import Location, ProblemCollector
from . import yamldoc as Y

INSTANCE_KEYS = ("template", "ports", "description")
TEMPLATE_KEYS = ("ports", "components", "description")
GLOBAL_NODES = ("ground",)
MAX_DEPTH = 8
MAX_COMPONENTS = 5_000   # components after template expansion (a self-nesting template grows fast)


@dataclass
class CompSource:
    """Where a (possibly expanded) component's mapping came from, for located messages.

    ``key_locs`` holds the locations of template-instance overrides, which sit in the
    instance's file rather than in the template's."""

    cmap: object
    file: str
    ypath: str
    key_locs: dict[str, Location] = field(default_factory=dict)
    instance: str | None = None

    def key_loc(self, key, ypath: str | None = None) -> Location:
        if str(key) in self.key_locs:
            return self.key_locs[str(key)]
        return Y.key_loc(self.cmap, key, self.file, ypath or f"{self.ypath}.{key}")

    def value_loc(self, key, ypath: str | None = None) -> Location:
        if str(key) in self.key_locs:
            return self.key_locs[str(key)]
        return Y.value_loc(self.cmap, key, self.file, ypath or f"{self.ypath}.{key}")

    def node_loc(self) -> Location:
        if Y.is_map(self.cmap):
            return Y.node_loc(self.cmap, self.file, self.ypath)
        return Location(self.file, None, None, self.ypath)


def expand_templates(components, templates, errs: ProblemCollector) -> dict[str, CompSource]:
    """{name: CompSource} with every template instance flattened (nested templates too)."""
    tdefs = templates if isinstance(templates, dict) else {}
    for tname, (tdef, parent, tfile) in tdefs.items():
        tloc = Y.key_loc(parent, tname, tfile, f"templates.{tname}")
        if not Y.is_map(tdef) or not Y.is_map(tdef.get("components")):
            errs.add(f"template '{tname}' needs 'ports:' (a list) and 'components:' (a mapping)", tloc,
                     "see docs/ARCHITECTURE.md, 'templates'")
            continue
        for k in tdef:
            if k not in TEMPLATE_KEYS:
                errs.add(f"unknown key '{k}' in template '{tname}'{suggest(str(k), TEMPLATE_KEYS)}",
                         Y.key_loc(tdef, k, tfile, f"templates.{tname}.{k}"), f"allowed: {', '.join(TEMPLATE_KEYS)}")
        if tdef.get("ports") is not None and not Y.is_seq(tdef.get("ports")):
            errs.add(f"'ports' of template '{tname}' must be a list of node names",
                     Y.value_loc(tdef, "ports", tfile, f"templates.{tname}.ports"), "e.g. ports: [P, T, rod]")
    out: dict[str, CompSource] = {}
    if not isinstance(components, dict):
        return out
    for name, (cmap, parent, file) in components.items():
        _expand(CompSource(cmap, file, f"components.{name}"), str(name), tdefs, errs, out, 0)
        if len(out) > MAX_COMPONENTS:
            errs.add(f"the machine has more than {MAX_COMPONENTS} components (after expanding templates)",
                     Y.key_loc(parent, name, file, f"components.{name}"),
                     "split the machine; check that no template instantiates itself")
            break
    return out


def _expand(src: CompSource, name: str, tdefs, errs, out, depth, chain: tuple[str, ...] = ()) -> None:
    if len(out) > MAX_COMPONENTS:
        return
    if Y.is_map(src.cmap) and "template" in src.cmap:
        tname = str(src.cmap["template"])
        if tname in chain:
            errs.add(f"template '{tname}' instantiates itself (via {' -> '.join(chain + (tname,))})",
                     src.value_loc("template"), "a template must not contain an instance of itself")
            return
        _expand_instance(name, src, tdefs, errs, out, depth, chain + (tname,))
    else:
        if name in out:
            errs.add(f"two components are both named '{name}' (a component written '{name}' and one "
                     "expanded from a template instance)", src.node_loc(), "rename one of them")
            return
        out[name] = src


def _expand_instance(inst, src: CompSource, tdefs, errs, out, depth, chain=()) -> None:
    cmap = src.cmap
    tname = str(cmap["template"])
    if depth > MAX_DEPTH:
        errs.add(f"templates nested too deeply at '{inst}'", src.node_loc(), "a template must not instantiate itself")
        return
    if tname not in tdefs:
        errs.add(f"unknown template '{tname}'{suggest(tname, tdefs)}", src.value_loc("template"),
                 f"define it under 'templates:' (known: {', '.join(map(str, tdefs)) or 'none'})")
        return
    tdef, _, tfile = tdefs[tname]
    if not Y.is_map(tdef) or not Y.is_map(tdef.get("components")) or not Y.is_seq(tdef.get("ports") or []):
        return  # reported once by expand_templates
    external = [str(p) for p in (tdef.get("ports") or [])]
    pmap = cmap.get("ports") or {}
    if not Y.is_map(pmap):
        errs.add(f"'ports' of template instance '{inst}' must map template ports to nodes", src.value_loc("ports"),
                 f"e.g. ports: {{{', '.join(f'{p}: <node>' for p in external)}}}")
        return
    for p in pmap:
        if str(p) not in external:
            errs.add(f"template '{tname}' has no port '{p}'{suggest(str(p), external)}",
                     Y.key_loc(pmap, p, src.file, f"{src.ypath}.ports.{p}"), f"its ports: {', '.join(external)}")
    for p in external:
        if p not in pmap:
            errs.add(f"port '{p}' of template instance '{inst}' is not connected", src.node_loc(),
                     f"add '{p}: <node>' under ports")

    def rename(node: str) -> str:
        if node in pmap:
            return str(pmap[node])
        if node in GLOBAL_NODES:
            return node
        return f"{inst}.{node}"

    inner_comps = tdef["components"]
    overrides: dict[str, list] = {}
    for k, v in cmap.items():
        if k in INSTANCE_KEYS:
            continue
        inner, _, rest = str(k).partition(".")
        kloc = src.key_loc(k)
        if not rest:
            errs.add(f"'{k}' in template instance '{inst}' must be written <component>.<parameter>", kloc,
                     f"e.g. {next(iter(inner_comps), 'valve')}.Kv: 1e-6")
        elif inner not in inner_comps:
            errs.add(f"template '{tname}' has no component '{inner}'{suggest(inner, inner_comps)}", kloc,
                     f"its components: {', '.join(map(str, inner_comps))}")
        else:
            overrides.setdefault(inner, []).append((rest, v, src.value_loc(k)))
    for cname, cdef in inner_comps.items():
        if not Y.is_map(cdef):
            errs.add(f"component '{cname}' of template '{tname}' must be a mapping",
                     Y.key_loc(inner_comps, cname, tfile, f"templates.{tname}.components.{cname}"))
            continue
        clone = copy.deepcopy(cdef)
        ports = clone.get("ports")
        if Y.is_map(ports):
            for port in list(ports):
                if isinstance(ports[port], str):
                    ports[port] = rename(ports[port])
        locs = {}
        for rest, v, vloc in overrides.get(str(cname), []):
            clone[rest] = v
            locs[rest] = vloc
        child = CompSource(clone, tfile, f"templates.{tname}.components.{cname}", locs, instance=inst)
        _expand(child, f"{inst}.{cname}", tdefs, errs, out, depth + 1, chain)
