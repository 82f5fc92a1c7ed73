"""Every candidate the catalogue offers on every shipped machine edits into a valid machine.

The shipped machines span the topologies users write: flat files, template instances in
included files (the knuckle-boom crane, the harvester), jet-pipe and load-sensing valves, four
metering edges, multibody chains. A candidate whose edit cannot be made there is a diagnosis
that stops with an internal error on a user's machine (the crane's KeyError 'inner.dcv',
session 46)."""
from pathlib import Path

import pytest

from hydrocli.diagnose import locate
from hydrocli.diagnose.candidates import Context, catalogue
from hydrocli.diagnose.engine import diagnosed_machine
from hydrocli.model.builder import build_model

MACHINES = sorted((Path(__file__).resolve().parents[2] / "machines").glob("*.yaml"))


@pytest.mark.parametrize("path", MACHINES, ids=lambda p: p.stem)
def test_every_candidate_builds_on_every_shipped_machine(path):
    net, _, _ = diagnosed_machine(str(path))
    model = build_model(net)
    ctx = Context(net, set(model.free_params), {}, locate.output_quantities(model), {})
    cands, skipped = catalogue(ctx)
    assert cands and all(s.reason for s in skipped)
    for c in cands:
        aug = c.build(net)                      # each edit re-checks the machine (augment.reload_doc)
        assert all(p.name.rpartition(".")[0] in aug.components for p in c.params), c.key
