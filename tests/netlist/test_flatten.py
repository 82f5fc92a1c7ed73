"""flatten.flat_doc: a machine with includes and template instances written as one flat
document describes the same machine (what the diagnosis edits)."""
from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

from hydrocli.model.builder import build_model
from hydrocli.netlist import yamldoc as Y
from hydrocli.netlist.flatten import flat_doc, is_flat
from hydrocli.netlist.loader import load_doc, load_netlist

MACHINES = Path(__file__).resolve().parents[2] / "machines"


def test_the_templated_crane_flattens_to_the_same_model():
    net = load_netlist(MACHINES / "knuckle_boom_crane.yaml")
    assert not is_flat(net)
    doc = flat_doc(net)
    assert "templates" not in doc and "include" not in doc
    assert {"inner.dcv", "outer.cyl", "inter.friction"} <= set(doc["components"])
    flat = load_doc(Y.load_text(Y.dump_text(doc), net.file), net.file)    # written and read back
    assert is_flat(flat)
    m0, m1 = build_model(net), build_model(flat)
    assert m1.param_names == m0.param_names and m1.free_params == m0.free_params
    assert np.array_equal(m1.p0, m0.p0)
    assert m1.output_names == m0.output_names and np.array_equal(m1.x0, m0.x0)
    # the instance's own override (inter: friction.F_S 4909, the template's is another value)
    assert flat.components["inter.friction"].params["F_S"].value == pytest.approx(4909)


def test_includes_merge_and_the_main_file_wins(tmp_path):
    (tmp_path / "lib.yaml").write_text(textwrap.dedent("""\
        templates:
          leg:
            ports: [P]
            components:
              vol: {type: volume, ports: {P: P}, V: 0.001}
        components:
          t: {type: tank, ports: {T: n}}
          s: {type: pressure_source, ports: {P: n2}, p: 1.0e5}
        """))
    main = tmp_path / "main.yaml"
    main.write_text(textwrap.dedent("""\
        include: lib.yaml
        components:
          s: {type: pressure_source, ports: {P: n2}, p: 2.0e5}
          a: {template: leg, ports: {P: n}, vol.V: 0.003}
          o: {type: orifice, ports: {A: n2, B: n}}
        """))
    net = load_netlist(main)
    flat = load_doc(flat_doc(net), str(main))
    assert set(flat.components) == {"t", "s", "a.vol", "o"}
    assert flat.components["s"].params["p"].value == pytest.approx(2.0e5)
    assert flat.components["a.vol"].params["V"].value == pytest.approx(3e-3)
    assert is_flat(load_netlist(MACHINES / "eha_testbench.yaml"))
