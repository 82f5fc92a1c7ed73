"""Machine-file loading: located errors (all at once), did-you-mean, includes, templates,
units, safe YAML and --set overrides."""
from __future__ import annotations

import textwrap

from pathlib import Path

import pytest

from hydrocli.errors import NetlistError, UnitError, UsageError
from hydrocli.netlist.loader import load_netlist, load_netlist_text
from hydrocli.netlist.overrides import apply_overrides

EHA = str(Path(__file__).parents[2] / "machines" / "eha_testbench.yaml")


def _load(text: str, file: str = "m.yaml"):
    return load_netlist_text(textwrap.dedent(text), file)


def _err(text: str, cls=NetlistError):
    with pytest.raises(cls) as info:
        _load(text)
    return info.value


def test_shipped_machine_loads_in_si():
    net = load_netlist(EHA)
    assert net.components["valve"].params["tau"].value == pytest.approx(4e-3)
    assert net.components["valve"].params["tau"].unit == "ms"
    beta = net.components["cylinder"].params["beta"]   # from the fluid section
    assert beta.value == pytest.approx(1.73e9) and beta.free and not beta.given


def test_all_problems_reported_together_with_locations_and_did_you_mean():
    err = _err("""\
        nme: x
        components:
          v:
            typ: volume
          w:
            type: volumee
          q:
            type: volume
            ports: {P: n, Q: m}
            VV: 3
        """)
    msgs = [(p.message, p.location.line, p.location.col) for p in err.problems]
    assert len(msgs) == 5
    assert ("unknown top-level key 'nme' (did you mean 'name'?)", 1, 1) in msgs
    assert any("'typ' a misspelt 'type'" in m and line == 4 for m, line, _ in msgs)
    assert any("did you mean 'volume'" in m and (line, col) == (6, 11) for m, line, col in msgs)
    assert any("no port 'Q'" in m and line == 9 for m, line, _ in msgs)
    assert any("no parameter 'VV' (did you mean 'V'?)" in m and line == 10 for m, line, _ in msgs)
    assert all(p.hint and p.location.file == "m.yaml" for p in err.problems)


@pytest.mark.parametrize("text, line, words", [
    ("name: a\nname: b\n", 2, "duplicate key: 'name' appears twice"),
    ("components:\n\tt: 1\n", 2, "\\t"),
    ("components: {t: [1, 2\n", 2, "line 1, column 17"),
    ("- a\n- b\n", 1, "top level, not a list"),
    ("components: !!python/object:os.system {}\n", 1, "YAML tag"),
    ("a: !foo 3\n", 1, "YAML tag"),
])
def test_malformed_yaml_is_located(text, line, words):
    err = _err(text)
    assert err.problems[0].location.line == line
    assert words in err.render()


def test_wrong_unit_dimension_is_a_unit_error_with_location():
    err = _err("""\
        components:
          v:
            type: volume
            ports: {P: n}
            V: "3 bar"
        """, UnitError)
    p = err.problems[0]
    assert (p.location.line, p.location.col) == (5, 8) and "m^3" in p.message


@pytest.mark.parametrize("value, words", [
    ("true", "boolean"), ('"3 furlongz"', "unknown unit 'furlongz'"), ("{value: 1, unit: bar}", "not convertible"),
])
def test_bad_values_are_unit_errors(value, words):
    err = _err(f"components:\n  v:\n    type: volume\n    ports: {{P: n}}\n    V: {value}\n", UnitError)
    assert words in err.render() and err.problems[0].location.line == 5


def test_invalid_values_and_bounds():
    err = _err("""\
        components:
          v: {type: volume, ports: {P: n}, V: "-1 L"}
          w: {type: volume, ports: {P: n}, V: {value: "1 L", bounds: ["2 L", "0.5 L"]}}
          x: {type: volume, ports: {P: n}, V: {value: 1, free: yes please}}
        """)
    text = err.render()
    assert "V must be > 0" in text and "lower < upper" in text and "'free' must be true or false" in text


def test_sections_of_the_wrong_kind_are_refused():
    err = _err("components: [a, b]\ninputs: 3\n")
    assert [p.location.line for p in err.problems] == [1, 2]
    assert "'components' must be a mapping" in err.render()


def test_unconnected_port_and_missing_type():
    err = _err("components:\n  o:\n    type: orifice\n    ports: {A: n}\n")
    assert "port 'B' of 'o' (orifice, hydraulic) is not connected" in err.render()


def test_file_default_units_apply_to_bare_numbers():
    net = _load("""\
        units: {volume: L, pressure: bar}
        fluid: {p_tank: 2}
        components:
          v: {type: volume, ports: {P: n}, V: 0.5}
        """)
    assert net.components["v"].params["V"].value == pytest.approx(5e-4)
    assert net.fluid["p_tank"].value == pytest.approx(2e5)
    assert net.unit_defaults


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(textwrap.dedent(text))
    return p


