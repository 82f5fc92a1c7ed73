"""FMU export (FMI 2.0 co-simulation and model exchange, FMI 3.0 co-simulation).

``export_fmu(model, "eha.fmu", ExportOptions(fmi=2, kind="cs"))``: see docs/export.md.
"""
from .fmu import ExportOptions, export_fmu, model_identifier

__all__ = ["ExportOptions", "export_fmu", "model_identifier"]
