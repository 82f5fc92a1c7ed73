"""hydrocli.executor: the one fan-out of batch identify and the diagnosis (a process pool,
or a Dask client when a scheduler is named)."""
from __future__ import annotations

import os

import pytest

from hydrocli.errors import IdentifyError
from hydrocli.executor import executor


def _square_and_pid(x: int) -> tuple[int, int]:
    return x * x, os.getpid()


def test_pool_gives_results_in_submission_order_from_other_processes():
    with executor(2) as ex:
        out = [f.result() for f in [ex.submit(_square_and_pid, x) for x in range(6)]]
    assert [r[0] for r in out] == [x * x for x in range(6)]
    assert os.getpid() not in {r[1] for r in out}


def test_unreachable_scheduler_is_a_located_identify_error():
    pytest.importorskip("distributed")
    with pytest.raises(IdentifyError, match="cannot connect to the Dask scheduler"):
        with executor(2, "tcp://127.0.0.1:9"):
            pass
