"""hydrocli.executor: one fan-out for batch identify and diagnosis (order kept, serial
when there is one job, the same results over a process pool)."""
from __future__ import annotations

import os

import pytest

from hydrocli.errors import IdentifyError
from hydrocli.executor import executor, run_all


def _square_and_pid(x: int) -> tuple[int, int]:
    return x * x, os.getpid()


def test_serial_when_one_job_runs_in_this_process_in_order():
    seen = []
    out = run_all(_square_and_pid, [3, 1, 2], jobs=1, on_done=lambda i, r: seen.append(i))
    assert [r[0] for r in out] == [9, 1, 4]
    assert {r[1] for r in out} == {os.getpid()}
    assert seen == [0, 1, 2]


def test_pool_gives_the_same_results_in_order_from_other_processes():
    out = run_all(_square_and_pid, list(range(6)), jobs=2)
    assert [r[0] for r in out] == [x * x for x in range(6)]
    assert os.getpid() not in {r[1] for r in out}


def test_unreachable_scheduler_is_a_located_identify_error():
    pytest.importorskip("distributed")
    with pytest.raises(IdentifyError, match="cannot connect to the Dask scheduler"):
        with executor(2, "tcp://127.0.0.1:9"):
            pass
