"""The law's own uncertainty on every suite scenario: how far the answers of three
standard neo-Hookean laws (and the linear law) lie apart, beside how far the ranked
models lie from the reference, so that no ranking claims more than the law allows.

Usage: /usr/bin/python3 analysis/law_sensitivity.py [RESULTS/suite] [OUT] [--data-dir DIR] [--with RUNS/suite]

Reads only the results tree (results_index.py). In each scenario the laws are: the
reference case's (the coupled neo-Hookean law, Newton), each case experiment.json lists
under law_references (the suite's reference-isochoric and reference-stable: the same
Newton solve under another law), and the linear law: the first case of the
reference's model whose run.json reports a linear solve (fem-linear). A case's law is
the one its run.json's model report names (fine_solve.material_law). A law reference
whose answer inverts a tet (its smallest det F <= 0) is left out, and named. The ranked
models are the cases that are none of the references (results_index.Experiment.
is_reference). --with takes the law references from another run of the suite (the
law cases run alone) and scores them beside RESULTS' cases, on the same meshes (the
rest positions are checked).

For each scenario, between each pair of laws and between each ranked model and the
reference:
- surface field: ||u_a - u_b|| / ||u_ref||, the Euclidean norm over every observed
  vertex's displacement vector (the leaderboard's relative L2; u_ref the reference's);
- probes: the same over the scenario's interior probes (the beads on the Truth Cube);
- tool force: at the last frame, the largest over the tools of |F_a - F_b| / |F_ref|;
- on the Truth Cube, each law's RMS bead error (mm, as analysis/truth_cube.py);
and the ranked models' surface errors with each other nonlinear law's answer as the
reference: which pairs of models change order (with the smallest per-frame budget
both fit), and which of the leaderboard's cells (the most accurate case within 0.1, 1
and 16 ms) would go to another model.
Writes OUT/tables/law_sensitivity.md (short lines on what it means for the ranking,
then the tables) and OUT/tables/law_sensitivity.csv (one value a row).
"""
import argparse
import csv
import itertools
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import leaderboard  # noqa: E402
import metrics  # noqa: E402
import results_index  # noqa: E402
from results_index import ResultsError  # noqa: E402
from table_io import markdown_table, machine_note  # noqa: E402

LINEAR = "linear"
# Short names of the laws of models/numerics/materials/material_laws.h in the tables;
# a law not listed keeps its own name.
SHORT_NAMES = {"neo_hookean": "coupled", "neo_hookean_isochoric": "isochoric", "stable_neo_hookean": "stable",
               LINEAR: "linear"}
LINEAR_SOLVES = ("direct", "iterative")
TIE = 1e-9  # two errors closer than this, relative, are the same place in a ranking


def short(law):
    return SHORT_NAMES.get(law, law)


def law_of(case):
    """The material law a case solved, as its run.json's model report names it: the fine
    solve's material_law, 'linear' for a linear solve (direct, iterative), else None."""
    report = case["run"].get("model_report", {}).get("fine_solve", {})
    if "material_law" in report:
        return report["material_law"]
    return LINEAR if report.get("solve") in LINEAR_SOLVES else None


def smallest_det_f(case):
    """The smallest det F over the tets of a case's answer, as its run.json's fine solve
    reports it (Newton's smallest_det_f_last_solve), or None."""
    return case["run"].get("model_report", {}).get("fine_solve", {}).get("smallest_det_f_last_solve")


def inverted_law_cases(exp, cases):
    """{law: (case name, smallest det F)} of the law references whose answer inverts a
    tet (det F <= 0): a law defined past J = 0 (the stable neo-Hookean) has equilibria
    no tissue reaches, which law_cases leaves out rather than call them the law's answer."""
    inverted = {}
    for name in [n for n in exp.law_references if n in cases]:
        det = smallest_det_f(cases[name])
        if det is not None and det <= 0:
            inverted[law_of(cases[name])] = (name, det)
    return inverted


