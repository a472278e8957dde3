"""Mesh-independent observation points for every suite scenario role, the converged
answer at them, interpolation from any discretisation onto them, and a scorer
(docs/benchmark_format.md).

Usage: /usr/bin/python3 analysis/observation_points.py [RESULTS/suite] [OUT] [--converged STUDY]

Today the leaderboard scores a case at the suite mesh's own vertices, so a model on
another mesh cannot be scored. The observation points are those vertices named once,
with their rest coordinates, so that any model can be read at them:

- surface points: the observed surface vertices of the role's paper-sized suite mesh
  (its reference case's top_surface.csv), named `s<vertex>`, on the scenario's observed
  patch (`observe.vertices`: `top` is the top face, `all` the whole surface). A refined
  role (`cube_pull_disc_10k`) shares its base role's points (converged_fields.base_role).
- interior points: the scenario's probes (`p<probe>`: the flap's centre, the liver's
  tumour) or the Truth Cube's beads (`b<row of the bead table>`).
- third-party geometry is never written with coordinates (README "Data"): the liver's
  surface points give `source_vertex`, the vertex's index in the surface the runner
  builds from the data directory's liver-smooth.obj (the index every committed liver CSV
  uses), and `file_vertex`, its vertex in that file (REPAIRED_SURFACES); the beads give
  their table row. FILE_COORDINATES and BEAD_COORDINATES say how a reader gets the
  coordinates; surface_coordinates gets them.

The converged answer at the surface points is converged_fields.read()'s field (the
reference study's finest run at the suite mesh's vertices), at the probes that run's
probes.csv; its label and its own estimated error (experiments/suite_reference_errors.json,
the role's "converged" entry) go in the sidecar JSON.

Writes OUT/<role>.csv (surface points), OUT/<role>_interior.csv (where the role has
probes) and OUT/<role>.json (the patch, the converged run and its error, or why there is
no converged answer) for every role of RESULTS/suite/experiment.json. Default OUT:
results/observation_points.
"""
import argparse
import csv
import json
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import converged_fields  # noqa: E402
import leaderboard  # noqa: E402
import metrics  # noqa: E402
import results_index  # noqa: E402
import truth_cube  # noqa: E402
from results_index import ResultsError  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SUITE = os.path.join(REPO, "results", "suite")
OUT = os.path.join(REPO, "results", "observation_points")
REFERENCE_ERRORS = leaderboard.REFERENCE_ERRORS

# A point farther than this fraction of the bounding-box diagonal of the model's rest
# surface (or volume) is an error: another frame, another unit, another body. A coarser
# model's facets of a curved boundary lie closer: the suite torus's points are within 0.9 %
# of the diagonal of the torus generated at resolution 10 (200 vertices; 3.7 % at 5), the
# liver's coarse mesh within 1 mm (1 %) of its fine surface (run.json max_embedding_distance).
REL_TOLERANCE = 0.02
INSIDE_TOLERANCE = 1e-12  # barycentric weight below zero still counted inside a tet (rounding)
CANDIDATES = 8  # nearest centroids whose exact distance bounds the search radius

PATCHES = {
    "top": ("top_face", "the top face: the surface vertices within observe.top_tolerance of the highest z "
                        "(the cube's face the disc load or the sphere acts on)"),
    "all": ("whole_surface", "the whole surface: every vertex of the body's boundary surface"),
}
FILE_COORDINATES = (
    "source_vertex: the vertex's index in the surface the runner builds from the data directory's file "
    "(source.surface: its vertices times source.unit_scale, in metres, its self-intersections repaired by "
    "CGAL), the index every committed CSV of this body uses. file_vertex: the same vertex's 0-based index "
    "among the file's vertices (its 'v' lines): its rest position is that vertex's coordinates times "
    "unit_scale, to the bit; -1 for a vertex the repair made, in no file, whose position only the runner's "
    "surface gives (`tissuebench mesh --surface FILE --unit-scale S --repair-self-intersections --out DIR`, "
    "DIR/fine_surface.vtu's point source_vertex, or a run's <scenario>/mesh/fine_surface.vtu). "
    "observation_points.surface_coordinates reads them.")
# The runner's surface built from a data file against the file: CGAL 5.5's repair
# (meshing/self_intersections.cc) keeps the file's vertices in their order but `dropped`,
# and makes vertices in no file, at the runner's indices `made` (recycled slots). Measured
# with `tissuebench mesh --surface liver-smooth.obj --unit-scale 0.01
# --repair-self-intersections`: every other vertex is the file's times 0.01, bit for bit.
# {(surface, vertices before the repair): map}; the tests check it against the committed
# reference's clamped and grasped vertices.
REPAIRED_SURFACES = {
    ("data:meshes/liver-smooth.obj", 2194): {"dropped": (384, 386, 835, 836, 837, 2030), "made": (2025,)},
}
BEAD_COORDINATES = (
    "table_row is the bead's row in the data directory's data/truthcube/uniaxial_positions.csv (after its "
    "header lines; analysis/truth_cube.py read_table). Its rest coordinates in metres: frame.centre_m + "
    "frame.axes * (table rest position in mm - frame.origin_mm) / 1000 (truth_cube.to_model_mm).")


