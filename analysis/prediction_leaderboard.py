"""The leaderboard of predictions: every (method, resolution) pair of the committed runs
scored against the converged continuum at the mesh-independent observation points
(analysis/observation_points.py), per suite scenario role and per-frame time budget.

Usage: /usr/bin/python3 analysis/prediction_leaderboard.py [OUT] [--data-dir DIR]

Today's leaderboard (analysis/leaderboard.py) ranks the solvers of one discrete problem,
each case against its own mesh's reference. Here a case on any mesh of the same problem
(the suite's paper-sized meshes, the ~10k-vertex studies results/*_10k, the 35k and 100k
studies where their observed surfaces are committed) is read at the role's observation
points (results/observation_points/<role>.csv) and scored by score_observations: the
relative L2 against the converged field, on the Truth Cube the RMS distance from the
CT-tracked beads. Which mesh wins a budget is then a result, not a given.

- A case on the points' own mesh (the suite's) gives its values at them directly: the
  points are its observed vertices (surface_values_at would return them exactly).
- A case on another mesh is interpolated by surface_values_at on its fine surface: the
  triangles come from the run's mesh folder (<scenario>/mesh/fine_surface.vtu beside the
  cases, as results_index.observed_rest reads it), which is regenerated, never committed
  (.gitignore): where it is not there the rows are left out and the notes say which.
- Interior points (probes, beads) are the case's own probes.csv, the runner's
  interpolation in its tets at the same points (checked: the same probe rows).
- A study joins a role only when it solves the same problem: its resolved scenario equals
  the suite reference's but for the mesh and what only names or describes it (same_problem).
- External submissions: results/submissions/<name>/score.json (tissuebench score), their
  times self-reported and normalised by the calibration figure.

Writes OUT/tables/prediction_leaderboard.{md,csv} (per role and budget, the best pair)
and OUT/tables/prediction_scores.{md,csv} (every pair). docs/prediction_leaderboard.md
says what the numbers mean.
"""
import argparse
import glob
import json
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import converged_fields  # noqa: E402
import leaderboard  # noqa: E402
import metrics  # noqa: E402
import observation_points as op  # noqa: E402
import results_index  # noqa: E402
from results_index import ResultsError  # noqa: E402
from table_io import fmt, machine_note, write_table  # noqa: E402

REPO = op.REPO
RESULTS = os.path.join(REPO, "results")
# The studies whose cases join the suite's: results/<study>/<study>/ (experiments/<study>.json).
STUDIES = ("flap_10k", "l_block_10k", "torus_10k", "truth_cube_10k", "liver_10k", "palpation_10k",
           "liver_35k", "cube_disc_100k", "flap_100k", "l_block_100k", "torus_100k", "truth_cube_100k",
           "liver_100k")
# A study's role is the suite role it refines with a size suffix: flap_gravity_10k -> flap_gravity.
SIZE_SUFFIX = re.compile(r"_\d+k$")
# Keys of a resolved scenario that name, describe or mesh it, or say what is written:
# not the problem. frames.max caps a dynamic model's frames (a run budget), not the load.
NOT_THE_PROBLEM = ("name", "description", "file", "mesh", "output", "observe", "probes")
SUBMISSIONS = os.path.join(RESULTS, "submissions")


# ---------------------------------------------------------------------------------
# Which runs solve which role's problem.

def study_folder(study, results=RESULTS):
    """results/<study>/<study>: a study's experiment folder."""
    return os.path.join(results, study, study)


def suite_role_of(study_role, suite_roles):
    """The suite role a study's role refines (its name without the size suffix), or None."""
    base = SIZE_SUFFIX.sub("", study_role or "")
    return base if base in suite_roles else None


def problem(run):
    """The resolved scenario of a run.json without what is not the problem (NOT_THE_PROBLEM)."""
    scenario = {k: v for k, v in run["scenario_resolved"].items() if k not in NOT_THE_PROBLEM}
    scenario["frames"] = {k: v for k, v in scenario.get("frames", {}).items() if k != "max"}
    return scenario


def same_problem(run, suite_run):
    """[keys of the resolved scenario that differ]: empty when both runs solve one problem."""
    mine, theirs = problem(run), problem(suite_run)
    return sorted(k for k in set(mine) | set(theirs) if mine.get(k) != theirs.get(k))