def law_cases(exp, cases):
    """{law: case name} of one scenario, in order: the reference's law, the law
    references' (but those whose answer inverts a tet: inverted_law_cases), then the
    linear law (the first case of the reference's model that solved it), each law once."""
    laws = {}
    inverted = {name for name, _ in inverted_law_cases(exp, cases).values()}
    for name in [exp.reference] + [n for n in exp.law_references if n in cases and n not in inverted]:
        law = law_of(cases[name])
        if law is None:
            raise ResultsError(f"{cases[name]['folder']}/run.json: the model report names no material law")
        laws.setdefault(law, name)
    ref = cases[exp.reference]
    if LINEAR not in laws:
        linear = [n for n, c in cases.items()
                  if c["run"]["model"] == ref["run"]["model"] and law_of(c) == LINEAR]
        if linear:
            laws[LINEAR] = linear[0]
    return laws


class Observables:
    """What each case of a scenario answers (its surface field, probes, tool forces),
    read once; the fields checked to be at the reference's vertices."""

    def __init__(self, cases, ref_name):
        self.cases = cases
        self.ref = ref_name
        self._read = {}

    def of(self, name):
        if name not in self._read:
            folder = self.cases[name]["folder"]
            try:
                observed = metrics.read_displacements(os.path.join(folder, "top_surface.csv"))
                probes, forces = leaderboard.probe_displacements(folder), leaderboard.final_tool_forces(folder)
            except (OSError, ValueError, IndexError) as e:  # ResultsError is a ValueError
                raise ResultsError(f"{folder}: unreadable results ({e})")
            if name != self.ref:
                observed_ref, _, probes_ref, _ = self.of(self.ref)
                if not results_index.same_vertices(observed, observed_ref):
                    raise ResultsError(f"{folder}: observed vertices differ from the reference's (another mesh?)")
                if probes is not None and probes_ref is not None and probes.shape != probes_ref.shape:
                    raise ResultsError(f"{folder}/probes.csv: {len(probes)} probes, the reference has {len(probes_ref)}")
            self._read[name] = (observed, observed[2], probes, forces)
        return self._read[name]

    def field(self, a, b):
        """||u_a - u_b|| / ||u_ref|| over the observed vertices."""
        return relative(self.of(a)[1], self.of(b)[1], self.of(self.ref)[1])

    def probes(self, a, b):
        """The same over the probes; NaN where a case has none (a surface-only model)."""
        pa, pb, pref = self.of(a)[2], self.of(b)[2], self.of(self.ref)[2]
        return float("nan") if pa is None or pb is None or pref is None else relative(pa, pb, pref)

    def force(self, a, b):
        """Largest over the reference's tools of |F_a - F_b| / |F_ref|; NaN where one
        measures no force on a tool (PBD's grasps)."""
        fa, fb, fref = self.of(a)[3], self.of(b)[3], self.of(self.ref)[3]
        diffs = []
        for tool, f_ref in fref.items():
            if tool not in fa or tool not in fb or not np.all(np.isfinite(fa[tool])) \
                    or not np.all(np.isfinite(fb[tool])) or not np.linalg.norm(f_ref) > 0:
                return float("nan")
            diffs.append(float(np.linalg.norm(fa[tool] - fb[tool]) / np.linalg.norm(f_ref)))
        return max(diffs) if diffs else float("nan")

    def norms(self):
        """{quantity: the reference's norm, as a string with its unit} (what each difference is divided by)."""
        _, u, p, f = self.of(self.ref)
        out = {"surface field": f"||u_ref|| = {np.linalg.norm(u) * 1000:.4g} mm"}
        if p is not None:
            out["probes"] = f"||u_ref|| = {np.linalg.norm(p) * 1000:.4g} mm"
        if f:
            out["tool force"] = "|F_ref| = " + ", ".join(f"{np.linalg.norm(v):.4g} N" for v in f.values())
        return out


def relative(a, b, ref):
    norm = float(np.linalg.norm(ref))
    return float(np.linalg.norm(a - b)) / norm if norm > 0 else float("nan")