# ---------------------------------------------------------------------------------
# Input checks: each failure one line naming the argument, the point or the vertex.

def _array(name, a, columns, dtype=float):
    """a as a #N by columns array of dtype; a ValueError naming `name` when its shape is not that."""
    try:
        out = np.asarray(a, dtype=dtype)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: not a numeric array ({e})") from None
    if out.ndim != 2 or out.shape[1] != columns:
        raise ValueError(f"{name}: expected #N by {columns}, got shape {out.shape}")
    return out


def _finite(name, a, what="row"):
    """Raises a ValueError naming the first row of `a` holding a NaN or an infinity."""
    bad = np.flatnonzero(~np.all(np.isfinite(a), axis=1))
    if len(bad):
        raise ValueError(f"{name}: {what} {bad[0]} is not finite ({a[bad[0]].tolist()})")


def _point_names(names, count):
    """The points' names for messages: "point <name>", or "point <row>" without names."""
    if names is None:
        return [f"point {k}" for k in range(count)]
    if len(names) != count:
        raise ValueError(f"names: {len(names)} names for {count} points")
    return [f"point {n}" for n in names]


def _check_points(points, names):
    """points as #P by 3 finite floats (at least one) and their names for messages."""
    p = _array("points", points, 3)
    if len(p) == 0:
        raise ValueError("points: none given")
    names = _point_names(names, len(p))
    bad = np.flatnonzero(~np.all(np.isfinite(p), axis=1))
    if len(bad):
        raise ValueError(f"points: {names[bad[0]]} is not finite ({p[bad[0]].tolist()})")
    return p, names


def _check_mesh(V, F, U, corners, what):
    """V #V by 3, F #F by corners (ints into V), U #V by 3, every array finite where F
    uses it; returns them as arrays."""
    V = _array("V", V, 3)
    F = _array(what, F, corners, dtype=float)
    U = _array("U", U, 3)
    if len(F) == 0 or len(V) == 0:
        raise ValueError(f"empty mesh: {len(V)} vertices, {len(F)} {what} rows")
    if np.any(F != np.round(F)):
        raise ValueError(f"{what}: indices must be integers")
    F = F.astype(np.int64)
    if F.min() < 0 or F.max() >= len(V):
        raise ValueError(f"{what}: index {F.min() if F.min() < 0 else F.max()} out of range for {len(V)} vertices")
    if U.shape != V.shape:
        raise ValueError(f"U: shape {U.shape}, V's is {V.shape}: one displacement per vertex")
    used = np.unique(F)
    for name, a in (("V", V), ("U", U)):
        bad = used[~np.all(np.isfinite(a[used]), axis=1)]
        if len(bad):
            raise ValueError(f"{name}: vertex {bad[0]} is not finite ({a[bad[0]].tolist()}) and {what} uses it")
    return V, F, U


def _within_tolerance(distance, names, V, used, rel_tolerance, what):
    """Raises a ValueError naming the farthest point beyond rel_tolerance times the bounding-box
    diagonal of V[used]."""
    box = V[used]
    diagonal = float(np.linalg.norm(box.max(axis=0) - box.min(axis=0)))
    limit = rel_tolerance * diagonal
    far = np.flatnonzero(distance > limit)
    if len(far):
        k = far[np.argmax(distance[far])]
        raise ValueError(f"{names[k]} is {distance[k]:.3g} m from the {what}, more than {rel_tolerance:g} of its "
                         f"bounding-box diagonal ({limit:.3g} m): another frame, unit or body? "
                         f"({len(far)} of {len(distance)} points that far)")


# ---------------------------------------------------------------------------------
# Geometry: closest points on triangles, barycentric weights in tets.

def closest_on_triangles(P, A, B, C):
    """The closest point of each triangle (A[i], B[i], C[i]) to P[i] (Ericson, Real-Time
    Collision Detection, 2005, 5.1.5: the Voronoi regions of the vertices, then of the
    edges, then the face).

    P, A, B, C  #N by 3 points and triangle corners
    Returns Q  #N by 3 closest points, W  #N by 3 their barycentric weights (Q = W A + W B + W C).
    A point at a corner gets that corner's weight exactly 1.
    """
    ab, ac = B - A, C - A
    ap, bp, cp = P - A, P - B, P - C
    dot = lambda x, y: np.einsum("ij,ij->i", x, y)  # noqa: E731
    d1, d2 = dot(ab, ap), dot(ac, ap)
    d3, d4 = dot(ab, bp), dot(ac, bp)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    W = np.empty((len(P), 3))
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v, w = vb / denom, vc / denom  # the face; a degenerate triangle falls to an edge or corner below
        W[:] = np.stack([1 - v - w, v, w], axis=1)
        # Assigned from the last region Ericson tests to the first, so the first that holds wins.
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        regions = [
            ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), np.stack([0 * t, 1 - t, t], axis=1)),  # edge BC
            ((vb <= 0) & (d2 >= 0) & (d6 <= 0), np.stack([1 - d2 / (d2 - d6), 0 * d2, d2 / (d2 - d6)], axis=1)),
            ((d6 >= 0) & (d5 <= d6), np.array([0.0, 0.0, 1.0])),  # corner C
            ((vc <= 0) & (d1 >= 0) & (d3 <= 0), np.stack([1 - d1 / (d1 - d3), d1 / (d1 - d3), 0 * d1], axis=1)),
            ((d3 >= 0) & (d4 <= d3), np.array([0.0, 1.0, 0.0])),  # corner B
            ((d1 <= 0) & (d2 <= 0), np.array([1.0, 0.0, 0.0])),  # corner A
        ]
        for mask, weights in regions:
            W[mask] = weights[mask] if weights.ndim == 2 else weights
    bad = ~np.all(np.isfinite(W), axis=1)  # a triangle of zero area that no region above caught
    if np.any(bad):
        corners = np.stack([A[bad], B[bad], C[bad]], axis=1)
        nearest = np.argmin(np.linalg.norm(corners - P[bad][:, None, :], axis=2), axis=1)
        W[bad] = np.eye(3)[nearest]
    Q = W[:, :1] * A + W[:, 1:2] * B + W[:, 2:] * C
    return Q, W


