"""One executor for every fan-out (batch identification, diagnosis candidates): a local
process pool by default, a Dask distributed client when a scheduler address is given.

Both offer ``submit(fn, *args) -> future`` and ``future.result()``, so the callers have one
code path. Jobs must be picklable (built models pickle; workers reload the compiled library
from the disk cache, ``solve.library``).
"""
from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator

from .errors import IdentifyError, Problem


@contextmanager
def executor(jobs: int = 2, scheduler: str | None = None) -> Iterator:
    """A process pool of ``jobs`` workers, or a Dask distributed client when ``scheduler``
    (``tcp://HOST:PORT``) is given; closed on exit."""
    if scheduler:
        try:
            from distributed import Client
        except ImportError:
            raise IdentifyError(Problem("--scheduler needs Dask distributed, which is not installed",
                                        hint="pip install 'hydrocli[dask]'")) from None
        try:
            _reachable(scheduler)
            client = Client(scheduler, timeout=10, set_as_default=False)
        except (OSError, TimeoutError) as exc:
            raise IdentifyError(Problem(f"cannot connect to the Dask scheduler {scheduler}: {exc}",
                                        hint="start one with 'dask scheduler' and 'dask worker ADDRESS', "
                                             "or drop --scheduler for a local process pool")) from None
        try:
            yield client
        finally:
            client.close()
    else:
        from concurrent.futures import ProcessPoolExecutor
        with ProcessPoolExecutor(max_workers=max(int(jobs), 1)) as pool:
            yield pool


def _reachable(address: str) -> None:
    """Fail fast (connection refused) before Dask's own retrying connect."""
    import socket
    from urllib.parse import urlparse
    u = urlparse(address if "://" in address else f"tcp://{address}")
    if u.scheme in ("tcp", "tls") and u.hostname and u.port:
        socket.create_connection((u.hostname, u.port), timeout=5).close()
