"""Compiled simulation: generated model C code + the Rosenbrock integrator (Rodas5P by
default; Rodas4 and Rodas4P selectable at compile time, ``csrc/hy_methods.h``) in one .so.

The code generator emits a C translation unit that defines ``HY_NX``, ``HY_NP``,
``HY_NU``, ``HY_NY``, ``HY_NNZ``, ``HY_JAC_ROW``/``HY_JAC_COL`` and the functions
``hy_rhs``/``hy_out`` (see ``csrc/hy_integrator.c`` for the exact contract).
:func:`build_library` appends the integrator source to it, compiles it once into a
content-addressed shared library in a cache directory, and :class:`CompiledModel`
calls ``hy_simulate`` through ctypes: one foreign call per simulation, parameters
and input tables passed as arrays (changing them never recompiles).
"""
from __future__ import annotations

import ctypes
import functools
import hashlib
import re
import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = [
    "CompileError",
    "CompiledModel",
    "SimResult",
    "SensResult",
    "build_library",
    "integrator_source",
    "default_cache_dir",
    "STATUS_MESSAGES",
]

_CSRC = Path(__file__).resolve().parent / "csrc"
_INTEGRATOR = _CSRC / "hy_integrator.c"

#: compiler flags (part of the cache key).  No -ffast-math: the integrator relies
#: on IEEE semantics (isfinite, NaN propagation); -ffp-contract=off keeps results free of
#: FMA contraction.  -O3 and -fno-math-errno (sqrt inlined; nothing here reads errno)
#: change no result bit and take ~12 % off the EHA's 20 s under Rodas4P (issue 16).
CFLAGS = ("-O3", "-fno-math-errno", "-fPIC", "-shared", "-ffp-contract=off")
#: the library with sensitivities (the same flags; -pthread for the pipelined column thread,
#: csrc/hy_sens_pipe.h)
SENS_CFLAGS = CFLAGS + ("-pthread",)
LDLIBS = ("-lm",)

STATS_NAMES = (
    "steps_accepted",
    "steps_rejected",
    "rhs_evals",
    "jacobian_evals",
    "lu_decompositions",
    "time_reached",
    "worst_state",
    "last_step",
)

STATUS_MESSAGES = {
    0: "ok",
    1: "step size underflow",
    2: "maximum number of steps exceeded",
    3: "non-finite value in state or right-hand side",
    -1: "invalid arguments or out of memory in the integrator",
}


class CompileError(Exception):
    """The C compiler is missing or rejected the generated model source."""


def default_cache_dir() -> Path:
    env = os.environ.get("HYDRO_CACHE_DIR")
    if env:
        return Path(env)
    return Path.home() / ".cache" / "hydrocli" / "models"


_LOCAL_INCLUDE = re.compile(r'^#include "(hy_\w+\.h)"\s*$', re.MULTILINE)


def integrator_source() -> str:
    """The integrator as one self-contained text: its local headers (method tables,
    linear algebra) are inlined, so the cached .c compiles without include paths and the
    cache key covers every file of the integrator."""
    text = _INTEGRATOR.read_text(encoding="utf-8")
    return _LOCAL_INCLUDE.sub(lambda m: (_CSRC / m.group(1)).read_text(encoding="utf-8"), text)


def _compiler() -> str:
    return os.environ.get("CC", "cc")


@functools.lru_cache(maxsize=8)
def _compiler_version(cc: str) -> str:
    exe = shutil.which(cc)
    if exe is None:
        raise CompileError(
            f"C compiler {cc!r} not found on PATH; install a C compiler (e.g. gcc) "
            "or set the CC environment variable"
        )
    try:
        out = subprocess.run(
            [exe, "--version"], capture_output=True, text=True, timeout=60, check=False
        )
    except OSError as exc:  # pragma: no cover - exotic
        raise CompileError(f"cannot run C compiler {cc!r}: {exc}") from exc
    return (out.stdout or out.stderr).strip()


