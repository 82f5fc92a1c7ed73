"""graph/: the machine's linear graph (terminal graph: every stamped element is a branch
from its node to the reference), its reduced incidence matrix and normal tree, checked
against ones derived by hand; topology errors keep their messages."""
from __future__ import annotations

import numpy as np
import pytest

from hydrocli.errors import TopologyError
from hydrocli.graph.linear import Branch, Kind, LinearGraph
from hydrocli.graph.topology import normal_tree
from hydrocli.model.builder import build_model, stamp
from hydrocli.netlist.loader import load_netlist_text

RC = """
name: rc
inputs: {Ps: {unit: Pa}}
components:
  supply: {type: pressure_source, ports: {P: sup, ref: Ps}}
  o1: {type: orifice, ports: {A: sup, B: n1}}
  v: {type: volume, ports: {P: n1}, V: 1 L}
  o2: {type: orifice, ports: {A: n1, B: ret}}
  tank: {type: tank, ports: {T: ret}}
"""

MSD = """
name: msd
inputs: {F: {unit: N}}
components:
  push: {type: force_source, ports: {a: x, F: F}}
  m: {type: mass, ports: {m: x}, m: 10}
  k: {type: spring, ports: {a: x, b: ground}, k: 1000}
"""


def _graph(text: str):
    net = load_netlist_text(text, "test.yaml")
    return net, stamp(net)[1]


def _tree(net, g):
    return normal_tree(g, set(net.inputs), set(net.components), {c.name: c.loc for c in net.components.values()})


def test_orifice_volume_orifice_incidence_and_normal_tree_by_hand():
    net, g = _graph(RC)
    assert list(g.nodes) == ["sup", "Ps", "n1", "ret"]          # order of first appearance
    S, C, T, I = Kind.SOURCE, Kind.CAPACITIVE, Kind.THROUGH, Kind.INPUT
    assert [(b.component, b.node, b.kind) for b in g.branches] == [
        ("<input>", "Ps", I),
        ("supply", "sup", S), ("o1", "sup", T),
        ("v", "n1", C), ("o1", "n1", T), ("o2", "n1", T),
        ("tank", "ret", S), ("o2", "ret", T)]
    assert g.incidence().tolist() == [
        [0, 1, 1, 0, 0, 0, 0, 0],      # sup: the supply's source branch and o1's A port
        [1, 0, 0, 0, 0, 0, 0, 0],      # Ps: the machine input
        [0, 0, 0, 1, 1, 1, 0, 0],      # n1: the volume and both orifices
        [0, 0, 0, 0, 0, 0, 1, 1]]      # ret: the tank and o2's B port
    tree = _tree(net, g)
    assert not tree.problems and tree.unused_inputs == []
    assert {n: (r.role, r.tree.component) for n, r in tree.roles.items()} == {
        "sup": ("imposed", "supply"), "Ps": ("imposed", "<input>"), "n1": ("state", "v"), "ret": ("imposed", "tank")}


def test_the_volume_node_balance_is_the_incidence_row():
    """dp/dt on n1 = (flow in through o1 − flow out through o2)·β/V: continuity, with the
    flows evaluated independently of the derivative."""
    net = load_netlist_text(RC, "test.yaml")
    model = build_model(net)
    assert model.state_names == ["n1.p"]
    x = np.array([[60e5]])
    u = np.array([[100e5]])
    dx, _, vs, _ = model.numpy_evaluate()(np.zeros(1), list(x.T), model.p0, list(u.T))
    q_in, q_out, cap = vs["o1.q"], vs["o2.q"], vs["n1.volume"]
    assert float(np.ravel(dx[0])[0]) == pytest.approx(float(np.ravel((q_in - q_out) / cap)[0]), rel=1e-12)
    assert float(np.ravel(q_in)[0]) > 0 and float(np.ravel(q_out)[0]) > 0


def test_reference_node_branches_are_absorbed():
    net, g = _graph(MSD)
    assert g.free_nodes == ["x", "F"]
    A = g.incidence()
    on_ground = [j for j, b in enumerate(g.branches) if b.node == "ground"]
    assert on_ground and not A[:, on_ground].any()               # the spring's b port: a zero column
    assert A.sum(axis=0).tolist() == [0 if b.node == "ground" else 1 for b in g.branches]
    tree = _tree(net, g)
    assert tree.roles["x"].role == "state" and tree.roles["x"].tree == Branch("m", "x", Kind.CAPACITIVE)
    assert [b.component for b in tree.tree] == ["m", "<input>"]


def test_from_terminals_and_incidence_of_a_hand_built_graph():
    from hydrocli.components.base import Domain
    g = LinearGraph.from_terminals([("a", "P", "n", Domain.HYDRAULIC), ("a", "T", "ground", Domain.HYDRAULIC),
                                    ("b", "P", "n", Domain.HYDRAULIC)])
    assert g.nodes["n"].terminals == (("a", "P"), ("b", "P")) and g.nodes["ground"].is_reference
    g = g.with_branches([Branch("a", "n"), Branch("a", "ground"), Branch("b", "n", Kind.CAPACITIVE)])
    assert g.incidence().tolist() == [[1, 0, 1]]


BAD = {
    "two sources": ("""
name: b
components:
  t1: {type: tank, ports: {T: ret}}
  t2: {type: tank, ports: {T: ret}}
""", "node 'ret' is driven by more than one source (t1, t2)"),
    "input and a block on one signal": ("""
name: b
inputs: {Ps: {unit: Pa}}
components:
  c: {type: constant, ports: {out: Ps}}
  s: {type: pressure_source, ports: {P: sup, ref: Ps}}
""", "node 'Ps' is driven by more than one source (machine input 'Ps', c)"),
    "undriven signal": ("""
name: b
components:
  g: {type: gain, ports: {in: s1, out: s2}}
""", "signal node 's1' has no driver (ports: g.in)"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_topology_messages_unchanged(case):
    text, message = BAD[case]
    with pytest.raises(TopologyError) as err:
        build_model(load_netlist_text(text, "bad.yaml"))
    assert message in err.value.render()
