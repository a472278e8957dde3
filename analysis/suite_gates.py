"""Two-sided CI gates on the suite's small level: every case's answer may not move
from its committed value, in either direction, beyond a stated tolerance.

Usage:
  /usr/bin/python3 analysis/suite_gates.py check  RESULTS/suite [GATES_JSON]
  /usr/bin/python3 analysis/suite_gates.py record RESULTS/suite [GATES_JSON] --commit C
GATES_JSON defaults to experiments/suite_gates.json. `check` exits 0 when every gate
holds, 1 otherwise, 2 on unusable input. `record` rewrites the file's values from a
run (an intended change of an answer updates them in the same commit, visibly in
its diff).

An upper bound on an error misses a change that moves a model towards its reference
or away from the truth by less than the bound's margin (a 5 % scale error in the
hybrid's control points moves its relative L2 from 0.418 to 0.410). So the gates
compare the field itself and the error, both ways: for every case of every scenario
(role), the quantities of `gated_values` below, each within rtol x |committed| +
atol of its committed value; the reference's RMS bead error on the Truth Cube may
not grow beyond it. A case run and not committed, or committed and not run, fails
too: a model added to the suite is gated from the commit that adds it; so does a
change in which cases fail (a solver refusing a tool: no results to compare).
"""
import argparse
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

# Absolute floors of the tolerance, per quantity: what a value at (or near) zero may
# differ by (round-off of a direct solve is far below; a real change far above).
ATOL = {"rel_l2": 1e-9, "u_rms_mm": 1e-9, "u_max_mm": 1e-9, "probe_rms_mm": 1e-9, "tool_force_n": 1e-12,
        "bead_rms_mm": 1e-9, "transient_rel": 1e-9}


def gated_values(exp, scenario, name, ref_name, beads):
    """{quantity: value} of one case: its observed field (RMS and largest |u|, mm),
    its error against the reference, its probes, the force on each tool, the beads,
    and a dynamic case's transient error against the transient reference."""
    case = exp.scenario(scenario)[name]
    _, _, u = metrics.read_displacements(os.path.join(case["folder"], "top_surface.csv"))
    mag = np.linalg.norm(u, axis=1) * 1000
    out = {"u_rms_mm": float(np.sqrt(np.mean(mag ** 2))), "u_max_mm": float(mag.max())}
    # A reference that failed on the small level (it is then in failed_cases, which is
    # gated too) leaves its scenario's cases gated on their own fields, not on an error.
    if name != ref_name and ref_name in exp.scenario(scenario):
        out["rel_l2"] = leaderboard.field_error(case, exp.scenario(scenario)[ref_name])[0]
    probes = leaderboard.probe_displacements(case["folder"])
    if probes is not None:
        out["probe_rms_mm"] = float(np.sqrt(np.mean(np.sum(probes ** 2, axis=1)))) * 1000
    for tool, force in leaderboard.final_tool_forces(case["folder"]).items():
        if np.all(np.isfinite(force)):
            out[f"tool_force_n:{tool}"] = float(np.linalg.norm(force))
    transient_ref = exp.scenario(scenario).get(exp.transient_reference) if exp.transient_reference else None
    if transient_ref is not None and name != exp.transient_reference and case["run"].get("dynamic"):
        rel = leaderboard.transient_error(case, transient_ref)[0]
        if math.isfinite(rel):
            out["transient_rel"] = rel
    if beads is not None:
        rms = beads.rms_mm(case)
        if math.isfinite(rms):
            out["bead_rms_mm"] = rms
    return out


def measure(results, data_flag=None):
    """{role: {case: {quantity: value}}} and the run's overrides (experiment.json)."""
    exp = results_index.Experiment(results)
    ref = exp.require_reference()
    beads = None
    out = {}
    for role in exp.roles:
        scenario = exp.scenario_name(role)
        if role.startswith(leaderboard.TRUTH_CUBE_ROLE_PREFIX) and beads is None:
            beads = leaderboard.Beads(data_flag)
        use_beads = beads if role.startswith(leaderboard.TRUTH_CUBE_ROLE_PREFIX) else None
        out[role] = {name: gated_values(exp, scenario, name, ref, use_beads) for name in exp.scenario(scenario)}
    with open(os.path.join(results, "experiment.json")) as f:
        overrides = json.load(f).get("overrides", [])
    failed = sorted(f"{scenario}/{case}" for scenario, cases in exp.listed_cases.items() for case in cases
                    if case not in exp.scenarios.get(scenario, {}))
    return out, overrides, failed


