"""The bench's in-code EHA is machines/eha_testbench.yaml, the hand-written baseline computes
the same right-hand side, and the work–precision table/plot are written."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from hydrocli import bench as B
from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist

ROOT = Path(__file__).resolve().parents[2]


def _states(rng, n=20):
    lo = np.array([-0.15, -0.15, -5.0, 2e6, 2e6, -0.08, 0.03])
    hi = np.array([0.15, 0.15, 5.0, 9e6, 9e6, 0.08, 0.12])
    return lo + (hi - lo) * rng.random((n, 7))


def test_bench_model_is_the_machine_file_and_the_hand_written_rhs():
    coded, filed = B.eha_model(), build_model(load_netlist(ROOT / "machines" / "eha_testbench.yaml"))
    assert coded.state_names == filed.state_names
    np.testing.assert_array_equal(coded.x0, filed.x0)
    order = [coded.state_index(n) for n in B.HAND_ORDER]
    t, U = B.eha_inputs(1.0)
    hand = B.handwritten_rhs(t, U, B.EhaParams())
    ev_c, ev_f = coded.numpy_evaluate(), filed.numpy_evaluate()
    for xh in _states(np.random.default_rng(1)):
        x = np.empty(7)
        x[order] = xh
        tt = 0.3712
        u = [np.interp(tt, t, U[:, j]) for j in range(3)]
        dc = np.asarray(ev_c(tt, x, coded.p0, u)[0], float)
        df = np.asarray(ev_f(tt, x, filed.p0, u)[0], float)
        dh = np.asarray(hand(tt, xh), float)
        np.testing.assert_allclose(dc, df, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(dc[order], dh, rtol=1e-9, atol=1e-9 * np.abs(dh).max())


def test_work_precision_table_and_plot(tmp_path):
    pts = [B.WPPoint("hydrocli scaled", r, 1e-2 / r ** 0.2, 1e5 * r, 1e3 * r, 100) for r in (1e-4, 1e-6)]
    pts += [B.WPPoint("scipy BDF", 1e-6, 5.0, 0.04, 0.3, 40000)]
    lines = []
    B.print_wp("title", pts, lines.append)
    assert len(lines) == 2 + len(pts) and "scipy BDF" in lines[-1]
    out = B.plot_wp({"EHA": pts, "10 circuits": pts}, tmp_path / "wp.png")
    assert out.stat().st_size > 10_000 and out.read_bytes()[:4] == b"\x89PNG"


def test_bench_cli_rejects_bad_options():
    from typer.testing import CliRunner

    from hydrocli.cli.main import app

    runner = CliRunner()
    res = runner.invoke(app, ["bench", "--only", "nope"])
    assert res.exit_code == 2 and "--only" in res.output
    res = runner.invoke(app, ["bench", "--only", "wp", "--plot", "figure.txt"])
    assert res.exit_code == 2 and ".png" in res.output