class Source:
    """One experiment's scenario scored in a role: label ("suite", "flap_10k"), role (the
    suite role it ranks under: the base role), scenario_role (the suite role whose committed
    points it is read at: a study's, the role it refines), exp (results_index.Experiment),
    scenario (its name)."""

    def __init__(self, label, role, scenario_role, exp, scenario):
        self.label, self.role, self.scenario_role, self.exp, self.scenario = label, role, scenario_role, exp, scenario


def suite_sources(suite):
    """[Source] of every suite role with results, in experiment.json's order."""
    exp = results_index.Experiment(suite)
    return [Source("suite", converged_fields.base_role(role), role, exp, scenario) for role, scenario, _ in op.suite_roles(suite)[0]
            if scenario in exp.scenarios]


def study_sources(suite, results, notes):
    """[Source] of the studies (STUDIES) that solve a suite role's problem; what is left out
    and why is appended to notes."""
    roles, _ = op.suite_roles(suite)
    suite_exp = results_index.Experiment(suite)
    reference = {r: op.reference_case(suite, r)["run"] for r, s, _ in roles if s in suite_exp.scenarios}
    out = []
    for study in STUDIES:
        folder = study_folder(study, results)
        if not os.path.isdir(folder):
            notes.append(f"{study}: no results folder ({folder})")
            continue
        exp = results_index.Experiment(folder)
        for study_role, scenarios in exp.roles.items():
            role = suite_role_of(study_role, reference)
            if role is None:
                notes.append(f"{study}: role {study_role} refines no suite role: left out")
                continue
            for scenario in scenarios:
                if scenario not in exp.scenarios:
                    notes.append(f"{study}/{scenario}: no case results: left out")
                    continue
                first = next(iter(exp.scenarios[scenario].values()))
                differ = same_problem(first["run"], reference[role])
                if differ:
                    notes.append(f"{study}/{scenario}: not {role}'s problem (its {', '.join(differ)} differ): left out")
                    continue
                out.append(Source(study, role, role, exp, scenario))
    return out


# ---------------------------------------------------------------------------------
# A case's values at the observation points.

def mesh_folder(case):
    """The run's mesh folder beside its case folders (<scenario>/mesh), as results_index reads it."""
    return os.path.join(os.path.dirname(case["folder"]), "mesh")


def on_points_mesh(points_ids, case, ids, rest, points_case):
    """The rows of the case's observed vertices (ids #O, rest #O by 3 or None) holding the points
    (points_ids #S, the suite mesh's vertices), or None when the case ran on another mesh: its
    mesh recipe is not that of the points' case (points_case, the role's suite reference), or,
    where both give coordinates, a point's vertex is elsewhere."""
    if case["run"]["scenario_resolved"].get("mesh") != points_case["run"]["scenario_resolved"].get("mesh"):
        return None
    row = {int(v): k for k, v in enumerate(ids)}
    rows = [row.get(int(v)) for v in points_ids]
    if any(r is None for r in rows):
        raise ResultsError(f"{case['folder']}/top_surface.csv: the suite mesh's vertex {points_ids[rows.index(None)]} "
                           "is not observed (another patch?)")
    rows = np.array(rows)
    if rest is not None and points_case["rest"] is not None and not np.array_equal(rest[rows], points_case["rest"]):
        raise ResultsError(f"{case['folder']}/top_surface.csv: the points' vertices are elsewhere (another mesh?)")
    return rows


def read_surface_mesh(case):
    """(V  #V by 3 rest positions, F  #F by 3 triangles) of the run's fine surface (its mesh
    folder's fine_surface.vtu); None when the folder is not there (not committed)."""
    path = os.path.join(mesh_folder(case), "fine_surface.vtu")
    if not os.path.isfile(path):
        return None
    from vtu_plot import read_vtu  # matplotlib: only when a mesh is read
    V, F, _ = read_vtu(path)
    expected = case["run"].get("mesh", {}).get("surface_vertices")
    if expected is not None and len(V) != expected:
        raise ResultsError(f"{path}: {len(V)} vertices, {case['folder']}/run.json's mesh has {expected}: another mesh")
    return V, F


def interpolated(case, ids, rest, u, points, names):
    """#S by 3 values at the points (rest positions #S by 3) from a case on another mesh
    (ids #O, rest #O by 3 or None, u #O by 3: its top_surface.csv), by surface_values_at on
    its fine surface (the observed patch's triangles); None without its mesh folder."""
    mesh = read_surface_mesh(case)
    if mesh is None:
        return None
    V, F = mesh
    if rest is not None and not np.array_equal(V[ids], rest):
        raise ResultsError(f"{mesh_folder(case)}/fine_surface.vtu: not the mesh of {case['folder']}/top_surface.csv "
                           "(other coordinates)")
    U = np.full_like(V, np.nan)  # the observed vertices alone are known
    U[ids] = u
    return op.surface_values_at(points, V, op.patch_faces(F, ids), U, names=names)[0]


