"""The suite's leaderboard: every case of every scenario of experiments/suite.json
scored against its scenario's reference case (and, on the Truth Cube, against the
CT-tracked beads), then, per scenario and per-frame time budget, the most accurate
case that fits the budget.

Usage: /usr/bin/python3 analysis/leaderboard.py [RESULTS/suite] [OUT] [--data-dir DIR] [--with RUNS/suite]
       [--readme README.md]

Reads only the results tree (results_index.py): the cases, their models and
parameters, the scenario roles and the reference come from experiment.json and each
case's run.json, so a model added to the suite (or run on it with --model) gets its
rows without an edit here. Writes OUT/tables/suite_scores.{md,csv} (every case, every
metric), OUT/tables/leaderboard.{md,csv} (per scenario and budget),
OUT/tables/leaderboard_converged.{md,csv} (the same, ranked against the converged
field of the reference study where it has one: converged_fields.py) and
OUT/figures/suite_<role>.png (time per frame against error, the Pareto front drawn).
docs/suite.md says what each number means.
"""
import argparse
import csv
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import converged_fields  # noqa: E402
import metrics  # noqa: E402
import results_index  # noqa: E402
import truth_cube  # noqa: E402
from results_index import ResultsError  # noqa: E402
from table_io import busy_cases, case_table, fmt, machine_note, markdown_table, write_table  # noqa: E402

BUDGETS_MS = (0.1, 1.0, 16.0)
# Between two runs of the suite on the 2-vCPU machines it was timed on, 9 in 10 cases'
# median frames moved by less than this factor either way (8 in 10 within 0.72-1.25x,
# the extremes 0.45-1.86x; docs/suite.md, "What the suite says"): a more accurate case
# that misses a budget by less is named beside the cell's.
EDGE_FACTOR = 1.5
TRUTH_CUBE_ROLE_PREFIX = "truth_cube"


def sig(x):
    """An error to three significant digits (errors span 1e-8 to 1); n/a when not a number."""
    return "n/a" if x is None or x != x else f"{x:.3g}"


def read_csv_rows(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def field_error(case, ref):
    """(relative L2, largest vertex error in m) of the case's observed surface
    displacement against the reference's, at the same vertices (metrics.compare's
    definitions; a scenario of tools alone has no load point for the others)."""
    ref_read = metrics.read_displacements(os.path.join(ref["folder"], "top_surface.csv"))
    case_read = metrics.read_displacements(os.path.join(case["folder"], "top_surface.csv"))
    if not results_index.same_vertices(ref_read, case_read):
        raise ResultsError(f"{case['folder']}: observed vertices differ from {ref['folder']}'s (another mesh?)")
    m = metrics.compare(case_read[2], ref_read[2], None, None)
    return m["rel_l2"], m["max_error"]


REFERENCE_ERRORS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "experiments",
                                "suite_reference_errors.json")


def read_reference_errors(path):
    """{role: declared entry} of the reference-error file (analysis/suite_reference_convergence.py
    writes it: each scenario's reference and its estimated discretisation error), {} when
    path is None or the file is not there."""
    if not path or not os.path.isfile(path):
        return {}
    with open(path) as f:
        doc = json.load(f)
    # "roles", not "scenarios": an experiments/*.json with "scenarios" is an experiment file.
    if not isinstance(doc.get("roles"), dict):
        raise ResultsError(f"{path}: no 'roles' object")
    return doc["roles"]


def reference_error_text(entry):
    """The reference's estimated discretisation error, for a table cell: the relative L2 of
    its observed field against the converged one (docs/reference_convergence.md), or why none."""
    if entry is None:
        return "not estimated"
    if entry.get("field_error") is None:
        return entry.get("note", "not estimated")
    finest = "P%d L%d" % (entry["converged"]["order"], entry["converged"]["level"])
    text = f"{sig(entry['field_error'])} (vs {entry.get('field_error_against') or finest})"
    beads = entry.get("qoi", {}).get("bead_rms_mm", {})
    if beads.get("finest_value") is not None:  # the Truth Cube ranks by the beads: their RMS on both
        text += f"; bead RMS {beads['value']:.2f} mm ({finest}: {beads['finest_value']:.2f})"
    return text