QUANTITIES = (("surface field", "field"), ("probes", "probes"), ("tool force", "force"))
BEADS = "bead RMS (mm)"


def spread(errors, gap=None):
    """{models min, median, max, n} of the ranked models' finite errors ({case: error});
    given a gap, also how many are below it (NaN when the gap is) and which ("models
    below": their names, smallest error first)."""
    finite = sorted((x, name) for name, x in errors.items() if math.isfinite(x))
    v = [x for x, _ in finite]
    nan = float("nan")
    out = {"models min": v[0] if v else nan, "models median": float(np.median(v)) if v else nan,
           "models max": v[-1] if v else nan, "models n": len(v)}
    if gap is not None:
        below = [name for x, name in finite if x < gap]
        out["models below the law gap"] = len(below) if math.isfinite(gap) else nan
        out["models below"] = below
    return out


def law_gap(values):
    """The largest difference between two nonlinear laws in {what: value}."""
    gaps = [v for what, v in values.items()
            if " vs " in what and short(LINEAR) not in what.split(" vs ") and math.isfinite(v)]
    return max(gaps) if gaps else float("nan")


def add_law_cases(exp, other_results):
    """The law references of another run of the suite (the law cases run alone, e.g.
    `tissuebench run experiments/suite.json --case reference-isochoric ...`), put into
    RESULTS' scenarios of the same name in place of any case of that name. Returns how many."""
    other = results_index.Experiment(other_results)
    added = 0
    for scenario, cases in other.scenarios.items():
        for name in other.law_references:
            if scenario in exp.scenarios and name in cases:
                exp.scenarios[scenario][name] = cases[name]
                added += 1
    if not added:
        raise ResultsError(f"{other_results}: no law reference ({', '.join(other.law_references) or 'none listed'}) "
                           f"of a scenario of {exp.root}")
    exp.law_references += [n for n in other.law_references if n not in exp.law_references]
    return added


def scenario_values(exp, role, beads):
    """One scenario: {"laws": {law: case}, "norms": {quantity: what it is divided by},
    "values": {quantity: {what: value}}, "beads": {law or models ...: RMS mm} or None};
    what: a pair of laws 'a vs b', or the ranked models' spread (spread())."""
    cases = exp.by_role(role)
    obs = Observables(cases, exp.reference)
    laws = law_cases(exp, cases)
    ranked = [n for n in cases if not exp.is_reference(n)]
    norms = obs.norms()
    values = {}
    for quantity, method in QUANTITIES:
        if quantity not in norms:
            continue
        measure = getattr(obs, method)
        pairs = sorted(itertools.combinations(laws.items(), 2), key=lambda p: LINEAR in (p[0][0], p[1][0]))
        v = {f"{short(la)} vs {short(lb)}": measure(a, b) for (la, a), (lb, b) in pairs}  # the nonlinear pairs first
        v.update(spread({n: measure(n, exp.reference) for n in ranked}, law_gap(v)))
        values[quantity] = v
    bead_values = None
    if beads is not None:
        bead_values = {short(law): beads.rms_mm(cases[name]) for law, name in laws.items()}
        bead_values.update(spread({n: beads.rms_mm(cases[n]) for n in ranked}))
    # The ranked models' surface errors with each nonlinear law's answer as the reference.
    rankings = {short(law): {n: obs.field(n, name) for n in ranked} for law, name in laws.items() if law != LINEAR}
    medians = {n: float(cases[n]["timings"]["step"]["median_ms"]) for n in ranked}
    return {"laws": laws, "norms": norms, "values": values, "beads": bead_values, "rankings": rankings,
            "medians": medians, "ranked_by_field": leaderboard.accuracy_key(role) == "rel_l2",
            "inverted": inverted_law_cases(exp, cases)}


