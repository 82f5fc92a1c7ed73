"""``--set comp.param=VALUE`` overrides applied to a loaded netlist (no file is changed)."""
from __future__ import annotations

import copy
import dataclasses

from ..components import registry
from ..suggest import suggest
from ..errors import HydroError, Location, NetlistError, Problem, UsageError
from .model import Netlist
from .params import Errors, convert


def parse_assignment(item: str) -> tuple[str, str]:
    """``"valve.Kv=5e-7"`` → ``("valve.Kv", "5e-7")``."""
    name, eq, value = item.partition("=")
    if not eq or not name.strip() or not value.strip() or "." not in name:
        raise UsageError(Problem(f"--set '{item}': expected COMPONENT.PARAMETER=VALUE", Location(path="--set"),
                                   "e.g. --set valve.Kv=5e-7 or --set cylinder.V_A0='0.2 L'"))
    return name.strip(), value.strip()


def apply_overrides(net: Netlist, items: list[str] | tuple[str, ...]) -> Netlist:
    """A copy of ``net`` with parameters replaced; values may carry units ("0.2 L").

    A bare number is read like one in the machine file (file default unit, else SI).
    Every bad item is reported together as a usage error (exit 2): the command line is wrong.
    """
    if not items:
        return net
    out = dataclasses.replace(net, components=copy.deepcopy(net.components))
    errs = Errors()
    for item in items:
        try:
            _apply_one(out, item)
        except HydroError as exc:
            errs.extend(exc)
    errs.raise_if_any(UsageError)          # units too: the command line is what is wrong
    out.text = net.text.rstrip("\n") + "\n" + "".join(f"# --set {i}\n" for i in items)
    return out


def _apply_one(net: Netlist, item: str) -> None:
    name, raw = parse_assignment(item)
    loc = Location(path=f"--set {item}")
    comp, _, pname = name.rpartition(".")
    decl = net.components.get(comp)
    if decl is None:
        raise NetlistError(Problem(f"no component '{comp}'{suggest(comp, net.components)}", loc,
                                   "'hydro check MACHINE' lists the components and parameters"))
    spec = registry.get(decl.type).param(pname)
    if spec is None:
        known = [p.name for p in registry.get(decl.type).parameters]
        raise NetlistError(Problem(f"{decl.type} '{comp}' has no parameter '{pname}'"
                                   f"{suggest(pname, known)}", loc, f"parameters: {', '.join(known)}"))
    if spec.vector:
        values = [convert(v.strip(), spec.unit, None, net.unit_defaults, loc, name) for v in raw.strip("[]").split(",")]
        value = values
    else:
        value = convert(raw, spec.unit, None, net.unit_defaults, loc, name)
    problem = spec.check(value)
    if problem:
        raise NetlistError(Problem(f"{name}: {problem}", loc, "give a physically valid value"))
    pv = decl.params[pname]
    decl.params[pname] = dataclasses.replace(pv, value=value, loc=loc, given=True)
