"""Test-wide settings: compiled models go to a cache inside pytest's temporary folder,
so a run never depends on (or pollutes) the user's ~/.cache; the ``slow`` marker, set on the
tests listed in tests/slow_tests.txt (measured), so that ``pytest -m "not slow"`` is the
everyday fast lane and ``pytest`` (``.ci/run``) still runs everything."""
from pathlib import Path

import pytest

SLOW_LIST = Path(__file__).with_name("slow_tests.txt")


@pytest.fixture(autouse=True)
def _model_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "hydro_cache"))


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: takes more than a few seconds, or is the bulk of a corpus; "
                            "the everyday fast lane is  pytest -m \"not slow\"")


def _slow_ids() -> set[str]:
    """Node ids (or files, or test functions without their parameters) measured as slow."""
    if not SLOW_LIST.exists():
        return set()
    return {line.split("#")[0].strip() for line in SLOW_LIST.read_text().splitlines()} - {""}


def pytest_collection_modifyitems(config, items):
    slow = _slow_ids()
    for item in items:
        nodeid = item.nodeid.replace("\\", "/")
        if nodeid in slow or nodeid.split("[")[0] in slow or nodeid.split("::")[0] in slow:
            item.add_marker(pytest.mark.slow)