def swapped(errors, other):
    """The pairs of models (a, b) ordered one way by `errors` and the other way by
    `other` ({model: error}, finite ones only), and how many pairs there are."""
    models = [m for m in errors if math.isfinite(errors[m]) and math.isfinite(other.get(m, float("nan")))]
    pairs = list(itertools.combinations(sorted(models, key=errors.get), 2))

    def before(e, a, b):  # a strictly before b: equal answers (fem-linear and condensed) are a tie, not a swap
        return e[b] - e[a] > TIE * max(abs(e[a]), abs(e[b]))
    return [(a, b) for a, b in pairs if before(errors, a, b) and before(other, b, a)], len(pairs)


def summary(everything):
    """The lines on top (a Markdown list): what the law-to-law differences mean for the ranking."""
    fields = {role: r["values"]["surface field"] for role, r in everything.items()}
    gaps = {role: law_gap(v) for role, v in fields.items() if math.isfinite(law_gap(v))}
    if not gaps:
        return ("No scenario has a second nonlinear law's answer: the law's own uncertainty is not measured here "
                "(the suite's law_references did not run).")
    lo, hi = min(gaps, key=gaps.get), max(gaps, key=gaps.get)
    linear = [v[f"coupled vs {short(LINEAR)}"] for v in fields.values() if f"coupled vs {short(LINEAR)}" in v]
    first = (f"- The largest difference between the observed surface fields of two neo-Hookean laws (the reference's "
             f"coupled law and the others) ranges over the scenarios from {sig(gaps[lo])} ({lo}) to {sig(gaps[hi])} "
             f"({hi}) of ||u_ref||")
    if linear:
        first += f"; the linear law differs from the coupled one by {sig(min(linear))} to {sig(max(linear))}"
    lines = [first + ".",
             "- A model whose error against the reference is below the largest of these law-to-law differences in "
             "its scenario is as close to the reference as another standard law is: its rank among such models says "
             "which is nearer the coupled law's answer, not which is nearer the tissue, and a difference between two "
             "of them smaller than the gap is no evidence that one is the better tissue model."]
    limited = [f"{role} ({', '.join(fields[role]['models below'])})" for role in gaps if fields[role]["models below"]]
    free = [role for role in gaps if not fields[role]["models below"]]
    if limited:
        lines.append("- Ranked models below the gap (surface field): " + "; ".join(limited) + ".")
    if free:
        lines.append("- No ranked model is below it in " + ", ".join(free) + ": there every model is further from "
                     "the reference than the laws are from each other.")
    changes = ranking_changes(everything)
    if changes:
        lines.append("- Measured directly (the last two tables), with another neo-Hookean law's answer as the "
                     "reference the ranked models change order in " + "; ".join(
                         f"{role} ({', '.join(f'{n} pair{plural(n)} under {law}' for law, n in counts.items())})"
                         for role, counts in changes.items())
                     + "; in every other scenario their order is the same under every law measured there.")
    else:
        lines.append("- Measured directly (the last table), the ranked models keep their order with any of these "
                     "laws' answers as the reference.")
    ranked = [r for r in everything.values() if r["ranked_by_field"]]
    cells = sum(max(len(r["rankings"]) - 1, 0) * len(leaderboard.BUDGETS_MS) for r in ranked)
    moved = [budget for r in ranked for _, _, budget, _, _ in cell_changes(r)]
    by_budget = ", ".join(f"{moved.count(b)} within {b:g} ms" for b in leaderboard.BUDGETS_MS if b in moved)
    lines.append(f"- With another law's answer as the reference, {len(moved)} of the {cells} leaderboard cells ranked "
                 "by the surface field (a scenario, a budget, a law) go to another model"
                 + (f" ({by_budget}: the next-to-last table)" if moved else "") + ".")
    return "\n".join(lines)


def plural(n):
    return "" if n == 1 else "s"


def ranking_changes(everything):
    """{role: {law: how many pairs}}: the pairs of ranked models in another order (surface
    field) with another nonlinear law's answer as the reference, where there are any."""
    out = {}
    for role, r in everything.items():
        coupled = r["rankings"].get(short(next(iter(r["laws"]))))
        if coupled is None:
            continue
        counts = {law: len(swapped(coupled, errors)[0]) for law, errors in r["rankings"].items()
                  if errors is not coupled}
        counts = {law: n for law, n in counts.items() if n}
        if counts:
            out[role] = counts
    return out


