"""Figure 4 of the paper: the cube deformed by every case of the experiment, pull
and push, on one colour scale; and u_z along the top-surface centre line y = 0.

Usage: /usr/bin/python3 analysis/figure4.py [results/paper] [results/figures]
The cases come from the results (experiment.json order), not from code.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import metrics  # noqa: E402
import numpy as np  # noqa: E402
import results_index  # noqa: E402
from table_io import LOAD_CASES, ROLES  # noqa: E402
from vtu_plot import DPI, draw_surface, plt, read_vtu  # noqa: E402


def make(exp_dir, out):
    """Writes figure4_cube_deformation.png and figure4_centre_line.png; returns the cases drawn."""
    exp = results_index.Experiment(exp_dir)
    cube = {lc: exp.scenario_name(ROLES["cube"][lc]) for lc in LOAD_CASES}
    cases = exp.case_names(list(cube.values()))
    fields = {(lc, c): read_vtu(os.path.join(exp.scenario(cube[lc])[c]["folder"], "surface.vtu"))
              for lc in LOAD_CASES for c in cases}
    vmax = max(f[2]["displacement_magnitude"].max() for f in fields.values())
    fig = plt.figure(figsize=(4 * len(cases), 8))
    for i, lc in enumerate(LOAD_CASES):
        for j, case in enumerate(cases):
            ax = fig.add_subplot(2, len(cases), len(cases) * i + j + 1, projection="3d")
            pts, tris, f = fields[lc, case]
            draw_surface(ax, pts, tris, f["displacement_magnitude"][:, 0], 0, vmax)
            ax.view_init(elev=20, azim=-60)
            ax.set_title(f"{case}, {lc} (max |u| {1000 * f['displacement_magnitude'].max():.1f} mm)", fontsize=9)
    sm = plt.cm.ScalarMappable(norm=plt.Normalize(0, vmax * 1000), cmap="viridis")
    fig.colorbar(sm, ax=fig.axes, shrink=0.6, label="|u| (mm)")
    fig.savefig(os.path.join(out, "figure4_cube_deformation.png"), dpi=DPI)
    plt.close(fig)

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, lc in zip(axes, LOAD_CASES):
        for case in cases:
            _, rest, u = metrics.read_displacements(
                os.path.join(exp.scenario(cube[lc])[case]["folder"], "top_surface.csv"))
            line = np.abs(rest[:, 1]) < 1e-9
            order = np.argsort(rest[line, 0])
            ax.plot(rest[line, 0][order] * 1000, u[line, 2][order] * 1000, marker="o", ms=3, label=case)
        ax.set_xlabel("x on the top face, y = 0 (mm)")
        ax.set_ylabel("u_z (mm)")
        ax.set_title(f"cube {lc}: top-surface centre line")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "figure4_centre_line.png"), dpi=DPI)
    plt.close(fig)
    return cases


if __name__ == "__main__":
    out = sys.argv[2] if len(sys.argv) > 2 else "results/figures"
    os.makedirs(out, exist_ok=True)
    results_index.main(lambda: make(sys.argv[1] if len(sys.argv) > 1 else "results/paper", out), "figure4")
    print("figure 4 written")
