"""Forward sensitivities from the compiled integrator (solve.sensitivities, csrc/hy_sens.h)
against closed forms (first-order lag; turbulent orifice filling a volume) and against
central finite differences of the EHA's outputs."""
from hydrocli.experiments.initial import initial_state
from pathlib import Path

import numpy as np
import pytest

from hydrocli.runner import load_machine
from hydrocli.solve.sensitivities import output_sensitivities
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate

ROOT = Path(__file__).resolve().parents[2]

LAG = """
name: lag
inputs: {u: {unit: "1"}}
components:
  lag:
    type: first_order_lag
    ports: {in: u, out: y}
    tau: {value: 0.2, free: true, bounds: [0.01, 1]}
    k: {value: 2.0, free: true, bounds: [0.1, 10]}
outputs: {y: lag.y}
"""

FILL = """
name: fill
inputs: {Ps: {unit: Pa}}
components:
  supply: {type: pressure_source, ports: {P: line, ref: Ps}}
  orifice: {type: orifice, ports: {A: line, B: tank_node}, Kv: 2.0e-11, dp_lam: "0.01 bar"}
  vol: {type: volume, ports: {P: tank_node}, V: "0.1 L", beta: "1.5 GPa"}
outputs: {p: tank_node.p}
initial: {tank_node.p: "10 bar"}
"""


@pytest.fixture(autouse=True)
def _cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "hydro_cache"))


def _machine(tmp_path, text, name):
    f = tmp_path / f"{name}.yaml"
    f.write_text(text)
    return load_machine(f)[1]


def test_first_order_lag_matches_the_closed_form(tmp_path):
    """y' = (k·u − y)/τ, u = 1, y(0) = y0: y = k + (y0 − k)e^(−t/τ);
    ∂y/∂τ = −(k − y0)·(t/τ²)·e^(−t/τ), ∂y/∂k = 1 − e^(−t/τ), ∂y/∂y0 = e^(−t/τ)."""
    m = _machine(tmp_path, LAG, "lag")
    tau, k, y0 = 0.2, 2.0, 0.5
    x0 = np.array([y0])
    t = np.linspace(0.0, 1.0, 51)
    st = output_sensitivities(m, InputTable(np.array([0.0]), np.array([[1.0]])), t, x0=x0,
                              wrt=["lag.tau", "lag.k", "x0:lag.y"], opts=SolverOptions(rtol=1e-9, atol_factor=1.0))
    e = np.exp(-t / tau)
    assert st.Y[:, 0] == pytest.approx(k + (y0 - k) * e, abs=1e-7)
    assert st.dY[:, 0, 0] == pytest.approx(-(k - y0) * t / tau ** 2 * e, abs=1e-6)
    assert st.dY[:, 0, 1] == pytest.approx(1.0 - e, abs=1e-7)
    assert st.dY[:, 0, 2] == pytest.approx(e, abs=1e-7)


def test_orifice_filling_a_volume_matches_the_closed_form(tmp_path):
    """(V/β)·dp/dt = Kv·sqrt(Ps − p) ⇒ sqrt(Ps − p) = s0 − a·t with a = Kv·β/(2V):
    ∂p/∂Kv = 2(s0 − a t)·t·β/(2V), ∂p/∂V = −2(s0 − a t)·a·t/V, ∂p/∂p0 = (s0 − a t)/s0."""
    m = _machine(tmp_path, FILL, "fill")
    Kv, V, beta, Ps, p0 = 2.0e-11, 1e-4, 1.5e9, 100e5, 10e5
    t = np.linspace(0.0, 10.0, 101)
    st = output_sensitivities(m, InputTable(np.array([0.0]), np.array([[Ps]])), t,
                              wrt=["orifice.Kv", "vol.V", "x0:tank_node.p"],
                              opts=SolverOptions(rtol=1e-10, atol_factor=1.0))
    s0, a = np.sqrt(Ps - p0), Kv * beta / (2 * V)
    s = s0 - a * t
    assert st.Y[:, 0] == pytest.approx(Ps - s ** 2, rel=1e-6)
    assert st.dY[:, 0, 0] == pytest.approx(s * t * beta / V, rel=1e-5, abs=1e-6 * Ps / Kv)
    assert st.dY[:, 0, 1] == pytest.approx(-2 * s * a * t / V, rel=1e-5, abs=1e-6 * Ps / V)
    assert st.dY[:, 0, 2] == pytest.approx(s / s0, rel=1e-5, abs=1e-7)


@pytest.fixture(scope="module")
def eha_case():
    from hydrocli.experiments.experiment_file import load_experiment
    _, model = load_machine(ROOT / "machines" / "eha_testbench.yaml")
    exp = load_experiment(ROOT / "experiments" / "eha" / "none_train.yaml", model)
    n = 1500                                   # 1.5 s: two command steps and a reversal
    return model, exp.inputs, exp.t_out[:n], initial_state(model, exp)