def best_within(errors, medians, budget):
    """(case, error) of the most accurate ranked case whose median frame fits the budget, as
    leaderboard.best_within picks it (a tie to the faster), or None."""
    fits = [n for n in errors if math.isfinite(errors[n]) and medians.get(n, math.inf) <= budget]
    if not fits:
        return None
    best = min(fits, key=lambda n: (errors[n], medians[n]))
    return best, errors[best]


def best_text(best):
    return "none fits" if best is None else f"{best[0]} {best[1]:.4g}"


def both_within(a, b, medians):
    """The smallest of the leaderboard's budgets both cases' median frames fit, as text."""
    slower = max(medians.get(a, math.inf), medians.get(b, math.inf))
    fits = [budget for budget in leaderboard.BUDGETS_MS if slower <= budget]
    return f"{fits[0]:g} ms" if fits else f"over {leaderboard.BUDGETS_MS[-1]:g} ms"


def cell_changes(r):
    """[(law, reference law, budget, best under the reference's law, best under that law)] of
    one scenario's leaderboard cells that another nonlinear law's answer gives to another
    case; none where the leaderboard ranks by something no law changes (the beads)."""
    ref_law = short(next(iter(r["laws"])))
    under_ref = r["rankings"].get(ref_law)
    if not r["ranked_by_field"] or under_ref is None:
        return []
    out = []
    for law, errors in r["rankings"].items():
        if law == ref_law:
            continue
        for budget in leaderboard.BUDGETS_MS:
            ref, other = best_within(under_ref, r["medians"], budget), best_within(errors, r["medians"], budget)
            if (ref and ref[0]) != (other and other[0]):
                out.append((law, ref_law, budget, ref, other))
    return out


def sig(x):
    return leaderboard.sig(x)


def make(results, out, data_flag=None, with_results=None):
    """Writes OUT/tables/law_sensitivity.{md,csv}; returns {role: scenario_values()}."""
    exp = results_index.Experiment(results)
    exp.require_reference()
    if with_results:
        add_law_cases(exp, with_results)
    beads = None
    everything, missing = {}, []
    for role in exp.roles:
        scenario = exp.roles[role][0]
        if scenario not in exp.scenarios or exp.reference not in exp.scenarios[scenario]:
            missing.append(role)
            continue
        use_beads = None
        if role.startswith(leaderboard.TRUTH_CUBE_ROLE_PREFIX):
            beads = beads or leaderboard.Beads(data_flag)
            use_beads = beads
        everything[role] = scenario_values(exp, role, use_beads)
    if not everything:
        raise ResultsError(f"{results}: no scenario has its reference case's results")
    write(everything, exp, missing, os.path.join(out, "tables"))
    return everything


SPREAD = ("models min", "models median", "models max")


def number(x):
    """A value of the CSV: a count as an integer, else every digit."""
    return str(x) if isinstance(x, int) else repr(float(x))


def difference_table(everything):
    """The pairs of laws and the models' spread, per scenario and quantity: (Markdown, CSV rows)."""
    pairs = []
    for r in everything.values():
        pairs += [w for v in r["values"].values() for w in v if " vs " in w and w not in pairs]
    rows, csv_rows = [], []
    for role, r in everything.items():
        for quantity, v in r["values"].items():
            below = v["models below the law gap"]
            rows.append([role, short(next(iter(r["laws"]))), quantity, r["norms"][quantity]]
                        + [sig(v.get(p)) for p in pairs + list(SPREAD)]
                        + ["n/a" if below != below else f"{below} of {v['models n']}"])
            csv_rows += [[role, quantity, what, number(x), r["norms"][quantity]] for what, x in v.items()
                         if what != "models below"]
    md = [markdown_table(["role", "reference law", "quantity", "normalised by"] + pairs
                         + list(SPREAD) + ["models below the law gap"], rows), "",
          "Each pair: the difference between the answers of two laws on the same mesh, load and solver (Newton; "
          "the linear law: the linear FEM), ||a - b|| / ||ref|| over the observed surface vertices (the Euclidean "
          "norm of all their displacement vectors: the leaderboard's relative L2) or over the interior probes "
          "(the Truth Cube's: its beads); tool force: at the last frame, the largest over the tools of "
          "|F_a - F_b| / |F_ref|. Models: the same error of each ranked model against the reference (min, "
          "median, max over the models that measure it). Below the law gap: the ranked models whose error is "
          "smaller than the largest difference between two nonlinear laws in that scenario."]
    unmeasured = [role for role, r in everything.items() if sum(law != LINEAR for law in r["laws"]) < 2]
    if unmeasured:
        md[-1] += (" No law difference is measured on " + ", ".join(unmeasured) + ": its law references are not run "
                   "(or left out), so only the linear law stands beside the reference's.")
    return md, csv_rows


