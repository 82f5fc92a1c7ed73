"""No import loop between modules of hydrocli/ (issue 11), found by parsing every module's
imports with ``ast`` — module-level, inside functions and under ``TYPE_CHECKING`` alike,
since a lazy import only hides a loop. Also: the library never imports the command line
(terminal output lives in hydrocli/cli/), and the top-level packages form no loop either
(the expression language ``model.expr`` is a leaf every layer may use)."""
from __future__ import annotations

import ast
from pathlib import Path

PKG = Path(__file__).resolve().parents[2] / "hydrocli"
LEAVES = {"hydrocli.model.expr"}


def _modules() -> dict[str, Path]:
    out = {}
    for f in PKG.rglob("*.py"):
        parts = list(f.relative_to(PKG.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = f
    return out


def import_graph() -> dict[str, set[str]]:
    """module → hydrocli modules it imports (``from pkg import sub`` counts as ``pkg.sub``)."""
    mods = _modules()
    edges: dict[str, set[str]] = {m: set() for m in mods}
    for m, f in mods.items():
        here = m.split(".") if f.name == "__init__.py" else m.split(".")[:-1]
        for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = ".".join(here[:len(here) - node.level + 1] + [node.module or ""]).strip(".") \
                    if node.level else (node.module or "")
                targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in mods else base for a in node.names]
            else:
                continue
            for t in targets:
                while t and t not in mods:
                    t = t.rpartition(".")[0]
                if t and t != m:
                    edges[m].add(t)
    return edges


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one member (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    for root in sorted(edges):
        if root in index:
            continue
        work = [(root, iter(sorted(edges[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(edges.get(w, ())))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))
    return out


def _explain(edges, comps) -> str:
    lines = []
    for comp in comps:
        lines.append(" ↔ ".join(comp))
        lines += [f"    {a} imports {', '.join(sorted(edges[a] & set(comp)))}" for a in comp]
    return "\n".join(lines)


def test_cycle_finder_finds_a_planted_loop():
    edges = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": {"e2"}, "e2": set()}
    assert cycles(edges) == [["a", "b", "c"]]


def test_graph_sees_relative_lazy_and_package_imports():
    g = import_graph()
    assert "hydrocli.model.expr" in g["hydrocli.model.codegen"]        # from . import expr as E
    assert "hydrocli.errors" in g["hydrocli.model.equations"]          # from ..errors import …
    assert "hydrocli.model.registry" not in g["hydrocli.model.builder"]
    assert "hydrocli.components.registry" in g["hydrocli.model.builder"]  # from ..components import registry
    assert "hydrocli.model.jacobian" in g["hydrocli.model.codegen"]    # lazy, inside generate_c


def test_no_import_loop_between_modules():
    g = import_graph()
    comps = cycles(g)
    assert not comps, "import loops:\n" + _explain(g, comps)


def test_library_never_imports_the_command_line():
    g = import_graph()
    bad = sorted(f"{m} imports {t}" for m, ts in g.items() if not m.startswith("hydrocli.cli")
                 for t in ts if t == "hydrocli.cli" or t.startswith("hydrocli.cli."))
    assert not bad, "terminal output belongs in hydrocli/cli/:\n" + "\n".join(bad)


def test_no_loop_between_packages():
    g = import_graph()

    def pkg(m: str) -> str:
        return ".".join(m.split(".")[:2])

    pg: dict[str, set[str]] = {}
    for m, ts in g.items():
        for t in ts:
            if t not in LEAVES and pkg(t) != pkg(m):
                pg.setdefault(pkg(m), set()).add(pkg(t))
            pg.setdefault(pkg(t), set())
    comps = cycles(pg)
    detail = [f"    {m} imports {t}" for comp in comps for m, ts in sorted(g.items()) for t in sorted(ts)
              if t not in LEAVES and pkg(m) in comp and pkg(t) in comp and pkg(m) != pkg(t)]
    assert not comps, "package loops: " + "; ".join(" ↔ ".join(c) for c in comps) + "\n" + "\n".join(detail)