TEMPLATES = """\
    # shared parts
    fluid: {beta: "1.6 GPa"}
    templates:
      branch:
        ports: [P, T]
        components:
          orif: {type: orifice, ports: {A: P, B: mid}, Kv: 1e-7}
          vol: {type: volume, ports: {P: mid}, V: "0.1 L"}
          out: {type: orifice, ports: {A: mid, B: T}}
      double:
        ports: [P, T]
        components:
          b1: {template: branch, ports: {P: P, T: T}, orif.Kv: 3e-7}
          b2: {template: branch, ports: {P: P, T: T}}
    """


def test_include_and_nested_templates(tmp_path):
    _write(tmp_path, "lib/common.yaml", TEMPLATES)
    main = _write(tmp_path, "main.yaml", """\
        include: [lib/common.yaml]
        components:
          tank: {type: tank, ports: {T: ret}}
          src: {type: tank, ports: {T: sup}}
          outer:
            template: double
            ports: {P: sup, T: ret}
            b2.orif.Kv: 5e-7
            b1.vol.V: "0.3 L"
        """)
    net = load_netlist(main)
    c = net.components
    assert set(c) == {"tank", "src"} | {f"outer.{b}.{k}" for b in ("b1", "b2") for k in ("orif", "vol", "out")}
    assert c["outer.b1.orif"].params["Kv"].value == pytest.approx(3e-7)    # set by the outer template
    assert c["outer.b2.orif"].params["Kv"].value == pytest.approx(5e-7)    # set by the instance
    assert c["outer.b1.vol"].params["V"].value == pytest.approx(3e-4)
    assert c["outer.b1.vol"].params["V"].loc.file == str(main)             # located at the override
    assert c["outer.b2.vol"].params["beta"].value == pytest.approx(1.6e9)  # fluid from the include
    assert c["outer.b1.orif"].ports == {"A": "sup", "B": "outer.b1.mid"}
    assert c["outer.b1.out"].ports == {"A": "outer.b1.mid", "B": "ret"}


def test_template_errors_are_located_at_the_instance(tmp_path):
    _write(tmp_path, "common.yaml", TEMPLATES)
    main = _write(tmp_path, "main.yaml", """\
        include: common.yaml
        components:
          a: {template: double, ports: {P: s, T: r}, b3.orif.Kv: 1}
          b: {template: dubble, ports: {P: s, T: r}}
          c: {template: branch, ports: {P: s, T: r}, orif.Kvv: 1}
        """)
    with pytest.raises(NetlistError) as info:
        load_netlist(main)
    probs = {p.message: p.location for p in info.value.problems}
    assert len(probs) == 3
    msg = next(m for m in probs if "no component 'b3'" in m)
    assert probs[msg].line == 3
    msg = next(m for m in probs if "dubble" in m)
    assert "did you mean 'double'" in msg and probs[msg].line == 4
    msg = next(m for m in probs if "Kvv" in m)
    assert probs[msg].file == str(main) and probs[msg].line == 5


def test_include_cycle_and_missing_include(tmp_path):
    _write(tmp_path, "a.yaml", "include: b.yaml\n")
    _write(tmp_path, "b.yaml", "include: [a.yaml, nothere.yaml]\n")
    with pytest.raises(NetlistError) as info:
        load_netlist(tmp_path / "a.yaml")
    text = info.value.render()
    assert "include cycle: a.yaml -> b.yaml -> a.yaml" in text
    assert "'nothere.yaml' not found" in text
    assert all(p.location.line == 1 and p.location.file.endswith("b.yaml") for p in info.value.problems)


def test_errors_inside_an_included_file_point_into_it(tmp_path):
    _write(tmp_path, "inc.yaml", "components:\n  v: {type: volume, ports: {P: n}, V: 3 bar}\nbogus: 1\n")
    _write(tmp_path, "main.yaml", "include: inc.yaml\n")
    with pytest.raises(NetlistError) as info:
        load_netlist(tmp_path / "main.yaml")
    assert {(p.location.file.endswith("inc.yaml"), p.location.line) for p in info.value.problems} == {(True, 2), (True, 3)}


def test_apply_overrides_with_units_and_did_you_mean():
    net = load_netlist(EHA)
    new = apply_overrides(net, ["valve.Kv=5e-7", "cylinder.V_A0=0.2 L"])
    assert new.components["valve"].params["Kv"].value == 5e-7
    assert new.components["cylinder"].params["V_A0"].value == pytest.approx(2e-4)
    assert net.components["valve"].params["Kv"].value == pytest.approx(4.68e-7)   # original untouched
    assert new.text != net.text
    with pytest.raises(UsageError) as info:         # a bad --set is a usage error (exit 2)
        apply_overrides(net, ["valv.Kv=1", "valve.Kvv=2", "cylinder.V_A0=-1 L", "nonsense"])
    text = info.value.render()
    assert len(info.value.problems) == 4
    assert "did you mean 'valve'" in text and "did you mean 'Kv'" in text and "must be > 0" in text
    with pytest.raises(UsageError, match="dimension"):
        apply_overrides(net, ["cylinder.V_A0=3 bar"])
