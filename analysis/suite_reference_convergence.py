"""Every suite scenario's reference under refinement (docs/reference_convergence.md,
"Every suite scenario"): the quantities of interest on each level and element
order, their Richardson-style error estimates, the cost, and the declared error
of the reference the suite scores against.

Usage: /usr/bin/python3 analysis/suite_reference_convergence.py [results/suite_reference_convergence] [results]
       [--data-dir DIR] [--errors experiments/suite_reference_errors.json]

Reads RESULTS/suite_reference_convergence/<scenario>/<case>/ (scenario names
sref-<role>-L<level>-p<order>; scripts/suite_reference_convergence writes them)
and RESULTS/cases.csv (each process's wall time, ranks and the machine's load).
Writes OUT/tables/suite_reference_convergence.{md,csv}, OUT/tables/suite_reference_cost.{md,csv}
and the declared errors (--errors; leaderboard.py reads them).

Quantities of interest (QoIs):
- field: the observed surface displacement at the level-0 observed vertices (every
  level keeps them at the same coordinates), compared as ||u - u_finest|| / ||u_finest||;
- the cube: u_z at the load point (the top centre); the grasps and the Truth Cube's
  plate: the tool's reaction force (its z component, N); the liver and the flap: |u| at
  the probe; the Truth Cube: the RMS bead error against the CT-measured beads (mm) and
  the largest horizontal displacement of the surface (its bulge, mm).
Richardson (generalised Richardson extrapolation and the observed order: Roache 1998,
"Verification and Validation in Computational Science and Engineering", ch. 5): on levels with mesh ratio r (h_k / h_{k+1}, from
the dofs: (n_{k+1} / n_k)^(1/3)) a QoI behaves as Q_k = Q + C h_k^p. Three levels of
one order give the observed p = ln((Q_1 - Q_0) / (Q_2 - Q_1)) / ln r; two give nothing
to observe, and p is assumed: 2 for P1 and 3 for P2 (the L2 orders of the displacement
on a smooth solution; smaller where the solution is singular: a clamp's edge, a grasp's
rim). The extrapolated Q* = Q_f + (Q_f - Q_{f-1}) / (r^p - 1) from the two finest, and
each level's estimated error is |Q_k - Q*| (the field: ||u_k - u*|| / ||u*||). An observed
p outside [0.5, the assumed one + 1] (a pre-asymptotic or cancelling sequence), or changes
that do not shrink, are not trusted: the assumed p is used and the row says so.
"""
import argparse
import csv
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import leaderboard  # noqa: E402
import metrics  # noqa: E402
import results_index  # noqa: E402
from converged_fields import field_at_level0, finest_key, level0_vertices, parse, study_runs  # noqa: E402
from results_index import ResultsError  # noqa: E402
from table_io import fmt, write_table  # noqa: E402

ASSUMED_ORDER = {1: 2.0, 2: 3.0}
CUBE_LOAD_POINT = np.array([0.0, 0.0, 0.1])
# Roles with a tool whose reaction is a QoI, with a probe, on the Truth Cube.
TOOL_ROLES = ("truth_cube", "liver_grasp", "torus_grasp", "l_block_grasp", "cube_palpation")
PROBE_ROLES = ("liver_grasp_gravity", "flap_gravity")
# Suite scenarios this study does not solve, and why (declared all the same, so that
# every scenario of the leaderboard says where its reference's error stands).
NOT_ESTIMATED = {"cube_palpation": "not estimated: the study's palpation runs (sref-cube-palpation-*) are not in "
                                    "its results"}
# cases.csv's status of a case that left no results: scripts/suite_reference_convergence
# writes failed or timeout; "stopped" is written by hand for a case stopped to free the
# cores for others.
UNFINISHED = {"failed": "failed", "timeout": "stopped at TIMEOUT", "stopped": "stopped by hand (not converged yet)"}
QOI_LABELS = {"load_uz_mm": "load-point u_z (mm)", "tool_fz_n": "tool force z (N)", "probe_mm": "probe |u| (mm)",
              "bead_rms_mm": "bead RMS vs CT (mm)", "bulge_mm": "bulge (mm)"}


