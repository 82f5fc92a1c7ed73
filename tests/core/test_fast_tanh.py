"""The generated models' tanh (model/codegen.py: TANH_C): with HY_FAST_TANH (the Rodas4P
library) a polynomial / exp form within a few ulp of the C library's tanh; without it the C
library's tanh itself (the Rodas5P library of the fitting commands keeps its numbers)."""
import ctypes
import math
import os
import shutil
import subprocess

import numpy as np
import pytest

from hydrocli.model.codegen import TANH_C

CC = os.environ.get("CC", "cc")       # the compiler build_library uses
pytestmark = pytest.mark.skipif(shutil.which(CC) is None, reason="needs a C compiler")


def _tanh_fn(tmp_path, fast: bool):
    src = tmp_path / f"t{int(fast)}.c"
    so = tmp_path / f"t{int(fast)}.so"
    src.write_text(("#define HY_FAST_TANH\n" if fast else "") + "#include <math.h>\n" + TANH_C
                   + "\ndouble f(double x) { return hy_tanh(x); }\n")
    subprocess.run([CC, "-O3", "-fno-math-errno", "-ffp-contract=off", "-fPIC", "-shared", "-o", str(so),
                    str(src), "-lm"], check=True, capture_output=True)
    fn = ctypes.CDLL(str(so)).f
    fn.argtypes, fn.restype = [ctypes.c_double], ctypes.c_double
    return fn


def test_fast_tanh_is_within_a_few_ulp(tmp_path):
    fn = _tanh_fn(tmp_path, fast=True)
    rng = np.random.default_rng(1)
    xs = np.concatenate([10.0 ** rng.uniform(-12, 1.6, 20000), [0.0, 0.1, 0.55, 22.0, 40.0, 1e-300]])
    worst = 0.0
    for x in np.concatenate([xs, -xs]):
        want, got = math.tanh(x), fn(float(x))
        ulps = abs(got - want) / max(math.ulp(want), 5e-324)
        worst = max(worst, ulps)
        assert math.copysign(1.0, got) == math.copysign(1.0, want) or got == 0.0
    assert worst <= 3.0, worst        # measured: <= 0.51 ulp below 0.1, <= 1.5 ulp above 0.55 (vs tanhl)


def test_without_the_define_it_is_the_c_library_tanh(tmp_path):
    fn = _tanh_fn(tmp_path, fast=False)
    for x in (1e-9, 0.03, 0.3, 0.7, 3.0, 30.0, -0.3, -5.0):
        assert fn(x) == math.tanh(x)