def points_rest(role, suite, data_dir):
    """#S by 3 rest positions of the role's surface points (the liver's from the suite's mesh folder)."""
    base = converged_fields.base_role(role)
    scenario = {r: s for r, s, _ in op.suite_roles(suite)[0]}[base]
    folder = os.path.join(suite, scenario, "mesh")
    return op.surface_coordinates(role, mesh_folder=folder if os.path.isdir(folder) else None, data_dir=data_dir)


def probe_values(case, interior):
    """#I by 3 displacements at the role's interior points from the case's probes.csv, or None
    (no interior points, or the case wrote none); other probe rows are an error naming the file."""
    if interior is None or not os.path.isfile(os.path.join(case["folder"], "probes.csv")):
        return None
    rows = op.probe_rows(case["folder"])
    expected = [int(n[1:]) for n in interior["id"]]
    if rows.tolist() != expected:
        raise ResultsError(f"{case['folder']}/probes.csv: probes {rows.tolist()[:5]}..., the role's are "
                           f"{expected[:5]}...")
    return leaderboard.probe_displacements(case["folder"])


# ---------------------------------------------------------------------------------
# Scoring.

def rank_key(role):
    """What a role ranks by: the beads on the Truth Cube, else the field against the converged one."""
    return "bead_rms_mm" if leaderboard.accuracy_key(role) == "bead_rms_mm" else "rel_l2_converged"


def settled(case):
    """Whether the case reached its steady state (a static case always has)."""
    run = case["run"]
    return bool(run.get("reached_steady_state")) if run.get("dynamic", False) else True


class RolePoints:
    """A role's committed points, read once: files (op.read_role), case (the suite reference
    case whose mesh's vertices they are, "rest" added: the points' #S by 3 or None), rest #S by 3
    (None on the liver without the suite's mesh folder: only cases on its mesh can then be read)."""

    def __init__(self, role, suite, data_dir):
        self.files = op.read_role(role)
        self.case = op.reference_case(suite, converged_fields.base_role(role))
        self.case["rest"] = self.files["surface"]["rest"]
        try:
            self.rest = points_rest(role, suite, data_dir)
        except ResultsError:
            self.rest = None


def case_row(source, name, case, score):
    """A row dict of a case from its scores (score_observations' keys)."""
    run = case["run"]
    return {"role": source.role, "source": source.label, "scenario_role": source.scenario_role, "method": name,
            "model": run["model"], "surface_vertices": run.get("mesh", {}).get("surface_vertices"),
            "fine_tets": run.get("mesh", {}).get("fine_tets"),
            "rel_l2_converged": score["rel_l2_converged"], "probe_error_mm": score["probe_error_mm"],
            "bead_rms_mm": score["bead_rms_mm"], "median_ms": case["timings"]["step"]["median_ms"],
            "settled": settled(case), "self_reported": False, "is_reference": False, "note": score["note"]}


def beads_only(source, name, case, points, data_dir):
    """A Truth Cube case without a committed surface, scored by its beads alone (its probes.csv;
    op.bead_rms_mm), or None when it ranks by the field or wrote no beads."""
    interior = points.files["interior"]
    probes = probe_values(case, interior) if rank_key(source.role) == "bead_rms_mm" else None
    if probes is None:
        return None
    nan = float("nan")
    return case_row(source, name, case, {"rel_l2_converged": nan, "probe_error_mm": nan, "note": "",
                                         "bead_rms_mm": op.bead_rms_mm(interior, points.files["meta"], probes, data_dir)})


def score_case(source, name, case, points, data_dir):
    """One row dict of a case (None when its mesh folder is needed and not there)."""
    surface = points.files["surface"]
    ids, rest, u = metrics.read_displacements(os.path.join(case["folder"], "top_surface.csv"))
    vertices = surface.get("source_vertex") if surface["rest"] is None else np.array([int(n[1:]) for n in surface["id"]])
    rows = on_points_mesh(vertices, case, ids, rest, points.case)
    if rows is not None:
        values = u[rows]
    elif points.rest is None:
        return None
    else:
        values = interpolated(case, ids, rest, u, points.rest, surface["id"])
        if values is None:
            return None
    score = op.score_observations(source.scenario_role, values, probe_values(case, points.files["interior"]),
                                  data_dir=data_dir)
    return case_row(source, name, case, score)


