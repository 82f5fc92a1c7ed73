"""The ringing-transducer candidate (candidates/signals.py::_ringing_pressure): each measured
pressure read through a second-order response, swapped in place of the first-order nuisance
lag, and refused when the fit neither rings nor lags beyond a typical transducer."""
from pathlib import Path

import pytest

from hydrocli.diagnose.candidates import Context, catalogue
from hydrocli.diagnose.candidates.signals import CLEARLY_SLOW, RINGING
from hydrocli.diagnose.locate import output_quantities
from hydrocli.diagnose.measurement import PRESSURE_TAU_BOUNDS, with_pressure_sensors
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist

MACHINE = Path(__file__).parents[2] / "machines" / "eha_testbench.yaml"


@pytest.fixture(scope="module")
def ringing(tmp_path_factory):
    import os
    os.environ.setdefault("HYDRO_CACHE_DIR", str(tmp_path_factory.mktemp("cache")))
    net, sensors = with_pressure_sensors(load_netlist(MACHINE))
    model = build_model(net)
    ctx = Context(net, set(model.free_params), {"piston": (0.04, 0.2)}, output_quantities(model), {})
    cand = next(c for c in catalogue(ctx)[0] if c.effect == "sensor_lag" and c.variant == "resonant")
    return net, sensors, cand


def test_every_pressure_sensor_becomes_second_order_in_place(ringing):
    """Same components, same outputs (each still reads its sensor's p), each sensor's type
    the resonant one with its τ (primary, plausible from a 160 Hz resonance) and ζ (a
    companion started lightly damped, its other starts basins of their own) free."""
    net, sensors, cand = ringing
    aug = cand.build(net)
    assert {s: aug.components[s].type for s in sensors} == {s: "pressure_sensor_2nd" for s in sensors}
    assert {o: aug.outputs[o].expr for o in net.outputs} == {o: net.outputs[o].expr for o in net.outputs}
    taus = [p for p in cand.params if p.primary]
    zetas = [p for p in cand.params if not p.primary]
    assert [p.name for p in taus] == [f"{s}.tau" for s in sensors]
    assert all(p.plausible[0] == 1e-3 and p.bounds[0] == PRESSURE_TAU_BOUNDS[0] for p in taus)
    assert all(p.start < RINGING and p.basins and min(p.shapes) < p.start < max(p.shapes) for p in zetas)
    assert {p.name for p in cand.params} <= set(build_model(aug).free_params)


@pytest.mark.parametrize("tau, zeta, refused", [
    (4e-3, 0.05, False),            # a 40 Hz ring: a finding
    (1.2e-3, 0.7, True),            # a flat 130 Hz transducer: the nuisance lag, however it fits
    (1.2e-3, 1.0, True),
    (6e-3, 0.71, False),            # flat but slow: lags 8.5 ms, beyond a typical transducer
])
def test_a_fit_that_neither_rings_nor_lags_is_refused(ringing, tau, zeta, refused):
    _, sensors, cand = ringing
    est = {n: v for s in sensors for n, v in ((f"{s}.tau", tau), (f"{s}.zeta", zeta))}
    reasons = [why for check in cand.checks if (why := check(est))]
    assert bool(reasons) == refused
    assert (2 * zeta * tau >= CLEARLY_SLOW or zeta < RINGING) != refused
