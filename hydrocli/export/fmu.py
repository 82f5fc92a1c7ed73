"""Write an FMU: modelDescription.xml, the C sources and a binary compiled at export time.

The sources are the generated model (``Model.c_source``), the integrator exactly as
``hydro simulate`` compiles it (``solve.compiled.integrator_source``), a configuration
header written here (GUID, start values, state nominals, guard messages), the instance logic
(``templates/hydro_fmu_core.c``) and the FMI glue (``hydro_fmi2.c`` or ``hydro_fmi3.c``) with
the FMI headers. The binary
is built with the same compiler flags as the simulator's cache, so FMU and ``hydro simulate``
evaluate the same floating-point code. The archive is written to a temporary file and
renamed (never a half-written FMU).
"""
from __future__ import annotations

import hashlib
import os
import platform
import re
import subprocess
import sys
import tempfile
import uuid
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..version import __version__
from ..errors import HydroError, Problem, SolverError
from ..experiments.initial import start_without_data
from ..model.model import Model
from ..solve.compiled import CFLAGS, LDLIBS, integrator_source
from ..solve.simulate import SolverOptions
from .description import FmuInfo, model_description_fmi2, model_description_fmi3
from .variables import fmu_layout

_HERE = Path(__file__).resolve().parent
_TEMPLATES = _HERE / "templates"
_FMI = _HERE / "fmi"


class UsageError(HydroError):
    exit_code = 2


@dataclass
class ExportOptions:
    fmi: int = 2                    # 2 | 3
    kind: str = "cs"                # cs | me | both (FMI 2 only for me/both)
    rtol: float = 1e-6              # default tolerance of the co-simulation integrator
    stop_time: float = 1.0          # DefaultExperiment stopTime


def model_identifier(name: str) -> str:
    """A C identifier (and file name) from the machine name."""
    ident = re.sub(r"[^A-Za-z0-9_]", "_", name) or "model"
    return ident if not ident[0].isdigit() else f"m_{ident}"


def _kinds(opts: ExportOptions) -> tuple[str, ...]:
    kind = opts.kind.lower()
    if opts.fmi not in (2, 3):
        raise UsageError(Problem(f"--fmi {opts.fmi}: only FMI 2 and 3 are supported", hint="use --fmi 2 or --fmi 3"))
    allowed = {2: {"cs": ("cs",), "me": ("me",), "both": ("me", "cs")}, 3: {"cs": ("cs",)}}[opts.fmi]
    if kind not in allowed:
        raise UsageError(Problem(f"--kind {opts.kind} is not available for FMI {opts.fmi}",
                                 hint=f"use --kind {' | '.join(allowed)}"))
    return allowed[kind]


def _c_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _c_array(name: str, values) -> str:
    vals = [repr(float(v)) for v in values] or ["0.0"]
    return f"static const double {name}[{len(vals)}] = {{{', '.join(vals)}}};"


def config_header(model: Model, x0: np.ndarray, guid: str, rtol: float) -> str:
    so = SolverOptions()
    guards = [msg for _, msg in model.equations.guards]
    return "\n".join([
        f"/* hydrocli FMU configuration for '{model.name}' (generated; do not edit) */",
        f"#define HY_FMU_GUID {_c_string(guid)}",
        f"#define HY_FMU_RTOL {rtol!r}",
        f"#define HY_FMU_ATOL_FACTOR {float(so.atol_factor)!r}  /* atol_i = factor * rtol * nominal_i */",
        f"#define HY_FMU_MAX_STEPS {int(so.max_steps)}L",
        f"#define HY_FMU_NGUARD {len(guards)}",
        _c_array("HY_FMU_X0", x0),
        _c_array("HY_FMU_P0", model.p0),
        _c_array("HY_FMU_NOMINAL", [s.nominal if s.nominal > 0 else 1.0 for s in model.states]),
        f"static const char *const HY_FMU_GUARDS[{max(len(guards), 1)}] = "
        f"{{{', '.join(_c_string(g) for g in guards) or '0'}}};",
        "",
    ])


def _sources(model: Model, x0: np.ndarray, fmi: int, rtol: float) -> tuple[dict[str, str], str]:
    glue = f"hydro_fmi{fmi}.c"
    files = {"model.c": model.c_source, "hy_integrator.c": integrator_source(),
             "hydro_fmu_core.c": (_TEMPLATES / "hydro_fmu_core.c").read_text(encoding="utf-8"),
             glue: (_TEMPLATES / glue).read_text(encoding="utf-8")}
    for h in sorted(_FMI.glob(f"fmi{fmi}*.h")):
        files[h.name] = h.read_text(encoding="utf-8")
    files["FMI_HEADERS_LICENSE.txt"] = (_FMI / "LICENSE.txt").read_text(encoding="utf-8")
    digest = hashlib.sha256()
    for name in sorted(files):
        digest.update(name.encode() + b"\0" + files[name].encode() + b"\0")
    digest.update(np.asarray(x0, float).tobytes() + model.p0.tobytes() + str(fmi).encode())
    guid = "{" + str(uuid.UUID(bytes=digest.digest()[:16], version=4)) + "}"
    files["hy_fmu_config.h"] = config_header(model, x0, guid, rtol)
    return files, guid


