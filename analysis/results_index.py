"""Finds the raw results of an experiment: results/<experiment>/<scenario>/<case>/.

Everything the analysis knows about an experiment comes from these files, never
from code: experiment.json (written by the runner: the reference case, each
scenario's role in the experiment, and its cases in the order the experiment runs
them) and each case's run.json (model, its description, the parameters it ran
with, the resolved scenario) and timings.json. A model added to an experiment
therefore appears in every table and figure without an edit here, and a script
finds the scenarios it needs by role (experiments/paper.json gives "cube_pull",
"cube_push", "liver_pull", "liver_push"), never by their names.
"""
import json
import os
import re
import sys

import numpy as np

import metrics


class ResultsError(ValueError):
    """Results that cannot answer what a script asks: a folder, a role, a scenario's
    results, a case or the reference is missing. Its message is one line, printed by
    main() without a traceback."""


def main(make, name):
    """Runs make(); a ResultsError is printed as one line ("<name>: <message>") and exits 2."""
    try:
        return make()
    except ResultsError as e:
        print(f"{name}: {e}", file=sys.stderr)
        sys.exit(2)


# The runner stages a case folder as <case>.tmp<pid> and swaps an old one out as
# <case>.old<pid> (meshing/staged_folder.h); a run killed at the wrong moment leaves
# one behind, holding run.json. Neither is a result (docs/robustness.md).
STAGING_NAME = re.compile(r"\.(tmp|old)\d+$")


def is_case_folder(folder):
    """A case's results: a folder holding run.json (written last), not a staging folder."""
    return not STAGING_NAME.search(os.path.basename(folder)) and os.path.isfile(os.path.join(folder, "run.json"))


def load_case(folder):
    """run.json and timings.json of one case folder, with its path and name."""
    with open(os.path.join(folder, "run.json")) as f:
        run = json.load(f)
    with open(os.path.join(folder, "timings.json")) as f:
        timings = json.load(f)
    return {"folder": folder, "name": os.path.basename(folder), "run": run, "timings": timings}


class Experiment:
    """The results of one experiment.

    name, description, reference (case name or None), root (folder),
    scenarios: {scenario: {case: case dict}} with cases in the experiment's order.
    """

    def __init__(self, root):
        if not os.path.isdir(root):
            raise ResultsError(f"{root}: no such results folder (run tissuebench first)")
        self.root = root
        index_path = os.path.join(root, "experiment.json")
        index = {}
        if os.path.isfile(index_path):
            with open(index_path) as f:
                index = json.load(f)
        self.name = index.get("name", os.path.basename(os.path.normpath(root)))
        self.description = index.get("description", "")
        self.reference = index.get("reference") or None
        self.transient_reference = index.get("transient_reference") or None
        # Cases that solve the reference's problem under another material law (the suite's
        # reference-isochoric, reference-stable): references too, never ranked.
        self.law_references = list(index.get("law_references", []))
        order = {s["name"]: s["cases"] for s in index.get("scenarios", [])}
        self.listed_cases = order  # {scenario: [cases]} as the experiment lists them, failed ones included
        self.listed_points = index.get("scenarios", [])  # experiment.json's entries (name, role, cases, sweep)
        self.roles = {}  # {role: [scenario names]} in experiment.json's order (a sweep gives its points its role)
        for s in self.listed_points:
            if s.get("role"):
                self.roles.setdefault(s["role"], []).append(s["name"])
        self.scenarios = {}
        for scenario in sorted(os.listdir(root)):
            sdir = os.path.join(root, scenario)
            if not os.path.isdir(sdir):
                continue
            # A case whose latest run failed keeps its earlier folder (the runner replaces a
            # folder only on success) beside its <case>.failed.json: it counts as failed, so
            # a result the current code no longer produces is never scored.
            found = {c for c in os.listdir(sdir) if is_case_folder(os.path.join(sdir, c))
                     and not os.path.isfile(os.path.join(sdir, c + ".failed.json"))}
            if not found:
                continue
            listed = [c for c in order.get(scenario, []) if c in found]
            ordered = listed + sorted(found - set(listed))  # cases the index does not list come last
            self.scenarios[scenario] = {c: load_case(os.path.join(sdir, c)) for c in ordered}

    def is_reference(self, case):
        """Whether a case is one of the experiment's references (the reference, the
        transient reference, a law reference): scored, never ranked as a model."""
        return case in (self.reference, self.transient_reference) or case in self.law_references

    def failure(self, scenario, case):
        """The runner's message for a case that failed (<scenario>/<case>.failed.json), or None."""
        path = os.path.join(self.root, scenario, case + ".failed.json")
        if not os.path.isfile(path):
            return None
        with open(path) as f:
            return json.load(f).get("error")

    def scenario(self, name):
        if name not in self.scenarios:
            raise ResultsError(f"{self.root}/{name}: missing scenario results")
        return self.scenarios[name]

    def scenario_name(self, role):
        """The name of the one scenario experiment.json lists in `role`, if its results are there."""
        names = self.roles.get(role, [])
        if not names:
            listed = ", ".join(self.roles) or "none"
            raise ResultsError(f"{self.root}: experiment.json gives no scenario the role '{role}' (roles: {listed}; "
                               "an experiment file gives roles, and `tissuebench run FILE --index-only` rewrites "
                               "experiment.json)")
        if len(names) > 1:
            raise ResultsError(f"{self.root}: role '{role}' is held by {len(names)} scenarios (a sweep); "
                               "this script needs one")
        if names[0] not in self.scenarios:
            raise ResultsError(f"{self.root}: no results for role '{role}' (scenario '{names[0]}'): a partial run? "
                               f"run it with tissuebench run <experiment file> --scenario {names[0]}")
        return names[0]

    def by_role(self, role):
        """{case: case dict} of the scenario in `role` (scenario_name)."""
        return self.scenarios[self.scenario_name(role)]

    def case_names(self, scenario_names):
        """Case names present in every one of the scenarios, in the first one's order."""
        names = list(self.scenario(scenario_names[0]))
        return [n for n in names if all(n in self.scenario(s) for s in scenario_names[1:])]

    def compared_cases(self, scenario_names):
        """The cases compared with the reference: every case but the reference."""
        return [c for c in self.case_names(scenario_names) if c != self.require_reference()]

    def require_reference(self):
        if not self.reference:
            raise ResultsError(f"{self.root}/experiment.json: no reference case declared "
                             "(add \"reference\": \"<case>\" to the experiment file)")
        return self.reference

    def metrics(self, scenario, case, observed="top_surface.csv", reference=None):
        """metrics.compare of `case` against the reference case of `scenario`."""
        cases = self.scenario(scenario)
        ref_name = reference or self.require_reference()
        if ref_name not in cases:
            raise ResultsError(f"{self.root}/{scenario}/{ref_name}: missing reference results")
        return case_metrics(cases[case], cases[ref_name], observed)


