"""The JSON Schema generated from the specs accepts the shipped machines and rejects misspelt
keys. Checked with a minimal validator written here (and with jsonschema when installed)."""
from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from hydrocli.components import registry
from hydrocli.netlist import loader
from hydrocli.netlist.yamldoc import load_file, load_text
from hydrocli.schema import machine_schema

MACHINES = sorted((Path(__file__).parents[2] / "machines").rglob("*.yaml"))


def _type_ok(x, t) -> bool:
    return {"object": isinstance(x, dict), "array": isinstance(x, list), "string": isinstance(x, str),
            "boolean": isinstance(x, bool), "null": x is None,
            "number": isinstance(x, (int, float)) and not isinstance(x, bool)}[t]


def validate(x, s, root, path="") -> list[str]:
    """Errors of ``x`` against schema ``s`` (the subset of JSON Schema that machine_schema uses)."""
    if "$ref" in s:
        s = root["$defs"][s["$ref"].rsplit("/", 1)[1]]
    errs: list[str] = []
    if "type" in s and not _type_ok(x, s["type"]):
        return [f"{path}: expected {s['type']}"]
    if "const" in s and x != s["const"]:
        errs.append(f"{path}: expected {s['const']!r}")
    if "enum" in s and x not in s["enum"]:
        errs.append(f"{path}: {x!r} not one of the allowed values")
    if "pattern" in s and isinstance(x, str) and not re.search(s["pattern"], x):
        errs.append(f"{path}: {x!r} does not match")
    if isinstance(x, dict):
        errs += [f"{path}: missing {k}" for k in s.get("required", []) if k not in x]
        for k, v in x.items():
            sub = s.get("properties", {}).get(k)
            sub = sub if sub is not None else next(
                (ps for pat, ps in s.get("patternProperties", {}).items() if re.search(pat, k)), None)
            if sub is None:
                sub = s.get("additionalProperties", True)
                if sub is False:
                    errs.append(f"{path}.{k}: unknown key")
                    continue
            if isinstance(sub, dict):
                errs += validate(v, sub, root, f"{path}.{k}")
    if isinstance(x, list):
        if len(x) < s.get("minItems", 0) or len(x) > s.get("maxItems", len(x)):
            errs.append(f"{path}: wrong number of items")
        if "items" in s:
            for i, v in enumerate(x):
                errs += validate(v, s["items"], root, f"{path}[{i}]")
    if "oneOf" in s and sum(not validate(x, o, root, path) for o in s["oneOf"]) != 1:
        errs.append(f"{path}: matches not exactly one alternative")
    for sub in s.get("allOf", []):
        errs += validate(x, sub, root, path)
    if "if" in s:
        branch = s.get("then") if not validate(x, s["if"], root, path) else s.get("else")
        if branch:
            errs += validate(x, branch, root, path)
    return errs


def _plain(doc):
    return json.loads(json.dumps(doc))


@pytest.fixture(scope="module")
def schema():
    return machine_schema()


@pytest.mark.parametrize("path", MACHINES, ids=lambda p: p.name)
def test_shipped_machines_validate(schema, path):
    doc, _ = load_file(path)
    assert validate(_plain(doc), schema, schema) == []


@pytest.mark.parametrize("yaml, where", [
    ("nme: x\n", ".nme: unknown key"),
    ("components:\n  v: {type: volume, ports: {P: n}, VV: 1}\n", ".components.v.VV: unknown key"),
    ("components:\n  v: {type: volume, ports: {Q: n}}\n", ".components.v.ports.Q: unknown key"),
    ("components:\n  v: {type: volumee, ports: {P: n}}\n", "not one of the allowed values"),
    ("components:\n  v: {type: volume, ports: {P: n}, V: {value: 1, fre: true}}\n", "matches not exactly one"),
    ("components:\n  v: {type: volume, ports: {P: n}, V: true}\n", "matches not exactly one"),
    ("inputs: {u: {unit: bar, hold: cubic}}\n", "inputs.u"),
    ("components:\n  o: {template: t, ports: {P: n}, Kv: 1}\n", ".components.o.Kv: unknown key"),
    ("initial: {rod.x: {sameas: load.x}}\n", ".initial.rod.x: matches not exactly one"),
])
def test_misspelt_or_wrong_keys_fail(schema, yaml, where):
    errs = validate(_plain(load_text(yaml, "x.yaml")), schema, schema)
    assert any(where in e for e in errs), errs


def test_schema_covers_every_type_port_and_parameter(schema):
    types = registry.all_types()
    assert set(schema["$defs"]["component"]["else"]["properties"]["type"]["enum"]) == set(types)
    for name, cls in types.items():
        d = schema["$defs"][f"type_{name}"]["properties"]
        assert set(d["ports"]["properties"]) == {p.name for p in cls.ports}
        assert {p.name for p in cls.parameters} <= set(d)
        for p in cls.ports:
            assert d["ports"]["properties"][p.name]["description"].startswith(p.domain.value)
    assert set(schema["properties"]) == set(loader.TOP_KEYS)
    assert set(schema["properties"]["units"]["properties"]) == set(loader.UNIT_KEYS)


def test_against_jsonschema_when_installed(schema):
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.Draft202012Validator.check_schema(schema)
    v = jsonschema.Draft202012Validator(schema)
    for path in MACHINES:
        assert not list(v.iter_errors(_plain(load_file(path)[0])))
    assert list(v.iter_errors({"components": {"v": {"type": "volume", "ports": {"P": "n"}, "Vv": 1}}}))


def test_initial_values_and_rules_validate(schema):
    """An initial state is a value or a rule naming another state (the loader's INITIAL_RULES)."""
    doc = load_text('initial: {rod.x: "70 mm", p.p: 5.0e6, load.x: {same_as: rod.x}, valve.xr: {balance: chamber_a.p},'
                    ' b.x: {output: x}}\n', "x.yaml")
    assert validate(_plain(doc), schema, schema) == []