def _candidate_pairs(P, centroids, radius, closest_distance):
    """(point row, element row) pairs that may hold each point's closest element: the
    element whose centroid is nearest bounds the distance, and no element whose centroid
    lies farther than that bound plus `radius` (the largest centroid-to-corner distance)
    can be closer.

    P  #P by 3, centroids  #E by 3; closest_distance(rows, elements) the exact distances.
    """
    tree = cKDTree(centroids)
    k = min(CANDIDATES, len(centroids))
    _, near = tree.query(P, k=k)
    near = near.reshape(len(P), k)
    rows = np.repeat(np.arange(len(P)), k)
    bound = closest_distance(rows, near.ravel()).reshape(len(P), k).min(axis=1)
    lists = tree.query_ball_point(P, bound + radius * (1 + 1e-12) + 1e-300)
    rows = np.repeat(np.arange(len(P)), [len(c) for c in lists])
    elements = np.fromiter((e for c in lists for e in c), dtype=np.int64, count=len(rows))
    return rows, elements


def _first_minimum(rows, key, elements, count):
    """Per point row, the index into rows of its smallest key (ties: the lowest element)."""
    order = np.lexsort((elements, key, rows))
    firsts = np.r_[0, np.flatnonzero(np.diff(rows[order])) + 1]
    if len(firsts) != count:
        raise AssertionError("a point without a candidate element")
    return order[firsts]


def closest_points(points, V, F):
    """The closest point of the triangle surface (V, F) to each point.

    points  #P by 3 query points
    V  #V by 3 rest positions, F  #F by 3 triangles (indices into V)
    Returns tri  #P the closest triangle (the lowest index among equals), W  #P by 3 the
    closest point's barycentric weights in it, Q  #P by 3 the closest points, distance  #P.
    """
    A, B, C = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    centroids = (A + B + C) / 3
    radius = float(np.max(np.linalg.norm(np.stack([A, B, C]) - centroids, axis=2)))

    def distance(rows, tris):
        Q, _ = closest_on_triangles(points[rows], A[tris], B[tris], C[tris])
        return np.linalg.norm(Q - points[rows], axis=1)

    rows, tris = _candidate_pairs(points, centroids, radius, distance)
    Q, W = closest_on_triangles(points[rows], A[tris], B[tris], C[tris])
    d = np.linalg.norm(Q - points[rows], axis=1)
    best = _first_minimum(rows, d, tris, len(points))
    return tris[best], W[best], Q[best], d[best]


def surface_values_at(points, V, F, U, names=None, rel_tolerance=REL_TOLERANCE):
    """A surface model's displacement at observation points: at each point, the closest
    point of the model's rest surface (exact point-triangle distance, Ericson's method,
    among the triangles a cKDTree of their centroids leaves possible), its barycentric
    weights in its triangle, and the displacement interpolated linearly there.

    A point on a curved boundary (the torus, the liver) lies on the suite mesh's
    surface, not on the model's, which approximates the same curved boundary by its own
    facets: the closest point of the model's surface is taken and its distance reported.
    A point farther than rel_tolerance times the bounding-box diagonal of the surface
    F uses is an error naming it (another frame, unit or body). At a vertex of the
    model's surface the value is that vertex's exactly; a linear field is reproduced to
    rounding.

    points  #P by 3 rest positions of the observation points (m)
    V  #V by 3 rest positions of the model's surface vertices (m)
    F  #F by 3 triangles (indices into V): the whole surface or the observed patch
    U  #V by 3 displacements of the vertices (m); only the vertices F uses must be finite
    names  #P names for messages (default: the row)
    Returns values  #P by 3 displacements (m), distance  #P distances from the surface (m).
    Bad input (a NaN, a wrong shape, an empty mesh, a point too far) is a one-line ValueError.
    """
    points, labels = _check_points(points, names)
    V, F, U = _check_mesh(V, F, U, 3, "F")
    tri, W, _, distance = closest_points(points, V, F)
    _within_tolerance(distance, labels, V, np.unique(F), rel_tolerance, "surface")
    values = np.einsum("ij,ijk->ik", W, U[F[tri]])
    return values, distance


