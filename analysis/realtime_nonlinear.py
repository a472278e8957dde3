"""The real-time nonlinear solvers against Newton's answer on the same mesh
(docs/realtime_nonlinear.md, experiments/realtime_nonlinear.json).

Usage: /usr/bin/python3 analysis/realtime_nonlinear.py [runs/realtime_nonlinear] [results] [--data-dir DIR]

Per scenario (roles cube_pull, cube_push, truth_cube) and case: the law the case
solves; its settled displacement's relative L2 error (top surface of the paper cube,
every surface vertex of the Truth Cube) against the static Newton case of the same
law on the same mesh (a Newton case is the experiment's `fem` case with solver
newton) and against the experiment's reference (Newton, neo_hookean); whether it met
the runner's steady-state test and after how many frames (and how much simulated
time); its per-frame median and p95; and, on the Truth Cube, its RMS bead error.
Writes results/tables/<experiment>.{md,csv} and results/figures/<experiment>.png
(error against frame time, one panel per scenario), <experiment> the experiment's
name: realtime_nonlinear, realtime_nonlinear_100k (the same at 105 193 tets,
experiments/realtime_nonlinear_100k.json) or realtime_nonlinear_2ms (the paper cube's
cases that fit 2 ms, experiments/realtime_nonlinear_2ms.json).
"""
import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import metrics  # noqa: E402
import results_index  # noqa: E402
from results_index import ResultsError  # noqa: E402
from table_io import fmt, write_table  # noqa: E402

ROLES = {"cube_pull": ("paper cube, 1 N pull on the 5 mm disc", "top_surface.csv"),
         "cube_push": ("paper cube, 1 N push on the 5 mm disc", "top_surface.csv"),
         "truth_cube": ("Truth Cube, 18.25 %, plate bonded", "surface.csv"),
         "cube_pull_100k": ("paper cube at 105 193 tets, 1 N pull on the 5 mm disc", "top_surface.csv")}
# The law a model solves when its parameters do not name one (xpbd_neo's constraints
# minimise xpbd_neo_hookean; fem's direct and iterative solvers are linear).
IMPLIED_LAW = {"xpbd_neo": "xpbd_neo_hookean"}
# The frame budget drawn in each panel (ms): the 2 ms asked of the paper-sized meshes,
# 16 ms at 100 000 tets.
BUDGET_MS = {"cube_pull_100k": 16.0}


def law_of(case):
    run = case["run"]
    params = run.get("parameters", {})
    if "material_law" in params and (run["model"] != "fem" or params.get("solver") == "newton"):
        return params["material_law"]
    return IMPLIED_LAW.get(run["model"], "linear")


def is_newton(case):
    run = case["run"]
    return run["model"] == "fem" and run.get("parameters", {}).get("solver") == "newton"


def newton_by_law(cases):
    return {law_of(c): name for name, c in cases.items() if is_newton(c)}


def relative_l2(case, reference_case, observed):
    """||u - u_ref|| / ||u_ref|| over the observed vertices (the same in both)."""
    case_read = metrics.read_displacements(os.path.join(case["folder"], observed))
    ref_read = metrics.read_displacements(os.path.join(reference_case["folder"], observed))
    u, u_ref = case_read[2], ref_read[2]
    if not results_index.same_vertices(case_read, ref_read):
        raise ResultsError(f"{case['folder']}: observed vertices differ from {reference_case['folder']}'s")
    return float(np.linalg.norm(u - u_ref) / np.linalg.norm(u_ref))


def bead_rms_mm(case, table, data_flag):
    """RMS bead error (mm) of a Truth Cube case against the table's column, or None."""
    import truth_cube
    grid, positions, strains = table
    beads = truth_cube.case_beads(case, positions, strains)
    if beads is None:
        return None
    rest, measured, predicted = beads
    return truth_cube.errors(rest, measured, predicted, grid)["rms"]


def rows_of(exp, role, table, data_flag):
    title, observed = ROLES[role]
    cases = exp.by_role(role)
    reference = exp.require_reference()
    if reference not in cases:
        raise ResultsError(f"{exp.root}: no results for the reference case '{reference}' of role '{role}'")
    own = newton_by_law(cases)
    rows = []
    for name, case in cases.items():
        run, t = case["run"], case["timings"]
        law = law_of(case)
        err_ref = relative_l2(case, cases[reference], observed) if name != reference else 0.0
        own_name = own.get(law)
        err_own = (relative_l2(case, cases[own_name], observed)
                   if own_name and own_name != name else (0.0 if own_name == name else None))
        dynamic = run.get("dynamic", False)
        h = run.get("parameters", {}).get("time_step")
        frames = run.get("frames")
        settled = run.get("reached_steady_state") if dynamic else None
        change = (run["last_frame_change_m"] / run["max_displacement_m"]
                  if dynamic and run.get("max_displacement_m") else None)
        beads = bead_rms_mm(case, table, data_flag) if role == "truth_cube" and table else None
        step = t["step_after_ramp"] if dynamic and t.get("step_after_ramp", {}).get("count") else t["step"]
        rows.append({"scenario": title, "budget_ms": BUDGET_MS.get(role, 2.0), "case": name, "model": run["model"], "law": law,
                     "err_own": err_own, "err_ref": err_ref, "dynamic": dynamic, "frames": frames,
                     "simulated_s": frames * h if dynamic and h else None, "settled": settled,
                     "last_change": change, "median_ms": step["median_ms"], "p95_ms": step["p95_ms"],
                     "setup_ms": t.get("setup_ms"), "beads_mm": beads,
                     "threads": run.get("parameters", {}).get("threads")})
    return rows