def build_description(ident: str, glue: str) -> str:
    """FMI 3.0 sources/buildDescription.xml: one C file (it includes the others), libm."""
    return ('<?xml version="1.0" encoding="UTF-8"?>\n<fmiBuildDescription fmiVersion="3.0">\n'
            f'  <BuildConfiguration modelIdentifier="{ident}">\n'
            f'    <SourceFileSet language="C99">\n      <SourceFile name="{glue}"/>\n    </SourceFileSet>\n'
            '    <Library name="m"/>\n  </BuildConfiguration>\n</fmiBuildDescription>\n')


def _platform_dir(fmi: int) -> str:
    if sys.platform.startswith("linux") and platform.machine() in ("x86_64", "AMD64"):
        return "linux64" if fmi == 2 else "x86_64-linux"
    raise UsageError(Problem(f"FMU binaries are built for Linux x86-64 only (this is {sys.platform}/"
                             f"{platform.machine()})", hint="export on a Linux x86-64 machine"))


def _compile(src_dir: Path, glue: str, so_path: Path) -> None:
    cc = os.environ.get("CC", "cc")
    cmd = [cc, *CFLAGS, f"-I{src_dir}", "-o", str(so_path), str(src_dir / glue), *LDLIBS]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600, check=False)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise SolverError(Problem(f"cannot compile the FMU binary with {cc!r}: {exc}",
                                  hint="install a C compiler (gcc) or set CC")) from None
    if proc.returncode != 0:
        tail = "\n".join((proc.stderr or proc.stdout).strip().splitlines()[-20:])
        raise SolverError(Problem(f"compiling the FMU binary failed (exit {proc.returncode}):\n{tail}",
                                  hint="report this with the machine file; the sources are in the FMU's sources/"))


def export_fmu(model: Model, out: str | Path, opts: ExportOptions | None = None,
               x0: np.ndarray | None = None) -> Path:
    """Write ``out`` (.fmu) for ``model`` with its current parameter values as start values;
    the states start at the file's values with its ``same_as`` and ``balance`` initial rules
    applied (inputs at 0); ``output`` rules need a recording and keep the file's number."""
    opts = opts or ExportOptions()
    kinds = _kinds(opts)
    x0 = start_without_data(model) if x0 is None else np.asarray(x0, dtype=float)
    out = Path(out)
    plat = _platform_dir(opts.fmi)
    layout = fmu_layout(model, x0)
    ident = model_identifier(model.name)
    files, guid = _sources(model, x0, opts.fmi, opts.rtol)
    glue = f"hydro_fmi{opts.fmi}.c"
    info = FmuInfo(model_name=model.name, identifier=ident, guid=guid,
                   description=f"hydrocli machine '{model.name}' (netlist sha256 {model.netlist_sha[:16]})",
                   kinds=kinds, tool=f"hydrocli {__version__}", rtol=opts.rtol, stop_time=opts.stop_time,
                   source_files=(glue,))
    xml = model_description_fmi2(layout, info) if opts.fmi == 2 else model_description_fmi3(layout, info)
    out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="hydro_fmu_") as tmp:
        src = Path(tmp) / "sources"
        src.mkdir()
        for name, text in files.items():
            (src / name).write_text(text, encoding="utf-8")
        so = Path(tmp) / f"{ident}.so"
        _compile(src, glue, so)
        fd, tmp_fmu = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent)
        os.close(fd)
        try:
            with zipfile.ZipFile(tmp_fmu, "w", zipfile.ZIP_DEFLATED) as z:
                z.writestr("modelDescription.xml", xml)
                z.write(so, f"binaries/{plat}/{ident}.so")
                for name in sorted(files):
                    z.write(src / name, f"sources/{name}")
                if opts.fmi == 3:
                    z.writestr("sources/buildDescription.xml", build_description(ident, glue))
                    z.write(src / "FMI_HEADERS_LICENSE.txt", "documentation/licenses/FMI_HEADERS_LICENSE.txt")
            os.replace(tmp_fmu, out)
        finally:
            if os.path.exists(tmp_fmu):
                os.unlink(tmp_fmu)
    return out
