"""The compile fallback is explicit (only compiler/library failures), cached (the compiler is
not re-run for every simulation) and warned (once, with the reason and the fix); a broken
cached library is rebuilt instead of silently falling back."""
from __future__ import annotations

import numpy as np
import pytest

import bad_corpus
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.model.builder import build_model
from hydrocli.solve import compiled as C
from hydrocli.solve import library as L
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate
from hydrocli.errors import SolverError


def _model(name: str):
    text = bad_corpus.MACHINE.replace("name: rig", f"name: {name}")
    return build_model(load_netlist_text(text, "m.yaml"))


def _run(model, backend="auto"):
    t = np.linspace(0, 0.02, 21)
    u = InputTable(np.array([0.0, 1.0]), np.array([[5.0, 1e7], [5.0, 1e7]]))
    return simulate(model, u, t, opts=SolverOptions(backend=backend))


def test_missing_compiler_warns_once_and_is_not_retried(monkeypatch, capsys, tmp_path):
    monkeypatch.setenv("CC", "no-such-compiler-xyz")
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path))
    calls = []
    real = C.build_library
    monkeypatch.setattr(C, "build_library", lambda *a, **k: calls.append(1) or real(*a, **k))
    model = _model("fallback_rig")
    first, second = _run(model), _run(_model("fallback_rig"))
    assert first.stats["backend"] == second.stats["backend"] != "compiled"
    err = capsys.readouterr().err
    assert err.count("compiled backend unavailable") == 1 and "no-such-compiler-xyz" in err
    assert len(calls) == 1                                         # cached: the compiler ran once
    with pytest.raises(SolverError, match="cannot compile"):
        _run(_model("fallback_rig"), backend="compiled")


def test_broken_cached_library_is_rebuilt(monkeypatch, capsys, tmp_path):
    monkeypatch.setenv("HYDRO_CACHE_DIR", str(tmp_path))
    model = _model("broken_cache_rig")
    so = C.build_library(model.c_source)
    so.write_bytes(b"\x7fELF truncated")                             # a half-written / foreign library
    res = _run(model)
    assert res.stats["backend"] == "compiled"
    assert "unavailable" not in capsys.readouterr().err


def test_a_bug_is_not_hidden_by_the_fallback(monkeypatch):
    model = _model("bug_rig")
    monkeypatch.setattr(L, "compiled", lambda model, method="rodas5p": (_ for _ in ()).throw(KeyError("bug")))
    with pytest.raises(KeyError):
        _run(model)