@pytest.mark.parametrize("name", ["load.m", "cylinder.beta", "valve.Kv", "friction.kv_p", "valve.tau",
                                  "x0:piston.x"])
def test_eha_output_sensitivities_match_central_differences(eha_case, name):
    model, inputs, t, x0 = eha_case
    opts = SolverOptions(rtol=1e-10)     # differences of two solutions need both far below the step's effect
    st = output_sensitivities(model, inputs, t, x0=x0, wrt=[name], opts=opts)
    p = model.p0
    if name.startswith("x0:"):
        j = model.state_index(name[3:])
        h = 1e-2 * abs(x0[j])
        up, dn = x0.copy(), x0.copy()
        up[j] += h
        dn[j] -= h
        fd = (simulate(model, inputs, t, x0=up, opts=opts).Y - simulate(model, inputs, t, x0=dn, opts=opts).Y) / (2 * h)
    else:
        k = model.param_index(name)
        h = 1e-3 * abs(p[k])
        up, dn = p.copy(), p.copy()
        up[k] += h
        dn[k] -= h
        fd = (simulate(model, inputs, t, p=up, x0=x0, opts=opts).Y
              - simulate(model, inputs, t, p=dn, x0=x0, opts=opts).Y) / (2 * h)
    for o in ("P1", "P2", "v"):
        c = model.output_names.index(o)
        scale = np.max(np.abs(fd[:, c]))
        err = np.max(np.abs(st.dY[:, c, 0] - fd[:, c]))
        assert err <= 0.02 * scale, f"{name} → {o}: max error {err:.3g} vs max |dy| {scale:.3g}"


def test_sensitivity_run_gives_the_plain_trajectory(eha_case):
    """The sensitivity pass does not change the state integration."""
    model, inputs, t, x0 = eha_case
    st = output_sensitivities(model, inputs, t, x0=x0, wrt=["load.m"])
    plain = simulate(model, inputs, t, x0=x0)
    assert np.array_equal(st.Y, plain.Y)


def test_columns_computed_together_equal_each_column_alone(eha_case):
    """The sensitivity block is worked on row by row (state-major, csrc/hy_sens.h): every
    column of a joint run must be the column a one-column run gives (the same arithmetic)."""
    model, inputs, t, x0 = eha_case
    wrt = ["load.m", "x0:piston.x", "valve.Kv", "cylinder.beta", "friction.kv_p"]
    joint = output_sensitivities(model, inputs, t, x0=x0, wrt=wrt)
    for c, name in enumerate(wrt):
        alone = output_sensitivities(model, inputs, t, x0=x0, wrt=[name])
        np.testing.assert_allclose(joint.dY[:, :, c], alone.dY[:, :, 0], rtol=1e-12, atol=0.0)


def test_pipelined_and_split_runs_equal_one_sequential_run(eha_case):
    """``threads=2`` pipelines one run (the columns in a second thread a few steps behind the
    states, csrc/hy_sens_pipe.h), ``threads=4`` splits the columns between two pipelined
    runs: the block, the states' sensitivities and the outputs are bitwise those of one
    sequential run (the same arithmetic; the state steps do not depend on the columns)."""
    from hydrocli.solve.sensitivities import MIN_COLUMNS_PER_THREAD, column_split
    model, inputs, t, x0 = eha_case
    wrt = ["load.m", "x0:piston.x", "valve.Kv", "cylinder.beta", "friction.kv_p", "valve.tau", "cylinder.V_A0",
           "friction.ks_p", "cylinder.c_il"]
    one = output_sensitivities(model, inputs, t, x0=x0, wrt=wrt, states=True)
    assert not one.stats["pipelined"]
    for threads, runs in ((2, 1), (4, 2)):
        other = output_sensitivities(model, inputs, t, x0=x0, wrt=wrt, states=True, threads=threads)
        assert other.stats["pipelined"], threads
        assert np.array_equal(one.Y, other.Y) and np.array_equal(one.dY, other.dY) and np.array_equal(one.dX, other.dX)
        assert other.stats["sensitivity_evals"] == runs * one.stats["sensitivity_evals"], threads
    # the ring of step records (64) wraps around several times over this run
    assert one.stats["steps_accepted"] > 3 * 64
    assert column_split(9, 2) == [slice(0, 4), slice(4, 9)]
    assert column_split(2 * MIN_COLUMNS_PER_THREAD - 1, 2) == [slice(0, 2 * MIN_COLUMNS_PER_THREAD - 1)]
    assert column_split(3, 8) == [slice(0, 3)]


