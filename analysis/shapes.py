"""The shapes experiment (docs/shapes.md): each model against fem-direct on the same shape.

Usage: /usr/bin/python3 analysis/shapes.py [results/shapes] [results]
Reads results/shapes/<scenario>/<case>/ (experiments/shapes.json: six generated
surfaces at two resolutions, bottom fifth clamped, a pull at the highest surface
vertex, every surface vertex observed); writes results/tables/shapes.{csv,md} and
results/figures/shapes.png. A case without results (its run failed: the runner
writes nothing then) is listed as "no result", never left out.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import results_index  # noqa: E402
from table_io import fmt, write_table as write_table_files  # noqa: E402

NO_RESULT = "no result"


def shape_of(case):
    """(shape name, resolution, surface vertices) from a case's run.json."""
    run = case["run"]
    mesh = (run.get("scenario_resolved") or run["scenario_as_read"])["mesh"]
    return mesh.get("shape", mesh.get("type")), mesh.get("resolution"), run["mesh"]["surface_vertices"]


def listed_cases(exp, scenario):
    """The cases experiment.json lists for a scenario (failed ones included), else those with results."""
    with_results = list(exp.scenarios.get(scenario, {}))
    return exp.listed_cases.get(scenario, with_results)


def shape_rows(exp_dir):
    """One row per (scenario, case), sorted by shape name then surface vertices, in the experiment's case order."""
    exp = results_index.Experiment(exp_dir)
    ref = exp.require_reference()
    rows = []
    for scenario, cases in exp.scenarios.items():
        shape, resolution, vertices = shape_of(next(iter(cases.values())))
        order = listed_cases(exp, scenario)
        for model in order:
            row = {"scenario": scenario, "shape": shape, "resolution": resolution, "surface_vertices": vertices,
                   "model": model, "ok": model in cases, "order": order.index(model)}
            if model in cases:
                case = cases[model]
                row["median_ms"] = case["timings"]["step"]["median_ms"]
                row["p95_ms"] = case["timings"]["step"]["p95_ms"]
                row["steady"] = case["run"].get("reached_steady_state", True)
                row["metrics"] = exp.metrics(scenario, model) if ref in cases else None
            else:
                row["failure"] = exp.failure(scenario, model)
            rows.append(row)
    return sorted(rows, key=lambda r: (r["shape"], r["surface_vertices"], r["order"]))


def table_cells(r):
    head = [r["shape"], r["resolution"], r["surface_vertices"], r["model"]]
    if not r["ok"]:
        return head + [NO_RESULT] * 5
    m = r["metrics"]
    mark = "" if r["steady"] else " (not steady)"
    acc = ["n/a (no reference)"] * 3 if m is None else [fmt(m["corr_uz"]) + mark, fmt(m["rel_l2"]) + mark,
                                                        fmt(m["load_ratio"]) + mark]
    return head + acc + [fmt(r["median_ms"], 2), fmt(r["p95_ms"], 2)]


HEADER = ["shape", "resolution", "surface vertices", "model", "r(u_z)", "relative L2", "|u| ratio at load",
          "median ms", "p95 ms"]
NOTE = ("Each model against fem-direct on the same shape and fine mesh, over every surface vertex "
        "(experiments/shapes.json: bottom fifth of the height clamped, 0.1 N pull at the highest surface vertex). "
        "Resolution: edge segments per 0.1 m. '(not steady)': the frame budget ended before the steady-state test "
        f"was met; '{NO_RESULT}': the case failed (the runner's message is on stderr; the runner writes no result).")


def write_table(out_dir, rows, build):
    failures = sorted({f"{r['scenario']}/{r['model']}: {r['failure']}" for r in rows if not r["ok"] and r["failure"]})
    write_table_files(out_dir, "shapes", HEADER, [table_cells(r) for r in rows],
                      NOTE + " " + build + (" Failures: " + "; ".join(failures) + "." if failures else ""))


def build_note(exp_dir):
    for cases in results_index.load_experiment(exp_dir).values():
        for case in cases.values():
            b = case["run"].get("build", {})
            return (f"Measured on {b.get('cpu_model', '?')}, {b.get('build_type', '?')} build, "
                    f"{b.get('compiler', '?')}, commit {b.get('git_commit', '?')}; one thread.")
    return ""




def write_figure(path, rows):
    """r(u_z), relative L2 and median frame time per shape and resolution: hatched
    bars did not reach the steady state, x marks a case without result."""
    labels = []
    for r in rows:
        label = f"{r['shape']}\n{r['surface_vertices']}"
        if label not in labels:
            labels.append(label)
    x = np.arange(len(labels))
    fig, axes = plt.subplots(3, 1, figsize=(max(8, 0.9 * len(labels)), 9), sharex=True)
    models = sorted({r["model"] for r in rows}, key=lambda m: next(r["order"] for r in rows if r["model"] == m))
    colours = {m: f"C{k}" for k, m in enumerate(models)}
    compared = [m for m in models if any(r["model"] == m and r.get("metrics") and r["metrics"]["rel_l2"] > 0
                                         for r in rows)]
    panels = [("corr_uz", "r(u_z) against the reference", compared),
              ("rel_l2", "relative L2 error against the reference", compared),
              ("median_ms", "median ms per frame (log)", models)]
    for ax, (key, title, models) in zip(axes, panels):
        width = 0.8 / len(models)
        for k, model in enumerate(models):
            pos = x + (k - (len(models) - 1) / 2) * width
            for i, label in enumerate(labels):
                r = next((r for r in rows if f"{r['shape']}\n{r['surface_vertices']}" == label and r["model"] == model),
                         None)
                if r is None:
                    continue
                if not r["ok"]:
                    ax.plot(pos[i], 0.02, "x", color=colours[model], markersize=8, transform=ax.get_xaxis_transform())
                    continue
                v = r["median_ms"] if key == "median_ms" else (r["metrics"] or {}).get(key, np.nan)
                ax.bar(pos[i], v, width, color=colours[model], hatch=None if r["steady"] else "//",
                       edgecolor="white", label=model if i == 0 else None)
        ax.set_title(title)
        ax.grid(alpha=0.3, axis="y")
        if key == "median_ms":
            ax.set_yscale("log")
        ax.legend(fontsize=8, loc="upper left")
    axes[-1].set_xticks(x)
    axes[-1].set_xticklabels(labels, fontsize=8)
    axes[-1].set_xlabel("shape, surface vertices (hatched: not steady; x: no result)")
    fig.tight_layout()
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.savefig(path, dpi=150)
    plt.close(fig)


def make(exp_dir, out):
    rows = shape_rows(exp_dir)
    write_table(os.path.join(out, "tables"), rows, build_note(exp_dir))
    write_figure(os.path.join(out, "figures", "shapes.png"), rows)
    return rows


if __name__ == "__main__":
    written = make(sys.argv[1] if len(sys.argv) > 1 else "results/shapes", sys.argv[2] if len(sys.argv) > 2 else "results")
    failed = [f"{r['scenario']}/{r['model']}" for r in written if not r["ok"]]
    print(f"shapes table and figure written; {len(failed)} cases without result" + (": " + ", ".join(failed) if failed else ""))