def bead_table(everything):
    """Each law's and the models' bead RMS on the Truth Cube: (Markdown, CSV rows); none elsewhere."""
    rows, csv_rows = [], []
    for role, r in everything.items():
        b = r["beads"]
        if b:
            rows.append([role] + [sig(b.get(short(law))) for law in SHORT_NAMES] + [sig(b[w]) for w in SPREAD])
            csv_rows += [[role, BEADS, what, number(x), "mm"] for what, x in b.items()]
    if not rows:
        return [], []
    return ["", markdown_table(["role"] + [f"bead RMS, {short(law)} (mm)" for law in SHORT_NAMES]
                               + [f"{w} (mm)" for w in SPREAD], rows), "",
            "The Truth Cube: RMS over the CT-tracked beads of the distance between each law's (and each ranked "
            "model's) predicted and measured positions (analysis/truth_cube.py); the table itself resolves about "
            "0.3 mm (docs/truth_cube.md)."], csv_rows


def order_table(everything):
    """The ranking with each other nonlinear law's answer as the reference: per scenario and
    law, how many pairs of ranked models change order and which leaderboard cells go to
    another case; then each pair in another order, one a row. (Markdown, CSV rows)."""
    rows, pair_rows, csv_rows = [], [], []
    for role, r in everything.items():
        ref_law = short(next(iter(r["laws"])))
        under_ref = r["rankings"].get(ref_law)
        if under_ref is None:  # the reference's law is the linear one: no ranking under a nonlinear law to compare
            continue
        changed = {(law, budget): (ref, other) for law, _, budget, ref, other in cell_changes(r)}
        for law, errors in r["rankings"].items():
            if law == ref_law:
                continue
            pairs, total = swapped(under_ref, errors)
            cells = []
            for budget in leaderboard.BUDGETS_MS:
                if not r["ranked_by_field"]:
                    cells.append("n/a (the beads rank)")
                elif (law, budget) in changed:
                    ref, other = changed[(law, budget)]
                    cells.append(f"{best_text(other)} ({ref_law}: {best_text(ref)})")
                else:
                    cells.append("same")
            rows.append([role, law, f"{len(pairs)} of {total}"] + cells)
            pair_rows += [[role, law, both_within(a, b, r["medians"]), f"{a}, {b}",
                           f"{under_ref[a]:.4g}, {under_ref[b]:.4g}", f"{errors[a]:.4g}, {errors[b]:.4g}"]
                          for a, b in pairs]
            csv_rows += [[role, f"surface field, {law} as the reference", m, number(x), r["norms"]["surface field"]]
                         for m, x in errors.items()]
        if r["ranked_by_field"]:  # the leaderboard's cells under each law (the reference's too)
            for law, errors in r["rankings"].items():
                for budget in leaderboard.BUDGETS_MS:
                    best = best_within(errors, r["medians"], budget)
                    if best:
                        csv_rows.append([role, f"best within {budget:g} ms, {law} as the reference", best[0],
                                         number(best[1]), r["norms"]["surface field"]])
    if not rows:
        return [], []
    md = ["", markdown_table(["role", "law as the reference", "pairs of ranked models in another order"]
                             + [f"best within {b:g} ms" for b in leaderboard.BUDGETS_MS], rows), "",
          "The ranking with another law's answer as the reference: each ranked model's surface error against that "
          "law's case (relative to the reference's ||u_ref||, as above); a pair counts when the two models' order "
          "differs from their order under the reference's law (errors equal to 1e-9 are a tie). Best within a "
          "budget: the leaderboard's cell (the most accurate ranked case whose median frame fits it) with that "
          "law's answer as the reference, where it goes to another case than under the reference's law (in "
          "brackets), else same; on the Truth Cube the leaderboard ranks by the beads, which no law changes."]
    if pair_rows:
        md += ["", markdown_table(["role", "law as the reference", "both within", "models (the reference law's order)",
                                   "their errors under the reference's law", "their errors under that law"],
                                  pair_rows), "",
               "Each pair of ranked models in another order, one a row: both within, the smallest per-frame budget "
               "of the leaderboard (0.1, 1, 16 ms) both models' median frames fit, where the pair competes for a "
               "cell; errors: the relative L2 of the surface field against each law's answer."]
    return md, csv_rows


