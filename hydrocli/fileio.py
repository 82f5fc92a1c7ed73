"""Every file the tool writes goes through here: one output-path guard and one atomic writer.

* :func:`guard_output` refuses an output path that is an input of the same command (the
  machine, an included file, an experiment, its recording, a result being reported), a
  directory, a device or other non-regular file, or a folder that cannot be written —
  a usage error (exit 2) raised *before* any long work where the CLI calls it early.
* :func:`atomic_path` writes to a temporary file beside the target and renames it over the
  target only on success; on any failure (an exception, Ctrl-C, SIGTERM) the temporary file
  is removed and the target is untouched. Temporary names carry the writer's process id, so
  one left behind by a killed process (SIGKILL) is removed by the next write to that target.
* Inputs are recorded with :func:`note_input` by the readers (YAML, recordings, results)
  inside a :func:`command_scope`, so the writer also refuses a file discovered later (the
  CSV an experiment file points to).
* :func:`json_text` writes strict JSON (NaN/inf become ``null``).
"""
from __future__ import annotations

import contextvars
import json
import math
import os
import re
import signal
import stat
import tempfile
from contextlib import contextmanager
from pathlib import Path

from .errors import DataError, Location, Problem, UsageError

_INPUTS: contextvars.ContextVar[set | None] = contextvars.ContextVar("hydro_inputs", default=None)


# -- inputs of the running command ---------------------------------------------------------
@contextmanager
def command_scope():
    """Collect the files read by one command (the CLI wraps each command in this)."""
    token = _INPUTS.set(set())
    try:
        yield
    finally:
        _INPUTS.reset(token)


def note_input(path: str | Path) -> None:
    """Record that the running command reads ``path`` (no-op outside a command scope)."""
    seen = _INPUTS.get()
    if seen is not None:
        ident = _identity(Path(path))
        if ident is not None:
            seen.add(ident)


def _identity(path: Path):
    """(device, inode) of an existing file — hard links and symlinks compare equal."""
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return (st.st_dev, st.st_ino)


# -- the guard -----------------------------------------------------------------------------
def guard_output(path: str | Path, inputs=(), option: str = "--out") -> Path:
    """Check that ``path`` may be written by this command; raise UsageError (exit 2) if not."""
    path = Path(path)
    loc = Location(path=f"{option} {path}")
    if "\0" in str(path) or not str(path).strip():
        raise UsageError(Problem("not a usable file name (empty, or with a NUL character)", loc,
                                 "give a plain file name"))
    ident = _identity(path)
    taken = set(_INPUTS.get() or ())
    taken.update(i for i in (_identity(Path(p)) for p in inputs if p is not None) if i is not None)
    if ident is not None and ident in taken:
        raise UsageError(Problem("this file is an input of the command; writing it would destroy it",
                                 loc, "choose another output file name"))
    if path.exists() or path.is_symlink():
        try:
            mode = os.stat(path).st_mode
        except OSError:
            mode = 0
        if stat.S_ISDIR(mode):
            raise UsageError(Problem("this is a directory, not a file", loc,
                                     "give a file name inside it, e.g. " + str(path / "out")))
        if not stat.S_ISREG(mode):
            raise UsageError(Problem("this is not a regular file (a device, pipe or socket)", loc,
                                     "write to a regular file"))
    folder = _existing_parent(path.parent)
    if folder is None or not folder.is_dir():
        raise UsageError(Problem(f"'{folder or path.parent}' is not a folder", loc,
                                 "choose a path inside an existing folder"))
    if not os.access(folder, os.W_OK | os.X_OK):
        raise UsageError(Problem(f"the folder '{folder}' is not writable", loc,
                                 "choose a writable folder"))
    return path


def guard_output_dir(path: str | Path, files: tuple[str, ...], inputs=(), option: str = "--out") -> Path:
    """Check an output folder and the files the command will write inside it."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise UsageError(Problem("this exists and is not a directory", Location(path=f"{option} {path}"),
                                 "give a directory (it is created when missing)"))
    for name in files:
        guard_output(path / name, inputs, option)
    return path


def _existing_parent(folder: Path) -> Path | None:
    folder = folder if str(folder) else Path(".")
    for p in (folder, *folder.parents):
        if p.exists():
            return p
    return None


# -- the writer ----------------------------------------------------------------------------
@contextmanager
def atomic_path(path: str | Path, suffix: str = ".tmp"):
    """Yield a temporary path beside ``path``; on success it replaces ``path`` (with the
    usual umask permissions), on any error it is removed and ``path`` is untouched."""
    path = guard_output(path)
    _remove_stale(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}.", suffix=suffix, dir=str(path.parent))
        os.close(fd)
    except OSError as exc:
        raise _write_error(path, exc) from None
    try:
        with _terminate_as_exception():
            yield tmp
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)   # mkstemp creates 0600; results are meant to be shared
            os.replace(tmp, path)
    except OSError as exc:
        _unlink(tmp)
        raise _write_error(path, exc) from None
    except BaseException:
        _unlink(tmp)
        raise


def write_text_atomic(path: str | Path, text: str, newline: str | None = None) -> None:
    """Write ``text`` atomically; ``newline="\\r\\n"`` writes CRLF line ends (a file read with
    CRLF is written back with CRLF: see :func:`newline_of`)."""
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline=newline or "\n") as fh:
            fh.write(text)


def newline_of(path: str | Path) -> str:
    """The line end a text file uses ("\\r\\n" or "\\n")."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(65536)
    except OSError:
        return "\n"
    return "\r\n" if b"\r\n" in head else "\n"


def json_text(data, indent: int | None = 1) -> str:
    """Strict JSON (RFC 8259): NaN and ±inf become ``null``, numpy scalars/arrays plain numbers/lists."""
    return json.dumps(_plain(data), indent=indent, allow_nan=False) + "\n"


def _plain(x):
    if isinstance(x, dict):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple, set)):
        return [_plain(v) for v in x]
    if hasattr(x, "tolist"):           # numpy arrays and scalars
        return _plain(x.tolist())
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, (str, int, float, bool)) or x is None:
        return x
    return str(x)


def _write_error(path: Path, exc: OSError) -> DataError:
    return DataError(Problem(f"cannot write {path}: {exc.strerror or exc}", Location(str(path)),
                             "check free space and permissions, or choose another path"))


def _unlink(tmp: str) -> None:
    try:
        os.unlink(tmp)
    except OSError:
        pass


def _remove_stale(path: Path) -> None:
    """Remove temporary files of ``path`` left by writers that no longer run (killed hard)."""
    pattern = re.compile(r"^\." + re.escape(path.name) + r"\.(\d+)\.")
    try:
        entries = list(path.parent.iterdir()) if path.parent.is_dir() else []
    except OSError:
        return
    for entry in entries:
        m = pattern.match(entry.name)
        if m and not _alive(int(m.group(1))):
            _unlink(str(entry))


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True
    return True


@contextmanager
def _terminate_as_exception():
    """While a file is being written, SIGTERM/SIGHUP raise SystemExit so the temporary file is
    removed (only in the main thread; elsewhere signals cannot be handled)."""
    import threading
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    def _raise(signum, frame):
        raise SystemExit(128 + signum)
    old = {}
    for sig in (signal.SIGTERM, signal.SIGHUP):
        try:
            old[sig] = signal.signal(sig, _raise)
        except (ValueError, OSError):
            pass
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