def tet_barycentric(P, X0, X1, X2, X3):
    """Barycentric weights of P[i] in the tet (X0[i], X1[i], X2[i], X3[i]).

    P, X0..X3  #N by 3
    Returns W  #N by 4 (summing to 1; negative outside the tet; NaN for a flat tet).
    """
    a, b, c, p = X1 - X0, X2 - X0, X3 - X0, P - X0
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    with np.errstate(divide="ignore", invalid="ignore"):
        w1 = np.einsum("ij,ij->i", p, np.cross(b, c)) / det
        w2 = np.einsum("ij,ij->i", a, np.cross(p, c)) / det
        w3 = np.einsum("ij,ij->i", a, np.cross(b, p)) / det
    return np.stack([1 - w1 - w2 - w3, w1, w2, w3], axis=1)


def boundary_faces(T):
    """The boundary of a tet mesh: the faces that belong to one tet only.

    T  #T by 4 tets
    Returns #B by 3 faces (vertex indices; each tet's faces are (1 2 3), (0 3 2), (0 1 3), (0 2 1)).
    """
    faces = T[:, [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]]].reshape(-1, 3)
    _, inverse, counts = np.unique(np.sort(faces, axis=1), axis=0, return_inverse=True, return_counts=True)
    return faces[counts[inverse.ravel()] == 1]


def volume_values_at(points, X, T, U, names=None, rel_tolerance=REL_TOLERANCE):
    """A volumetric model's displacement at interior points (probes, beads): the linear
    interpolation in the tet that contains each point (barycentric weights; among tets
    sharing the point, the one it lies deepest in, then the lowest index). A point
    outside every tet (a curved boundary's facets cut inside it) takes the closest point
    of the nearest tet, that is of the mesh's boundary: its weights are the tet's,
    clamped to that face (the opposite corner's zero), and its distance is reported; a
    point farther than rel_tolerance times the mesh's bounding-box diagonal is an error
    naming it.

    points  #P by 3 rest positions (m)
    X  #X by 3 rest positions of the mesh's nodes (m), T  #T by 4 tets (indices into X)
    U  #X by 3 displacements of the nodes (m); only the nodes T uses must be finite
    names  #P names for messages (default: the row)
    Returns values  #P by 3 displacements (m), distance  #P (0 inside the mesh, m).
    """
    points, labels = _check_points(points, names)
    X, T, U = _check_mesh(X, T, U, 4, "T")
    corners = X[T]
    centroids = corners.mean(axis=1)
    radius = float(np.max(np.linalg.norm(corners - centroids[:, None, :], axis=2)))
    tree = cKDTree(centroids)
    lists = tree.query_ball_point(points, radius * (1 + 1e-12) + 1e-300)
    rows = np.repeat(np.arange(len(points)), [len(c) for c in lists])
    tets = np.fromiter((e for c in lists for e in c), dtype=np.int64, count=len(rows))
    W = tet_barycentric(points[rows], *(X[T[tets, k]] for k in range(4)))
    depth = np.nan_to_num(W.min(axis=1), nan=-np.inf)
    inside = depth >= -INSIDE_TOLERANCE
    values = np.empty((len(points), 3))
    distance = np.zeros(len(points))
    found = np.zeros(len(points), dtype=bool)
    if np.any(inside):
        r, t, w, dep = rows[inside], tets[inside], W[inside], depth[inside]
        best = _first_minimum(r, -dep, t, len(np.unique(r)))
        values[r[best]] = np.einsum("ij,ijk->ik", w[best], U[T[t[best]]])
        found[r[best]] = True
    outside = np.flatnonzero(~found)
    if len(outside):
        faces = boundary_faces(T)
        tri, Wf, _, d = closest_points(points[outside], X, faces)
        _within_tolerance(d, [labels[k] for k in outside], X, np.unique(T), rel_tolerance, "volume")
        values[outside] = np.einsum("ij,ijk->ik", Wf, U[faces[tri]])
        distance[outside] = d
    return values, distance


def patch_faces(F, observed):
    """The observed patch of a surface: the triangles whose three vertices are observed.

    F  #F by 3 triangles, observed  #O vertex indices (a top_surface.csv's vertex column)
    Returns #G by 3, the rows of F kept (the top face of a cube whose top is observed).
    """
    F = np.asarray(F)
    return F[np.all(np.isin(F, np.asarray(observed)), axis=1)]


# ---------------------------------------------------------------------------------
# The suite's roles, their points and the converged answer.

def suite_roles(suite=SUITE):
    """([(role, scenario name, scenario file)] in RESULTS/suite/experiment.json's order, its index object)."""
    path = os.path.join(suite, "experiment.json")
    if not os.path.isfile(path):
        raise ResultsError(f"{path}: missing (the suite's results: bash scripts/suite writes them)")
    with open(path) as f:
        index = json.load(f)
    return [(s["role"], s["name"], s["file"]) for s in index.get("scenarios", []) if s.get("role")], index


