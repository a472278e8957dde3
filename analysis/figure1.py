"""Figure 1 of the paper: the hybrid mesh construction (paper 1.2) on the cube.

Usage: /usr/bin/python3 analysis/figure1.py [results/paper] [results/figures]
Reads the meshes the runner wrote beside the cube pull's results
(results/<experiment>/<scenario in role cube_pull>/mesh/*.vtu; committed, the cube
being the project's own).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_index  # noqa: E402
from table_io import ROLES  # noqa: E402
from vtu_plot import DPI, draw_surface, plt, read_vtu, tet_edges  # noqa: E402
import numpy as np  # noqa: E402


def make(exp_dir, out):
    """Hybrid mesh construction (paper figure 1): fine surface, fine base mesh,
    selected vertices, coarse mesh, control points; a slice y = 0 of the cube."""
    exp = results_index.Experiment(exp_dir)
    mdir = os.path.join(exp.root, exp.scenario_name(ROLES["cube"]["pull"]), "mesh")
    for name in ["fine_surface.vtu", "fine_volume.vtu", "coarse_volume.vtu", "control_points.vtu"]:
        if not os.path.isfile(os.path.join(mdir, name)):
            raise results_index.ResultsError(f"{mdir}/{name}: missing (the runner writes the meshes beside the "
                                             "results unless --no-mesh-output)")
    sv, sf, _ = read_vtu(os.path.join(mdir, "fine_surface.vtu"))
    fv, ft, _ = read_vtu(os.path.join(mdir, "fine_volume.vtu"))
    cv, ct, _ = read_vtu(os.path.join(mdir, "coarse_volume.vtu"))
    cp, _, _ = read_vtu(os.path.join(mdir, "control_points.vtu"))
    fig = plt.figure(figsize=(16, 4))
    ax = fig.add_subplot(1, 4, 1, projection="3d")
    draw_surface(ax, sv, sf, sv[:, 2], 0, sv[:, 2].max())
    ax.set_title(f"1. fine surface\n{len(sv)} vertices, {len(sf)} triangles")

    def slice_edges(ax, V, T, color, lw):
        # Edges of the tets cut by the plane y = 0, drawn in x-z.
        cut = T[(V[T][:, :, 1].min(1) <= 0) & (V[T][:, :, 1].max(1) >= 0)]
        for a, b in tet_edges(cut):
            ax.plot(V[[a, b], 0], V[[a, b], 2], color=color, lw=lw)

    ax = fig.add_subplot(1, 4, 2)
    slice_edges(ax, fv, ft, "0.6", 0.2)
    ax.set_title(f"2. fine base mesh (TetGen), tets cut by y=0\n{len(fv)} nodes, {len(ft)} tets")
    ax.set_aspect("equal")
    ax = fig.add_subplot(1, 4, 3)
    ax.scatter(fv[:, 0], fv[:, 2], s=0.5, c="0.7")
    near = np.abs(cv[:, 1]) < 0.006
    ax.scatter(cv[near, 0], cv[near, 2], s=12, c="tab:red")
    ax.set_title(f"3. selected vertices (|y| < 6 mm shown)\n{len(cv)} selected")
    ax.set_aspect("equal")
    ax = fig.add_subplot(1, 4, 4, projection="3d")
    draw_surface(ax, sv, sf, np.zeros(len(sv)), 0, 1, cmap="Greys")
    ax.collections[-1].set_alpha(0.05)
    for a, b in tet_edges(ct):
        ax.plot(cv[[a, b], 0], cv[[a, b], 1], cv[[a, b], 2], color="tab:blue", lw=0.3)
    ax.scatter(cp[:, 0], cp[:, 1], cp[:, 2], s=6, c="tab:red")
    ax.set_title(f"4-5. coarse mesh {len(cv)} nodes / {len(ct)} tets\n+ {len(cp)} control points (red)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "figure1_hybrid_mesh.png"), dpi=DPI)
    plt.close(fig)


if __name__ == "__main__":
    out = sys.argv[2] if len(sys.argv) > 2 else "results/figures"
    os.makedirs(out, exist_ok=True)
    results_index.main(lambda: make(sys.argv[1] if len(sys.argv) > 1 else "results/paper", out), "figure1")
    print("figure 1 written")