def read_trajectory(folder):
    """(header, frames x columns array) of the case's trajectory.csv (the displacement of
    its tracked surface vertices at each of its first frames), or None when it wrote none."""
    path = os.path.join(folder, "trajectory.csv")
    if not os.path.isfile(path):
        return None
    header, rows = read_csv_rows(path)
    if not rows:
        raise ResultsError(f"{path}: no frame")
    if (len(header) - 1) % 3 or any(len(row) != len(header) for row in rows):
        raise ResultsError(f"{path}: each row must hold the frame and three values per tracked vertex of the header")
    return header[1:], np.array([[float(x) for x in row[1:]] for row in rows])


def transient_error(case, transient_ref):
    """(relative, largest in m) error of the case's trajectory against the transient
    reference's over the reference's frames, at the same tracked vertices: relative is
    sqrt(sum over frames and vertices |u - u_ref|^2 / sum |u_ref|^2); a case that settled
    earlier holds its last frame. (nan, nan) when either has no trajectory."""
    mine, ref = read_trajectory(case["folder"]), read_trajectory(transient_ref["folder"])
    if mine is None or ref is None:
        return float("nan"), float("nan")
    (header, u), (header_ref, u_ref) = mine, ref
    if header != header_ref:
        raise ResultsError(f"{case['folder']}/trajectory.csv: tracked vertices differ from "
                           f"{transient_ref['folder']}'s (another mesh?)")
    frames = u_ref.shape[0]
    if u.shape[0] < frames:
        u = np.vstack([u, np.repeat(u[-1:], frames - u.shape[0], axis=0)])
    diff = (u[:frames] - u_ref).reshape(frames, -1, 3)
    norm = float(np.sqrt(np.sum(u_ref ** 2)))
    return (float(np.sqrt(np.sum(diff ** 2))) / norm if norm > 0 else float("nan"),
            float(np.max(np.linalg.norm(diff, axis=2))))


def probe_displacements(folder):
    """#P x 3 displacements (m) of the case's probes.csv, or None when it wrote none."""
    path = os.path.join(folder, "probes.csv")
    if not os.path.isfile(path):
        return None
    with open(path) as f:
        header = f.readline().strip().split(",")
    if not all(c in header for c in ("ux", "uy", "uz")):
        raise ResultsError(f"{path}: no ux, uy, uz columns (header {header})")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return data[:, [header.index(c) for c in ("ux", "uy", "uz")]]  # "probe,x,y,z,ux,uy,uz" or "probe,ux,uy,uz"


def final_tool_forces(folder):
    """{tool key: force (N, 3-vector)} at the last frame of reactions.csv (the support
    left out: it is not an instrument), or {} when the case wrote none."""
    path = os.path.join(folder, "reactions.csv")
    if not os.path.isfile(path):
        return {}
    header, rows = read_csv_rows(path)
    if not rows:
        return {}
    last = max(int(r[0]) for r in rows)
    return {r[1]: np.array([float(v) for v in r[3:6]]) for r in rows
            if int(r[0]) == last and r[1] != "support"}


def tool_force_error(case_forces, ref_forces):
    """(largest |F - F_ref| over the tools in N, the same relative to |F_ref|), NaN
    when the case measures no force on a tool the reference measures (PBD's grasps)."""
    if not ref_forces:
        return float("nan"), float("nan")
    abs_err, rel_err = [], []
    for key, f_ref in ref_forces.items():
        f = case_forces.get(key)
        if f is None or not np.all(np.isfinite(f)):
            return float("nan"), float("nan")
        abs_err.append(float(np.linalg.norm(f - f_ref)))
        rel_err.append(abs_err[-1] / float(np.linalg.norm(f_ref)) if np.linalg.norm(f_ref) > 0 else float("nan"))
    return max(abs_err), max(rel_err)