def reference_case(suite, role):
    """The case dict (results_index.load_case) of the role's reference case in the suite's results."""
    roles, index = suite_roles(suite)
    scenario = {r: s for r, s, _ in roles}.get(role)
    if scenario is None:
        raise ResultsError(f"{suite}/experiment.json: no role '{role}' (roles: {', '.join(r for r, _, _ in roles)})")
    folder = os.path.join(suite, scenario, index.get("reference") or "reference")
    if not results_index.is_case_folder(folder):
        raise ResultsError(f"{folder}: no reference case results (run.json)")
    return results_index.load_case(folder)


def file_vertices(source, vertex, folder):
    """#S ints: the vertex of the data file (its 0-based 'v' line) each runner-surface vertex
    `vertex` (#S) is, -1 for one the repair made (REPAIRED_SURFACES); source as
    converged_fields.surface_source gives it. A file the map does not hold is an error."""
    mesh, before = source
    repair = REPAIRED_SURFACES.get((mesh.get("surface"), before)) if mesh.get("repair_self_intersections") else None
    if repair is None:
        raise ResultsError(f"{folder}/run.json: a surface from {mesh.get('surface')} ({before} vertices before a "
                           "repair) that REPAIRED_SURFACES does not map to its file's vertices (measure it: "
                           "tissuebench mesh --surface FILE ..., its fine_surface.vtu against the file)")
    index = np.delete(np.arange(before), repair["dropped"]).tolist()
    for k in sorted(repair["made"]):
        index.insert(k, -1)
    if np.max(vertex) >= len(index):
        raise ResultsError(f"{folder}/top_surface.csv: vertex {np.max(vertex)}, the repaired surface has {len(index)}")
    return np.array(index)[vertex]


class Interior:
    """A role's interior points: names  #I ids ("p0", "b17"), rest  #I by 3 (m) or None
    (the Truth Cube's beads: third-party, by table_row  #I), the source (the scenario's
    resolved probes object)."""

    def __init__(self, names, rest, table_row, source):
        self.names, self.rest, self.table_row, self.source = names, rest, table_row, source


def probe_rows(folder):
    """The probe column (#I ints) of a case's probes.csv."""
    path = os.path.join(folder, "probes.csv")
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows or rows[0][0] != "probe":
        raise ResultsError(f"{path}: no probe column")
    return np.array([int(r[0]) for r in rows[1:]], dtype=int)


def interior_points(case):
    """The role's interior points (Interior) from its reference case's probes, or None."""
    probes = case["run"].get("scenario_resolved", {}).get("probes")
    if not probes or not os.path.isfile(os.path.join(case["folder"], "probes.csv")):
        return None
    rows = probe_rows(case["folder"])
    if isinstance(probes, dict) and "truth_cube" in probes:
        return Interior([f"b{r}" for r in rows], None, rows, probes["truth_cube"])
    if not isinstance(probes, list):  # the runner resolves points and a file into the list of points
        raise ResultsError(f"{case['folder']}/run.json: scenario_resolved.probes is neither the points nor truth_cube")
    rest = _array(f"{case['folder']}/run.json scenario_resolved.probes", probes, 3)
    if len(rest) != len(rows):
        raise ResultsError(f"{case['folder']}/probes.csv: {len(rows)} probes, run.json gives {len(rest)} points")
    return Interior([f"p{r}" for r in rows], rest[rows], None, probes)


class RolePoints:
    """One role's observation points.

    role, base (the paper-sized role whose points these are), scenario and scenario_file
    (the role's own), patch and patch_description, vertex  #S (the suite mesh's vertex
    ids), names  #S ("s<vertex>"), rest  #S by 3 (m) or None (a surface from a data file:
    vertex is then its source_vertex, file_vertex  #S its vertex in the file), source
    (converged_fields.surface_source of the reference case), interior (Interior or None),
    run and folder (the reference case's run.json and folder).
    """

    def __init__(self, role, suite=SUITE):
        self.role, self.base = role, converged_fields.base_role(role)
        roles, _ = suite_roles(suite)
        files = {r: (s, f) for r, s, f in roles}
        if self.base not in files:
            raise ResultsError(f"{suite}/experiment.json: role '{role}' has no base role '{self.base}'")
        case = reference_case(suite, self.base)
        self.scenario, self.scenario_file = files[role]
        self.run = case["run"]
        self.folder = case["folder"]
        observe = self.run["scenario_resolved"].get("observe", {}).get("vertices", "top")
        if observe not in PATCHES:
            raise ResultsError(f"{self.folder}/run.json: observe.vertices '{observe}' (known: {', '.join(PATCHES)})")
        self.patch, self.patch_description = PATCHES[observe]
        self.vertex, self.rest, _ = metrics.read_displacements(os.path.join(self.folder, "top_surface.csv"))
        if observe == "top" and self.rest is not None:
            self.patch_description += f", at z = {self.rest[:, 2].max():.6g} m"
        self.names = [f"s{v}" for v in self.vertex]
        self.source = converged_fields.surface_source(case)
        self.file_vertex = None if self.rest is not None else file_vertices(self.source, self.vertex, self.folder)
        self.interior = interior_points(case)


class Converged:
    """A role's converged answer at its points: label ("P2 L1"), folder (the finest run),
    u  #S by 3 at the surface points, probes  #I by 3 or None, entry (the role's
    "converged" entry of suite_reference_errors.json: field_error, field_error_how, dofs)."""

    def __init__(self, label, folder, u, probes, entry):
        self.label, self.folder, self.u, self.probes, self.entry = label, folder, u, probes, entry


