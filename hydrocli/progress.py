"""Progress of a long run (a diagnosis): messages as they come, and between them the current
status — a live line on a terminal, a plain line every few seconds when stderr is a file or a
pipe (CI logs, ``nohup``), so a run is never silent for long.

The library reports through a plain callable ``progress(message)``; a :class:`Heartbeat` is
such a callable that also takes ``progress.status(text)`` updates (what is running now:
"base fit: simulation 12/90", "round 1: candidate fits 2/4 done"). Library code calls
:func:`status`, which does nothing for a progress callable without it.
"""
from __future__ import annotations

import sys
import threading
import time
from typing import Callable


def status(progress, text: str) -> None:
    """Tell ``progress`` what is running now (ignored by a plain message callable)."""
    fn = getattr(progress, "status", None)
    if fn is not None:
        fn(text)


class Heartbeat:
    """A progress callable: ``hb(message)`` prints the message; ``hb.status(text)`` sets the
    status, printed ``every`` seconds as ``  … text (elapsed s)`` if nothing else was printed
    meanwhile (or shown live on a terminal). Use as a context manager (starts/stops a daemon
    thread)."""

    def __init__(self, echo: Callable[[str], None], every: float = 5.0, live: bool | None = None,
                 clock: Callable[[], float] = time.monotonic):
        self.echo, self.every, self.clock = echo, float(every), clock
        self.live = sys.stderr.isatty() if live is None else bool(live)
        self.t0 = self.last = clock()
        self.text = ""
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def __call__(self, message: str) -> None:
        with self._lock:
            self._clear_live()
            self.echo(message)
            self.last = self.clock()
            self.text = ""

    def status(self, text: str) -> None:
        with self._lock:
            self.text = text

    def tick(self) -> None:
        """Print the status if it is due (the thread calls this; tests call it directly)."""
        with self._lock:
            now = self.clock()
            if not self.text:
                return
            line = f"  … {self.text} ({now - self.t0:.0f} s)"
            if self.live:
                sys.stderr.write("\r" + line[:120].ljust(120))
                sys.stderr.flush()
            elif now - self.last >= self.every:
                self.echo(line)
                self.last = now

    def _clear_live(self) -> None:
        if self.live and self.text:
            sys.stderr.write("\r" + " " * 120 + "\r")
            sys.stderr.flush()

    def _run(self) -> None:
        step = min(self.every, 1.0)
        while not self._stop.wait(step):
            self.tick()

    def __enter__(self) -> "Heartbeat":
        self._thread = threading.Thread(target=self._run, name="hydro-heartbeat", daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
        with self._lock:
            self._clear_live()
            self.text = ""