def peak_memory_mib(case):
    """The case's own peak (timings.json "peak_memory_mib": from its setup to its last frame, the mesh included);
    results written before it was measured give the process's peak so far. A case run over several ranks: their sum."""
    t = case["timings"]
    processes = t.get("processes", {})
    if processes.get("ranks", 1) > 1 and "peak_rss_mib_sum" in processes:
        return processes["peak_rss_mib_sum"]
    if "peak_memory_mib" in t:
        return t["peak_memory_mib"]
    return t.get("processes", {}).get("peak_rss_mib_max", t.get("build", {}).get("peak_memory_mib", float("nan")))


class Beads:
    """The Truth Cube's table, read once from the data directory (truth_cube.py)."""

    def __init__(self, data_flag):
        path = os.path.join(truth_cube.data_dir(data_flag), "data", "truthcube", "uniaxial_positions.csv")
        self.grid, self.positions, self.strains = truth_cube.read_table(path)

    def rms_mm(self, case):
        beads = truth_cube.case_beads(case, self.positions, self.strains)
        if beads is None:
            return float("nan")
        return truth_cube.errors(*beads, self.grid)["rms"]


def score_case(exp, scenario, name, ref_name, beads, converged=None):
    """Every metric of one case (docs/suite.md); converged: the scenario's converged field
    (converged_fields.ConvergedField) or None."""
    cases = exp.scenario(scenario)
    case, ref = cases[name], cases[ref_name]
    transient_ref = cases.get(exp.transient_reference) if exp.transient_reference else None
    run, timings = case["run"], case["timings"]
    rel_l2, max_error = field_error(case, ref) if name != ref_name else (0.0, 0.0)
    u_ref = probe_displacements(ref["folder"])
    u = probe_displacements(case["folder"])
    probe_err = (float(np.sqrt(np.mean(np.sum((u - u_ref) ** 2, axis=1)))) * 1000
                 if u is not None and u_ref is not None else float("nan"))
    force_abs, force_rel = tool_force_error(final_tool_forces(case["folder"]), final_tool_forces(ref["folder"]))
    dynamic = run.get("dynamic", False)
    transient_rel, transient_max = (transient_error(case, transient_ref)
                                    if dynamic and transient_ref is not None and name != exp.transient_reference
                                    else (float("nan"), float("nan")))
    return {
        "case": name, "model": run["model"],
        "rel_l2": rel_l2, "max_error_mm": max_error * 1000,
        "rel_l2_converged": converged.error(case) if converged is not None else float("nan"),
        "probe_error_mm": probe_err,
        "tool_force_error_n": force_abs, "tool_force_error_rel": force_rel,
        "bead_rms_mm": beads.rms_mm(case) if beads is not None else float("nan"),
        "transient_rel": transient_rel, "transient_max_mm": transient_max * 1000,
        "median_ms": timings["step"]["median_ms"], "p95_ms": timings["step"]["p95_ms"],
        "setup_ms": timings.get("setup_ms", float("nan")), "peak_mib": peak_memory_mib(case),
        "frames": run.get("frames"),
        "settled": (bool(run.get("reached_steady_state")) if dynamic else True),
    }


def folds_crossed(case):
    """How many times the case's Newton solve crossed a fold of its load path by
    pseudo-transient continuation over the run (run.json's model report,
    pseudo_transient_continuations; 0 where not reported). Past a fold the load may have
    several equilibria and the continuation's start picks one (docs/equations.md,
    'Crossing a fold sooner, and which equilibrium'): a reference that crossed one is
    flagged beside its scenario."""
    report = case["run"].get("model_report", {})
    return int(report.get("fine_solve", report).get("pseudo_transient_continuations", 0) or 0)


def accuracy_key(role):
    """What a scenario ranks by: the beads on the Truth Cube, else the surface field."""
    return "bead_rms_mm" if role.startswith(TRUTH_CUBE_ROLE_PREFIX) else "rel_l2"


def pareto_front(points):
    """The (time, error) points no other point beats in both, sorted by time."""
    front, best = [], math.inf
    for t, err, label in sorted(points):
        if err < best:
            front.append((t, err, label))
            best = err
    return front


def best_within(scores, key, budget):
    """The most accurate case (not the reference) whose median frame fits the budget, or None.
    Cases with the same error (condensed and fem-linear give the same linear answer)
    go to the faster one, then to the first listed."""
    fits = [s for s in scores if not s["is_reference"] and s["median_ms"] <= budget and math.isfinite(s[key])]
    return min(fits, key=lambda s: (s[key], s["median_ms"])) if fits else None


