import os

import pytest


@pytest.fixture(scope="session", autouse=True)
def _cache_dir(tmp_path_factory):
    old = os.environ.get("HYDRO_CACHE_DIR")
    os.environ["HYDRO_CACHE_DIR"] = str(tmp_path_factory.mktemp("hydro_cache"))
    yield
    if old is None:
        os.environ.pop("HYDRO_CACHE_DIR", None)
    else:
        os.environ["HYDRO_CACHE_DIR"] = old
