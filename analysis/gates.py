"""Accuracy gates (docs/usage.md): checks an experiment's results against every gate in
a gates file, printing the measured value beside the threshold.

Usage: /usr/bin/python3 analysis/gates.py RESULTS_DIR [GATES_JSON] [--repeat RESULTS_DIR_2]
  RESULTS_DIR   results/<experiment> of a run of the gates file's experiment
  GATES_JSON    default experiments/accuracy_gates.json
  --repeat DIR  a second run of the same experiment: "identical" gates compare
                its files byte for byte with RESULTS_DIR's
Exit status 0 when every gate holds, 1 otherwise (2 for unusable input).

A gate (one JSON object in "gates") is one of
  {"role", "case", "metric", "at_least" | "at_most": number, "source"}
  {"role", "case", "metric", "below_case": other case, "source"}  metric(case) < metric(other)
  {"role", "case", "identical": [file names], "source"}           needs --repeat
where role is the scenario's role in the experiment (experiment.json, e.g.
"cube_pull"), metric a key of metrics.compare (corr_uz, corr_mag, rel_l2,
max_error, load_ratio) against the experiment's reference case, and "source" says
where the threshold comes from (a measured value at a named commit minus a margin,
or a bound).
"""
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import results_index  # noqa: E402


def evaluate(exp, gate, repeat_dir=None):
    """(description, measured text, threshold text, passed) of one gate."""
    scenario, case = exp.scenario_name(gate["role"]), gate["case"]
    if "identical" in gate:
        if repeat_dir is None:
            raise ValueError("an 'identical' gate needs --repeat DIR (a second run)")
        a_dir = exp.scenario(scenario)[case]["folder"]
        b_dir = os.path.join(repeat_dir, scenario, case)
        differing = []
        for name in gate["identical"]:
            with open(os.path.join(a_dir, name), "rb") as fa, open(os.path.join(b_dir, name), "rb") as fb:
                if fa.read() != fb.read():
                    differing.append(name)
        return (f"{scenario}/{case}: {', '.join(gate['identical'])} identical in two runs",
                "identical" if not differing else "differ: " + ", ".join(differing), "identical", not differing)
    metric = gate["metric"]
    value = exp.metrics(scenario, case)[metric]
    if "below_case" in gate:
        other = exp.metrics(scenario, gate["below_case"])[metric]
        return (f"{scenario}: {metric}({case}) < {metric}({gate['below_case']})", f"{value:.6g}", f"< {other:.6g}",
                value < other)
    if "at_least" in gate:
        return f"{scenario}/{case}: {metric}", f"{value:.6g}", f">= {gate['at_least']:g}", value >= gate["at_least"]
    if "at_most" in gate:
        return f"{scenario}/{case}: {metric}", f"{value:.6g}", f"<= {gate['at_most']:g}", value <= gate["at_most"]
    raise ValueError(f"gate {gate}: needs at_least, at_most, below_case or identical")


def check(results_dir, gates_file, repeat_dir=None, out=sys.stdout):
    """Evaluates every gate; prints a table; returns True when all hold."""
    with open(gates_file) as f:
        gates = json.load(f)["gates"]
    exp = results_index.Experiment(results_dir)
    rows = [evaluate(exp, g, repeat_dir) + (g.get("source", ""),) for g in gates]
    width = max(len(r[0]) for r in rows)
    for desc, measured, threshold, ok, source in rows:
        print(f"{'PASS' if ok else 'FAIL'}  {desc:<{width}}  measured {measured:>12}  threshold {threshold:>14}"
              f"  ({source})", file=out)
    failed = sum(not r[3] for r in rows)
    print(f"{len(rows) - failed} of {len(rows)} gates hold", file=out)
    return failed == 0


if __name__ == "__main__":
    args = sys.argv[1:]
    repeat = None
    if "--repeat" in args:
        i = args.index("--repeat")
        repeat = args[i + 1]
        del args[i:i + 2]
    if not args:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    gates_path = args[1] if len(args) > 1 else os.path.join(os.path.dirname(HERE), "experiments", "accuracy_gates.json")
    try:
        sys.exit(0 if check(args[0], gates_path, repeat) else 1)
    except (OSError, ValueError, KeyError) as e:  # results_index.ResultsError is a ValueError
        print(f"gates: {e}", file=sys.stderr)
        sys.exit(2)
