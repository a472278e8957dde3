"""Table 2 of the paper: per-frame time on the cube, every case, beside the
paper's values.

Usage: /usr/bin/python3 analysis/table2.py [results/paper] [results/tables]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_index  # noqa: E402
from table_io import (LOAD_CASES, ROLES, case_table, fmt, machine_note, ordered_for_paper, paper_value,  # noqa: E402
                      paper_values, write_table)


def timing_rows(exp, body, cases, paper, table, with_setup):
    """Per case: median, p95 and the paper's value for each load case of `body`
    ("cube" or "liver": the scenarios in its roles), then the pull's setup time."""
    rows = []
    for case in cases:
        row = [case]
        for lc in LOAD_CASES:
            t = exp.by_role(ROLES[body][lc])[case]["timings"]
            p = paper_value(paper, table, case, lc)
            row += [fmt(t["step"]["median_ms"], 2), fmt(t["step"]["p95_ms"], 2), fmt(p, 1) if p is not None else ""]
        if with_setup:
            row.append(fmt(exp.by_role(ROLES[body]["pull"])[case]["timings"]["setup_ms"], 0))
        rows.append(row)
    return rows


def make(exp_dir, out_dir):
    exp = results_index.Experiment(exp_dir)
    paper = paper_values()
    scenarios = [exp.scenario_name(ROLES["cube"][lc]) for lc in LOAD_CASES]
    cases = ordered_for_paper(exp.case_names(scenarios), paper, "table2_ms_per_frame")
    rows = timing_rows(exp, "cube", cases, paper, "table2_ms_per_frame", True)
    pull = exp.by_role(ROLES["cube"]["pull"])
    write_table(out_dir, "table2",
                ["model", "pull median (ms)", "pull p95 (ms)", "pull paper (ms)", "push median (ms)", "push p95 (ms)",
                 "push paper (ms)", "setup, pull (ms)"], rows,
                "Per-frame time of step(), median and p95 over every frame run. Dynamic models (PBD, hybrid) run "
                "until steady; static ones (FEM) solve once per frame, the load ramping so every frame is a new "
                "solve. Model descriptions and every parameter value are in each case's run.json; the paper's FEM "
                "is one number and its solver is not stated. " + machine_note(pull) + f" Paper: {paper['machine']}."
                "\n\n" + case_table({c: pull[c] for c in cases}))
    return cases


if __name__ == "__main__":
    results_index.main(lambda: make(sys.argv[1] if len(sys.argv) > 1 else "results/paper",
                                    sys.argv[2] if len(sys.argv) > 2 else "results/tables"), "table2")
    print("table 2 written")
