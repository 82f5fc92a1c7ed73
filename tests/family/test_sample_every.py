"""The generator's rule-drawn sample (``--every K``): fixed by position in the listing alone."""
import pytest

from experiments.family.generate import main


def _listed(capsys, *args):
    assert main(["--split", "dev", "--seeds", "164", "--list", *args]) == 0
    lines = capsys.readouterr().out.splitlines()
    return [ln.split()[0] for ln in lines[:-1]], lines[-1]


def test_every_k_lists_the_cases_at_positions_0_k_2k(capsys):
    full, _ = _listed(capsys)
    third, tail = _listed(capsys, "--every", "3")
    assert third == full[::3] and len(third) == (len(full) + 2) // 3
    assert tail == f"{len(third)} cases"
    assert third[0] == "lift__none__base_a__s164"


def test_every_below_one_is_refused(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--seeds", "164", "--every", "0", "--list"])
    assert e.value.code == 2
    assert "--every must be at least 1" in capsys.readouterr().err