def figure(rows, out_dir, name):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    scenarios = list(dict.fromkeys(r["scenario"] for r in rows))
    fig, axes = plt.subplots(1, len(scenarios), figsize=(max(7.0, 5.2 * len(scenarios)), 4.2), squeeze=False)
    colours = {"vbd": "tab:blue", "xpbd_neo": "tab:orange", "fem": "tab:gray"}
    for ax, s in zip(axes[0], scenarios):
        for r in rows:
            if r["scenario"] != s or not r["dynamic"]:
                continue
            ax.scatter(r["median_ms"], max(r["err_ref"], 1e-12), color=colours.get(r["model"], "k"),
                       marker="o" if r["settled"] else "x")
            ax.annotate(r["case"], (r["median_ms"], max(r["err_ref"], 1e-12)), fontsize=7,
                        xytext=(3, 3), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.autoscale_view()
        for r in rows:
            if r["scenario"] == s and r["model"] == "fem" and r["law"] != "neo_hookean":
                ax.axhline(r["err_ref"], color="tab:gray", lw=0.8, ls="--")
                ax.annotate(f"Newton, {r['law']}", (0.02, r["err_ref"]), xycoords=("axes fraction", "data"),
                            fontsize=7, color="tab:gray", va="bottom")
        ax.set_xlabel("median time per frame (ms, 2 threads)")
        ax.set_ylabel("relative L2 error against Newton, neo_hookean")
        ax.set_title(s, fontsize=9)
        ax.axvline(next(r["budget_ms"] for r in rows if r["scenario"] == s), color="tab:red", lw=0.6)
    fig.suptitle("Settled error against frame cost (o: met the steady-state test, x: frame budget ended)",
                 fontsize=9)
    fig.tight_layout()
    os.makedirs(out_dir, exist_ok=True)
    fig.savefig(os.path.join(out_dir, name + ".png"), dpi=120)
    plt.close(fig)


def make(results_dir, out, data_flag):
    exp = results_index.Experiment(results_dir)
    table = None
    rows = []
    present = []
    for role in ROLES:
        if role not in exp.roles or exp.roles[role][0] not in exp.scenarios:
            if role in exp.roles:
                print(f"realtime_nonlinear: no results for role '{role}', skipped", file=sys.stderr)
            continue
        present.append(role)
        if role == "truth_cube":
            import truth_cube
            path = os.path.join(truth_cube.data_dir(data_flag), "data", "truthcube", "uniaxial_positions.csv")
            table = truth_cube.read_table(path)
        rows += rows_of(exp, role, table, data_flag)
    if not rows:
        raise ResultsError(f"{results_dir}: no scenario of roles {', '.join(ROLES)} has results")
    header = ["scenario", "case", "law", "error vs Newton, own law", "error vs Newton, neo_hookean",
              "frames (simulated s)", "steady", "last frame change", "median ms", "p95 ms", "setup ms",
              "bead RMS (mm)"]
    out_rows = []
    for r in rows:
        out_rows.append([r["scenario"], r["case"], r["law"], f"{r['err_own']:.3g}" if r["err_own"] is not None else "",
                         f"{r['err_ref']:.3g}",
                         f"{r['frames']} ({r['simulated_s']:.2f})" if r["simulated_s"] else str(r["frames"]),
                         {True: "yes", False: "no", None: "(static)"}[r["settled"]],
                         f"{r['last_change']:.2g}" if r["last_change"] is not None else "",
                         fmt(r["median_ms"], 3), fmt(r["p95_ms"], 3), fmt(r["setup_ms"], 0),
                         fmt(r["beads_mm"], 3) if r["beads_mm"] is not None else ""])
    b = next(iter(exp.scenarios.values()))[exp.reference]["run"]["build"]
    commits = sorted({c["run"]["build"]["git_commit"] for cases in exp.scenarios.values() for c in cases.values()})
    notes = (f"Relative L2 error of the settled displacement ({', '.join(f'{ROLES[r][0]}: {ROLES[r][1]}' for r in present)}) "
             "against the static Newton answer of the case's own law on the same mesh, and against Newton with "
             "neo_hookean (the reference). A dynamic case stops when a frame changes the body by at most the "
             "scenario's steady_tolerance of its largest displacement, or at its frame budget ('steady: no'); "
             "'last frame change' is that change over the largest displacement. Median and p95 of step() after the "
             "load ramp, the dynamic cases on the number of threads their parameters give. "
             f"Measured on {b.get('cpu_model', '?')} ({b.get('hardware_threads', '?')} hardware threads), "
             f"{b['build_type']} build, {b['compiler']}, commit{'s' if len(commits) > 1 else ''} {', '.join(commits)} "
             "(each case's in its run.json). "
             f"Case parameters: experiments/{exp.name}.json.")
    write_table(os.path.join(out, "tables"), exp.name, header, out_rows, notes)
    figure(rows, os.path.join(out, "figures"), exp.name)
    print(f"realtime_nonlinear: wrote {out}/tables/{exp.name}.{{md,csv}}, {out}/figures/{exp.name}.png")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("results", nargs="?", default="runs/realtime_nonlinear")
    p.add_argument("out", nargs="?", default="results")
    p.add_argument("--data-dir", default=None)
    a = p.parse_args()
    results_index.main(lambda: make(a.results, a.out, a.data_dir), "realtime_nonlinear")


if __name__ == "__main__":
    main()
