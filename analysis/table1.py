"""Table 1 of the paper (correlation of u_z with the fine FEM on the cube's top
surface) beside the paper's values, and its continuation with the metrics
correlation hides, for every case of the experiment against its reference.

Usage: /usr/bin/python3 analysis/table1.py [results/paper] [results/tables]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_index  # noqa: E402
from table_io import LOAD_CASES, ROLES, fmt, ordered_for_paper, paper_value, paper_values, write_table  # noqa: E402

METRICS = [("corr_uz", "r(u_z)", 3), ("corr_mag", "r(|u|)", 3), ("rel_l2", "relative L2 error", 3),
           ("max_error", "max error (mm)", 2), ("load_ratio", "|u| ratio at load point", 3)]


def make(exp_dir, out_dir):
    exp = results_index.Experiment(exp_dir)
    paper = paper_values()
    cube = {lc: exp.scenario_name(ROLES["cube"][lc]) for lc in LOAD_CASES}
    ref = exp.require_reference()
    compared = ordered_for_paper(exp.compared_cases(list(cube.values())), paper, "table1_correlation_top_surface")
    m = {(case, lc): exp.metrics(cube[lc], case) for case in compared for lc in LOAD_CASES}

    rows = []
    for case in compared:
        row = [f"{case} vs {ref}"]
        for lc in LOAD_CASES:
            p = paper_value(paper, "table1_correlation_top_surface", case, lc)
            row += [fmt(m[case, lc]["corr_uz"]), fmt(p) if p is not None else ""]
        rows.append(row)
    write_table(out_dir, "table1", ["models", "pull (measured)", "pull (paper)", "push (measured)", "push (paper)"],
                rows, f"Pearson r of u_z over the cube's top-surface vertices, against {ref}. "
                "The paper reports the hybrid and PBD only.")

    rows = []
    for case in compared:
        for key, label, digits in METRICS:
            row = [case, label]
            for lc in LOAD_CASES:
                v = m[case, lc][key]
                row.append(fmt(v * 1000 if key == "max_error" else v, digits))
            rows.append(row)
    write_table(out_dir, "table1_metrics", ["model", "metric", "pull", "push"], rows,
                f"Cube top surface, each case against {ref}.")
    return compared


if __name__ == "__main__":
    results_index.main(lambda: make(sys.argv[1] if len(sys.argv) > 1 else "results/paper",
                                    sys.argv[2] if len(sys.argv) > 2 else "results/tables"), "table1")
    print("table 1 written")
