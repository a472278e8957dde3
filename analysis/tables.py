"""Tables 1-3 of the paper, regenerated from raw results beside the paper's values.

Usage: /usr/bin/python3 analysis/tables.py [results/paper] [results/tables]
Reads only results/<experiment>/<scenario>/<case>/ files and paper_values.json.
Writes table1, table1_metrics, table2, table3 (and table3_metrics) as .md and .csv.
"""
import csv
import io
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import metrics  # noqa: E402
import results_index  # noqa: E402

REFERENCE = "fem-direct"
CASES = ["pull", "push"]


def case_metrics(scenario_cases, case):
    """Metrics of `case` against the scenario's fine-FEM reference."""
    ref = scenario_cases[REFERENCE]
    mine = scenario_cases[case]
    _, rest, u_ref = metrics.read_displacements(os.path.join(ref["folder"], "top_surface.csv"))
    _, rest2, u = metrics.read_displacements(os.path.join(mine["folder"], "top_surface.csv"))
    if rest.shape != rest2.shape:
        raise ValueError(f"{mine['folder']}: observed vertices differ from the reference's")
    load_point = mine["run"]["scenario_as_read"]["load"]["point"]
    return metrics.compare(u, u_ref, rest, load_point)


def fmt(x, digits=3):
    if isinstance(x, str):
        return x
    if x is None or x != x:
        return "n/a"
    return f"{x:.{digits}f}"


def write_table(out_dir, name, header, rows, notes=""):
    """Writes name.md and name.csv."""
    os.makedirs(out_dir, exist_ok=True)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    with open(os.path.join(out_dir, name + ".csv"), "w") as f:
        f.write(buf.getvalue())
    md = "| " + " | ".join(h.replace("|", "\\|") for h in header) + " |\n|" + "---|" * len(header) + "\n"
    md += "".join("| " + " | ".join(str(c).replace("|", "\\|") for c in r) + " |\n" for r in rows)
    if notes:
        md += "\n" + notes.strip() + "\n"
    with open(os.path.join(out_dir, name + ".md"), "w") as f:
        f.write(md)


def machine_note(exp):
    any_case = next(iter(next(iter(exp.values())).values()))
    b = any_case["run"]["build"]
    return (f"Measured on {b.get('cpu_model', '?')} ({b.get('hardware_threads', '?')} hardware threads), "
            f"{b['build_type']} build, {b['compiler']}, commit {b['git_commit']}; one thread.")


