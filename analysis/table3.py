"""Table 3 of the paper (per-frame time on the liver, every case, beside the
paper's hybrid value) and, beyond the paper, the liver's accuracy against the
reference.

Usage: /usr/bin/python3 analysis/table3.py [results/paper] [results/tables]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import results_index  # noqa: E402
from table2 import timing_rows  # noqa: E402
from table_io import LOAD_CASES, ROLES, fmt, machine_note, ordered_for_paper, paper_values, write_table  # noqa: E402


def make(exp_dir, out_dir):
    exp = results_index.Experiment(exp_dir)
    paper = paper_values()
    liver = {lc: exp.scenario_name(ROLES["liver"][lc]) for lc in LOAD_CASES}
    scenarios = list(liver.values())
    cases = ordered_for_paper(exp.case_names(scenarios), paper, "table3_liver_ms_per_frame")
    rows = timing_rows(exp, "liver", cases, paper, "table3_liver_ms_per_frame", False)
    write_table(out_dir, "table3", ["model", "pull median (ms)", "pull p95 (ms)", "pull paper (ms)",
                                    "push median (ms)", "push p95 (ms)", "push paper (ms)"], rows,
                "Liver, per-frame time. The paper reports the hybrid only (5.5 ms). " +
                machine_note(exp.scenario(liver["pull"])))

    ref = exp.require_reference()
    rows = []
    for case in [c for c in cases if c != ref]:
        for key, label, digits in [("corr_uz", "r(u_z)", 3), ("rel_l2", "relative L2 error", 3),
                                   ("load_ratio", "|u| ratio at load point", 3)]:
            row = [case, label]
            for lc in LOAD_CASES:
                c = exp.scenario(liver[lc])[case]
                v = exp.metrics(liver[lc], case)[key]
                row.append(fmt(v, digits) + ("" if c["run"]["reached_steady_state"] else " (not steady)"))
            rows.append(row)
    write_table(out_dir, "table3_metrics", ["model", "metric", "pull", "push"], rows,
                f"Liver, every surface vertex, against {ref} (the fine FEM on TetGen of the repaired surface). "
                "Beyond the paper, which gives no accuracy for the liver. '(not steady)': the frame budget ended "
                "before the steady-state test was met.")
    return cases


if __name__ == "__main__":
    results_index.main(lambda: make(sys.argv[1] if len(sys.argv) > 1 else "results/paper",
                                    sys.argv[2] if len(sys.argv) > 2 else "results/tables"), "table3")
    print("table 3 written")
