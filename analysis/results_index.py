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


def case_metrics(case, reference_case, observed="top_surface.csv", extended=False):
    """metrics.compare (or metrics.extended) of one case's displacements against
    another's, at the same vertices."""
    _, rest, u_ref = metrics.read_displacements(os.path.join(reference_case["folder"], observed))
    _, rest2, u = metrics.read_displacements(os.path.join(case["folder"], observed))
    if rest.shape != rest2.shape or not (rest == rest2).all():
        raise ValueError(f"{case['folder']}: observed vertices differ from {reference_case['folder']}'s")
    return (metrics.extended if extended else metrics.compare)(u, u_ref, rest, load_point(case))


def load_experiment(root):
    """Experiment(root); kept for the scripts that index it as {scenario: {case: case}}."""
    return Experiment(root).scenarios
