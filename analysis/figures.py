"""Figures 1, 4, 5 of the paper (and a time-vs-accuracy plot) from raw results.

Usage: /usr/bin/python3 analysis/figures.py [results/paper] [results/figures]
Reads results/<experiment>/<scenario>/{mesh,<case>}/ files only.
"""
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import metrics  # noqa: E402
import results_index  # noqa: E402

DPI = 150
MODELS = [("fem-direct", "fine FEM"), ("pbd", "PBD"), ("hybrid", "hybrid")]


def read_vtu(path):
    """Points (#V x 3), cells (#C x k) and point fields {name: array} of an ASCII .vtu."""
    text = open(path).read()

    def array(name_pattern, after=0):
        m = re.search(r"<DataArray[^>]*" + name_pattern + r"[^>]*>(.*?)</DataArray>", text[after:], re.S)
        if not m:
            raise ValueError(f"{path}: no DataArray {name_pattern}")
        return np.array(m.group(1).split(), dtype=float)

    points = array('Name="Points"').reshape(-1, 3)
    conn = array('Name="connectivity"').astype(int)
    offsets = array('Name="offsets"').astype(int)
    k = offsets[0] if len(offsets) else 0
    cells = conn.reshape(-1, k) if k else np.zeros((0, 0), int)
    fields = {}
    pd = re.search(r"<PointData>(.*?)</PointData>", text, re.S)
    if pd:
        for m in re.finditer(r'<DataArray[^>]*Name="([^"]+)"[^>]*NumberOfComponents="(\d+)"[^>]*>(.*?)</DataArray>',
                             pd.group(1), re.S):
            fields[m.group(1)] = np.array(m.group(3).split(), dtype=float).reshape(-1, int(m.group(2)))
    return points, cells, fields


def draw_surface(ax, points, tris, values, vmin, vmax, cmap="viridis"):
    polys = points[tris]
    face_values = values[tris].mean(axis=1)
    norm = plt.Normalize(vmin, vmax)
    coll = Poly3DCollection(polys, facecolors=plt.get_cmap(cmap)(norm(face_values)), edgecolor="k", linewidths=0.05)
    ax.add_collection3d(coll)
    lo, hi = points.min(0), points.max(0)
    c, r = (lo + hi) / 2, (hi - lo).max() / 2
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_axis_off()


def tet_edges(tets):
    """The unique edges (a, b), a < b, of a list of tets (#T x 4)."""
    edges = set()
    for t in tets:
        for a in range(4):
            for b in range(a + 1, 4):
                edges.add((min(t[a], t[b]), max(t[a], t[b])))
    return sorted(edges)


def figure1(exp_dir, out):
    """Hybrid mesh construction (paper figure 1): fine surface, fine base mesh,
    selected vertices, coarse mesh, control points; a slice y = 0 of the cube."""
    mdir = os.path.join(exp_dir, "cube-pull", "mesh")
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


def figure4(exp_dir, out):
    """The cube deformed by each model, pull and push, one colour scale; and u_z
    along the top-surface centre line y = 0."""
    fields = {}
    for case in ["pull", "push"]:
        for model, _ in MODELS:
            fields[case, model] = read_vtu(os.path.join(exp_dir, f"cube-{case}", model, "surface.vtu"))
    vmax = max(f[2]["displacement_magnitude"].max() for f in fields.values())
    fig = plt.figure(figsize=(12, 8))
    for i, case in enumerate(["pull", "push"]):
        for j, (model, label) in enumerate(MODELS):
            ax = fig.add_subplot(2, 3, 3 * i + j + 1, projection="3d")
            pts, tris, f = fields[case, model]
            draw_surface(ax, pts, tris, f["displacement_magnitude"][:, 0], 0, vmax)
            ax.view_init(elev=20, azim=-60)
            ax.set_title(f"{label}, {case} (max |u| {1000 * f['displacement_magnitude'].max():.1f} mm)")
    sm = plt.cm.ScalarMappable(norm=plt.Normalize(0, vmax * 1000), cmap="viridis")
    fig.colorbar(sm, ax=fig.axes, shrink=0.6, label="|u| (mm)")
    fig.savefig(os.path.join(out, "figure4_cube_deformation.png"), dpi=DPI)
    plt.close(fig)

    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=False)
    for ax, case in zip(axes, ["pull", "push"]):
        for model, label in MODELS + [("fem-iterative", "fine FEM (iterative)")]:
            if model == "fem-iterative":
                continue
            _, rest, u = metrics.read_displacements(os.path.join(exp_dir, f"cube-{case}", model, "top_surface.csv"))
            line = np.abs(rest[:, 1]) < 1e-9
            order = np.argsort(rest[line, 0])
            ax.plot(rest[line, 0][order] * 1000, u[line, 2][order] * 1000, marker="o", ms=3, label=label)
        ax.set_xlabel("x on the top face, y = 0 (mm)")
        ax.set_ylabel("u_z (mm)")
        ax.set_title(f"cube {case}: top-surface centre line")
        ax.grid(alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "figure4_centre_line.png"), dpi=DPI)
    plt.close(fig)


def figure5(exp_dir, out):
    """The liver at rest, pulled and pushed (hybrid)."""
    rest_pts, tris, _ = read_vtu(os.path.join(exp_dir, "liver-pull", "mesh", "fine_surface.vtu"))
    views = [("rest", rest_pts, np.zeros(len(rest_pts)))]
    for case in ["pull", "push"]:
        pts, _, f = read_vtu(os.path.join(exp_dir, f"liver-{case}", "hybrid", "surface.vtu"))
        views.append((f"hybrid, {case}", pts, f["displacement_magnitude"][:, 0]))
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


def time_vs_accuracy(exp_dir, out):
    """Per-frame time against relative L2 error, every model, cube pull and push."""
    exp = results_index.load_experiment(exp_dir)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for case, marker in [("pull", "o"), ("push", "s")]:
        cases = exp[f"cube-{case}"]
        _, rest, u_ref = metrics.read_displacements(os.path.join(cases["fem-direct"]["folder"], "top_surface.csv"))
        for name, c in cases.items():
            if name == "fem-direct":
                err = 0.0
            else:
                _, _, u = metrics.read_displacements(os.path.join(c["folder"], "top_surface.csv"))
                err = np.linalg.norm(u - u_ref) / np.linalg.norm(u_ref)
            t = c["timings"]["step"]["median_ms"]
            ax.scatter(t, max(err, 1e-4), marker=marker)
            ax.annotate(f"{name} ({case})", (t, max(err, 1e-4)), fontsize=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("median per-frame time (ms)")
    ax.set_ylabel("relative L2 error vs fine FEM (floored at 1e-4)")
    ax.set_title("cube: time vs accuracy")
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "time_vs_accuracy.png"), dpi=DPI)
    plt.close(fig)


def make_figures(exp_dir, out):
    os.makedirs(out, exist_ok=True)
    figure1(exp_dir, out)
    figure4(exp_dir, out)
    figure5(exp_dir, out)
    time_vs_accuracy(exp_dir, out)


if __name__ == "__main__":
    exp_dir = sys.argv[1] if len(sys.argv) > 1 else "results/paper"
    out = sys.argv[2] if len(sys.argv) > 2 else "results/figures"
    make_figures(exp_dir, out)
    print(f"figures written to {out}")
