"""Writing values and edits back into machine files: comments kept, units kept, reload gives
the new values."""
from __future__ import annotations

import textwrap

from pathlib import Path

import pytest

from hydrocli.errors import NetlistError
from hydrocli.netlist import writer as W
from hydrocli.netlist.loader import load_netlist, load_netlist_text

EHA = str(Path(__file__).parents[2] / "machines" / "eha_testbench.yaml")


@pytest.fixture()
def net():
    return load_netlist(EHA)


def _reload(text, net):
    return load_netlist_text(text, net.file)


def _comments(text):
    return [line.split("#", 1)[1].strip() for line in text.splitlines() if "#" in line]


def test_set_parameters_round_trip_keeps_comments_and_units(net):
    new = W.set_parameters(net, {"valve.Kv": 5.123456789e-7, "valve.tau": 5.5e-3, "load.m": 80.0,
                                 "fluid.p_tank": 2e5, "valve.zeta": 0.8, "cylinder.beta": 1.8e9})
    assert _comments(new) == _comments(net.text)
    lines = {ln.strip().split(":")[0]: ln.strip() for ln in new.splitlines() if ":" in ln}
    assert lines["tau"].startswith('tau: "5.5 ms"')                        # unit string kept
    assert lines["Kv"].startswith("Kv: {value: 5.12346e-07, free: true, bounds: [1.0e-7, 2.0e-6]}")
    assert lines["p_tank"] == 'p_tank: "2 bar"'
    back = _reload(new, net)
    p = {c: d.params for c, d in back.components.items()}
    assert p["valve"]["Kv"].value == pytest.approx(5.12346e-7, rel=1e-9)
    assert p["valve"]["Kv"].free and p["valve"]["Kv"].bounds == (1e-7, 2e-6)
    assert p["valve"]["tau"].value == pytest.approx(5.5e-3)
    assert p["load"]["m"].value == 80.0
    assert p["valve"]["zeta"].value == 0.8 and p["valve"]["zeta"].given      # default → written
    assert back.fluid["p_tank"].value == pytest.approx(2e5)
    beta = p["cylinder"]["beta"]                                              # fluid default → on the component
    assert beta.value == pytest.approx(1.8e9) and beta.given and beta.unit == "GPa" and beta.free
    assert p["friction"]["kv_p"].value == net.components["friction"].params["kv_p"].value   # untouched
    assert back.components["cylinder"].params["V_A0"].value == pytest.approx(2.11e-4)


def test_file_default_units_are_used_for_bare_numbers():
    text = "units: {pressure: bar}\ncomponents:\n  s: {type: tank, ports: {T: n}, p: 2}  # tank\n"
    net = load_netlist_text(text, "m.yaml")
    new = W.set_parameters(net, {"s.p": 3.5e5})
    assert "p: 3.5} # tank" in new
    assert load_netlist_text(new, "m.yaml").components["s"].params["p"].value == pytest.approx(3.5e5)


LEG = textwrap.dedent("""\
    templates:
      leg:
        ports: [P]
        components:
          vol: {type: volume, ports: {P: P}, V: "1 L"}
    components:
      t: {type: tank, ports: {T: n}}
      a:
        template: leg   # first leg
        ports: {P: n}
    """)   # a machine with one template instance


def test_template_instance_parameters_become_overrides():
    net = load_netlist_text(LEG, "m.yaml")
    new = W.set_parameters(net, {"a.vol.V": 2e-3})
    assert 'vol.V: "2 L"' in new and "# first leg" in new   # in the unit the template used
    assert load_netlist_text(new, "m.yaml").components["a.vol"].params["V"].value == pytest.approx(2e-3)


def test_set_free_adds_bounds_in_the_files_unit(net):
    new = W.set_free(net, "valve.tau", True, (1e-3, 1e-2))
    assert 'tau: {value: "4 ms", free: true, bounds: ["1 ms", "10 ms"]}' in new
    tau = _reload(new, net).components["valve"].params["tau"]
    assert tau.free and tau.bounds == pytest.approx((1e-3, 1e-2))
    fixed = _reload(W.set_free(net, "load.m", False), net).components["load"].params["m"]
    assert not fixed.free and fixed.value == pytest.approx(74.11)