def make_tables(exp_dir, out_dir):
    exp = results_index.load_experiment(exp_dir)
    with open(os.path.join(HERE, "paper_values.json")) as f:
        paper = json.load(f)

    def scen(kind, case):
        name = f"{kind}-{case}"
        if name not in exp:
            raise FileNotFoundError(f"{exp_dir}/{name}: missing scenario results")
        return exp[name]

    # Table 1: correlation of u_z on the top surface with the fine FEM.
    p1 = paper["table1_correlation_top_surface"]
    rows = []
    for model, label in [("hybrid", "hybrid vs FEM"), ("pbd", "PBD vs FEM")]:
        row = [label]
        for case in CASES:
            row += [fmt(case_metrics(scen("cube", case), model)["corr_uz"]), fmt(p1[model][case])]
        rows.append(row)
    write_table(out_dir, "table1", ["models", "pull (measured)", "pull (paper)", "push (measured)", "push (paper)"],
                rows, "Pearson r of u_z over the cube's top-surface vertices, against the fine FEM (fem-direct).")

    # Table 1, second part: the metrics correlation hides.
    rows = []
    for model in ["hybrid", "pbd", "fem-iterative"]:
        for key, label, d in [("corr_uz", "r(u_z)", 3), ("corr_mag", "r(|u|)", 3), ("rel_l2", "relative L2 error", 3),
                              ("max_error", "max error (mm)", 2), ("load_ratio", "|u| ratio at load point", 3)]:
            row = [model, label]
            for case in CASES:
                v = case_metrics(scen("cube", case), model)[key]
                row.append(fmt(v * 1000 if key == "max_error" else v, d))
            rows.append(row)
    write_table(out_dir, "table1_metrics", ["model", "metric", "pull", "push"], rows,
                "Cube top surface, each model against fem-direct. fem-iterative is a solver check (should be ~0 error).")

    # Table 2: per-frame time on the cube.
    p2 = paper["table2_ms_per_frame"]
    rows = []
    for model, paper_key in [("hybrid", "hybrid"), ("pbd", "pbd"), ("fem-direct", "fem"), ("fem-iterative", "fem")]:
        row = [model]
        for case in CASES:
            t = scen("cube", case)[model]["timings"]
            row += [fmt(t["step"]["median_ms"], 2), fmt(t["step"]["p95_ms"], 2), fmt(p2[paper_key][case], 1)]
        row.append(fmt(scen("cube", "pull")[model]["timings"]["setup_ms"], 0))
        rows.append(row)
    iters = scen("cube", "pull")["pbd"]["run"]["parameters"]["iterations"]
    # Results from before the preconditioner parameter existed used IC alone.
    iterative_parameters = scen("cube", "pull")["fem-iterative"]["run"]["parameters"]
    preconditioner = iterative_parameters.get("preconditioner", "ic")
    tolerance = iterative_parameters.get("cg_tolerance", "not recorded")
    preconditioner_text = {"ic": "incomplete Cholesky",
                           "two_level": "incomplete Cholesky plus a coarse correction on the hybrid's coarse mesh"}
    write_table(out_dir, "table2",
                ["model", "pull median (ms)", "pull p95 (ms)", "pull paper (ms)", "push median (ms)", "push p95 (ms)",
                 "push paper (ms)", "setup, pull (ms)"], rows,
                f"Per-frame time of step(), median and p95 over every frame run. PBD and hybrid: {int(iters)} iterations. "
                "fem-direct: back-substitution with a factorisation made in setup; fem-iterative: CG "
                f"(preconditioner: {preconditioner_text.get(preconditioner, preconditioner)}; relative tolerance {tolerance}) "
                "warm-started from the previous frame (the load ramps, so every frame is a new solve). The paper's FEM is one "
                "number; its solver is not stated. " + machine_note(exp) + f" Paper: {paper['machine']}.")

    # Table 3: the liver.
    p3 = paper["table3_liver_ms_per_frame"]
    rows = []
    for model in ["hybrid", "pbd", "fem-direct", "fem-iterative"]:
        row = [model]
        for case in CASES:
            t = scen("liver", case)[model]["timings"]
            row += [fmt(t["step"]["median_ms"], 2), fmt(t["step"]["p95_ms"], 2),
                    fmt(p3[model][case], 1) if model in p3 else ""]
        rows.append(row)
    write_table(out_dir, "table3", ["model", "pull median (ms)", "pull p95 (ms)", "pull paper (ms)",
                                    "push median (ms)", "push p95 (ms)", "push paper (ms)"], rows,
                "Liver, per-frame time. The paper reports the hybrid only (5.5 ms). " + machine_note(exp))
    rows = []
    for model in ["hybrid", "pbd"]:
        for key, label, d in [("corr_uz", "r(u_z)", 3), ("rel_l2", "relative L2 error", 3),
                              ("load_ratio", "|u| ratio at load point", 3)]:
            row = [model, label]
            for case in CASES:
                c = scen("liver", case)
                v = case_metrics(c, model)[key]
                steady = c[model]["run"]["reached_steady_state"]
                row.append(fmt(v, d) + ("" if steady else " (not steady)"))
            rows.append(row)
    write_table(out_dir, "table3_metrics", ["model", "metric", "pull", "push"], rows,
                "Liver, every surface vertex, against the liver's fine FEM (fem-direct on TetGen of the repaired "
                "surface). Beyond the paper, which gives no accuracy for the liver. '(not steady)': the frame "
                "budget ended before the steady-state test was met.")


if __name__ == "__main__":
    exp_dir = sys.argv[1] if len(sys.argv) > 1 else "results/paper"
    out_dir = sys.argv[2] if len(sys.argv) > 2 else "results/tables"
    make_tables(exp_dir, out_dir)
    print(f"tables written to {out_dir}")