def read_submission(path):
    """A row dict of a submission's score.json (tissuebench score), its time the normalised median."""
    try:
        with open(path) as f:
            doc = json.load(f)
        return {"role": converged_fields.base_role(doc["role"]), "source": "submission " + os.path.basename(os.path.dirname(path)),
                "scenario_role": doc["role"], "method": doc["method"], "model": "external",
                "surface_vertices": doc["resolution"].get("surface_vertices"), "fine_tets": doc["resolution"].get("tets"),
                "rel_l2_converged": number(doc["rel_l2_converged"]), "probe_error_mm": number(doc["probe_error_mm"]),
                "bead_rms_mm": number(doc["bead_rms_mm"]),
                "median_ms": float(doc["timing"]["frame_median_ms"]["normalised"]), "settled": True,
                "self_reported": True, "is_reference": False, "note": doc.get("note", "")}
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as e:
        raise ResultsError(f"{path}: not a tissuebench score.json ({type(e).__name__}: {e})") from None


def number(x):
    """A score.json number: null is NaN."""
    return float("nan") if x is None else float(x)


def submission_rows(folder=SUBMISSIONS):
    """Row dicts of every results/submissions/<name>/score.json, in name order ([] without the folder)."""
    return [read_submission(p) for p in sorted(glob.glob(os.path.join(folder, "*", "score.json")))]


def label(row):
    """A pair's name in a cell: 'method @ surface vertices', marked when self-reported."""
    return f"{row['method']} @ {row['surface_vertices']}" + (" (self-reported)" if row["self_reported"] else "")


# ---------------------------------------------------------------------------------
# The tables.

def missing_mesh_note(source, case, points):
    """Why a scenario's cases on another mesh are left out: its mesh folder, or (the liver's
    points, third-party geometry) the suite's, is not there."""
    folder = mesh_folder(case) if points.rest is not None else mesh_folder(points.case)
    what = "its mesh folder" if points.rest is not None else f"the coordinates of {source.scenario_role}'s points"
    experiment = source.label if points.rest is not None else "suite"
    return (f"{source.label}/{source.scenario}: left out: {what} needs {op.rel(folder)} (built meshes are regenerated, "
            f"not committed: `tissuebench run experiments/{experiment}.json` writes it)")


def collect(suite, results, data_dir, submissions=SUBMISSIONS):
    """(rows: every pair's row dict, cases: {"source/scenario/case": case} for the machine note,
    notes: what is left out and why)."""
    notes = []
    sources = suite_sources(suite) + study_sources(suite, results, notes)
    rows, cases, points = [], {}, {}
    for source in sources:
        if source.scenario_role not in points:
            points[source.scenario_role] = RolePoints(source.scenario_role, suite, data_dir)
        missing = 0
        for name, case in source.exp.scenario(source.scenario).items():
            if not os.path.isfile(os.path.join(case["folder"], "top_surface.csv")):
                row = beads_only(source, name, case, points[source.scenario_role], data_dir)
                missing += 1
                if row is not None:
                    rows.append(row)
                    cases[f"{source.label}/{source.scenario}/{name}"] = case
                continue
            row = score_case(source, name, case, points[source.scenario_role], data_dir)
            if row is None:
                notes.append(missing_mesh_note(source, case, points[source.scenario_role]))
                break
            rows.append(row)
            cases[f"{source.label}/{source.scenario}/{name}"] = case
        if missing:
            ranked = ("scored by their beads alone (probes.csv)" if rank_key(source.role) == "bead_rms_mm"
                      else "left out")
            notes.append(f"{source.label}/{source.scenario}: {missing} case(s) without a committed top_surface.csv "
                         f"(the observed surface is not committed: .gitignore): {ranked}")
    rows += submission_rows(submissions)
    order = [r for r, _, _ in op.suite_roles(suite)[0]]
    rows.sort(key=lambda r: (order.index(r["role"]), r["surface_vertices"] or 0))
    return rows, cases, notes


def winners(rows, role, key):
    """{budget: best row within it or None} of a role's rows (leaderboard.best_within)."""
    mine = [r for r in rows if r["role"] == role]
    return {b: leaderboard.best_within(mine, key, b) for b in leaderboard.BUDGETS_MS}


