"""Test-wide settings: compiled models go to a cache inside pytest's temporary folder,
so a run never depends on (or pollutes) the user's ~/.cache."""
import pytest


@pytest.fixture(autouse=True)
def _model_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "hydro_cache"))


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: takes more than ~10 s (deselect with -m 'not slow')")
