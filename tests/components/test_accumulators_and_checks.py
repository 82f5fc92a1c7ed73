"""Accumulators (seed 001 eq. 8; polytropic gas law) and parameter validation (exit 3)."""
import numpy as np
import pytest

from simhelpers import col, run
from hydrocli.errors import NetlistError
from hydrocli.netlist.loader import load_netlist_text


def test_accumulator_capacitance_eq8():
    """C_A·dp/dt = Q: p = p0 + Q·t/C_A."""
    m, tr, _ = run("""
name: acc
components:
  pump: {type: flow_source, ports: {P: n}, Q: 1e-6}
  acc: {type: accumulator, ports: {P: n}, C: 1e-11}
initial: {n.p: 10e5}
""", 1.0, n=11)
    assert np.allclose(col(m, tr, "n.p"), 10e5 + 1e-6 * tr.t / 1e-11, rtol=1e-6)


def test_gas_accumulator_isothermal():
    """Isothermal gas (n = 1) charged at p0: p·V_g = p0·V0, V_g = V0 − ∫Q dt (oil dead volume
    compressibility is negligible here)."""
    V0, p0, Q = 1e-3, 50e5, 1e-4
    m, tr, _ = run(f"""
name: gas
components:
  pump: {{type: flow_source, ports: {{P: n}}, Q: {Q}}}
  acc: {{type: gas_accumulator, ports: {{P: n}}, V0: {V0}, p0: {p0}, n: 1.0, V_oil: 1e-7, eps_p: 100}}
initial: {{n.p: {p0 + 2000}}}
""", 5.0, n=11)
    p_ref = p0 * V0 / (V0 - Q * tr.t)
    assert np.allclose(col(m, tr, "n.p")[1:], p_ref[1:], rtol=2e-3)


@pytest.mark.parametrize("snippet, word", [
    ("vol: {type: volume, ports: {P: n}, V: -1e-4}", "V must be > 0"),
    ("h: {type: hose, ports: {A: n, B: m}, l: 2, lumps: 0}", "lumps"),
    ("cbv: {type: counterbalance_valve, ports: {L: n, V: m, X: m}, p_cr: 0}", "p_cr"),
    ("acc: {type: gas_accumulator, ports: {P: n}, n: 2.5}", "n must be"),
])
def test_bad_values_are_netlist_errors_with_location(snippet, word):
    text = f"name: bad\ncomponents:\n  {snippet}\n"
    with pytest.raises(NetlistError) as exc:
        load_netlist_text(text, file="bad.yaml")
    msg = exc.value.render() if hasattr(exc.value, "render") else str(exc.value)
    assert word in msg and "bad.yaml:3" in msg
