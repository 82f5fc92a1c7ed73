"""Run a block of code with single-threaded BLAS/LAPACK.

The identification's linear algebra is on tall, thin matrices (90 003 × 15 for 30 s of three
signals at 1 kHz): OpenBLAS threads buy nothing there and, on a machine whose cores are busy
(with the fit's own simulation threads or other jobs), their spin-waiting makes each SVD of
SciPy's trust-region step up to ten times slower (0.24 s instead of 0.02 s CPU measured on
the EHA fit). :func:`single_threaded` sets every loaded OpenBLAS (NumPy's and SciPy's each
bundle one) to one thread for the duration of a ``with`` block and restores the previous
counts afterwards — what ``threadpoolctl.threadpool_limits(1)`` does, without the
dependency. Results do not depend on it beyond rounding. Where the libraries cannot be found
(not Linux, another BLAS) it does nothing.
"""
from __future__ import annotations

import ctypes
import threading
from contextlib import contextmanager

_SUFFIXES = ("", "64_", "_64_")
_PREFIXES = ("scipy_openblas", "openblas")
_lock = threading.Lock()
_depth = 0
_saved: list[tuple[object, int]] = []


def _openblas_handles() -> list[tuple[object, object]]:
    """(get, set) thread-count functions of every OpenBLAS mapped into this process."""
    try:
        with open("/proc/self/maps") as fh:
            paths = sorted({line.split()[-1] for line in fh if "openblas" in line.lower() and "/" in line})
    except OSError:
        return []
    out = []
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for pre in _PREFIXES:
            for suf in _SUFFIXES:
                get = getattr(lib, f"{pre}_get_num_threads{suf}", None)
                put = getattr(lib, f"{pre}_set_num_threads{suf}", None)
                if get is not None and put is not None:
                    get.restype, get.argtypes = ctypes.c_int, []
                    put.restype, put.argtypes = None, [ctypes.c_int]
                    out.append((get, put))
                    break
            else:
                continue
            break
    return out


@contextmanager
def single_threaded():
    """BLAS/LAPACK on one thread inside the block (re-entrant, thread-safe)."""
    global _depth
    with _lock:
        if _depth == 0:
            _saved.clear()
            for get, put in _openblas_handles():
                try:
                    _saved.append((put, int(get())))
                    put(1)
                except Exception:   # noqa: BLE001 - a library we cannot drive is left alone
                    pass
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0:
                for put, n in _saved:
                    put(n)
                _saved.clear()


def thread_counts() -> list[int]:
    """Current thread count of each loaded OpenBLAS (for tests)."""
    return [int(get()) for get, _ in _openblas_handles()]
