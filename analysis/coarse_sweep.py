"""Beyond the paper: the hybrid's accuracy and cost against its coarse mesh size.

Usage: /usr/bin/python3 analysis/coarse_sweep.py [results/coarse_sweep] [results]
Reads results/coarse_sweep/<scenario>/{fem-direct,hybrid}/ (experiments/coarse_sweep.json);
writes results/tables/coarse_sweep.{md,csv} and results/figures/coarse_sweep.png.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import results_index  # noqa: E402
from table_io import fmt, write_table  # noqa: E402


def sweep_rows(exp_dir):
    """One row per scenario, sorted by coarse node count."""
    exp = results_index.Experiment(exp_dir)
    rows = []
    for scenario, cases in exp.scenarios.items():
        hybrid = cases["hybrid"]
        m = exp.metrics(scenario, "hybrid")
        mesh = hybrid["run"]["mesh"]
        rows.append({"scenario": scenario, "coarse_nodes": mesh["coarse_nodes"], "coarse_tets": mesh["coarse_tets"],
                     "control_points": mesh["control_points"], "median_ms": hybrid["timings"]["step"]["median_ms"],
                     **m})
    return sorted(rows, key=lambda r: r["coarse_nodes"])


def make(exp_dir, out):
    rows = sweep_rows(exp_dir)
    write_table(
        os.path.join(out, "tables"), "coarse_sweep",
        ["coarse nodes", "coarse tets", "control points", "r(u_z)", "relative L2", "|u| ratio at load", "median ms"],
        [[r["coarse_nodes"], r["coarse_tets"], r["control_points"], fmt(r["corr_uz"]),
          fmt(r["rel_l2"]), fmt(r["load_ratio"]), fmt(r["median_ms"], 2)] for r in rows],
        "Cube pull, hybrid against fem-direct on the same fine mesh, as the coarse selection target varies "
        "(experiments/coarse_sweep.json). Beyond the paper, which uses one coarse mesh (153 nodes).")
    fig, ax = plt.subplots(figsize=(6, 4))
    n = [r["coarse_nodes"] for r in rows]
    for key, label in [("corr_uz", "r(u_z)"), ("rel_l2", "relative L2 error"), ("load_ratio", "|u| ratio at load point")]:
        ax.plot(n, [r[key] for r in rows], marker="o", label=label)
    ax.set_xscale("log")
    ax.set_xlabel("coarse nodes")
    ax.set_title("hybrid vs fine FEM, cube pull")
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    fig.tight_layout()
    os.makedirs(os.path.join(out, "figures"), exist_ok=True)
    fig.savefig(os.path.join(out, "figures", "coarse_sweep.png"), dpi=150)
    plt.close(fig)


if __name__ == "__main__":
    make(sys.argv[1] if len(sys.argv) > 1 else "results/coarse_sweep", sys.argv[2] if len(sys.argv) > 2 else "results")
    print("coarse sweep table and figure written")