def tolerance(gates, quantity, committed):
    return gates["rtol"] * abs(committed) + ATOL[quantity.split(":")[0]]


def check(results, gates_path, data_flag=None, out=sys.stdout):
    with open(gates_path) as f:
        gates = json.load(f)
    measured, overrides, failed_cases = measure(results, data_flag)
    if overrides != gates["overrides"]:
        raise ValueError(f"{results}: run with --set {overrides}, the gates were recorded with {gates['overrides']} "
                         "(run tests/experiments/run_suite_gates.sh)")
    ref = gates["reference"]
    failed, total = 0, 0
    # The cases that fail (no results: e.g. a solver refusing a tool) are committed too.
    total += 1
    if failed_cases != gates.get("failed_cases", []):
        failed += 1
        print(f"FAIL  failed cases: {failed_cases}, committed {gates.get('failed_cases', [])}", file=out)
    else:
        print(f"PASS  failed cases as committed ({len(failed_cases)})", file=out)
    for role in sorted(set(gates["values"]) | set(measured)):
        committed_cases, run_cases = gates["values"].get(role, {}), measured.get(role, {})
        for name in sorted(set(committed_cases) | set(run_cases)):
            if name not in run_cases or name not in committed_cases:
                total += 1
                failed += 1
                why = "committed, not in the results" if name not in run_cases else "in the results, not committed"
                print(f"FAIL  {role}/{name}: {why}", file=out)
                continue
            for quantity in sorted(set(committed_cases[name]) | set(run_cases[name])):
                total += 1
                c, v = committed_cases[name].get(quantity), run_cases[name].get(quantity)
                if c is None or v is None:
                    ok, text = False, f"{'not committed' if c is None else 'not measured'}"
                elif quantity == "bead_rms_mm" and name == ref:
                    ok = v <= c + tolerance(gates, quantity, c)  # the reference's distance to the beads may not grow
                    text = f"{v:.9g} <= {c:.9g} + {tolerance(gates, quantity, c):.2g}"
                else:
                    ok = abs(v - c) <= tolerance(gates, quantity, c)
                    text = f"{v:.9g} vs committed {c:.9g} (+-{tolerance(gates, quantity, c):.2g})"
                failed += not ok
                print(f"{'PASS' if ok else 'FAIL'}  {role}/{name} {quantity}: {text}", file=out)
    print(f"{total - failed} of {total} suite gates hold ({gates['source']})", file=out)
    return failed == 0


def record(results, gates_path, commit, data_flag=None):
    with open(gates_path) as f:
        gates = json.load(f)
    measured, overrides, failed_cases = measure(results, data_flag)
    gates["failed_cases"] = failed_cases
    gates["values"] = measured
    gates["overrides"] = overrides
    gates["measured_at"] = commit
    with open(gates_path, "w") as f:
        json.dump(gates, f, indent=1, sort_keys=False)
        f.write("\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("action", choices=["check", "record"])
    parser.add_argument("results")
    parser.add_argument("gates", nargs="?", default=os.path.join(os.path.dirname(HERE), "experiments",
                                                                   "suite_gates.json"))
    parser.add_argument("--commit", default=None, help="record: the commit the values were measured at")
    parser.add_argument("--data-dir", default=None)
    a = parser.parse_args()
    try:
        if a.action == "record":
            if not a.commit:
                parser.error("record needs --commit (the commit the run was built from)")
            record(a.results, a.gates, a.commit, a.data_dir)
            return 0
        return 0 if check(a.results, a.gates, a.data_dir) else 1
    except (OSError, ValueError, KeyError) as e:  # results_index.ResultsError is a ValueError
        print(f"suite_gates: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
