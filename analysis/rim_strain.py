#!/usr/bin/python3
"""The surface strain around a grasped patch, at several mesh sizes.

Reads the surface.vtu a case writes (its points deformed, the displacement per
vertex beside them) and
reports the principal stretches of the surface (the singular values of the
deformation gradient's restriction to each triangle's plane) in bands around the
grasped patch: the held vertices are those displaced by exactly the tool's
displacement (--displacement: a rigid grasp, in a model that holds the fine
surface's vertices themselves: the FEM reference, pd, VBD, XPBD, PBD; on a coarse
model's interpolated surface none is exactly held), or those whose rest position
lies within a radius of a point (--patch: a compliant grasp's pads, which move
with the tissue); the rim's triangles have one or two held vertices; the other free
triangles are banded by the straight-line distance of their centroid from the
nearest held vertex. A
strain that concentrates at the patch's rim (the edge of a rigid punch, where the
continuum's displacement gradient is singular) grows there as the triangles shrink,
and converges away from it.

  /usr/bin/python3 analysis/rim_strain.py --displacement 0 0 0.015 \
      LABEL=path/to/surface.vtu ...
  /usr/bin/python3 analysis/rim_strain.py --patch X Y Z RADIUS LABEL=surface.vtu ...
"""
import argparse
import re
import sys

import numpy as np


def read_surface_vtu(path):
    """Rest points, displacement and triangles of a surface.vtu (ASCII; its points
    are the deformed ones, so the rest is points - displacement)."""
    try:
        text = open(path).read()
    except OSError as e:
        sys.exit(f"{path}: {e.strerror}")

    def array(name, dtype):
        m = re.search(r'<DataArray[^>]*Name="%s"[^>]*format="ascii"[^>]*>(.*?)</DataArray>' % name, text, re.S)
        if not m:
            sys.exit(f"{path}: no ASCII DataArray named {name}")
        return np.array(m.group(1).split(), dtype=dtype)

    points = array("Points", float).reshape(-1, 3)
    displacement = array("displacement", float).reshape(-1, 3)
    connectivity = array("connectivity", np.int64)
    offsets = array("offsets", np.int64)
    if not np.array_equal(np.diff(np.concatenate([[0], offsets])), np.full(len(offsets), 3)):
        sys.exit(f"{path}: not a triangle surface")
    return points - displacement, displacement, connectivity.reshape(-1, 3)


def principal_stretches(rest, deformed, triangles):
    """Largest and smallest in-plane stretch of each triangle (n x 2)."""
    e1 = rest[triangles[:, 1]] - rest[triangles[:, 0]]
    e2 = rest[triangles[:, 2]] - rest[triangles[:, 0]]
    # An orthonormal frame of each rest triangle's plane, and the edges in it.
    t1 = e1 / np.linalg.norm(e1, axis=1, keepdims=True)
    normal = np.cross(e1, e2)
    t2 = np.cross(normal / np.linalg.norm(normal, axis=1, keepdims=True), t1)
    rest_2d = np.stack([np.stack([np.einsum("ij,ij->i", e, t) for t in (t1, t2)], 1) for e in (e1, e2)], 2)
    d1 = deformed[triangles[:, 1]] - deformed[triangles[:, 0]]
    d2 = deformed[triangles[:, 2]] - deformed[triangles[:, 0]]
    deformed_edges = np.stack([d1, d2], 2)  # n x 3 x 2
    F = deformed_edges @ np.linalg.inv(rest_2d)  # n x 3 x 2
    s = np.linalg.svd(F, compute_uv=False)
    return s


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    held_by = p.add_mutually_exclusive_group(required=True)
    held_by.add_argument("--displacement", type=float, nargs=3, help="a rigid grasp's displacement (m)")
    held_by.add_argument("--patch", type=float, nargs=4, metavar=("X", "Y", "Z", "RADIUS"),
                         help="a compliant grasp's point and radius (m), in the rest configuration")
    p.add_argument("cases", nargs="+", help="LABEL=surface.vtu")
    a = p.parse_args()
    bands_mm = [(0, 0.5), (0.5, 1), (1, 2), (2, 5), (5, np.inf)]
    header = ["case", "triangles", "median edge (mm)", "held vertices", "rim: max stretch", "rim: min stretch"]
    header += [f"free, {lo:g}-{hi:g} mm: max stretch" for lo, hi in bands_mm]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for case in a.cases:
        label, _, path = case.partition("=")
        rest, u, tri = read_surface_vtu(path)
        if a.patch is not None:
            held = np.linalg.norm(rest - np.array(a.patch[:3]), axis=1) <= a.patch[3]
            if not held.any():
                sys.exit(f"{path}: no vertex within {a.patch[3]} m of {a.patch[:3]}")
        else:
            held = np.linalg.norm(u - np.array(a.displacement), axis=1) < 1e-12 * (1 + np.linalg.norm(a.displacement))
            if not held.any():
                sys.exit(f"{path}: no vertex displaced by {a.displacement}")
        s = principal_stretches(rest, rest + u, tri)
        held_in_triangle = held[tri].sum(1)
        rim = (held_in_triangle > 0) & (held_in_triangle < 3)
        free = held_in_triangle == 0
        if not rim.any():
            sys.exit(f"{path}: no triangle on the held patch's rim (every triangle held, or none touching it)")
        held_points = rest[held]
        centroids = rest[tri].mean(1)
        distance = np.full(len(tri), np.inf)
        for start in range(0, len(tri), 4096):  # distance to the nearest held vertex, in blocks
            block = centroids[start:start + 4096]
            distance[start:start + 4096] = np.sqrt(((block[:, None, :] - held_points[None]) ** 2).sum(2).min(1))
        edges = np.linalg.norm(rest[tri[:, 1]] - rest[tri[:, 0]], axis=1)
        row = [label, str(len(tri)), f"{1e3 * np.median(edges):.2f}", str(int(held.sum())),
               f"{s[rim, 0].max():.3f}", f"{s[rim, 1].min():.3f}"]
        for lo, hi in bands_mm:
            inside = free & (distance >= lo * 1e-3) & (distance < hi * 1e-3)
            row.append(f"{s[inside, 0].max():.3f}" if inside.any() else "n/a")
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