def near_miss(scores, key, budget, best):
    """The most accurate case more accurate than `best` (None: any) whose median frame misses
    the budget by less than EDGE_FACTOR, or None."""
    misses = [s for s in scores if not s["is_reference"] and budget < s["median_ms"] <= EDGE_FACTOR * budget
              and math.isfinite(s[key]) and (best is None or s[key] < best[key])]
    return min(misses, key=lambda s: (s[key], s["median_ms"])) if misses else None


def budget_cell(scores, key, budget):
    """A leaderboard cell: the best case within the budget and its error, then in brackets a
    more accurate one just over it (near_miss)."""
    best = best_within(scores, key, budget)
    text = ("none fits" if best is None else
            f"{best['case']} {sig(best[key])}{'' if best['settled'] else ' (not settled)'}")
    miss = near_miss(scores, key, budget, best)
    if miss:
        text += f" ({miss['case']} {sig(miss[key])} at {miss['median_ms']:.3g} ms)"
    return text


def converged_row(role, field, declared, scores, ref):
    """A row of the table against the converged field: the field's run and its own
    estimated error (where the declared file names that run), the budget cells by
    rel_l2_converged, the reference case's distance from it."""
    entry = declared.get(field.role, {}).get("converged", {})
    same_run = (entry.get("order"), entry.get("level")) == field.key
    own = entry.get("field_error") if same_run else None
    own_text = (f" (its own est. {sig(own)})" if own is not None else
                f" ({entry.get('field_error_how', 'no estimate')} of its own error)" if same_run else "")
    return ([role, field.label + own_text] + [budget_cell(scores, "rel_l2_converged", b) for b in BUDGETS_MS]
            + [sig(ref["rel_l2_converged"])])


def not_run_cases(exp, scenario):
    """[(case, reason)]: cases the suite lists but did not run here (skipped or failed)."""
    out = []
    for entry in exp.listed_points:
        if entry["name"] == scenario:
            out += [(n["case"], n["reason"]) for n in entry.get("not_run", [])]
    for case in exp.listed_cases.get(scenario, []):
        if case not in exp.scenario(scenario):
            out.append((case, "failed: " + (exp.failure(scenario, case) or "no results")))
    return out


