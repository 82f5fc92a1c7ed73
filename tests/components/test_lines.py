"""Hose lumps (seed 002 §2b–3c): lumping criterion eq. 3 and T/L/π natural frequencies with the
measured I and C of the 4 m, 3/4 in hose."""
import math

import numpy as np
import pytest

from simhelpers import col, oscillation_frequency, run
from hydrocli.components.hydraulic.lines import laminar_resistance, single_lump_frequency
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text

I_HOSE, C_HOSE = 3.06e7, 1.59e-12


def test_single_lump_criterion_51_hz():
    """Seed 002 eq. 3: β = 1.6e9 Pa, ρ = 970 kg/m³, l = 4 m → f = 51 Hz."""
    assert single_lump_frequency(1.6e9, 970.0, 4.0) == pytest.approx(51.0, abs=0.5)


def _hose_machine(f_max, lumps=1, length=4.0):
    return build_model(load_netlist_text(f"""
name: h
fluid: {{beta: 1.6e9, rho: 970}}
components:
  src: {{type: pressure_source, ports: {{P: a}}, p: 100e5}}
  hose: {{type: hose, ports: {{A: a, B: b}}, l: {length}, lumps: {lumps}, f_max: {f_max}}}
"""))


def test_lumping_warning():
    assert not _hose_machine(f_max=45).warnings
    warn = _hose_machine(f_max=60).warnings
    assert len(warn) == 1 and "51.1 Hz" in warn[0] and "lumps ≥ 2" in warn[0]
    assert not _hose_machine(f_max=60, lumps=2).warnings


def test_hagen_poiseuille():
    # 128 μ l/(π d⁴) for μ = 0.04 Pa·s, l = 2 m, d = 10 mm
    assert laminar_resistance(800.0, 5e-5, 2.0, 0.01) == pytest.approx(128 * 0.04 * 2 / (math.pi * 1e-8))


@pytest.mark.parametrize("arrangement, factor", [(1, 1.0), (0, math.sqrt(2.0))])
def test_lump_natural_frequency(arrangement, factor):
    """Source at A, B blocked: the L lump (I then C, seed 002 eq. 6) rings at 1/sqrt(IC)
    = 143 rad/s; the π lump (C/2 at B) at sqrt(2/(IC))."""
    text = f"""
name: ring
components:
  src: {{type: pressure_source, ports: {{P: a}}, p: 50e5}}
  hose: {{type: hose, ports: {{A: a, B: b}}, I: {I_HOSE}, C: {C_HOSE}, laminar: 0, arrangement: {arrangement},
          f_max: 1}}
"""
    m, tr, _ = run(text, 0.3, n=30001)
    w = oscillation_frequency(tr.t, col(m, tr, "b.p"))
    assert w == pytest.approx(factor / math.sqrt(I_HOSE * C_HOSE), rel=0.005)


@pytest.mark.parametrize("split", [0.2, 0.9])
def test_pi_split_moves_the_end_capacitance(split):
    """π lump with ``split`` s: (1 − s)·C at B. Source at A, B blocked: B rings at
    1/sqrt(I·(1 − s)·C) (0.5 is the symmetric π of the test above); both ends blocked, the
    two end capacitances ring through the inertance at sqrt((1/C_A + 1/C_B)/I) while the
    stored volume C_A·p_A + C_B·p_B stays what it was (conservation)."""
    text = f"""
name: ring
components:
  src: {{type: pressure_source, ports: {{P: a}}, p: 50e5}}
  hose: {{type: hose, ports: {{A: a, B: b}}, I: {I_HOSE}, C: {C_HOSE}, laminar: 0, arrangement: 0, split: {split},
          f_max: 1}}
"""
    m, tr, _ = run(text, 0.3, n=30001)
    w = oscillation_frequency(tr.t, col(m, tr, "b.p"))
    assert w == pytest.approx(1.0 / math.sqrt(I_HOSE * (1.0 - split) * C_HOSE), rel=0.005)
    c_a, c_b = split * C_HOSE, (1.0 - split) * C_HOSE
    closed = f"""
name: closed
components:
  hose: {{type: hose, ports: {{A: a, B: b}}, I: {I_HOSE}, C: {C_HOSE}, laminar: 0, arrangement: 0, split: {split},
          f_max: 1}}
initial: {{a.p: 80e5, b.p: 20e5}}
"""
    m, tr, _ = run(closed, 0.3, n=30001)
    pa, pb = col(m, tr, "a.p"), col(m, tr, "b.p")
    w = oscillation_frequency(tr.t, pb)
    assert w == pytest.approx(math.sqrt((1.0 / c_a + 1.0 / c_b) / I_HOSE), rel=0.005)
    stored = c_a * pa + c_b * pb
    assert np.max(np.abs(stored - stored[0])) < 1e-6 * stored[0]
    # on an L or T lump the split has no place: said at build time, not silently ignored
    lump = closed.replace("arrangement: 0", "arrangement: 2").replace("initial: {a.p: 80e5, b.p: 20e5}", "")
    lump += "  va: {type: volume, ports: {P: a}}\n  vb: {type: volume, ports: {P: b}}\n"
    warn = build_model(load_netlist_text(lump)).warnings
    assert any("split" in w for w in warn) == (split != 0.5)


def test_t_lump_between_volumes_and_multi_lump_dc():
    """T lump between two held pressures: the internal capacitance C rings against the two
    half-inertances in parallel (I/4), ω = 2/sqrt(I·C); N lumps carry the steady laminar flow
    Δp/(128μl/(πd⁴)) of the whole line."""
    text = f"""
name: tring
components:
  s1: {{type: pressure_source, ports: {{P: a}}, p: 50e5}}
  s2: {{type: pressure_source, ports: {{P: b}}, p: 50e5}}
  hose: {{type: hose, ports: {{A: a, B: b}}, I: {I_HOSE}, C: {C_HOSE}, laminar: 0, arrangement: 2, f_max: 1}}
initial: {{hose.p1: 60e5}}
"""
    m, tr, _ = run(text, 0.2, n=20001)
    w = oscillation_frequency(tr.t, col(m, tr, "hose.p1"))
    assert w == pytest.approx(2 / math.sqrt(I_HOSE * C_HOSE), rel=0.005)
    text = """
name: dc
fluid: {rho: 870, nu: 4.6e-5}
components:
  s1: {type: pressure_source, ports: {P: a}, p: 20e5}
  s2: {type: pressure_source, ports: {P: b}, p: 10e5}
  hose: {type: hose, ports: {A: a, B: b}, l: 3, d: 0.006, lumps: 4}
"""
    m, tr, _ = run(text, 0.5, n=11)
    q_ref = 10e5 / laminar_resistance(870, 4.6e-5, 3.0, 0.006)
    for k in range(4):
        assert col(m, tr, f"hose.q{k}")[-1] == pytest.approx(q_ref, rel=1e-3)
