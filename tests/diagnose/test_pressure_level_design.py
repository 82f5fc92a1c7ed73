"""The discriminating test that tells a pressure-dependent stiffness from a constant one
(issue 10: entrained air against a compliant mount): a small command sine with the supply
lowered in steps (design.SUPPLY_LEVELS).

Reference (closed form, Merritt / Jelali & Kroll eq. 3.12): 1 % free air in oil of 1.73 GPa at
the EHA's resting chamber pressure ≈ Ps/2 = 5 MPa gives an effective modulus of ≈ 1.5 GPa, at
0.35·Ps/2 ≈ 1.75 MPa ≈ 0.9 GPa. A model with air and one whose oil modulus is set to the
air model's effective modulus at the recorded supply answer the sine alike at the recorded
supply and apart at the lowest level."""
from pathlib import Path

import numpy as np
import pytest

from hydrocli.diagnose import augment, design
from hydrocli.experiments.experiment_file import load_all, load_experiment_file
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist

ROOT = Path(__file__).resolve().parents[2]


def _mixture(beta, p, air, n=1.4, p0=1e5):
    """β_e = β(1 + r)/(1 + rβ/(n p)), r = α(p₀/p)^(1/n) (Merritt; Jelali & Kroll eq. 3.12)."""
    r = air * (p0 / p) ** (1.0 / n)
    return beta * (1.0 + r) / (1.0 + r * beta / (n * p))


def test_supply_is_found_by_role():
    net = load_netlist(ROOT / "machines" / "eha_testbench.yaml")
    assert design.supply_inputs(net) == {"Ps"}


def test_the_supply_level_test_separates_air_from_a_constant_stiffness(tmp_path):
    net = load_netlist(ROOT / "machines" / "eha_testbench.yaml")
    base = build_model(net)
    train = load_all(ROOT / "experiments" / "quickstart" / "train.yaml", base)
    ps = float(np.mean(np.concatenate([e.inputs.U[:, base.input_names.index("Ps")] for e in train])))
    beta = base.p0[base.param_index("cylinder.beta")]
    air = build_model(augment.set_values(net, {"cylinder.air": 0.01}))
    beta_at_ps = _mixture(beta, ps / 2, 0.01)
    assert 1.4e9 < beta_at_ps < 1.6e9                                   # the closed form's ≈ 1.5 GPa
    const = build_model(augment.set_values(net, {"cylinder.beta": beta_at_ps}))

    d = next(d for d in design.designs(base, net, train) if d.name == "sine_5Hz_supply_levels")
    path = tmp_path / "levels.yaml"
    path.write_text(design.experiment_text(d, "eha"))
    ya = design._simulate(air, air.p0, load_experiment_file(path, air))
    yc = design._simulate(const, const.p0, load_experiment_file(path, const))
    e = load_experiment_file(path, base)
    t = e.t_out
    ps_in = np.interp(t, e.inputs.t, e.inputs.U[:, base.input_names.index("Ps")])
    assert ps_in[t < 3.9].mean() == pytest.approx(ps, rel=1e-3)
    assert ps_in[t > 8.6].mean() == pytest.approx(design.SUPPLY_LEVELS[-1] * ps, rel=1e-3)

    k = air.output_names.index("P1")
    def rms_gap(sel):
        return float(np.sqrt(np.mean((ya[sel, k] - yc[sel, k]) ** 2)))
    settled = (t > 1.0) & (t < 3.9)
    low = t > 9.0
    # at the recorded supply the two agree within a fraction of the lowest level's gap
    assert rms_gap(low) > 3.0 * rms_gap(settled)
