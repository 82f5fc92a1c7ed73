"""``hydro components [TYPE]``: the component library as tables (from the specs)."""
from __future__ import annotations

import inspect

import typer

from .tables import console, fmt, table


def register(app: typer.Typer) -> None:
    @app.command("components")
    def components_cmd(type_name: str = typer.Argument(None, metavar="[TYPE]", help="a component type")) -> None:
        """List the component types, or describe one: ports, parameters, states, equations."""
        from .main import run_guarded
        run_guarded(show_components, type_name)


def show_components(type_name: str | None) -> None:
    from ..components import registry
    from ..suggest import suggest
    from ..errors import Location, Problem, UsageError
    types = registry.all_types()
    out = console()
    if not type_name:
        t = table(f"{len(types)} component types ('hydro components TYPE' for details)", "type", "family", "description")
        for name, cls in sorted(types.items(), key=lambda kv: (kv[1].family, kv[0])):
            t.add_row(name, cls.family, cls.description)
        out.print(t)
        return
    cls = types.get(type_name)
    if cls is None:
        raise UsageError(Problem(f"unknown component type '{type_name}'{suggest(type_name, types)}",
                                   Location(path="hydro components TYPE"), "'hydro components' lists the types"))
    describe(cls, out)


def describe(cls, out) -> None:
    out.print(f"[bold]{cls.type}[/bold] ({cls.family}): {cls.description}")
    if cls.source:
        out.print(f"source: {cls.source}")
    t = table("ports", "port", "domain", "description")
    for p in cls.ports:
        t.add_row(p.name + (" (optional)" if p.optional else ""), p.domain.value, p.description)
    out.print(t)
    t = table("parameters", "name", "unit", "default", "bounds", "description", "source")
    for p in cls.parameters:
        flags = [f for f, on in (("fluid: " + str(p.fluid), p.fluid), ("structural", p.structural)) if on]
        desc = p.description + (f" ({', '.join(flags)})" if flags else "")
        bounds = f"[{fmt(p.bounds[0])}, {fmt(p.bounds[1])}]" if p.bounds else "—"
        t.add_row(p.name, p.unit, fmt(p.default), bounds, desc, p.source or "")
    out.print(t)
    if cls.states:
        t = table("states", "name", "unit", "initial", "description")
        for s in cls.states:
            t.add_row(s.name, s.unit, fmt(s.initial), s.description)
        out.print(t)
    if cls.variables:
        t = table("variables (usable in outputs as <component>.<name>)", "name", "unit", "description")
        for v in cls.variables:
            t.add_row(v.name, v.unit, v.description)
        out.print(t)
    doc = inspect.getdoc(cls)
    if doc:
        out.print("[bold]equations[/bold]")
        out.print(doc, markup=False)