def dofs_of(case):
    """The case's dofs: fem_distributed reports them; the serial P1 FEM has three per fine node."""
    report = case["run"].get("model_report", {})
    if "dofs" in report:
        return int(report["dofs"])
    return 3 * int(case["run"]["mesh"]["fine_nodes"])


def qois(role, case, level0, beads):
    """The observed field at the level-0 vertices (#V0 x 3, m) and the scalar QoIs."""
    observed = metrics.read_displacements(os.path.join(case["folder"], "top_surface.csv"))
    u = observed[2]
    u0 = field_at_level0(case, level0, observed)
    rest0 = level0[1]
    q = {}
    if role.startswith("cube_") and role != "cube_palpation":  # the sphere moves off the top centre
        k = int(np.argmin(np.linalg.norm(rest0 - CUBE_LOAD_POINT, axis=1)))
        q["load_uz_mm"] = 1000 * u0[k, 2]
    if role.startswith(TOOL_ROLES):
        forces = leaderboard.final_tool_forces(case["folder"])
        if forces:
            q["tool_fz_n"] = float(forces[sorted(forces)[0]][2])
    if role in PROBE_ROLES:
        p = leaderboard.probe_displacements(case["folder"])
        if p is not None:
            q["probe_mm"] = 1000 * float(np.linalg.norm(p[0]))
    if role.startswith("truth_cube") and beads is not None:
        q["bead_rms_mm"] = beads.rms_mm(case)
        q["bulge_mm"] = 1000 * float(np.max(np.linalg.norm(u[:, :2], axis=1)))
    return u0, q


def richardson(values, dofs, order):
    """Estimated errors of a QoI on successive levels of one order.

    values: the QoI per level (scalars, or fields as arrays); dofs: per level.
    Returns (errors per level (relative to |Q*| for fields, absolute for scalars),
    the order used, how it was obtained). One level: no estimate.
    """
    n = len(values)
    if n < 2:
        return [float("nan")] * n, float("nan"), "one level: no estimate"
    values = [np.asarray(v, float) for v in values]
    ratios = [(dofs[k + 1] / dofs[k]) ** (1 / 3) for k in range(n - 1)]
    p, how = ASSUMED_ORDER[order], f"assumed p = {ASSUMED_ORDER[order]:g} (two levels)"
    if n >= 3:
        d0 = float(np.linalg.norm(values[-2] - values[-3]))
        d1 = float(np.linalg.norm(values[-1] - values[-2]))
        r = math.sqrt(ratios[-2] * ratios[-1])
        observed = math.log(d0 / d1) / math.log(r) if d0 > 0 and d1 > 0 else float("nan")
        if 0.5 <= observed <= ASSUMED_ORDER[order] + 1:
            p, how = observed, f"observed p = {observed:.2f} (three levels)"
        else:
            how = f"observed p = {observed:.2f} not trusted; assumed p = {ASSUMED_ORDER[order]:g}"
    extrapolated = values[-1] + (values[-1] - values[-2]) / (ratios[-1] ** p - 1)
    scale = float(np.linalg.norm(extrapolated)) if extrapolated.ndim else 1.0
    errors = [float(np.linalg.norm(v - extrapolated)) / scale for v in values]
    return errors, p, how