def _tail(text: str, n: int = 40) -> str:
    lines = text.strip().splitlines()
    return "\n".join(lines[-n:])


def build_library(c_source: str, *, cache_dir: Path | None = None, cflags: tuple[str, ...] = CFLAGS) -> Path:
    """Compile ``c_source`` + the integrator into a cached shared library.

    The cache key is the sha256 of the model source, the integrator source, the
    compiler flags and the compiler version string.  An existing library is reused
    without invoking the compiler.  Compilation writes to temporary names in the
    cache directory and renames atomically, so concurrent processes never load a
    half-written library.  Raises :class:`CompileError` if the compiler is missing
    or fails.
    """
    cache = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    cc = _compiler()
    integ = integrator_source()
    full = (
        c_source
        + "\n\n/* ---- hydrocli integrator (appended by build_library) ---- */\n"
        + '#line 1 "hy_integrator.c"\n'
        + integ
    )
    version = _compiler_version(cc)
    h = hashlib.sha256()
    for part in (c_source, integ, " ".join(cflags + LDLIBS), cc, version):
        h.update(part.encode("utf-8"))
        h.update(b"\0")
    key = h.hexdigest()[:32]
    so_path = cache / f"hy_{key}.so"
    if so_path.exists():
        return so_path

    cache.mkdir(parents=True, exist_ok=True)
    fd, tmp_c = tempfile.mkstemp(prefix=f".hy_{key}_", suffix=".c", dir=cache)
    tmp_so = tmp_c[:-2] + ".so"
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(full)
        cmd = [cc, *cflags, "-o", tmp_so, tmp_c, *LDLIBS]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600, check=False)
        except OSError as exc:
            raise CompileError(f"cannot run C compiler {cc!r}: {exc}") from exc
        except subprocess.TimeoutExpired as exc:
            raise CompileError(f"C compiler {cc!r} timed out compiling the model") from exc
        if proc.returncode != 0 or not os.path.exists(tmp_so):
            raise CompileError(
                f"compiling the generated model failed (exit {proc.returncode}); "
                f"command: {' '.join(cmd)}\n{_tail(proc.stderr or proc.stdout)}"
            )
        os.replace(tmp_c, cache / f"hy_{key}.c")  # keep the source for inspection
        os.replace(tmp_so, so_path)
    finally:
        for tmp in (tmp_c, tmp_so):
            try:
                os.unlink(tmp)
            except FileNotFoundError:
                pass
    return so_path


@dataclass
class SimResult:
    """Result of one compiled simulation."""

    t: np.ndarray
    X: np.ndarray
    Y: np.ndarray
    status: int
    message: str
    stats: dict = field(default_factory=dict)

    @property
    def success(self) -> bool:
        return self.status == 0


@dataclass
class SensResult(SimResult):
    """A simulation with output sensitivities ``dY[i, o, c]`` = ∂y_o(t_i)/∂θ_c."""

    dY: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 0)))
    dX: np.ndarray | None = None


_dp = ctypes.c_void_p
_ARGTYPES = [
    _dp,  # p
    ctypes.c_int, _dp,  # n_tin, t_in
    _dp,  # U
    _dp,  # u_hold
    ctypes.c_double, _dp,  # t0, x0
    ctypes.c_int, _dp,  # n_out, t_out
    ctypes.c_double, _dp,  # rtol, atol
    ctypes.c_double, ctypes.c_double, ctypes.c_long,  # h0, hmax, max_steps
    _dp, _dp, _dp,  # X_out, Y_out, stats
]


def _finite_increasing(t: np.ndarray, strict: bool) -> bool:
    """All finite and (strictly) increasing, in one pass over the differences: between finite
    ends a NaN or infinity makes a difference NaN, and NaN fails every comparison.  (Two
    passes over the 20 001-sample tables were ~2 % of the EHA's 20 s simulation.)"""
    if t.shape[0] == 0:
        return True
    if not (np.isfinite(t[0]) and np.isfinite(t[-1])):
        return False
    if t.shape[0] == 1:
        return True
    d = np.min(np.diff(t))
    return bool(d > 0) if strict else bool(d >= 0)


