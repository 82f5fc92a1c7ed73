"""hydrocli: model, simulate, identify, validate and diagnose hydraulic machines.

Python API (hydrocli.api; docs/export.md)::

    import hydrocli as hy
    m = hy.load_machine("machines/eha_testbench.yaml", set={"load.m": "80 kg"})
    r = m.simulate("experiments/quickstart/validate.yaml"); r.to_pandas(); r.plot()
    fit = m.identify(["experiments/quickstart/train.yaml"])
    d = hy.diagnose(m, train=[...], validate=[...])
    m.export_fmu("eha.fmu")

The API is imported on first use, so ``import hydrocli`` (and ``hydro --version``) stays light.
``hydrocli.diagnose`` is both the diagnosis subpackage and, as DESIGN.md's API asks, a
callable: calling it runs :func:`hydrocli.api.diagnose`.
"""
import sys as _sys
import types as _types

__version__ = "0.1.0"

__all__ = ["__version__", "load_machine", "load_experiment", "diagnose", "Machine", "SimulationResult", "Fit"]


class _CallableDiagnose(_types.ModuleType):
    """The ``hydrocli.diagnose`` subpackage, callable as ``hy.diagnose(machine, train=…, validate=…)``."""

    def __call__(self, *args, **kwargs):
        from .api import diagnose
        return diagnose(*args, **kwargs)


class _Package(_types.ModuleType):
    def __setattr__(self, name, value):
        if name == "diagnose" and isinstance(value, _types.ModuleType):
            value.__class__ = _CallableDiagnose     # set by the import system when the subpackage loads
        super().__setattr__(name, value)


_sys.modules[__name__].__class__ = _Package


def __getattr__(name: str):
    if name == "diagnose":
        import importlib
        return importlib.import_module(".diagnose", __name__)
    if name in __all__ and name != "__version__":
        from . import api
        return getattr(api, name)
    raise AttributeError(f"module 'hydrocli' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