class Study:
    """{role: {(order, level): case}} of the results, with each role's QoIs."""

    def __init__(self, root, data_flag):
        self.cases = study_runs(root)
        if not self.cases:
            raise ResultsError(f"{os.path.join(root, 'suite_reference_convergence')}: no sref-* results "
                               "(run scripts/suite_reference_convergence)")
        self.process = {}  # (scenario, case): row of cases.csv (the last run of it)
        path = os.path.join(root, "cases.csv")
        if os.path.isfile(path):
            with open(path, newline="") as f:
                for row in csv.DictReader(f):
                    self.process[(row["scenario"], row["case"])] = row
        self.beads = leaderboard.Beads(data_flag) if any(r.startswith("truth_cube") for r in self.cases) else None

    def role_rows(self, role):
        """Every run of the role, with its QoIs, changes against the finest and estimated errors."""
        runs = self.cases[role]
        level0 = level0_vertices(runs, role)
        rows = {}
        for key, case in runs.items():
            u0, q = qois(role, case, level0, self.beads)
            rows[key] = {"role": role, "order": key[0], "level": key[1], "dofs": dofs_of(case), "u": u0, "qoi": q,
                         "case": case}
        finest = finest_key(rows, runs)
        u_fin = rows[finest]["u"]
        for r in rows.values():
            r["finest"], r["finest_key"] = f"P{finest[0]} L{finest[1]}", finest
            r["change"] = float(np.linalg.norm(r["u"] - u_fin) / np.linalg.norm(u_fin))
        for order in (1, 2):
            series = sorted(k for k in rows if k[0] == order)
            dofs = [rows[k]["dofs"] for k in series]
            errs, p, how = richardson([rows[k]["u"] for k in series], dofs, order)
            for k, e in zip(series, errs):
                rows[k].update(field_error=e, field_p=p, field_how=how, qoi_error={})
            for name in {n for k in series for n in rows[k]["qoi"]}:
                if all(name in rows[k]["qoi"] for k in series):
                    errs, _, qhow = richardson([rows[k]["qoi"][name] for k in series], dofs, order)
                    for k, e in zip(series, errs):
                        rows[k]["qoi_error"][name] = (e, qhow)
        return [rows[k] for k in sorted(rows)]

    def cost(self, row):
        """Wall time (s) of the whole process, setup and solve, peak memory (MiB, all ranks), ranks, load."""
        case = row["case"]
        scenario = os.path.basename(os.path.dirname(case["folder"]))
        proc = self.process.get((scenario, case["name"]), {})
        t = case["timings"]
        ranks = int(t.get("processes", {}).get("ranks", proc.get("ranks", 1) or 1))
        # The solve: every frame's (one for a static solve at the full load; the
        # palpation's 31 along its path).
        frames = int(t["step"].get("count", 1))
        return {"wall_s": float(proc.get("wall_s", "nan")), "setup_s": t["setup_ms"] / 1000,
                "solve_s": t["step"].get("mean_ms", t["step"]["median_ms"]) * frames / 1000, "peak_mib": leaderboard.peak_memory_mib(case),
                "ranks": ranks, "load": f"{proc.get('load_before', '?')} / {proc.get('load_after', '?')}",
                "newton": newton_iterations(case)}


def newton_iterations(case):
    """The Newton iterations of the solve: fem_distributed's of its one frame; the serial
    Newton's summed over the frames when it ran several (its per-frame counts in timings.json)."""
    per_frame = case["timings"].get("solver_iterations_per_frame")
    if case["run"].get("model") == "fem" and isinstance(per_frame, list) and len(per_frame) > 1:
        return f"{sum(per_frame)} over {len(per_frame)} frames"
    report = case["run"].get("model_report", {})
    if "newton_iterations_last_step" in report:
        return report["newton_iterations_last_step"]
    return report.get("fine_solve", {}).get("newton_iterations_last_solve", "n/a")


# Roles whose grasp holds one surface vertex on level 0 (docs/reference_convergence.md,
# "The grasps"): a held point, whose answer has no limit under refinement; P2 on
# level 0 holds the same point and solves a more singular problem, not a finer
# approximation of the held patch, so it does not measure the reference's error.
POINT_HOLD_ON_LEVEL_0 = ("torus_grasp", "l_block_grasp")


