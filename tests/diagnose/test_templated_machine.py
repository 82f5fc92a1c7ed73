"""The diagnosis on a machine written with includes and template instances (the knuckle-boom
crane: three jib circuits from templates in an included file). Every candidate and nuisance
parameter edits components of the main document; before the machine was flattened at the
start, the first such edit failed (KeyError 'inner.dcv', an "internal error")."""
from __future__ import annotations

from pathlib import Path

import yaml

from hydrocli.diagnose.engine import prepare
from hydrocli.diagnose.stage import Settings
from hydrocli.netlist.flatten import is_flat
from hydrocli.runner import load_machine

CRANE = Path(__file__).resolve().parents[2] / "machines" / "knuckle_boom_crane.yaml"


def test_a_templated_crane_is_prepared_flat_with_its_valves_spool_lags_as_nuisances(tmp_path):
    import hydrocli as hy
    exp = {"name": "short", "duration": "1 s", "rate": "100 Hz",
           "inputs": {"u_inner": 0, "u_inter": 0, "u_outer": {"step": {"at": "0.2 s", "to": 0.3}}}}
    (tmp_path / "e.yaml").write_text(yaml.safe_dump(exp))
    r = hy.load_machine(str(CRANE)).simulate(str(tmp_path / "e.yaml"))
    y, u = r.to_pandas("outputs"), r.to_pandas("inputs")
    table = u.join(y[["l_outer", "p2_outer", "p3_outer"]])
    table.index.name = "t"
    table.to_csv(tmp_path / "rec.csv")
    su = prepare(str(CRANE), [str(tmp_path / "rec.csv")], [str(tmp_path / "rec.csv")], Settings(jobs=1))
    assert is_flat(su.net) and "inner.dcv" in su.net.components
    assert set(su.outputs) == {"l_outer", "p2_outer", "p3_outer"}
    lags = {n.name for n in su.nuisance}
    assert any(name.startswith(("inner.", "inter.", "outer.")) for name in lags), lags
    assert lags <= set(su.model.free_params)
    # the file on disk is the user's: flattened in memory only
    assert "include:" in CRANE.read_text()
    load_machine(str(CRANE))