def _vec(a, n: int, name: str) -> np.ndarray:
    arr = np.ascontiguousarray(a, dtype=np.float64).reshape(-1)
    if arr.shape[0] != n:
        raise ValueError(f"{name} must have {n} elements, got {arr.shape[0]}")
    return arr


class CompiledModel:
    """A compiled model library; picklable (reloads the .so by path)."""

    def __init__(self, so_path, nx: int, np_: int, nu: int, ny: int):
        self.so_path = Path(so_path)
        self.nx, self.np_, self.nu, self.ny = int(nx), int(np_), int(nu), int(ny)
        self._load()

    # -- loading / pickling -------------------------------------------------
    def _load(self) -> None:
        try:
            lib = ctypes.CDLL(str(self.so_path))
        except OSError as exc:
            raise ValueError(f"cannot load compiled model {self.so_path}: {exc}") from exc
        fn = lib.hy_simulate
        fn.argtypes = _ARGTYPES
        fn.restype = ctypes.c_int
        info = (ctypes.c_int * 8)()
        try:
            lib.hy_model_info.argtypes = [_dp]
            lib.hy_model_info(ctypes.addressof(info))
            sizes = tuple(info[:4])
            if sizes != (self.nx, self.np_, self.nu, self.ny):
                raise ValueError(
                    f"compiled model {self.so_path.name} has (nx, np, nu, ny) = {sizes}, "
                    f"but {(self.nx, self.np_, self.nu, self.ny)} was given"
                )
        except AttributeError:  # pragma: no cover - older library
            pass
        # the library's dense-LU limit (HY_DENSE_MAX): above it the LU is sparse, its factors
        # live in the integrator's workspace, and a sensitivity run cannot be pipelined
        self.dense_max = int(info[6])
        self._lib = lib
        self._fn = fn
        self._fn_sens = getattr(lib, "hy_simulate_sens", None)
        if self._fn_sens is not None:
            self._fn_sens.argtypes = _ARGTYPES + [ctypes.c_int, _dp, _dp, _dp, _dp, ctypes.c_int]
            self._fn_sens.restype = ctypes.c_int

    @property
    def pipelinable(self) -> bool:
        """Whether a sensitivity run can put its columns in a second thread
        (``csrc/hy_sens_pipe.h``): the model's states fit the dense LU (``HY_DENSE_MAX``)."""
        return self.nx <= self.dense_max

    @property
    def has_sensitivities(self) -> bool:
        """Whether the library was generated with sensitivities (``hy_simulate_sens``)."""
        return self._fn_sens is not None

    def __getstate__(self):
        return {"so_path": str(self.so_path), "nx": self.nx, "np_": self.np_,
                "nu": self.nu, "ny": self.ny}

    def __setstate__(self, state):
        self.so_path = Path(state["so_path"])
        self.nx, self.np_ = state["nx"], state["np_"]
        self.nu, self.ny = state["nu"], state["ny"]
        self._load()

    def __repr__(self) -> str:
        return (f"CompiledModel({str(self.so_path)!r}, nx={self.nx}, np_={self.np_}, "
                f"nu={self.nu}, ny={self.ny})")

    # -- simulation -----------------------------------------------------------
    def simulate(
        self,
        p,
        t_in,
        U,
        u_hold,
        t0,
        x0,
        t_out,
        rtol: float = 1e-6,
        atol=1e-8,
        h0: float = 0.0,
        hmax: float = np.inf,
        max_steps: int = 10_000_000,
    ) -> SimResult:
        args, _keep, t_out, X, Y, stats = self._arguments(p, t_in, U, u_hold, t0, x0, t_out, rtol, atol, h0, hmax,
                                                   max_steps)
        status = self._fn(*args)
        return _result(SimResult, status, t_out, X, Y, stats)

    def simulate_sens(self, p, t_in, U, u_hold, t0, x0, t_out, col_p, S0, rtol: float = 1e-6, atol=1e-8,
                      h0: float = 0.0, hmax: float = np.inf, max_steps: int = 10_000_000,
                      states: bool = False, pipelined: bool = False) -> SensResult:
        """:meth:`simulate` plus output sensitivities (forward, direct-decoupled; see
        ``csrc/hy_sens.h``). ``col_p[c]``: parameter index of column c, or -1 for an
        initial-state column; ``S0`` (nx × ns): ∂x0/∂θ (a unit column for a free initial
        state, zeros or dx0/dp for a parameter). ``states``: also return ``dX[i, j, c]``.
        ``pipelined``: the columns in a second thread while this one integrates the states
        (``csrc/hy_sens_pipe.h``; the same numbers; ``stats["pipelined"]`` says whether it
        ran so: a model with a sparse LU runs in sequence)."""
        if self._fn_sens is None:
            raise ValueError(f"compiled model {self.so_path.name} was built without sensitivities")
        col = np.ascontiguousarray(col_p, dtype=np.intc).reshape(-1)
        ns = col.shape[0]
        if ns < 1:
            raise ValueError("at least one sensitivity column is required")
        if np.any(col >= self.np_) or np.any(col < -1):
            raise ValueError(f"col_p entries must be -1 or parameter indices < {self.np_}")
        S0 = np.asarray(S0, dtype=np.float64)
        if S0.shape != (self.nx, ns):
            raise ValueError(f"S0 must have shape ({self.nx}, {ns}), got {S0.shape}")
        S0c = np.ascontiguousarray(S0)             # state-major (S0[j, c]) for the C side
        args, _keep, t_out, X, Y, stats = self._arguments(p, t_in, U, u_hold, t0, x0, t_out, rtol, atol, h0, hmax,
                                                   max_steps)
        dY = np.full((t_out.shape[0], self.ny, ns), np.nan)
        dyp = dY if self.ny else np.zeros(1)
        dX = np.full((t_out.shape[0], self.nx, ns), np.nan) if states else None
        status = self._fn_sens(*args, ns, col.ctypes.data, S0c.ctypes.data, dyp.ctypes.data,
                               None if dX is None else dX.ctypes.data, int(bool(pipelined)))
        res = _result(SensResult, status, t_out, X, Y, stats)
        res.dY, res.dX = dY, dX
        res.stats["sensitivity_evals"] = int(stats[8])
        res.stats["pipelined"] = bool(stats[9])
        return res

    def _arguments(self, p, t_in, U, u_hold, t0, x0, t_out, rtol, atol, h0, hmax, max_steps):
        """Checked, contiguous arguments of ``hy_simulate`` (+ the arrays it fills)."""
        nx, nu, ny = self.nx, self.nu, self.ny
        p = _vec(p, self.np_, "p") if self.np_ else np.zeros(1)
        x0 = _vec(x0, nx, "x0")
        t_out = np.ascontiguousarray(t_out, dtype=np.float64).reshape(-1)
        n_out = t_out.shape[0]
        t0 = float(t0)
        if not np.isfinite(t0):
            raise ValueError("t0 must be finite")
        if n_out and not _finite_increasing(t_out, strict=False):
            if not np.all(np.isfinite(t_out)):
                raise ValueError("t_out must be finite")
            if np.any(np.diff(t_out) < 0):
                raise ValueError("t_out must be non-decreasing")
        if n_out and t_out[0] < t0:
            raise ValueError(f"t_out[0] = {t_out[0]} is before t0 = {t0}")
        if nu > 0:
            if t_in is None or U is None or u_hold is None:
                raise ValueError(f"the model has {nu} inputs: t_in, U and u_hold are required")
            t_in = np.ascontiguousarray(t_in, dtype=np.float64).reshape(-1)
            n_tin = t_in.shape[0]
            if n_tin < 1:
                raise ValueError("t_in must have at least one sample")
            if not _finite_increasing(t_in, strict=True):
                raise ValueError("t_in must be finite and strictly increasing")
            U = np.ascontiguousarray(U, dtype=np.float64)
            if U.ndim == 1 and nu == 1:
                U = U.reshape(-1, 1)
            if U.shape != (n_tin, nu):
                raise ValueError(f"U must have shape ({n_tin}, {nu}), got {U.shape}")
            hold = np.asarray(u_hold)
            if hold.ndim == 0:
                hold = np.full(nu, hold)
            hold = hold.reshape(-1)
            # 0 linear, 1 zero-order hold, 2 linear with steps ending on its kinks
            hold = np.ascontiguousarray(np.where(hold == 2, 2, hold != 0), dtype=np.intc)
            if hold.shape[0] != nu:
                raise ValueError(f"u_hold must have {nu} elements, got {hold.shape[0]}")
        else:
            n_tin = 0
            t_in = np.zeros(1)
            U = np.zeros(1)
            hold = np.zeros(1, dtype=np.intc)
        rtol = float(rtol)
        if not (rtol > 0 and np.isfinite(rtol)):
            raise ValueError("rtol must be positive and finite")
        atol_a = np.asarray(atol, dtype=np.float64)
        if atol_a.ndim == 0:
            atol_a = np.full(nx, float(atol_a))
        atol_a = _vec(atol_a, nx, "atol")
        if np.any(~np.isfinite(atol_a)) or np.any(atol_a < 0):
            raise ValueError("atol must be finite and non-negative")
        if np.any(atol_a == 0) and rtol <= 0:
            raise ValueError("atol and rtol cannot both be zero")
        hmax = float(hmax)
        if not hmax > 0:
            raise ValueError("hmax must be positive")
        max_steps = int(max_steps)

        X = np.empty((n_out, nx))
        Y = np.empty((n_out, ny))
        stats = np.zeros(16)
        ydummy = Y if ny else np.zeros(1)
        # ``keep`` holds the arrays whose addresses ``args`` passes (alive during the call)
        keep = (p, t_in, U, hold, x0, t_out, atol_a, X, ydummy, stats)
        args = (p.ctypes.data, n_tin, t_in.ctypes.data, U.ctypes.data, hold.ctypes.data,
                t0, x0.ctypes.data, n_out, t_out.ctypes.data, rtol, atol_a.ctypes.data,
                float(h0), hmax if np.isfinite(hmax) else 1e300, max_steps,
                X.ctypes.data, ydummy.ctypes.data, stats.ctypes.data)
        return args, keep, t_out, X, Y, stats


def _result(cls, status: int, t_out, X, Y, stats) -> SimResult:
    st = {name: stats[i] for i, name in enumerate(STATS_NAMES)}
    for key in ("steps_accepted", "steps_rejected", "rhs_evals", "jacobian_evals",
                "lu_decompositions", "worst_state"):
        st[key] = int(st[key])
    return cls(t=t_out, X=X, Y=Y, status=int(status), message=_message(int(status), st), stats=st)


def _message(status: int, st: dict) -> str:
    t = st["time_reached"]
    w = st["worst_state"]
    if status == 0:
        return "ok"
    if status == 1:
        return f"step size underflow at t={t:.6g} s; worst state index {w}"
    if status == 2:
        return f"maximum number of steps exceeded at t={t:.6g} s"
    if status == 3:
        return f"non-finite value at t={t:.6g} s; first non-finite state index {w}"
    if status >= 100:
        return f"model returned status {status - 100} at t={t:.6g} s"
    return STATUS_MESSAGES.get(status, f"integrator error {status}") + f" (status {status})"


# -- the explicit, cached, warned fallback to the Python backend ----------------------------
#: sha256 of a model's C source → why the compiled backend is unavailable for it (this process)