def declared(rows):
    """The suite's reference (P1 level 0, the suite's mesh) and the finest run, with
    the reference's estimated field error: the largest of its Richardson estimate and
    its change against the finest run of each order, P1 and P2 (P2 on level 0 left out
    where it is a point hold, POINT_HOLD_ON_LEVEL_0). A change against run k bounds the
    reference's error e_0 by |e_0 - e_k| <= change <= e_0 + e_k: neither run is
    converged, so the change alone can understate e_0 or, by up to e_k, overstate it;
    the two orders disagree on which is nearer the limit (a P2 level 0 against a P1
    level 1 of the same size), so the largest is declared, an upper estimate. Relative
    to the other run's field, ||u_ref - u_k|| / ||u_k|| (the models' errors divide by the
    reference's own norm: docs/reference_convergence.md)."""
    by_key = {(r["order"], r["level"]): r for r in rows}
    ref = by_key[(1, 0)]
    finest = rows[0]["finest_key"]
    fin = by_key[finest]
    point_hold = ref["role"] in POINT_HOLD_ON_LEVEL_0
    # The finest run of each order (its highest level), P2 on level 0 left out where it is a point hold.
    finest_of_order = {}
    for k in sorted(by_key):
        if k != (1, 0) and not (point_hold and k[0] == 2 and k[1] == 0):
            finest_of_order[k[0]] = k
    changes = {k: float(np.linalg.norm(ref["u"] - by_key[k]["u"]) / np.linalg.norm(by_key[k]["u"]))
               for k in sorted(finest_of_order.values())}
    p1_levels = sorted(k[1] for k in by_key if k[0] == 1)
    richardson_how = "Richardson on P1 levels %s (%s)" % (p1_levels, ref["field_how"])
    candidates = {richardson_how: ref["field_error"]} if changes else {}
    candidates.update({f"change against P{k[0]} L{k[1]}": v for k, v in changes.items()})
    candidates = {how: v for how, v in candidates.items() if v == v}
    largest = max(candidates, key=candidates.get) if candidates else None
    out = {
        "reference": "P1 level 0 (the suite's mesh and solver: Newton neo-Hookean)",
        "reference_dofs": ref["dofs"],
        "field_error": candidates[largest] if candidates else None,
        # What the declared error was measured against: a run, or the extrapolated limit.
        "field_error_against": (largest.replace("change against ", "") if largest.startswith("change")
                                else f"Richardson's limit of P1 L{p1_levels[0]}-{p1_levels[-1]}")
        if candidates else None,
        "field_error_how": ("the largest of " + ", ".join(f"{how} {v:.3g}" for how, v in candidates.items())
                            + f": {largest}") if candidates else "",
        "qoi": {name: {"value": v, "finest_value": fin["qoi"].get(name),
                       "error": (lambda e: None if e != e else e)(ref["qoi_error"].get(name, (math.nan,))[0])}
                for name, v in ref["qoi"].items()},
        "note": "not estimated: no other level or order of it finished" if not changes else "",
        "converged": {"order": finest[0], "level": finest[1], "dofs": fin["dofs"],
                      "field_error": None if fin["field_error"] != fin["field_error"] else fin["field_error"],
                      "field_error_how": fin["field_how"]},
    }
    return out