def test_add_set_port_remove_component(net):
    new = W.add_component(net, "acc", "volume", {"P": "chamber_1"},
                          {"V": "0.1 L", "air": {"value": 0.01, "free": True, "bounds": [0, 0.1]}})
    acc = _reload(new, net).components["acc"]
    assert acc.ports == {"P": "chamber_1"} and acc.params["V"].value == pytest.approx(1e-4)
    assert acc.params["air"].free and _comments(new) == _comments(net.text)
    moved = _reload(W.set_port(net, "valve", "A", "chamber_x"), net)
    assert moved.components["valve"].ports["A"] == "chamber_x"
    gone = _reload(W.remove_component(net, "external"), net)
    assert "external" not in gone.components and "valve" in gone.components
    assert net.doc["components"].get("external") is not None    # the loaded netlist is untouched


def test_writer_refuses_unknown_names_with_suggestions(net):
    with pytest.raises(NetlistError, match="did you mean 'valve.Kv'"):
        W.set_parameters(net, {"valve.Kw": 1.0})
    with pytest.raises(NetlistError, match="unknown component type"):
        W.add_component(net, "x", "volumee", {"P": "n"})
    with pytest.raises(NetlistError, match="already exists"):
        W.add_component(net, "valve", "volume", {"P": "n"})
    with pytest.raises(NetlistError, match="no port 'Q'"):
        W.set_port(net, "valve", "Q", "n")


def test_diff_text(net):
    new = W.set_parameters(net, {"valve.tau": 6e-3})
    d = W.diff_text(net.text, new, "eha.yaml")
    assert d.startswith("--- a/eha.yaml\n+++ b/eha.yaml\n")
    assert '-    tau: "4 ms"' in d and '+    tau: "6 ms"' in d
    assert W.diff_text(net.text, net.text) == ""


def test_nested_template_and_included_components(tmp_path):
    (tmp_path / "lib.yaml").write_text(textwrap.dedent("""\
        templates:
          leg:
            ports: [P]
            components:
              vol: {type: volume, ports: {P: P}, V: 0.001}
          pair:
            ports: [P]
            components:
              l1: {template: leg, ports: {P: P}}
        components:
          t: {type: tank, ports: {T: n}}
        """))
    main = tmp_path / "main.yaml"
    main.write_text("include: lib.yaml\ncomponents:\n  p: {template: pair, ports: {P: n}}  # the pair\n")
    net = load_netlist(main)
    new = W.set_parameters(net, {"p.l1.vol.V": 2.5e-3})
    assert "l1.vol.V: 0.0025" in new and "# the pair" in new
    assert load_netlist_text(new, str(main)).components["p.l1.vol"].params["V"].value == pytest.approx(2.5e-3)
    # a component defined in the included file is copied into the main file with its new value
    # (the included file is an input: never changed); the result loads the same machine
    lib_before = (tmp_path / "lib.yaml").read_text()
    new = W.set_parameters(net, {"t.p": 2e5})
    again = load_netlist_text(new, str(main))
    assert again.components["t"].params["p"].value == pytest.approx(2e5)
    assert again.components["t"].ports == net.components["t"].ports
    assert (tmp_path / "lib.yaml").read_text() == lib_before
    with pytest.raises(NetlistError, match="lib.yaml; edit that file"):
        W.set_port(net, "t", "T", "m")


def test_free_on_a_log_scale_reaches_a_template_instances_parameter():
    # the diagnosis frees a valve's spool lag on a log scale; on a crane whose valves sit in
    # template instances that edit had raised KeyError 'inner.dcv' (the instance's components
    # are not keys of the document)
    net = load_netlist_text(LEG, "m.yaml")
    doc = W.with_free(net, "a.vol.V", True, (5e-4, 4e-3), log=True)
    v = load_netlist_text(W.Y.dump_text(doc), "m.yaml").components["a.vol"].params["V"]
    assert v.free and v.log and v.bounds == pytest.approx((5e-4, 4e-3)) and v.value == pytest.approx(1e-3)