def load_point(case):
    """The load point a case ran with (resolved scenario in run.json)."""
    run = case["run"]
    scenario = run.get("scenario_resolved") or run.get("scenario_as_read")  # the latter: results before 2026-11
    return scenario["load"]["point"]


def same_vertices(a, b):
    """Whether two read_displacements results hold the same vertices: the same
    indices and, where both give them, the same rest coordinates."""
    (ids_a, rest_a, _), (ids_b, rest_b, _) = a, b
    if not np.array_equal(ids_a, ids_b) or (rest_a is None) != (rest_b is None):
        return False
    return rest_a is None or np.array_equal(rest_a, rest_b)


def observed_rest(case, observed="top_surface.csv"):
    """The rest coordinates (#V x 3) of a case's vertices in `observed`: from the
    file, or, when it gives none (a mesh read from a third-party file, whose geometry
    the repository does not hold: README "Data"), from the fine surface of the mesh
    folder the run wrote beside the case (<scenario>/mesh/, never committed)."""
    ids, rest, _ = metrics.read_displacements(os.path.join(case["folder"], observed))
    if rest is not None:
        return rest
    surface = os.path.join(os.path.dirname(case["folder"]), "mesh", "fine_surface.vtu")
    if not os.path.isfile(surface):
        raise ResultsError(f"{case['folder']}/{observed}: no coordinates (a third-party mesh, README 'Data') and "
                           f"no {surface} to take them from: rerun the scenario here (with its mesh output)")
    from vtu_plot import read_vtu  # matplotlib: only when a figure or a distance needs the geometry
    points = read_vtu(surface)[0]
    if ids.max() >= len(points):
        raise ResultsError(f"{surface}: {len(points)} vertices, {observed} names vertex {ids.max()} (another mesh?)")
    return points[ids]


def observed_load_row(case, ids):
    """The row of `ids` holding the observed vertex the runner found nearest the load
    point (run.json "observed_vertex_nearest_load"), None when it names none."""
    vertex = case["run"].get("observed_vertex_nearest_load")
    rows = np.flatnonzero(ids == vertex) if vertex is not None else []
    return int(rows[0]) if len(rows) else None


def case_metrics(case, reference_case, observed="top_surface.csv", extended=False):
    """metrics.compare (or metrics.extended) of one case's displacements against
    another's, at the same vertices. Without coordinates in the files, the vertex at
    the load is the one run.json names, and metrics.extended's distances take the
    rest surface from the run's mesh folder (observed_rest)."""
    ref_read = metrics.read_displacements(os.path.join(reference_case["folder"], observed))
    case_read = metrics.read_displacements(os.path.join(case["folder"], observed))
    if not same_vertices(ref_read, case_read):
        raise ValueError(f"{case['folder']}: observed vertices differ from {reference_case['folder']}'s")
    ids, rest, u = case_read
    u_ref = ref_read[2]
    if extended:
        return metrics.extended(u, u_ref, rest if rest is not None else observed_rest(case, observed),
                                load_point(case))
    return metrics.compare(u, u_ref, rest, load_point(case), None if rest is not None else observed_load_row(case, ids))


def load_experiment(root):
    """Experiment(root); kept for the scripts that index it as {scenario: {case: case}}."""
    return Experiment(root).scenarios
