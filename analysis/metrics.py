"""Accuracy metrics of one model's surface displacement against a reference.

Every metric compares the same vertices (the observed set of the scenario: the
top surface of the cube, every surface vertex of the liver), vertex by vertex.
Correlation is blind to scale, so it is never reported alone (docs/design.md, "Metrics").
"""
import csv

import numpy as np


WITH_COORDINATES = ["vertex", "x", "y", "z", "ux", "uy", "uz"]
# A mesh read from a third-party file (README "Data"): the runner writes no coordinates.
WITHOUT_COORDINATES = ["vertex", "ux", "uy", "uz"]


def read_displacements(path):
    """Reads a top_surface.csv / surface.csv: returns (ids #V, rest #Vx3, u #Vx3);
    rest is None when the file gives no coordinates (a third-party mesh's case:
    results_index.observed_rest finds them in the run's mesh folder)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows or rows[0] not in (WITH_COORDINATES, WITHOUT_COORDINATES):
        raise ValueError(f"{path}: not a tissuebench displacement CSV (bad header)")
    data = np.array(rows[1:], dtype=float)
    if data.size == 0:
        raise ValueError(f"{path}: no vertices")
    if rows[0] == WITHOUT_COORDINATES:
        return data[:, 0].astype(int), None, data[:, 1:4]
    return data[:, 0].astype(int), data[:, 1:4], data[:, 4:7]


def pearson(a, b):
    """Pearson correlation of two 1-D arrays; nan if either is constant."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    da, db = a - a.mean(), b - b.mean()
    denom = np.sqrt((da * da).sum() * (db * db).sum())
    return float((da * db).sum() / denom) if denom > 0 else float("nan")


def spearman(a, b):
    """Spearman rank correlation (Pearson of the ranks, ties averaged); nan if either is constant."""
    from scipy.stats import rankdata
    return pearson(rankdata(a), rankdata(b))


def extended(u, u_ref, rest, load_point, exclude_radius=0.01):
    """compare() plus Spearman correlations, and r(u_z) without the vertices within
    `exclude_radius` (m) of the load point (the singular neighbourhood of a point load)."""
    out = compare(u, u_ref, rest, load_point)
    u, u_ref, rest = np.asarray(u, float), np.asarray(u_ref, float), np.asarray(rest, float)
    out["spearman_uz"] = spearman(u[:, 2], u_ref[:, 2])
    out["spearman_mag"] = spearman(np.linalg.norm(u, axis=1), np.linalg.norm(u_ref, axis=1))
    far = np.linalg.norm(rest - np.asarray(load_point, float), axis=1) > exclude_radius
    out["corr_uz_far"] = pearson(u[far, 2], u_ref[far, 2]) if far.sum() > 2 else float("nan")
    out["rel_l2_far"] = (float(np.linalg.norm(u[far] - u_ref[far]) / np.linalg.norm(u_ref[far]))
                         if far.any() and np.linalg.norm(u_ref[far]) > 0 else float("nan"))
    # The "deformation region": vertices the reference moves by at least 5% of its largest displacement.
    mag = np.linalg.norm(u_ref, axis=1)
    region = mag >= 0.05 * mag.max() if mag.max() > 0 else np.zeros(len(mag), bool)
    out["corr_uz_region"] = pearson(u[region, 2], u_ref[region, 2]) if region.sum() > 2 else float("nan")
    return out


def compare(u, u_ref, rest, load_point, load_row=None):
    """Metrics of u (#V x 3) against u_ref (#V x 3) at the same vertices.

    corr_uz:   Pearson r of the z displacements (the paper's table 1)
    corr_mag:  Pearson r of |u|
    rel_l2:    ||u - u_ref|| / ||u_ref|| (Frobenius over all vertices)
    max_error: max over vertices of |u - u_ref| (m)
    load_ratio: |u| / |u_ref| at the vertex nearest the load point: the row
                `load_row` when given, else found from `rest`; nan when neither is
    """
    u = np.asarray(u, float)
    u_ref = np.asarray(u_ref, float)
    if u.shape != u_ref.shape:
        raise ValueError(f"shape mismatch {u.shape} vs {u_ref.shape}")
    ref_norm = np.linalg.norm(u_ref)
    k = load_row
    if k is None and rest is not None:
        k = int(np.argmin(np.linalg.norm(np.asarray(rest) - np.asarray(load_point), axis=1)))
    ref_at_load = np.linalg.norm(u_ref[k]) if k is not None else 0.0
    return {
        "corr_uz": pearson(u[:, 2], u_ref[:, 2]),
        "corr_mag": pearson(np.linalg.norm(u, axis=1), np.linalg.norm(u_ref, axis=1)),
        "rel_l2": float(np.linalg.norm(u - u_ref) / ref_norm) if ref_norm > 0 else float("nan"),
        "max_error": float(np.linalg.norm(u - u_ref, axis=1).max()),
        "load_ratio": float(np.linalg.norm(u[k]) / ref_at_load) if ref_at_load > 0 else float("nan"),
    }
