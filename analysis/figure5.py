"""Figure 5 of the paper: the liver at rest, pulled and pushed, with the case the
paper shows (paper_values.json "figure5_case": the hybrid).

Usage: /usr/bin/python3 analysis/figure5.py [results/paper] [results/figures]
Reads the liver scenarios' cases (roles liver_pull and liver_push): each case's
surface.csv (displacement by surface vertex, no coordinates) and the liver's rest
surface, points and triangles, from the mesh folder the run wrote
(<scenario>/mesh/fine_surface.vtu). That folder derives from third-party data and
is not committed (README "Data"): the figure is remade where the liver was run
(scripts/reproduce), and analysis/reproduce.py says so and goes on without it
elsewhere.
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
    pull = folders["pull"][case]
    rest_pts = results_index.observed_rest(pull, "surface.csv")
    _, tris, _ = read_vtu(os.path.join(os.path.dirname(pull["folder"]), "mesh", "fine_surface.vtu"))
    views = [("rest", rest_pts, np.zeros(len(rest_pts)))]
    for lc in LOAD_CASES:
        folder = folders[lc][case]["folder"]
        ids, _, u = metrics.read_displacements(os.path.join(folder, "surface.csv"))
        if not (ids == np.arange(len(rest_pts))).all():
            raise results_index.ResultsError(f"{folder}/surface.csv: not the {len(rest_pts)} surface vertices in order")
        views.append((f"{case}, {lc}", rest_pts + u, np.linalg.norm(u, axis=1)))
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