def make(root, out, data_flag, errors_path):
    study = Study(root, data_flag)
    table, cost_table, decl = [], [], {}
    for role in sorted(study.cases):
        rows = study.role_rows(role)
        decl[role] = declared(rows)
        for r in rows:
            c = study.cost(r)
            q = "; ".join(f"{QOI_LABELS[n]} {v:.4g}" + (f" ± {r['qoi_error'][n][0]:.2g}"
                                                        if r["qoi_error"].get(n, (math.nan,))[0] == r["qoi_error"].get(n, (math.nan,))[0] else "")
                          for n, v in sorted(r["qoi"].items()))
            table.append([role, r["level"], f"P{r['order']}", r["dofs"], q, fmt(r["change"], 3), r["finest"],
                          fmt(r["field_error"], 3), r["field_how"], fmt(c["wall_s"], 1), fmt(c["peak_mib"] / 1024, 2),
                          c["ranks"]])
            cost_table.append([role, r["level"], f"P{r['order']}", r["dofs"], c["ranks"], c["newton"],
                               fmt(c["setup_s"], 1), fmt(c["solve_s"], 1), fmt(c["wall_s"], 1),
                               fmt(c["peak_mib"] / 1024, 2), c["load"]])
    # Cases that ran and left no results (Newton failed, or stopped at TIMEOUT): their cost.
    done = {(os.path.basename(os.path.dirname(c["folder"])), c["name"])
            for role in study.cases.values() for c in role.values()}
    unfinished = []
    for (scenario, case), proc in sorted(study.process.items()):
        p = parse(scenario)
        if p and (scenario, case) not in done and proc.get("status") != "ok":
            how = UNFINISHED.get(proc["status"], proc["status"])
            unfinished.append(f"- {p[0]} level {p[1]} P{p[2]} (case {case}): {how} after {float(proc['wall_s']):.0f} s "
                              f"({proc['ranks']} rank(s), load average {proc['load_before']} / {proc['load_after']})")
    unfinished_note = ("\n\nRun and not finished (no results; the wall time it cost):\n" + "\n".join(unfinished)
                       if unfinished else "")
    tables = os.path.join(out, "tables")
    write_table(tables, "suite_reference_convergence",
                ["scenario (role)", "level", "order", "dofs", "QoIs (± Richardson estimate of the error)",
                 "field change vs finest (rel L2)", "finest", "field error (Richardson, rel L2)", "order p",
                 "wall (s)", "peak memory (GiB)", "ranks"],
                table,
                "Newton neo-Hookean on each suite scenario refined `level` times (surface triangles split in four "
                "per level, TetGen's volume bound / 8); the field is the observed surface displacement at the "
                "level-0 vertices. The suite scores every model against P1 level 0 (the suite's own mesh). "
                "Richardson: analysis/suite_reference_convergence.py's docstring. Wall: the whole process "
                "(TetGen included) on a loaded machine (2 cores shared with other jobs; the load average is in "
                "results/tables/suite_reference_cost.md)." + unfinished_note)
    write_table(tables, "suite_reference_cost",
                ["scenario (role)", "level", "order", "dofs", "ranks", "Newton iterations", "setup (s)", "solve (s)",
                 "wall (s)", "peak memory, all ranks (GiB)", "load average before / after"],
                cost_table,
                "Setup: mesh, dofs, assembly; solve: the Newton solve with its load increments. Wall: the whole "
                "process, TetGen included. Intel Xeon, 2 vCPUs shared with other jobs (the machine's 1-minute load "
                "average before and after each case is given): the times measure the load as much as the solver."
                + unfinished_note)
    doc = {"description": "Each suite scenario's reference and its estimated discretisation error (written by "
           "analysis/suite_reference_convergence.py from results/suite_reference_convergence; "
           "docs/reference_convergence.md, 'Every suite scenario'). field_error: relative L2 of the observed "
           "surface displacement of the suite's reference (P1 level 0) against the converged field; qoi: its "
           "quantities of interest with their Richardson estimates (null: fewer than two levels).",
           "roles": dict(decl, **{role: {"field_error": None, "note": note}
                                      for role, note in NOT_ESTIMATED.items() if role not in decl})}
    with open(errors_path, "w") as f:
        json.dump(doc, f, indent=2, sort_keys=True)
        f.write("\n")
    return decl


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="?", default="results/suite_reference_convergence")
    parser.add_argument("out", nargs="?", default="results")
    parser.add_argument("--data-dir", default=None)
    parser.add_argument("--errors", default=os.path.join(os.path.dirname(HERE), "experiments",
                                                         "suite_reference_errors.json"))
    a = parser.parse_args()
    results_index.main(lambda: make(a.results, a.out, a.data_dir, a.errors), "suite_reference_convergence")
    print(f"written: {a.out}/tables/suite_reference_convergence.md, suite_reference_cost.md, {a.errors}")


if __name__ == "__main__":
    main()
