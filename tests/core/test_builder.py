"""Builder: states from the linear graph, refused topologies, generated code."""
import numpy as np
import pytest

from hydrocli.errors import TopologyError
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text

TWO_VOLUMES = """
name: two_volumes
inputs: {}
components:
  v1: {type: volume, ports: {P: a}, V: 1e-3, beta: 1e9}
  v2: {type: volume, ports: {P: b}, V: 2e-3, beta: 1e9}
  orf: {type: orifice, ports: {A: a, B: b}, Kv: 1e-7}
initial: {a.p: 100 bar, b.p: 10 bar}
outputs: {pa: a.p, pb: b.p, q: orf.q}
"""


def test_capacitive_nodes_become_pressure_states():
    m = build_model(load_netlist_text(TWO_VOLUMES))
    assert m.state_names == ["a.p", "b.p"]
    assert m.x0[0] == pytest.approx(1e7) and m.x0[1] == pytest.approx(1e6)
    assert "hy_rhs" in m.c_source and "#define HY_NX 2" in m.c_source


def test_flow_leaving_one_volume_enters_the_other():
    """Continuity: C_a·dp_a/dt + C_b·dp_b/dt = 0 for an orifice between two volumes."""
    m = build_model(load_netlist_text(TWO_VOLUMES))
    dx, _, _, _ = m.numpy_evaluate()(0.0, m.x0, m.p0, np.zeros(0))
    assert dx[0] < 0 < dx[1]
    assert 1e-3 / 1e9 * dx[0] + 2e-3 / 1e9 * dx[1] == pytest.approx(0.0, abs=1e-18)


def test_node_without_volume_between_orifices_is_refused_with_names():
    text = TWO_VOLUMES.replace("orf: {type: orifice, ports: {A: a, B: b}, Kv: 1e-7}",
                               "orf: {type: orifice, ports: {A: a, B: mid}, Kv: 1e-7}\n"
                               "  orf2: {type: orifice, ports: {A: mid, B: b}, Kv: 1e-7}")
    with pytest.raises(TopologyError) as exc:
        build_model(load_netlist_text(text))
    msg = exc.value.render()
    assert "'mid'" in msg and "orf.B" in msg and "orf2.A" in msg and "volume" in msg


def test_two_sources_on_one_node_are_a_loop_of_sources():
    text = """
inputs: {}
components:
  s1: {type: pressure_source, ports: {P: n}, p: 1e6}
  s2: {type: pressure_source, ports: {P: n}, p: 2e6}
"""
    with pytest.raises(TopologyError) as exc:
        build_model(load_netlist_text(text))
    assert "more than one source" in exc.value.render()


def test_undriven_signal_node_is_refused():
    text = """
inputs: {u: {unit: "1"}}
components:
  g: {type: gain, ports: {in: w, out: y}}
outputs: {y: y}
"""
    with pytest.raises(TopologyError) as exc:
        build_model(load_netlist_text(text))
    assert "signal node 'w' has no driver" in exc.value.render()


def test_algebraic_signal_loop_is_refused():
    text = """
inputs: {}
components:
  g1: {type: gain, ports: {in: a, out: b}}
  g2: {type: gain, ports: {in: b, out: a}}
outputs: {y: a}
"""
    with pytest.raises(TopologyError) as exc:
        build_model(load_netlist_text(text))
    assert "algebraic loop" in exc.value.render()


def test_parameters_are_symbols_not_constants():
    """Changing a parameter must not need a rebuild: the C source holds p[i], not values."""
    m = build_model(load_netlist_text(TWO_VOLUMES))
    assert "1e-07" not in m.c_source and "p[" in m.c_source


def test_param_vector_sets_names_into_a_copy_of_the_file_values_or_of_a_given_vector():
    m = build_model(load_netlist_text(TWO_VOLUMES))
    i = m.param_index("orf.Kv")
    p = m.param_vector({"orf.Kv": 3e-7})
    assert p[i] == 3e-7 and np.array_equal(np.delete(p, i), np.delete(m.p0, i))
    base = np.arange(len(m.param_names), dtype=float) + 1.0
    q = m.param_vector({"orf.Kv": 5e-7}, base=base)
    assert q[i] == 5e-7 and np.array_equal(np.delete(q, i), np.delete(base, i))
    assert base[i] == i + 1.0          # the given vector is not changed
