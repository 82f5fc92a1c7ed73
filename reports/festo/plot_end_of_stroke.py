"""Plot the 1 V end-of-stroke pressures: real recording, the issue-5 machine (hard stops only)
and the cushioned machine (issue 15). Run from the repository root:
    python3 reports/festo/plot_end_of_stroke.py   → reports/festo/end_of_stroke_1V.png"""
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from hydrocli.experiments.experiment_file import load_all  # noqa: E402
from hydrocli.metrics import esr  # noqa: E402
from hydrocli.runner import load_machine  # noqa: E402
from hydrocli.solve.simulate import SolverOptions, simulate  # noqa: E402

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
MACHINES = {"issue 5 (hard stops)": HERE / "festo_tp511_identified_issue5.yaml",
            "issue 15 (end cushions)": HERE / "festo_tp511_identified.yaml"}
CASES = [("pA", "festo_pA_1V", (4.4, 5.4)), ("pB", "festo_pB_1V", (4.4, 5.4)),
         ("pA", "festo_pA_1V", (16.4, 17.4)), ("pB", "festo_pB_1V", (16.4, 17.4))]


def main():
    fig, axes = plt.subplots(2, 2, figsize=(11, 7), sharey=False)
    for ax, (out, name, (t0, t1)) in zip(axes.T.ravel(), CASES):
        plotted = False
        for label, path in MACHINES.items():
            _, model = load_machine(path, [])
            exp, = load_all(ROOT / "experiments" / "festo" / f"steps_{out}.yaml#{name}", model)
            tr = simulate(model, exp.inputs, exp.t_out, x0=exp.x0(model), opts=SolverOptions(rtol=1e-6))
            w = (exp.t_out >= t0) & (exp.t_out <= t1)
            y, y_hat = exp.measured[out], tr.Y[:, model.output_names.index(out)]
            if not plotted:
                ax.plot(exp.t_out[w], y[w] / 1e5, "k.", ms=2, label="measured")
                plotted = True
            ax.plot(exp.t_out[w], y_hat[w] / 1e5, label=f"{label}: ESR {esr(y, y_hat):.3f} %")
        ax.set_title(f"{name} {'extended' if t0 < 10 else 'retracted'} end")
        ax.set_xlabel("t [s]")
        ax.set_ylabel(f"{out} [bar abs]")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(HERE / "end_of_stroke_1V.png", dpi=110)


if __name__ == "__main__":
    main()
