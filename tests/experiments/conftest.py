import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "identify"))
from synth import _cache_dir, eha  # noqa: E402,F401  (fixtures)
