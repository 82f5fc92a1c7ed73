"""``hydro check MACHINE [--set …]``: load and build a machine, and show what the model is."""
from __future__ import annotations

from pathlib import Path

import typer

from .options import SET
from .tables import console, fmt, table


def register(app: typer.Typer) -> None:
    @app.command("check")
    def check_cmd(machine: Path = typer.Argument(..., help="machine YAML file"), sets: list[str] = SET) -> None:
        """Check a machine file: nodes, states, inputs, outputs, parameters and warnings."""
        from .main import run_guarded
        run_guarded(check_machine, machine, sets)


def check_machine(machine: Path, sets: list[str] | None = None) -> None:
    from ..runner import load_machine
    net, model = load_machine(machine, sets or [])
    show(net, model)


def show(net, model) -> None:
    out = console()
    out.print(f"[bold]{net.name}[/bold] ({net.file}): {len(net.components)} components, "
              f"{len(model.states)} states, {len(model.params)} parameters "
              f"({sum(p.free for p in model.params)} free)")
    out.print(_nodes(net, model))
    t = table("states", "state", "unit", "initial", "description")
    for s, x0 in zip(model.states, model.x0):
        t.add_row(s.name, s.unit, fmt(x0), s.description)
    out.print(t)
    t = table("inputs", "input", "unit", "hold", "description")
    for name, decl in net.inputs.items():
        t.add_row(name, decl.unit, decl.hold, decl.description)
    out.print(t)
    t = table("outputs", "output", "expression", "unit")
    for name, decl in net.outputs.items():
        t.add_row(name, decl.expr, decl.unit or model.output_units.get(name) or "SI")
    out.print(t)
    t = table("parameters (* = free)", "parameter", "value", "unit", "bounds", "description")
    for p in model.params:
        unit = p.display_unit or p.unit
        b = f"[{fmt(_shown(p.bounds[0], unit))}, {fmt(_shown(p.bounds[1], unit))}]" if p.free and p.bounds else ""
        t.add_row(("* " if p.free else "  ") + p.name, fmt(_shown(p.value, unit)), unit, b, p.description)
    out.print(t)
    for w in model.warnings:
        out.print(f"[yellow]warning:[/yellow] {w}")
    out.print("[green]ok[/green]" + (f" ({len(model.warnings)} warnings)" if model.warnings else ""))


def _nodes(net, model):
    from ..components import registry
    states = set(model.state_names)
    t = table("nodes", "node", "domain", "role", "ports")
    for node, ports in sorted(net.nodes().items()):
        comp, port = ports[0]
        dom = registry.get(net.components[comp].type).port(port).domain
        across = node if dom.value == "signal" else f"{node}.{dom.across}"
        role = ("reference" if node == "ground" else "state" if across in states
                else "machine input" if node in net.inputs else "imposed")
        t.add_row(node, dom.value, role, ", ".join(f"{c}.{p}" for c, p in ports))
    return t


def _shown(value: float, unit: str) -> float:
    from ..units import from_si
    try:
        return from_si(value, unit)
    except Exception:  # a display unit that does not parse: show SI
        return value
