#!/usr/bin/python3
"""A simulator outside the C++ tree: small-strain linear FEM on P1 tetrahedra in numpy
and scipy, which reads only a problem package (`tissuebench export`) and writes a
submission (`tissuebench score` ranks it). docs/benchmark_format.md is the contract;
this file is its worked example and the proof that a model needs nothing of this
repository but the package.

    /usr/bin/python3 examples/external_model/linear_fem.py PACKAGE OUT \
        [--calibration calibration.json]   # `tissuebench calibrate`'s output

What it solves: the static equilibrium K u = f of small-strain linear elasticity
(Hooke's law with the package's Lame parameters, P1 tets) on the package's volume.msh,
frame by frame
under that frame's loads and tools. The support holds every node in the support box
(interior ones too: a support of the lowest fraction of the height is a slab); volume
node v is surface vertex v (meshes.volume.surface_vertices_first).
Loads: a point force shared by the nodes of the tet that holds its point by their
barycentric weights; a surface traction spread
uniformly over the disc by the polar quadrature of disc_weights below (the one the
in-tree models use, models/numerics/embedding/surface_load.h); a body force lumped as
rho g V/4 per node of each tet. Tools: a grasp holds the surface vertices within its radius of
its point, a bonded plate those in its box (all three components), a sliding plate
only the component along its normal; each moved by its path. Spheres and compliant
grasps are not taken: one error says so. The reaction on a tool is the force the
tissue exerts on it, f - K u summed over the vertices it holds.

Observation points are read by barycentric interpolation in the tet that contains
them (the nearest of a few candidates by centroid distance, its weights clamped to
the tet when a point on a curved boundary lies just outside).
"""
import argparse
import csv
import json
import os
import platform
import resource
import sys
import time

import numpy as np
import scipy.sparse
import scipy.sparse.linalg
from scipy.spatial import cKDTree


class PackageError(Exception):
    pass


def read_csv(path, columns):
    """The named columns of a CSV with a header, as float arrays (or strings for "id" and "patch")."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        raise PackageError(f"{path}: {e.strerror}") from None
    out = {}
    for c in columns:
        if rows and c not in rows[0]:
            raise PackageError(f"{path}: no column {c}")
        values = [r[c] for r in rows]
        out[c] = values if c in ("id", "patch") else np.array(values, dtype=float)
    return out


def read_gmsh41(path):
    """Nodes (#N x 3) and 4-node tets (#T x 4, 0-based) of a Gmsh 4.1 ASCII file."""
    with open(path) as f:
        lines = [line.strip() for line in f]
    section = {name: lines.index(f"${name}") for name in ("MeshFormat", "Nodes", "Elements") if f"${name}" in lines}
    if len(section) < 3 or not lines[section["MeshFormat"] + 1].startswith("4.1"):
        raise PackageError(f"{path}: not a Gmsh 4.1 ASCII mesh")
    k = section["Nodes"] + 1
    blocks, count = int(lines[k].split()[0]), int(lines[k].split()[1])
    tags, xyz = [], []
    k += 1
    for _ in range(blocks):
        n = int(lines[k].split()[3])
        tags += [int(t) for t in lines[k + 1:k + 1 + n]]
        xyz += [[float(v) for v in line.split()[:3]] for line in lines[k + 1 + n:k + 1 + 2 * n]]
        k += 1 + 2 * n
    index = {t: i for i, t in enumerate(tags)}
    k = section["Elements"] + 1
    blocks = int(lines[k].split()[0])
    tets = []
    k += 1
    for _ in range(blocks):
        _, _, kind, n = (int(v) for v in lines[k].split())
        if kind == 4:  # 4-node tetrahedron
            tets += [[index[int(v)] for v in line.split()[1:5]] for line in lines[k + 1:k + 1 + n]]
        k += 1 + n
    if len(xyz) != count or not tets:
        raise PackageError(f"{path}: {len(xyz)} nodes of {count} declared, {len(tets)} tets")
    return np.array(xyz), np.array(tets, dtype=int)


def read_obj_faces(path):
    faces = []
    with open(path) as f:
        for line in f:
            if line.startswith("f "):
                faces.append([int(v.split("/")[0]) - 1 for v in line.split()[1:4]])
    return np.array(faces, dtype=int)


def shape_gradients(X, T):
    """Each tet's constant shape-function gradients (#T x 4 x 3) and volume."""
    D = np.stack([X[T[:, 1]] - X[T[:, 0]], X[T[:, 2]] - X[T[:, 0]], X[T[:, 3]] - X[T[:, 0]]], axis=2)
    volume = np.linalg.det(D) / 6
    if np.any(volume <= 0):
        raise PackageError(f"volume.msh: {int(np.sum(volume <= 0))} tets of non-positive volume")
    Dinv = np.linalg.inv(D)  # rows: gradients of the barycentric coordinates 1..3
    G = np.empty((len(T), 4, 3))
    G[:, 1:, :] = Dinv
    G[:, 0, :] = -Dinv.sum(axis=1)
    return G, volume


def stiffness(X, T, mu, lam):
    """K of linear elasticity: k_ab = V (lam g_a g_b^T + mu g_b g_a^T + mu (g_a . g_b) I)."""
    G, volume = shape_gradients(X, T)
    n = len(T)
    blocks = (lam * np.einsum("tai,tbj->tabij", G, G) + mu * np.einsum("tbi,taj->tabij", G, G)
              + mu * np.einsum("tak,tbk->tab", G, G)[:, :, :, None, None] * np.eye(3))
    blocks *= volume[:, None, None, None, None]
    dof = (3 * T[:, :, None] + np.arange(3)).reshape(n, 12)
    rows = np.repeat(dof[:, :, None], 12, axis=2).ravel()
    cols = np.repeat(dof[:, None, :], 12, axis=1).ravel()
    values = blocks.transpose(0, 1, 3, 2, 4).reshape(n, 12, 12).ravel()
    N = 3 * len(X)
    return scipy.sparse.csr_matrix((values, (rows, cols)), shape=(N, N)), volume


def closest_points_on_triangles(q, A, B, C):
    """The closest point to q of each triangle (A, B, C: #T x 3), Ericson 2005,
    Real-Time Collision Detection, section 5.1.5, vectorised."""
    ab, ac, ap = B - A, C - A, q - A
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = q - B
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp = q - C
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = 1 / (va + vb + vc)
        out = A + ab * (vb * denom)[:, None] + ac * (vc * denom)[:, None]  # inside the face
        cases = [  # in Ericson's order; the first that holds is taken, so apply them last to first
            ((d1 <= 0) & (d2 <= 0), A),
            ((d3 >= 0) & (d4 <= d3), B),
            ((vc <= 0) & (d1 >= 0) & (d3 <= 0), A + ab * (d1 / (d1 - d3))[:, None]),
            ((d6 >= 0) & (d5 <= d6), C),
            ((vb <= 0) & (d2 >= 0) & (d6 <= 0), A + ac * (d2 / (d2 - d6))[:, None]),
            (((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)),
             B + (C - B) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))[:, None]),
        ]
    for mask, point in reversed(cases):
        out = np.where(mask[:, None], point, out)
    return out


