"""Reading the runner's ASCII .vtu files and drawing surfaces with matplotlib:
shared by the figure scripts."""
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

DPI = 150


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
