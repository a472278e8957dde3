"""Figure 5 of the paper: the liver at rest, pulled and pushed, with the case the
paper shows (paper_values.json "figure5_case": the hybrid).

Usage: /usr/bin/python3 analysis/figure5.py [results/paper] [results/figures]
Reads the liver scenarios' cases (roles liver_pull and liver_push): the surface at
rest from the pull case's surface.csv (every surface vertex, rest coordinates to 17
digits, the fine surface's order), the triangles and deformed surfaces from each
case's surface.vtu. The liver's mesh folder is not needed (it derives from
third-party data and is not committed: README "Data").
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np  # noqa: E402
import results_index  # noqa: E402
import metrics  # noqa: E402
from table_io import LOAD_CASES, ROLES, paper_values  # noqa: E402
from vtu_plot import DPI, draw_surface, plt, read_vtu  # noqa: E402


def make(exp_dir, out):
    exp = results_index.Experiment(exp_dir)
    case = paper_values()["figure5_case"]
    folders = {lc: exp.by_role(ROLES["liver"][lc]) for lc in LOAD_CASES}
    for lc, cases in folders.items():
        if case not in cases:
            raise results_index.ResultsError(f"{exp.root}: the {ROLES['liver'][lc]} scenario has no '{case}' results")
    pull = folders["pull"][case]["folder"]
    ids, rest_pts, _ = metrics.read_displacements(os.path.join(pull, "surface.csv"))
    if not (ids == np.arange(len(ids))).all():
        raise ValueError(f"{pull}/surface.csv: vertices not in surface order")
    _, tris, _ = read_vtu(os.path.join(pull, "surface.vtu"))
    views = [("rest", rest_pts, np.zeros(len(rest_pts)))]
    for lc in LOAD_CASES:
        pts, _, f = read_vtu(os.path.join(folders[lc][case]["folder"], "surface.vtu"))
        views.append((f"{case}, {lc}", pts, f["displacement_magnitude"][:, 0]))
    vmax = max(v[2].max() for v in views)
    fig = plt.figure(figsize=(15, 5))
    for k, (title, pts, val) in enumerate(views):
        ax = fig.add_subplot(1, 3, k + 1, projection="3d")
        draw_surface(ax, pts, tris, val, 0, vmax)
        ax.view_init(elev=15, azim=-70)
        ax.set_title(title)
    sm = plt.cm.ScalarMappable(norm=plt.Normalize(0, vmax * 1000), cmap="viridis")
    fig.colorbar(sm, ax=fig.axes, shrink=0.6, label="|u| (mm)")
    fig.savefig(os.path.join(out, "figure5_liver.png"), dpi=DPI)
    plt.close(fig)


if __name__ == "__main__":
    out = sys.argv[2] if len(sys.argv) > 2 else "results/figures"
    os.makedirs(out, exist_ok=True)
    results_index.main(lambda: make(sys.argv[1] if len(sys.argv) > 1 else "results/paper", out), "figure5")
    print("figure 5 written")
