"""Per-frame time against accuracy, every case of the experiment on the cube
(pull and push): the choice a simulator designer makes.

Usage: /usr/bin/python3 analysis/time_vs_accuracy.py [results/paper] [results/figures]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_index  # noqa: E402
from table_io import LOAD_CASES, ROLES  # noqa: E402
from vtu_plot import DPI, plt  # noqa: E402

FLOOR = 1e-4  # errors below this (the reference itself, solver checks) are drawn here


def make(exp_dir, out):
    """Writes time_vs_accuracy.png; returns the case names plotted."""
    exp = results_index.Experiment(exp_dir)
    ref = exp.require_reference()
    cube = {lc: exp.scenario_name(ROLES["cube"][lc]) for lc in LOAD_CASES}
    cases = exp.case_names(list(cube.values()))
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for lc, marker in zip(LOAD_CASES, ["o", "s"]):
        for case in cases:
            err = 0.0 if case == ref else exp.metrics(cube[lc], case)["rel_l2"]
            t = exp.scenario(cube[lc])[case]["timings"]["step"]["median_ms"]
            ax.scatter(t, max(err, FLOOR), marker=marker)
            ax.annotate(f"{case} ({lc})", (t, max(err, FLOOR)), fontsize=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("median per-frame time (ms)")
    ax.set_ylabel(f"relative L2 error vs {ref} (floored at {FLOOR:g})")
    ax.set_title("cube top surface: time vs accuracy")
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "time_vs_accuracy.png"), dpi=DPI)
    plt.close(fig)
    return cases


if __name__ == "__main__":
    out = sys.argv[2] if len(sys.argv) > 2 else "results/figures"
    os.makedirs(out, exist_ok=True)
    results_index.main(lambda: make(sys.argv[1] if len(sys.argv) > 1 else "results/paper", out), "time_vs_accuracy")
    print("time vs accuracy written")