def figure(role, scenario, scores, key, out_dir):
    from vtu_plot import DPI, plt
    floor = 1e-4 if key == "rel_l2" else 1e-2
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    points = []
    for s in scores:
        if s["is_reference"] or not math.isfinite(s[key]):
            continue
        err = max(s[key], floor)
        points.append((s["median_ms"], err, s["case"]))
        ax.scatter(s["median_ms"], err, marker="o" if s["settled"] else "x")
        ax.annotate(s["case"], (s["median_ms"], err), fontsize=7)
    front = pareto_front(points)
    if front:
        ax.step([p[0] for p in front], [p[1] for p in front], where="post", color="k", alpha=0.4, label="Pareto front")
    for b in BUDGETS_MS:
        ax.axvline(b, color="grey", ls=":", lw=0.8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("median per-frame time (ms); dotted: the budgets 0.1, 1, 16 ms")
    ax.set_ylabel("bead RMS error (mm)" if key == "bead_rms_mm" else f"relative L2 error vs reference (floored at {floor:g})")
    ax.set_title(f"{scenario}: time vs accuracy (x: not settled)")
    ax.grid(alpha=0.3, which="both")
    if front:
        ax.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(out_dir, f"suite_{role}.png")
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def add_cases_from(exp, other_results, ref_name):
    """Cases of another run of the suite (e.g. `tissuebench run experiments/suite.json
    --model mymodel --out runs`) added to the results' scenarios of the same name;
    a name the results already hold gets " (new)". The other run's references (the
    reference, the transient and law references) are not added: renamed, they would be
    ranked as models. Returns the names added."""
    other = results_index.Experiment(other_results)
    added = set()
    for scenario, cases in other.scenarios.items():
        if scenario not in exp.scenarios:
            continue
        for name, case in cases.items():
            if name == ref_name or other.is_reference(name) or exp.is_reference(name):
                continue
            label = name + " (new)" if name in exp.scenarios[scenario] else name
            exp.scenarios[scenario][label] = dict(case, name=label)
            added.add(label)
    if not added:
        raise ResultsError(f"{other_results}: no case of a scenario of {exp.root} to add")
    return added


def make(results, out, data_flag, figures=True, with_results=None, reference_errors=REFERENCE_ERRORS,
         converged=None):
    """Writes the tables (and figures); returns {role: [scores]}. with_results: a
    second results tree whose cases are scored beside the first's (add_cases_from).
    reference_errors: the file of each scenario's reference and its estimated
    discretisation error (read_reference_errors), carried beside each scenario.
    converged: the reference study's results folder (converged_fields.read), whose finest
    field per scenario every case is also scored against; None: not scored so."""
    exp = results_index.Experiment(results)
    declared = read_reference_errors(reference_errors)
    fields = converged_fields.read(converged) if converged else {}
    converged_rows = []
    error_notes = []
    ref_name = exp.require_reference()
    added = add_cases_from(exp, with_results, ref_name) if with_results else set()
    beads = None
    everything, score_rows, board_rows, notes, not_run = {}, [], [], [], []
    roles = [r for r in exp.roles if exp.roles[r] and exp.roles[r][0] in exp.scenarios]
    if not roles:
        raise ResultsError(f"{results}: no scenario with a role has results")
    for role in roles:
        scenario = exp.scenario_name(role)
        key = accuracy_key(role)
        if key == "bead_rms_mm" and beads is None:
            beads = Beads(data_flag)
        if ref_name not in exp.scenario(scenario):  # a partial run, or the reference failed: nothing to score against
            why = exp.failure(scenario, ref_name) or "not run yet"
            notes.append(f"- {role}: not scored: its reference case '{ref_name}' has no results ({why})")
            continue
        scores = []
        for name in exp.scenario(scenario):
            s = score_case(exp, scenario, name, ref_name, beads if key == "bead_rms_mm" else None,
                           fields.get(converged_fields.base_role(role)))
            # The transient and the law references are references too: scored, never ranked.
            s["is_reference"] = exp.is_reference(name)
            scores.append(s)
        everything[role] = scores
        for s in scores:
            if s["case"] in added:
                print(f"{role}: {s['case']}: relative L2 {sig(s['rel_l2'])} (against the converged field "
                      f"{sig(s['rel_l2_converged'])}), bead RMS {sig(s['bead_rms_mm'])} mm, "
                      f"tool force error {sig(s['tool_force_error_n'])} N, median {fmt(s['median_ms'])} ms "
                      f"(the committed cases: results/tables/suite_scores.md)")
        for s in scores:
            score_rows.append([role, s["case"], s["model"], sig(s["rel_l2"]), sig(s["rel_l2_converged"]),
                               sig(s["max_error_mm"]),
                               sig(s["probe_error_mm"]), sig(s["tool_force_error_n"]), sig(s["tool_force_error_rel"]),
                               sig(s["bead_rms_mm"]), sig(s["transient_rel"]), sig(s["transient_max_mm"]),
                               fmt(s["median_ms"]), fmt(s["p95_ms"]), fmt(s["setup_ms"]),
                               fmt(s["peak_mib"]), str(s["frames"]), "yes" if s["settled"] else "no"])
        ref = next(s for s in scores if s["case"] == ref_name)
        # Only the ranked cases' times place a model in a cell; the references' are not ranked.
        busy = busy_cases({n: c for n, c in exp.scenario(scenario).items() if not exp.is_reference(n)})
        flag = f" (times of {len(busy)} case{'s' if len(busy) > 1 else ''} from a busy machine)" if busy else ""
        folds = folds_crossed(exp.scenario(scenario)[ref_name])
        if folds:
            flag += f" (its reference crossed {folds} fold{'s' if folds > 1 else ''}: one equilibrium of possibly several)"
            notes.append(f"- {role}: {ref_name} crossed {folds} fold{'s' if folds > 1 else ''} of its load path by "
                         "pseudo-transient continuation; past a fold the load may have several equilibria and the "
                         "continuation's start picks one (docs/equations.md, 'Crossing a fold sooner, and which "
                         "equilibrium'): the ranking holds for that equilibrium")
        row = [role + flag, ref["model"] + " (" + ("beads" if key == "bead_rms_mm" else "field") + ")"]
        for budget in BUDGETS_MS:
            row.append(budget_cell(scores, key, budget))
        row.append(reference_error_text(declared.get(role)))
        board_rows.append(row)
        field = fields.get(converged_fields.base_role(role))
        if field is not None and math.isfinite(ref["rel_l2_converged"]):
            converged_rows.append(converged_row(role, field, declared, scores, ref))
        if role in declared:
            error_notes.append(f"- {role}: {ref_name}'s estimated discretisation error (relative L2 of the field): "
                               f"{reference_error_text(declared[role])}")
        not_run += [[role, c, r] for c, r in not_run_cases(exp, scenario)]
        if figures:
            os.makedirs(os.path.join(out, "figures"), exist_ok=True)
            figure(role, scenario, scores, key, os.path.join(out, "figures"))
    tables = os.path.join(out, "tables")
    if not everything:
        raise ResultsError(f"{results}: no scenario has its reference case's results")
    all_cases = {f"{role}/{n}": c for role in everything for n, c in exp.scenario(exp.scenario_name(role)).items()}
    machine = machine_note(all_cases, "threads as each case's parameters say (one unless a `threads` is given)")
    legend = "### Cases\n\n" + case_table({c["name"]: c for c in all_cases.values()})
    not_run_table = ("\n\n### Not run\n\nCases the suite lists that did not run on a scenario (the model refuses "
                     "its tools, or the run failed):\n\n" + markdown_table(["scenario (role)", "case", "why"], not_run)
                     if not_run else "")
    reference_note = ("\n\n### The reference's own error\n\nThe reference is a discretisation too; its estimated "
                      "error per scenario (docs/reference_convergence.md, 'Every suite scenario'):\n\n"
                      + "\n".join(error_notes) if error_notes else "")
    write_table(tables, "suite_scores",
                ["role", "case", "model", "rel L2 vs reference", "rel L2 vs converged", "max error (mm)",
                 "probe error (mm)",
                 "tool force error (N)", "tool force error (rel)", "bead RMS (mm)", "transient error (rel)",
                 "transient max error (mm)", "median (ms)", "p95 (ms)",
                 "setup (ms)", "peak memory (MiB)", "frames", "settled"],
                score_rows, machine + "\n\n" + legend + not_run_table + reference_note)
    write_table(tables, "leaderboard",
                ["scenario (role)", "reference (ranked by)"] + [f"best within {b:g} ms" for b in BUDGETS_MS]
                + ["reference's own error (est.)"],
                board_rows,
                LEADERBOARD_CAPTION + "\n\n" + machine + "\n\n### The columns\n\n"
                f"In brackets: a more accurate case whose median misses the budget by less than {EDGE_FACTOR:g} "
                "times (9 in 10 cases' median frames moved by less between two runs on the machines measured, "
                "docs/suite.md). The reference's own error: the estimated discretisation error of the reference "
                "case's field (relative L2 against the converged field of the run named, "
                "docs/reference_convergence.md, 'Every suite scenario'): errors below it rank models on what the "
                "reference cannot resolve.\n\n" + legend + not_run_table
                + ("\n\n### Notes\n\n" + "\n".join(notes) if notes else ""))
    write_table(tables, "leaderboard_converged",
                ["scenario (role)", "converged field (finest run of the reference study)"]
                + [f"best within {b:g} ms" for b in BUDGETS_MS] + ["the reference case's own"],
                converged_rows,
                ("" if converged_rows else "No scenario of these results has a converged field at its vertices. ") +
                CONVERGED_CAPTION + "\n\n### The columns\n\n"
                "The same cells ranked by the relative L2 of the observed surface against the converged field: the "
                "finest run of the reference study (Newton neo-Hookean, the scenario refined, P1 or P2; "
                "docs/reference_convergence.md, 'Every suite scenario'; analysis/converged_fields.py) at the vertices "
                "of the suite's mesh, with that run's own estimated error; a refined scenario (a role ending in _10k) "
                "against its paper-sized role's field at those vertices, which its surface keeps. The last column is "
                "the scenario's reference case (P1 on its mesh) against it: its distance from that run (leaderboard.md's "
                "'reference's own error' is the largest of it and the Richardson estimates), which every fine-mesh "
                "model of the scenario carries too. Scenarios the study did not refine (the liver's pads) "
                "have no row; on the Truth Cube the beads still rank (leaderboard.md). On the torus and the L-block "
                "the suite's grasp holds one surface vertex, the refined levels' the 5 mm patch "
                "(docs/reference_convergence.md, 'The grasps'): their converged field is the patch's, and a model's "
                "distance from it includes the point hold's.")
    return everything


# The caption the README shows under the table (at most three short lines); the rest of
# what the table needs is under it in leaderboard.md.
LEADERBOARD_CAPTION = ("Each cell: the most accurate case whose median frame fits the budget, and its error against "
                       "the scenario's reference (relative L2 of the observed surface; on the Truth Cube, the RMS "
                       "bead error in mm); in brackets, a more accurate case just over the budget.")
CONVERGED_CAPTION = ("The same cells ranked against the converged field (the reference study's finest run, at the "
                     "suite mesh's vertices); the last column is the reference case's own distance from it.")

README_BEGIN = "<!-- leaderboard:begin (written by analysis/leaderboard.py --readme) -->"
README_END = "<!-- leaderboard:end -->"


def readme_block(tables_dir):
    """The README's verdict: leaderboard.md's table and caption, and where the rest is
    (the converged-field table, the machine, the cases, the cases not run)."""
    def table_and_caption(name):
        with open(os.path.join(tables_dir, name + ".md")) as f:
            paragraphs = f.read().strip().split("\n\n")
        return paragraphs[0] + "\n\n" + paragraphs[1]
    return table_and_caption("leaderboard") + (
        "\n\nWhere and when measured, every case's parameters, the cases not run: "
        "[results/tables/leaderboard.md](results/tables/leaderboard.md);\nthe same cells against the converged field: "
        "[leaderboard_converged.md](results/tables/leaderboard_converged.md);\nevery metric of every case: "
        "[suite_scores.md](results/tables/suite_scores.md).")


def update_readme(path, tables_dir):
    """Writes readme_block between the README's leaderboard markers."""
    with open(path) as f:
        text = f.read()
    if README_BEGIN not in text or README_END not in text:
        raise ResultsError(f"{path}: no leaderboard markers ({README_BEGIN} ... {README_END})")
    head, rest = text.split(README_BEGIN, 1)
    _, tail = rest.split(README_END, 1)
    with open(path, "w") as f:
        f.write(head + README_BEGIN + "\n" + readme_block(tables_dir) + "\n" + README_END + tail)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="?", default="results/suite")
    parser.add_argument("out", nargs="?", default="results")
    parser.add_argument("--data-dir", default=None)
    parser.add_argument("--no-figures", action="store_true")
    parser.add_argument("--readme", default=None, help="also copy the leaderboard into this README's markers")
    parser.add_argument("--reference-errors", default=REFERENCE_ERRORS,
                        help="each scenario's reference and its estimated discretisation error (JSON; "
                        "analysis/suite_reference_convergence.py writes it)")
    parser.add_argument("--converged", default=converged_fields.STUDY,
                        help="the reference study's results (scripts/suite_reference_convergence), whose finest "
                        "field per scenario every case is also scored against; '' for none")
    parser.add_argument("--with", dest="with_results", default=None,
                        help="another run of the suite (e.g. one model's, --model) scored beside RESULTS")
    a = parser.parse_args()

    def run():
        make(a.results, a.out, a.data_dir, not a.no_figures, a.with_results, a.reference_errors, a.converged or None)
        if a.readme:
            update_readme(a.readme, os.path.join(a.out, "tables"))
    results_index.main(run, "leaderboard")
    print(f"leaderboard written to {a.out}/tables/leaderboard.md")


if __name__ == "__main__":
    main()