def converged_at(points, field, runs, declared):
    """The converged answer (Converged) at a role's points from its base role's
    converged_fields.ConvergedField and study runs; an error naming the files when the
    study's level-0 vertices are not the suite mesh's observed ones."""
    ids0, rest0 = field.level0
    same = np.array_equal(ids0, points.vertex) and ((rest0 is None and points.rest is None) or (
        rest0 is not None and points.rest is not None and np.array_equal(rest0, points.rest)))
    if not same or (rest0 is None and field.source != points.source):
        raise ResultsError(f"{points.folder}/top_surface.csv: its vertices are not the reference study's level-0 "
                           f"vertices of {field.role} (another mesh?)")
    folder = runs[field.key]["folder"]
    probes = None
    if points.interior is not None:
        path = os.path.join(folder, "probes.csv")
        if not os.path.isfile(path):
            raise ResultsError(f"{path}: missing; the suite's reference has probes")
        mine = runs[field.key]["run"]["scenario_resolved"].get("probes")
        if not np.array_equal(probe_rows(folder), probe_rows(points.folder)) or mine != points.run[
                "scenario_resolved"]["probes"]:
            raise ResultsError(f"{path}: not the probes of {points.folder}/probes.csv")
        probes = leaderboard.probe_displacements(folder)
    entry = declared.get(field.role, {}).get("converged", {})
    return Converged(field.label, folder, field.u, probes, entry)


def no_converged_note(role):
    """Why a role has no converged answer (the sidecar's note)."""
    return (f"no converged answer: the reference study (experiments/scenarios/suite_reference/generate.py, "
            f"SCENARIOS) does not refine {converged_fields.base_role(role)}, so there is no finer run than the "
            f"suite's own reference to take as converged (the leaderboard's converged column is n/a here)")


# ---------------------------------------------------------------------------------
# Writing and reading results/observation_points.

def fmt(x):
    """A float written so that reading it gives the same float (repr); ints as ints."""
    return repr(float(x)) if not isinstance(x, (int, np.integer)) else str(int(x))


def surface_rows(points, converged):
    """(header, rows) of <role>.csv."""
    where = ["x", "y", "z"] if points.rest is not None else ["source_vertex", "file_vertex"]
    header = ["id", "patch"] + where + (["ux", "uy", "uz"] if converged else [])
    rows = []
    for k, name in enumerate(points.names):
        loc = (list(points.rest[k]) if points.rest is not None
               else [int(points.vertex[k]), int(points.file_vertex[k])])
        rows.append([name, points.patch] + [fmt(v) for v in loc] + ([fmt(v) for v in converged.u[k]]
                                                                     if converged else []))
    return header, rows


def interior_rows(interior, converged):
    """(header, rows) of <role>_interior.csv."""
    where = ["x", "y", "z"] if interior.rest is not None else ["table_row"]
    header = ["id", "patch"] + where + (["ux", "uy", "uz"] if converged else [])
    rows = []
    for k, name in enumerate(interior.names):
        loc = list(interior.rest[k]) if interior.rest is not None else [int(interior.table_row[k])]
        rows.append([name, "interior"] + [fmt(v) for v in loc] + ([fmt(v) for v in converged.probes[k]]
                                                                  if converged else []))
    return header, rows


def rel(path):
    """A path inside the repository relative to it (the sidecar's paths), any other as given."""
    return os.path.relpath(path, REPO) if os.path.abspath(path).startswith(REPO + os.sep) else path


def sidecar(points, converged):
    """The <role>.json object: what the points are, where the converged answer comes from."""
    doc = {
        "role": points.role,
        "points_of": points.base,
        "scenario": points.scenario,
        "scenario_file": points.scenario_file,
        "patch": points.patch,
        "patch_description": points.patch_description,
        "surface_points": len(points.names),
        "surface_points_from": rel(os.path.join(points.folder, "top_surface.csv")),
        "location": "x, y, z: rest position (m)" if points.rest is not None else FILE_COORDINATES,
        "interior_points": 0 if points.interior is None else len(points.interior.names),
    }
    if points.rest is None:
        mesh, before = points.source
        doc["source"] = {"surface": mesh.get("surface"), "unit_scale": mesh.get("unit_scale"),
                         "repair_self_intersections": mesh.get("repair_self_intersections"),
                         "vertices_before_repair": before,
                         "made_by_repair": [n for n, f in zip(points.names, points.file_vertex) if f < 0]}
    if points.interior is not None:
        doc["interior_location"] = ("x, y, z: rest position (m), the scenario's probes (its own points)"
                                    if points.interior.rest is not None else BEAD_COORDINATES)
        if points.interior.rest is None:
            doc["frame"] = points.interior.source["frame"]
            doc["compare_at_strain"] = points.interior.source["compare_at_strain"]
    if converged is None:
        doc["converged"] = None
        doc["note"] = no_converged_note(points.role)
        return doc
    doc["converged"] = {
        "run": converged.label,
        "folder": rel(converged.folder),
        "frame": "the run's last frame (top_surface.csv, probes.csv)",
        "estimated_error": converged.entry.get("field_error"),
        "estimated_error_how": converged.entry.get("field_error_how", "not estimated"),
        "dofs": converged.entry.get("dofs"),
        "how": "converged_fields.read(): the reference study's finest run (Newton, neo-Hookean) at the suite "
               "mesh's observed vertices; estimated_error: its relative L2 from the law's continuum answer "
               "(experiments/suite_reference_errors.json, the role's converged entry)",
    }
    doc["note"] = ("" if points.role == points.base else
                   f"a refined role: {points.base}'s points and converged answer (the refined mesh keeps them)")
    return doc