def board_row(rows, role, points_meta):
    """A row of prediction_leaderboard: the role, what it ranks by, a cell per budget, the pairs."""
    key = rank_key(role)
    mine = [dict(r, case=label(r)) for r in rows if r["role"] == role]
    if points_meta["converged"] is None and key == "rel_l2_converged":
        cells = ["not ranked: no converged answer"] * len(leaderboard.BUDGETS_MS)
    else:
        cells = [leaderboard.budget_cell(mine, key, b) for b in leaderboard.BUDGETS_MS]
    ranked_by = "bead RMS (mm)" if key == "bead_rms_mm" else "rel L2 vs converged"
    resolutions = sorted({r["surface_vertices"] for r in mine if r["surface_vertices"]})
    return [role, ranked_by] + cells + [len(mine), ", ".join(str(v) for v in resolutions)]


def score_table_row(r):
    """A row of prediction_scores."""
    sig = leaderboard.sig
    return [r["role"], r["source"], r["method"], r["model"], str(r["surface_vertices"]), str(r["fine_tets"]),
            sig(r["rel_l2_converged"]), sig(r["probe_error_mm"]), sig(r["bead_rms_mm"]), fmt(r["median_ms"]), "yes" if r["settled"] else "no",
            "yes" if r["self_reported"] else "no"]


CAPTION = ("Each cell: the (method @ surface vertices of its mesh) pair whose median frame fits the budget with the "
           "lowest error against the converged continuum at the role's observation points (relative L2; on the "
           "Truth Cube, the bead RMS in mm); in brackets, a more accurate pair just over the budget.")


def notes_text(roles_without, notes, machine):
    """The table's notes: the machine once, then a short list."""
    items = [f"- {role}: {note}" for role, note in roles_without]
    items += [f"- {n}" for n in notes]
    items.append("- A suite role's `_10k` cases (cube_pull_disc_10k, cube_push_disc_10k) rank under their base role: "
                 "the same problem, points and converged answer (results/observation_points).")
    items.append("- Self-reported: an external submission's time (results/submissions/<name>/score.json), "
                 "normalised by `tissuebench calibrate`'s figure; not measured here.")
    return machine + "\n\n### Notes\n\n" + "\n".join(items)


def make(out=RESULTS, suite=None, results=RESULTS, data_dir=None, submissions=SUBMISSIONS):
    """Writes OUT/tables/prediction_leaderboard.{md,csv} and prediction_scores.{md,csv};
    returns the row dicts."""
    suite = suite or os.path.join(results, "suite")
    rows, cases, notes = collect(suite, results, data_dir, submissions)
    if not rows:
        raise ResultsError(f"{suite}: no case to score")
    board, without = [], []
    for role, _, _ in op.suite_roles(suite)[0]:
        if converged_fields.base_role(role) != role:
            continue  # ranked under its base role
        meta = op.read_role(role)["meta"]
        board.append(board_row(rows, role, meta))
        if meta["converged"] is None:
            ranked = "beads" if rank_key(role) == "bead_rms_mm" else "nothing: its rows are listed unranked"
            without.append((role, f"{meta['note']}; ranked by {ranked}"))
    machine = machine_note(cases, "threads as each case's parameters say (one unless a `threads` is given)")
    tables = os.path.join(out, "tables")
    write_table(tables, "prediction_leaderboard",
                ["role", "ranked by"] + [f"best within {b:g} ms" for b in leaderboard.BUDGETS_MS]
                + ["pairs", "resolutions (surface vertices)"],
                board, CAPTION + "\n\n" + notes_text(without, notes, machine)
                + "\n\nEvery pair's scores: [prediction_scores.md](prediction_scores.md).")
    write_table(tables, "prediction_scores",
                ["role", "source", "method", "model", "surface vertices", "fine tets", "rel L2 vs converged",
                 "probe error vs converged (mm)", "bead RMS (mm)", "median (ms)", "settled", "self-reported"],
                [score_table_row(r) for r in rows],
                "Every (method, resolution) pair at the role's observation points (analysis/prediction_leaderboard.py); "
                "the winners per budget: [prediction_leaderboard.md](prediction_leaderboard.md).\n\n" + machine)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default=RESULTS, help="writes OUT/tables (default results)")
    parser.add_argument("--results", default=RESULTS, help="the results tree read (default results)")
    parser.add_argument("--data-dir", default=None, help="the Truth Cube's bead table and the liver's files")
    a = parser.parse_args()
    rows = results_index.main(lambda: make(a.out, None, a.results, a.data_dir), "prediction_leaderboard")
    print(f"written: {a.out}/tables/prediction_leaderboard.md ({len(rows)} pairs)")


if __name__ == "__main__":
    main()
