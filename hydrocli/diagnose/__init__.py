"""``hydro diagnose``: locate the mismatch, name the missing physics, model it, show the
fit improve on held-out data. See :mod:`.engine` and docs/diagnose.md."""
from .engine import Diagnosis, Settings, diagnose

__all__ = ["Diagnosis", "Settings", "diagnose"]