def disc_weights(X, F, centre, radius, radial=32, angular=128):
    """Per surface vertex, its share of a unit total force spread as a uniform traction
    over the disc of `radius` around `centre` in the surface's tangent plane there (the
    area-weighted normal of the triangles touching `centre`): a polar quadrature (radial
    Gauss-Legendre points with weight r dr, `angular` equispaced angles), each point
    taken to the closest point of the surface and shared by its triangle's vertices by
    its barycentric coordinates. Independent of the mesh, so it converges under
    refinement, where a point force does not (docs/reference_convergence.md)."""
    A, B, C = X[F[:, 0]], X[F[:, 1]], X[F[:, 2]]
    on_surface = 1e-9 * np.linalg.norm(X.max(axis=0) - X.min(axis=0))
    distance = np.linalg.norm(closest_points_on_triangles(centre, A, B, C) - centre, axis=1)
    touching = distance <= on_surface
    if not touching.any():
        raise PackageError(f"problem.json: the disc's centre {centre.tolist()} is {distance.min()} m from the surface")
    normal = np.cross(B - A, C - A)[touching].sum(axis=0)
    normal /= np.linalg.norm(normal)
    axis = int(np.argmin(np.abs(normal)))
    e1 = np.eye(3)[axis] - normal[axis] * normal
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    candidates = np.flatnonzero(distance <= 1.01 * radius + on_surface)
    x, w = np.polynomial.legendre.leggauss(radial)
    s, w = (x + 1) / 2, w / 2
    share = np.zeros(len(X))
    total = 0.0
    for sk, wk in zip(s, w):
        for j in range(angular):
            theta = 2 * np.pi * (j + 0.5) / angular
            q = centre + radius * sk * (np.cos(theta) * e1 + np.sin(theta) * e2)
            a, b, c = A[candidates], B[candidates], C[candidates]
            p = closest_points_on_triangles(q, a, b, c)
            d = np.linalg.norm(p - q, axis=1)
            best = int(np.argmin(d))
            if d[best] > 0.01 * radius:
                raise PackageError(f"problem.json: the disc of radius {radius} m leaves the surface")
            position = q if d[best] <= on_surface else p[best]
            # barycentric coordinates of the position in its triangle
            v0, v1, v2 = b[best] - a[best], c[best] - a[best], position - a[best]
            d00, d01, d11 = v0 @ v0, v0 @ v1, v1 @ v1
            d20, d21 = v2 @ v0, v2 @ v1
            den = d00 * d11 - d01 * d01
            l1, l2 = (d11 * d20 - d01 * d21) / den, (d00 * d21 - d01 * d20) / den
            weight = wk * sk
            share[F[candidates[best]]] += weight * np.array([1 - l1 - l2, l1, l2])
            total += weight
    return share / total