def write(everything, exp, missing, tables):
    differences, csv_rows = difference_table(everything)
    csv_rows += [[role, "left out: inverts a tet", f"{short(law)} ({name})", sig(det), "smallest det F"]
                 for role, r in everything.items() for law, (name, det) in r["inverted"].items()]
    md = ["# The law's own uncertainty on every suite scenario", "", summary(everything), ""] + differences
    for table in (bead_table, order_table):
        text, rows = table(everything)
        md += text
        csv_rows += rows
    inverted = [f"{short(law)} on {role} ({name}: smallest det F {det:.3g})"
                for role, r in everything.items() for law, (name, det) in r["inverted"].items()]
    if inverted:
        md += ["", "Left out, their answer inverting tets (the law is defined past det F = 0, a tissue is not): "
               + "; ".join(inverted) + "."]
    if missing:
        md += ["", "Not measured (no reference results): " + ", ".join(missing) + "."]
    all_cases = {f"{role}/{n}": c for role in everything for n, c in exp.by_role(role).items()}
    md += ["", provenance(all_cases) + " Law cases: "
           + "; ".join(f"{role}: " + ", ".join(f"{short(law)} {name}" for law, name in r["laws"].items())
                       for role, r in everything.items()) + "."]
    os.makedirs(tables, exist_ok=True)
    with open(os.path.join(tables, "law_sensitivity.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    with open(os.path.join(tables, "law_sensitivity.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["role", "quantity", "compared", "value", "normalised by"])
        w.writerows(csv_rows)


def provenance(cases):
    """Machine, build and commit of the cases ({role/case: case}, table_io.machine_note); when
    they differ (law cases run alone, --with), each with the cases it ran."""
    threads = "threads as each case's parameters say"
    busy_clause = " On a busy machine"  # machine_note's sentence naming the busy cases, given once for all
    groups = {}
    for key, case in cases.items():
        note = machine_note({key: case}, threads).split(busy_clause)[0]
        groups.setdefault(note, []).append(key.split("/", 1)[1])
    if len(groups) == 1:
        return machine_note(cases, threads)
    whole = machine_note(cases, threads)
    busy = busy_clause + whole.split(busy_clause, 1)[1] if busy_clause in whole else ""
    return " ".join(f"{note[:-1]} ({', '.join(dict.fromkeys(names))})." for note, names in groups.items()) + busy


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="?", default="results/suite")
    parser.add_argument("out", nargs="?", default="results")
    parser.add_argument("--data-dir", default=None)
    parser.add_argument("--with", dest="with_results", default=None,
                        help="another run of the suite whose law references are scored beside RESULTS' cases")
    a = parser.parse_args()
    results_index.main(lambda: make(a.results, a.out, a.data_dir, a.with_results), "law_sensitivity")
    print(f"law sensitivity written to {a.out}/tables/law_sensitivity.md")


if __name__ == "__main__":
    main()
