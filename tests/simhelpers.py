"""Helpers shared by the physics and component tests: build a machine from YAML text and
simulate it; measure an oscillation frequency."""
import numpy as np

from hydrocli.model.builder import build_model
from hydrocli.netlist.loader import load_netlist_text
from hydrocli.solve.simulate import InputTable, SolverOptions, simulate


def run(text, t_end, n=2001, inputs=None, rtol=1e-8, x0=None, backend="auto", max_step=np.inf):
    """Build a machine from YAML text and simulate it with constant (or tabulated) inputs."""
    m = build_model(load_netlist_text(text))
    t = np.linspace(0.0, t_end, n)
    if inputs is None:
        tab = InputTable.constant(m)
    elif callable(inputs):
        tab = InputTable(t, np.column_stack([inputs(t)[k] for k in m.input_names]))
    else:
        tab = InputTable.constant(m, values=inputs)
    xs = m.x0.copy()
    for k, v in (x0 or {}).items():
        xs[m.state_index(k)] = v
    tr = simulate(m, tab, t, p=m.p0, x0=xs, opts=SolverOptions(rtol=rtol, backend=backend, max_step=max_step))
    return m, tr, tab


def col(m, tr, name):
    return tr.X[:, m.state_index(name)]


def oscillation_frequency(t, y):
    """Angular frequency from the mean spacing of upward zero crossings of y − mean(y)."""
    y = y - 0.5 * (y.max() + y.min())
    idx = np.where((y[:-1] < 0) & (y[1:] >= 0))[0]
    tc = t[idx] - y[idx] * (t[idx + 1] - t[idx]) / (y[idx + 1] - y[idx])
    assert len(tc) >= 3, "no oscillation found"
    return 2 * np.pi / np.mean(np.diff(tc))