class LinearFem:
    def __init__(self, package):
        self.dir = package
        with open(os.path.join(package, "problem.json")) as f:
            self.problem = json.load(f)
        p = self.problem
        if not p["meshes"]["volume"].get("surface_vertices_first"):
            raise PackageError(f"{package}/problem.json: surface vertices are not the volume's first nodes")
        self.X, self.T = read_gmsh41(os.path.join(package, p["meshes"]["volume"]["gmsh"]))
        self.F = read_obj_faces(os.path.join(package, p["meshes"]["surface"]["obj"]))
        self.frames = int(p["time"]["frames"])
        m = p["material"]
        self.K, self.volume = stiffness(self.X, self.T, m["lame_mu"], m["lame_lambda"])
        # The support box holds every node in it, interior ones too (a support of the
        # lowest fraction of the height is a slab); support_vertices.csv lists the
        # surface's, which a surface-only simulator holds.
        box = p["support"]["definition"]["box"]
        lo = np.array([-np.inf if v is None else v for v in box["min"]])
        hi = np.array([np.inf if v is None else v for v in box["max"]])
        support = np.flatnonzero(np.all((self.X >= lo) & (self.X <= hi), axis=1))
        surface_support = read_csv(os.path.join(package, p["support"]["vertices"]), ["vertex"])["vertex"].astype(int)
        if not set(surface_support.tolist()) <= set(support.tolist()):
            raise PackageError(f"{package}/support_vertices.csv: vertices outside the support box")
        held = {3 * v + c for v in support for c in range(3)}
        self.loads = []  # (per-node weights #N, its path #frames x 3, kind)
        for load in p.get("loads", []):
            path = read_csv(os.path.join(package, load["path"]), ["x", "y", "z"])
            values = np.stack([path["x"], path["y"], path["z"]], axis=1)
            weights = np.zeros(len(self.X))
            if load["type"] == "point_force":
                tet, w = self.locate(np.array([load["point"]]))
                weights[self.T[tet[0]]] = w[0]
            elif load["type"] == "surface_traction":
                ns = int(p["meshes"]["surface"]["vertices"])
                weights[:ns] = disc_weights(self.X[:ns], self.F, np.array(load["point"]), load["radius"])
            else:  # body_force: the acceleration times rho V / 4 at each tet's nodes
                np.add.at(weights, self.T.ravel(), np.repeat(m["density"] * self.volume / 4, 4))
            self.loads.append((weights, values))
        self.tools = []  # (the dofs it holds, its path #frames x 3)
        ns = int(p["meshes"]["surface"]["vertices"])
        for tool in p.get("tools", []):
            Xs = self.X[:ns]
            if tool["type"] == "grasp":
                vertices = np.flatnonzero(np.linalg.norm(Xs - np.array(tool["point"]), axis=1) <= tool["radius"])
                components = [0, 1, 2]
            elif tool["type"] in ("bonded_plate", "sliding_plate"):
                lo, hi = np.array(tool["box"]["min"]), np.array(tool["box"]["max"])
                vertices = np.flatnonzero(np.all((Xs >= lo) & (Xs <= hi), axis=1))
                components = [0, 1, 2] if tool["type"] == "bonded_plate" else ["xyz".index(tool["normal"])]
            else:
                raise PackageError(f"{package}/problem.json: {tool['key']}: this model does not take a {tool['type']}")
            if len(vertices) == 0:
                raise PackageError(f"{package}/problem.json: {tool['key']} holds no surface vertex")
            path = read_csv(os.path.join(package, tool["path"]), ["x", "y", "z"])
            values = np.stack([path["x"], path["y"], path["z"]], axis=1)
            dofs = np.array([3 * v + c for v in vertices for c in components])
            self.tools.append((dofs, np.array([c for v in vertices for c in components]), values))
            held |= set(dofs.tolist())
        self.held = np.array(sorted(held), dtype=int)
        self.free = np.setdiff1d(np.arange(3 * len(self.X)), self.held)
        self.solve = scipy.sparse.linalg.factorized(self.K[self.free][:, self.free].tocsc())
        self.K_fh = self.K[self.free][:, self.held]

    def step(self, frame):
        """u (#N x 3) and each tool's reaction at `frame`."""
        N = len(self.X)
        f = np.zeros(3 * N)
        for weights, values in self.loads:
            f += np.outer(weights, values[frame]).ravel()
        u = np.zeros(3 * N)
        for dofs, components, values in self.tools:
            u[dofs] = values[frame][components]
        u[self.free] = self.solve(f[self.free] - self.K_fh @ u[self.held])
        residual = f - self.K @ u  # the force the tissue exerts on what holds it
        reactions = []
        for dofs, _, _ in self.tools:
            r = np.zeros(3)
            np.add.at(r, dofs % 3, residual[dofs])
            reactions.append(r)
        return u.reshape(N, 3), reactions

    def locate(self, points):
        """Per point: its tet and clamped barycentric weights."""
        G, _ = shape_gradients(self.X, self.T)
        tree = cKDTree(self.X[self.T].mean(axis=1))
        _, candidates = tree.query(points, k=min(24, len(self.T)))
        tets, weights = [], []
        for p, cand in zip(points, np.atleast_2d(candidates)):
            w = np.einsum("tai,ti->ta", G[cand], p - self.X[self.T[cand, 0]])
            w[:, 0] += 1
            best = int(np.argmax(w.min(axis=1)))
            clamped = np.clip(w[best], 0, None)
            tets.append(cand[best])
            weights.append(clamped / clamped.sum())
        return np.array(tets), np.array(weights)