def write_csv(path, header, rows):
    """One CSV file with Unix line ends (the same bytes on every platform)."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        w.writerows(rows)


def make(suite=SUITE, out=OUT, study=None, reference_errors=REFERENCE_ERRORS):
    """Writes every role's files into out; returns {role: has a converged answer}."""
    fields = converged_fields.read(study)
    runs = converged_fields.study_runs(study or converged_fields.STUDY)
    declared = leaderboard.read_reference_errors(reference_errors)
    os.makedirs(out, exist_ok=True)
    done = {}
    for role, _, _ in suite_roles(suite)[0]:
        points = RolePoints(role, suite)
        field = fields.get(points.base)
        converged = converged_at(points, field, runs[points.base], declared) if field is not None else None
        write_csv(os.path.join(out, f"{role}.csv"), *surface_rows(points, converged))
        if points.interior is not None:
            write_csv(os.path.join(out, f"{role}_interior.csv"), *interior_rows(points.interior, converged))
        with open(os.path.join(out, f"{role}.json"), "w") as f:
            json.dump(sidecar(points, converged), f, indent=1)
            f.write("\n")
        done[role] = converged is not None
    return done


def read_points_csv(path):
    """{id: #N names, patch: #N, x/y/z or source_vertex or table_row columns, u: #N by 3 or None}
    of a <role>.csv or <role>_interior.csv."""
    if not os.path.isfile(path):
        raise ResultsError(f"{path}: missing (analysis/observation_points.py writes it)")
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows or rows[0][:2] != ["id", "patch"]:
        raise ResultsError(f"{path}: not an observation-points file (header {rows[0] if rows else 'none'})")
    header, body = rows[0], rows[1:]
    if not body or any(len(r) != len(header) for r in body):
        raise ResultsError(f"{path}: no rows, or a row without {len(header)} fields")
    col = {h: [r[k] for r in body] for k, h in enumerate(header)}
    out = {"id": col["id"], "patch": col["patch"], "u": None, "rest": None}
    if "x" in col:
        out["rest"] = np.column_stack([col["x"], col["y"], col["z"]]).astype(float)
    for key in ("source_vertex", "file_vertex", "table_row"):
        if key in col:
            out[key] = np.array(col[key], dtype=int)
    if "ux" in col:
        out["u"] = np.column_stack([col["ux"], col["uy"], col["uz"]]).astype(float)
    return out


def read_role(role, root=OUT):
    """A role's committed files: {"surface": read_points_csv, "interior": the same or None,
    "meta": the sidecar JSON}."""
    meta_path = os.path.join(root, f"{role}.json")
    if not os.path.isfile(meta_path):
        raise ResultsError(f"{meta_path}: missing: no observation points for role '{role}'")
    with open(meta_path) as f:
        meta = json.load(f)
    interior = os.path.join(root, f"{role}_interior.csv")
    return {"surface": read_points_csv(os.path.join(root, f"{role}.csv")),
            "interior": read_points_csv(interior) if os.path.isfile(interior) else None, "meta": meta}


def read_obj_vertices(path):
    """#V by 3 coordinates of an OBJ file's 'v' lines, in its units."""
    if not os.path.isfile(path):
        raise ResultsError(f"{path}: not there (third-party data, README 'Data' says where to obtain it)")
    with open(path) as f:
        return np.array([[float(x) for x in line.split()[1:4]] for line in f if line.startswith("v ")])


def surface_coordinates(role, root=OUT, data_dir=None, mesh_folder=None):
    """#S by 3 rest positions (m) of a role's surface points, in <role>.csv's order: its x, y,
    z; for a surface read from a data file (the liver), that file's vertices (file_vertex, from
    the data directory: data_dir as truth_cube.data_dir reads it) times unit_scale, or, given
    mesh_folder (a run's <scenario>/mesh or `tissuebench mesh`'s --out), its
    fine_surface.vtu's points (source_vertex), which also holds the vertices the repair made."""
    files = read_role(role, root)
    surface, meta = files["surface"], files["meta"]
    if surface["rest"] is not None:
        return surface["rest"]
    if mesh_folder is not None:
        from vtu_plot import read_vtu  # matplotlib: only when a mesh folder is read
        path = os.path.join(mesh_folder, "fine_surface.vtu")
        if not os.path.isfile(path):
            raise ResultsError(f"{path}: not there (a run's <scenario>/mesh, or tissuebench mesh --out)")
        points = read_vtu(path)[0]
        if len(points) != len(surface["id"]) or surface["source_vertex"].max() >= len(points):
            raise ResultsError(f"{path}: {len(points)} vertices, {role}'s surface has {len(surface['id'])}")
        return points[surface["source_vertex"]]
    made = np.flatnonzero(surface["file_vertex"] < 0)
    if len(made):
        raise ResultsError(f"{role}: point {surface['id'][made[0]]} is a vertex the repair of "
                           f"{meta['source']['surface']} made, in no file: give mesh_folder")
    path = os.path.join(truth_cube.data_dir(data_dir), meta["source"]["surface"].split(":", 1)[1])
    vertices = read_obj_vertices(path)
    if len(vertices) != meta["source"]["vertices_before_repair"]:
        raise ResultsError(f"{path}: {len(vertices)} vertices, the runner read "
                           f"{meta['source']['vertices_before_repair']} (another file?)")
    return vertices[surface["file_vertex"]] * meta["source"]["unit_scale"]


