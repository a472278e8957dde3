"""Each suite scenario's converged field: the observed surface displacement of the
finest run of the reference study (results/suite_reference_convergence: Newton on the
neo-Hookean law, the scenario refined level by level, P1 and P2; docs/reference_convergence.md,
"Every suite scenario") at the level-0 vertices, the vertices of the suite's own
paper-sized mesh. The leaderboard scores every case against it as well as against its
own mesh's reference: the distance from the continuum's answer of the law, which the
reference's own discretisation error is part of.

The finest run is chosen as analysis/suite_reference_convergence.py chooses it
(finest_key); its own estimated error is that study's (experiments/suite_reference_errors.json,
each role's "converged" entry).
"""
import os
import re

import numpy as np

import metrics
import results_index
from reference_convergence import match_vertices
from results_index import ResultsError

NAME = re.compile(r"^sref-(.+)-L(\d+)-p([12])$")
SIZED_ROLE = re.compile(r"^(.+)_\d+k$")  # a refined scenario's role: "cube_pull_disc_10k"
NEARLY_INCOMPRESSIBLE = 0.49  # Poisson's ratio from which P1 locks (the Truth Cube: 0.499)
MATCH_TOLERANCE = 1e-9  # m: level-0 vertices at the same coordinates on every level
STUDY = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "results",
                     "suite_reference_convergence")


def base_role(role):
    """The paper-sized role a refined scenario's role names ("cube_pull_disc_10k" ->
    "cube_pull_disc"): the same body, law and tools on a finer mesh, whose converged field
    is the paper-sized one's (its observed vertices include the level-0 ones where the
    refinement keeps them: the cube's grids, the surfaces split in four)."""
    m = SIZED_ROLE.match(role)
    return m.group(1) if m else role


def parse(name):
    """(role, level, order) of a scenario name, or None."""
    m = NAME.match(name)
    return None if not m else (m.group(1).replace("-", "_"), int(m.group(2)), int(m.group(3)))


def level0_rows(level0, observed, folder):
    """The rows of `observed` (read_displacements) at the level-0 vertices `level0`
    (ids, rest): matched by coordinates, or, in files without them (a third-party
    mesh), by index: a refined surface keeps the level-0 vertices first, at the same
    indices (meshing/surface_subdivision.h), and an order-2 run has its level's."""
    (ids0, rest0), (ids, rest, _) = level0, observed
    if rest0 is not None and rest is not None:
        return match_vertices(rest0, rest, MATCH_TOLERANCE)
    if (rest0 is None) != (rest is None):
        raise ResultsError(f"{folder}/top_surface.csv: coordinates in one file and not the other (another surface?)")
    row = {v: k for k, v in enumerate(ids)}
    missing = [v for v in ids0 if v not in row]
    if missing:
        raise ResultsError(f"{folder}/top_surface.csv: no level-0 vertex {missing[0]} (another surface?)")
    return np.array([row[v] for v in ids0], dtype=int)


def nearly_incompressible(case):
    return case["run"]["scenario_resolved"]["material"]["poisson_ratio"] >= NEARLY_INCOMPRESSIBLE


def finest_key(keys, runs):
    """The (order, level) of the run taken as the converged field: the highest level,
    P2 before P1 on it. The level sets what the surface resolves (a disc load's or a
    grasp's held vertices: the grasps hold 1 vertex on the torus and the L-block at level
    0, 5 at level 1), which no element order recovers. Nearly incompressible (the Truth
    Cube): P2 first, then the level, as P1 locks there (the doc's locking comparison)."""
    if nearly_incompressible(runs[(1, 0)]):
        return max(keys, key=lambda k: (k[0], k[1]))
    return max(keys, key=lambda k: (k[1], k[0]))


def study_runs(root):
    """{role: {(order, level): case}} of the study's results under root."""
    exp_root = os.path.join(root, "suite_reference_convergence")
    out = {}
    for scenario, cases in results_index.load_experiment(exp_root).items():
        p = parse(scenario)
        if p and cases:
            out.setdefault(p[0], {})[(p[2], p[1])] = next(iter(cases.values()))
    return out


def level0_vertices(runs, role):
    """(ids, rest) of the role's level-0 P1 run's observed vertices (the suite's mesh)."""
    if (1, 0) not in runs:
        raise ResultsError(f"{role}: no level-0 P1 run (the suite's mesh): the level-0 vertices are its")
    return metrics.read_displacements(os.path.join(runs[(1, 0)]["folder"], "top_surface.csv"))[:2]


def field_at_level0(case, level0, observed=None):
    """A case's observed displacement at the level-0 vertices (#V0 x 3, m); observed: its
    top_surface.csv as read_displacements reads it, when already read."""
    if observed is None:
        observed = metrics.read_displacements(os.path.join(case["folder"], "top_surface.csv"))
    return observed[2][level0_rows(level0, observed, case["folder"])]


# The scenario's mesh keys that make a surface read from a file (scenario_schema.md);
# its refinement (refine_levels) keeps the level-0 vertices first and is left out.
SURFACE_KEYS = ("type", "surface", "unit_scale", "repair_self_intersections")


def surface_source(case):
    """What a case's surface is built from, whatever its refinement: the scenario's mesh
    keys that make it (SURFACE_KEYS) and the source surface's vertex count. Two cases
    with the same source share their level-0 vertices at the same indices
    (meshing/surface_subdivision.h)."""
    mesh = case["run"].get("scenario_resolved", {}).get("mesh", {})
    return ({k: mesh.get(k) for k in SURFACE_KEYS},
            case["run"].get("mesh", {}).get("surface_vertices_before_repair"))


class ConvergedField:
    """One role's finest run: its (order, level) and label ("P2 L1"), and its field at the level-0 vertices."""

    def __init__(self, role, key, level0, u, source):
        self.role, self.key, self.level0, self.u, self.source = role, key, level0, u, source
        self.label = f"P{key[0]} L{key[1]}"

    def error(self, case):
        """Relative L2 of the case's observed field against this one at the level-0
        vertices; NaN where the case's observed vertices are not the level-0 ones (another
        mesh: one meshed anew, or a --set that changed the surface). Files without
        coordinates (a third-party surface) are matched by index only on the same source
        surface (surface_source)."""
        if self.level0[1] is None and surface_source(case) != self.source:
            return float("nan")
        try:
            u = field_at_level0(case, self.level0)
        except (ValueError, ResultsError, IndexError):
            return float("nan")
        return float(np.linalg.norm(u - self.u) / np.linalg.norm(self.u))


def read(root=None):
    """{role: ConvergedField} of the study's results under root (default: the committed
    results). A root without the study's results is a one-line error (a mistyped
    --converged would otherwise score nothing and say nothing)."""
    root = STUDY if root is None else root
    if not os.path.isdir(os.path.join(root, "suite_reference_convergence")):
        raise ResultsError(f"{root}: no reference study results (a suite_reference_convergence folder; "
                           "scripts/suite_reference_convergence writes them)")
    out = {}
    for role, runs in sorted(study_runs(root).items()):
        level0 = level0_vertices(runs, role)
        key = finest_key(list(runs), runs)
        out[role] = ConvergedField(role, key, level0, field_at_level0(runs[key], level0),
                                   surface_source(runs[(1, 0)]))
    return out