def machine():
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return {"cpu": cpu, "cores": os.cpu_count() or 1}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("package", help="a problem package folder (tissuebench export)")
    parser.add_argument("out", help="the submission folder to write")
    parser.add_argument("--calibration", help="the JSON `tissuebench calibrate` printed on this machine")
    parser.add_argument("--method", default="python-linear-fem")
    args = parser.parse_args()
    started = time.perf_counter()
    model = LinearFem(args.package)
    p = model.problem
    observed = read_csv(os.path.join(args.package, p["observation"]["surface_points"]), ["id", "x", "y", "z"])
    ids, points = list(observed["id"]), np.stack([observed["x"], observed["y"], observed["z"]], axis=1)
    if p["observation"].get("interior_points"):
        interior = read_csv(os.path.join(args.package, p["observation"]["interior_points"]), ["id", "x", "y", "z"])
        ids += interior["id"]
        points = np.vstack([points, np.stack([interior["x"], interior["y"], interior["z"]], axis=1)])
    tets, weights = model.locate(points)
    setup_s = time.perf_counter() - started
    report = set(p["observation"]["frames"])
    times, displacement_rows, force_rows = [], [], []
    for frame in range(model.frames):
        t0 = time.perf_counter()
        u, reactions = model.step(frame)
        times.append(1e3 * (time.perf_counter() - t0))
        if frame in report:
            at = np.einsum("pa,pai->pi", weights, u[model.T[tets]])
            displacement_rows += [[frame, i, *map(repr, v)] for i, v in zip(ids, at.tolist())]
            force_rows += [[frame, tool["name"], *map(repr, r.tolist())]
                           for tool, r in zip(p.get("tools", []), reactions)]
    calibration = {"figure_ms": 1.0, "command": "tissuebench calibrate"}
    if args.calibration:
        with open(args.calibration) as f:
            calibration["figure_ms"] = json.load(f)["figure_ms"]
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "displacements.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["frame", "id", "ux", "uy", "uz"])
        w.writerows(displacement_rows)
    if model.tools:
        with open(os.path.join(args.out, "forces.csv"), "w", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(["frame", "tool", "fx", "fy", "fz"])
            w.writerows(force_rows)
    meta = {
        "format": "tissuebench-submission/1", "scenario": p["scenario"], "role": p["role"], "method": args.method,
        "resolution": {"description": "the package's own tet mesh, P1", "surface_vertices": int(p["meshes"]["surface"]["vertices"]),
                       "tets": len(model.T)},
        "units": {"length": "m", "force": "N", "time": "ms", "memory": "MiB"},
        "timing": {"frame_median_ms": float(np.median(times)), "frame_p95_ms": float(np.percentile(times, 95)),
                   "setup_s": setup_s},
        "peak_memory_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "threads": 1, "machine": machine(), "calibration": calibration,
        "provenance": "examples/external_model/linear_fem.py (numpy, scipy) of the tissuebench repository",
    }
    with open(os.path.join(args.out, "submission.json"), "w") as f:
        json.dump(meta, f, indent=1)
    print(f"linear_fem: {len(ids)} points x {len(report)} frame(s) written to {args.out}", file=sys.stderr)


if __name__ == "__main__":
    try:
        main()
    except PackageError as e:
        sys.exit(f"linear_fem: {e}")