def probe_rms_mm(u, u_ref):
    """RMS over the points of |u - u_ref| in mm (the leaderboard's probe error's formula;
    score_observations takes u_ref from the converged run, not the suite's reference).
    u, u_ref  #I by 3 (m)."""
    return float(np.sqrt(np.mean(np.sum((u - u_ref) ** 2, axis=1)))) * 1000


def bead_rms_mm(interior, meta, u, data_dir=None):
    """RMS distance (mm) of the beads moved by u (#I by 3, m) from their measured positions
    at the role's strain (truth_cube.errors; the table read from the data directory)."""
    path = os.path.join(truth_cube.data_dir(data_dir), "data", "truthcube", "uniaxial_positions.csv")
    grid, positions, strains = truth_cube.read_table(path)
    rows = interior["table_row"]
    if rows.max() >= len(positions):
        raise ResultsError(f"{path}: {len(positions)} beads, the observation points name row {rows.max()}")
    column = min(range(len(strains)), key=lambda i: abs(strains[i] - meta["compare_at_strain"]))
    rest = truth_cube.to_model_mm(positions[rows, 0, :], meta["frame"])
    measured = truth_cube.to_model_mm(positions[rows, column, :], meta["frame"])
    return truth_cube.errors(rest, measured, rest + u * 1000, grid[rows])["rms"]


def _values(name, values, count, path):
    """values as #count by 3 finite floats; a ValueError naming `path`'s point count otherwise."""
    v = _array(name, values, 3)
    if len(v) != count:
        raise ValueError(f"{name}: {len(v)} rows, {path} has {count} points")
    _finite(name, v)
    return v


def score_observations(role, values, probe_values=None, root=OUT, data_dir=None):
    """A prediction's scores at a role's observation points.

    values  #S by 3 displacements (m) at the role's surface points, in the order of
            <root>/<role>.csv (surface_values_at gives them from any surface mesh)
    probe_values  #I by 3 displacements (m) at its interior points (<role>_interior.csv;
            volume_values_at gives them from any tet mesh), or None
    Returns {"rel_l2_converged": the relative L2 (Frobenius) of values against the converged
    field, metrics.compare's rel_l2 (converged_fields' and the leaderboard's definition);
    "probe_error_mm": the RMS probe error against the converged run's probes; "bead_rms_mm"
    on the Truth Cube: the RMS distance from the CT-measured beads (the table from the data
    directory, data_dir as truth_cube.data_dir reads it); "converged_run", its
    "converged_error" (estimated, relative), "note"}. NaN where there is no converged answer
    (the role's note says why) or no probe values.
    """
    files = read_role(role, root)
    surface, interior, meta = files["surface"], files["interior"], files["meta"]
    path = os.path.join(root, f"{role}.csv")
    values = _values("values", values, len(surface["id"]), path)
    nan = float("nan")
    out = {"role": role, "rel_l2_converged": nan, "probe_error_mm": nan, "bead_rms_mm": nan,
           "converged_run": (meta["converged"] or {}).get("run"),
           "converged_error": (meta["converged"] or {}).get("estimated_error"), "note": meta.get("note", "")}
    if surface["u"] is not None:
        out["rel_l2_converged"] = metrics.compare(values, surface["u"], None, None)["rel_l2"]
    if probe_values is not None:
        if interior is None:
            raise ValueError(f"probe_values: role {role} has no interior points ({path})")
        probes = _values("probe_values", probe_values, len(interior["id"]), os.path.join(root, f"{role}_interior.csv"))
        if interior["u"] is not None:
            out["probe_error_mm"] = probe_rms_mm(probes, interior["u"])
        if "table_row" in interior:
            out["bead_rms_mm"] = bead_rms_mm(interior, meta, probes, data_dir)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="?", default=SUITE, help="the suite's results (default results/suite)")
    parser.add_argument("out", nargs="?", default=OUT, help="default results/observation_points")
    parser.add_argument("--converged", default=None,
                        help="the reference study's results (default results/suite_reference_convergence)")
    a = parser.parse_args()
    done = results_index.main(lambda: make(a.results, a.out, a.converged), "observation_points")
    with_answer = [r for r, has in done.items() if has]
    print(f"written: {a.out}: {len(done)} roles, {len(with_answer)} with a converged answer "
          f"(none: {', '.join(r for r, has in done.items() if not has) or 'none'})")


if __name__ == "__main__":
    main()
