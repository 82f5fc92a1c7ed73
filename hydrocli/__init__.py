"""hydrocli: model, simulate, identify, validate and diagnose hydraulic machines.

Python API (see hydrocli.api and docs/export.md)::

    import hydrocli as hy
    m = hy.load_machine("machines/eha_testbench.yaml", set={"load.m": "80 kg"})
    r = m.simulate("experiments/quickstart/validate.yaml"); r.to_pandas(); r.plot()
    fit = m.identify(["experiments/quickstart/train.yaml"])
    d = hy.diagnose(m, train=[...], validate=[...])
    m.export_fmu("eha.fmu")
"""
__version__ = "0.1.0"

__all__ = ["__version__", "load_machine", "load_experiment", "diagnose", "Machine", "SimulationResult", "Fit"]


def __getattr__(name: str):
    """The API is imported on first use, so ``import hydrocli`` (and ``hydro --version``) stays light."""
    if name in __all__ and name != "__version__":
        from . import api
        return getattr(api, name)
    raise AttributeError(f"module 'hydrocli' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + __all__)