def test_a_pipelined_run_that_fails_stops_its_column_thread(eha_case):
    """An integration that fails half-way (here: too few steps allowed) ends the pipelined
    run with the sequential run's error, the column thread stopped and joined (no hang, no
    stray thread)."""
    import threading

    from hydrocli.errors import SolverError
    model, inputs, t, x0 = eha_case
    opts = SolverOptions(max_steps=300)
    before = threading.active_count()
    messages = []
    for threads in (1, 2):
        with pytest.raises(SolverError) as err:
            output_sensitivities(model, inputs, t, x0=x0, wrt=["load.m", "valve.Kv"], opts=opts, threads=threads)
        messages.append(str(err.value))
    assert messages[0] == messages[1] and "steps" in messages[0]
    assert threading.active_count() == before


def _chain(n: int) -> str:
    """A supply filling n volumes in series through laminar orifices (n states, tridiagonal
    Jacobian: above 24 states the integrator factorises it sparsely)."""
    comps = ["  supply: {type: pressure_source, ports: {P: n0, ref: Ps}}"]
    for i in range(1, n + 1):
        comps.append(f"  o{i}: {{type: orifice, ports: {{A: n{i - 1}, B: n{i}}}, Kv: 1.0e-7, dp_lam: \"10 bar\"}}")
        comps.append(f"  v{i}: {{type: volume, ports: {{P: n{i}}}, V: \"0.1 L\", beta: \"1.5 GPa\"}}")
    return ("name: chain\ninputs: {Ps: {unit: Pa}}\ncomponents:\n" + "\n".join(comps)
            + f"\noutputs: {{p_mid: n{n // 2}.p, p_end: n{n}.p}}\n"
            + "initial: {" + ", ".join(f"n{i}.p: \"10 bar\"" for i in range(1, n + 1)) + "}\n")


def test_sparse_factorisation_sensitivities_match_central_differences(tmp_path):
    """30 volumes in series (sparse LU path): several columns at once against central
    differences of the outputs."""
    m = _machine(tmp_path, _chain(30), "chain")
    assert len(m.state_names) == 30
    inputs = InputTable(np.array([0.0, 0.5, 0.5001, 2.0]), np.array([[100e5], [100e5], [150e5], [150e5]]))
    t = np.linspace(0.0, 2.0, 201)
    wrt = ["o1.Kv", "v15.V", "o30.Kv", "x0:n10.p"]
    opts = SolverOptions(rtol=1e-10)
    st = output_sensitivities(m, inputs, t, wrt=wrt, opts=opts)
    # a pipeline needs the dense LU of each step: a sparse model's columns are split between
    # two runs instead (the same numbers), and asked directly for a pipeline the C side runs
    # in sequence
    eight = wrt + ["o2.Kv", "v5.V", "o20.Kv", "v25.V"]
    one = output_sensitivities(m, inputs, t, wrt=eight, opts=opts)
    two = output_sensitivities(m, inputs, t, wrt=eight, opts=opts, threads=2)
    assert np.array_equal(two.dY, one.dY) and two.stats["sensitivity_evals"] == 2 * one.stats["sensitivity_evals"]
    from hydrocli.solve.sensitivities import columns, sensitivity_library
    from hydrocli.solve.simulate import _hold_flags, atol_vector
    lib = sensitivity_library(m)              # the limit is the compiled library's HY_DENSE_MAX
    assert lib.dense_max == 24 and not lib.pipelinable
    col_p, S0 = columns(m, wrt)
    piped = sensitivity_library(m).simulate_sens(m.p0, inputs.t, inputs.U, _hold_flags(m), 0.0, m.x0, t, col_p, S0,
                                                 rtol=opts.rtol, atol=atol_vector(m, opts), pipelined=True)
    assert not piped.stats["pipelined"] and np.array_equal(piped.dY, st.dY)
    p, x0 = m.p0, m.x0
    for c, name in enumerate(wrt):
        up_p, dn_p, up_x, dn_x = p.copy(), p.copy(), x0.copy(), x0.copy()
        if name.startswith("x0:"):
            j = m.state_index(name[3:])
            h = 1e-3 * abs(x0[j])
            up_x[j] += h
            dn_x[j] -= h
        else:
            k = m.param_index(name)
            h = 1e-2 * abs(p[k])
            up_p[k] += h
            dn_p[k] -= h
        fd = (simulate(m, inputs, t, p=up_p, x0=up_x, opts=opts).Y
              - simulate(m, inputs, t, p=dn_p, x0=dn_x, opts=opts).Y) / (2 * h)
        scale = np.max(np.abs(fd), axis=0)
        assert np.all(scale > 0)
        err = np.max(np.abs(st.dY[:, :, c] - fd), axis=0)
        assert np.all(err <= 1e-3 * scale), f"{name}: max error {err} vs max |dy| {scale}"
