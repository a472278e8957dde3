"""Scaling (docs/scaling.md): PBD and hybrid per-frame time against the surface size, threads and precision.

Usage: /usr/bin/python3 analysis/scaling.py [results/scaling] [results]
Reads results/scaling/<scenario>/<case>/{run,timings}.json (experiments/scaling/*.json, run by
scripts/scaling); writes results/tables/scaling.{md,csv}, results/tables/scaling_mesh.{md,csv} and
results/figures/scaling.png. Every number comes from those files: the case's model and
parameters from run.json, its frame times (after the load ramp) and named phases from timings.json,
the mesh's size, build time and peak memory from run.json's mesh summary.
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import results_index  # noqa: E402
import table_io as tables  # noqa: E402


def case_rows(exp_dir):
    """One row per (scenario, case)."""
    rows = []
    for scenario, cases in results_index.load_experiment(exp_dir).items():
        for case, c in cases.items():
            run, timings = c["run"], c["timings"]
            mesh, params = run["mesh"], run["parameters"]
            step = timings["step_after_ramp"]
            phases = {k: v["median_ms"] for k, v in timings.get("phases_after_ramp", {}).items()}
            rows.append({
                "scenario": scenario, "case": case, "model": run["model"],
                "vertices": int(mesh["surface_vertices"]),
                "coarse_nodes": int(mesh["coarse_nodes"]) if run["model"] == "hybrid" else None,
                "threads": int(params.get("threads", 1)), "precision": params.get("precision", "double"),
                "domains": int(params.get("domains", 1)),
                "isa": run.get("model_report", {}).get("instruction_set", "?"),
                "median_ms": step["median_ms"], "p95_ms": step["p95_ms"], "frames": step["count"],
                "phases": phases,
                "build_s": mesh.get("build_seconds"), "peak_mib": mesh.get("process_peak_memory_mib_after_build"),
                "from_cache": mesh.get("read_from_cache"), "fine_tets": mesh["fine_tets"],
                "coarse_target": scenario.rsplit("coarse", 1)[-1],
                "build": run["build"],
            })
    return sorted(rows, key=lambda r: (r["model"], r["coarse_target"], r["precision"], r["domains"], r["threads"],
                                       r["vertices"]))


def series_key(r):
    """The series a row belongs to: model, coarse target (hybrid), precision, sweep domains (if more than
    one), threads."""
    coarse = f", coarse {r['coarse_target']}" if r["model"] == "hybrid" else ""
    domains = f", {r['domains']} domains" if r["domains"] > 1 else ""
    return f"{r['model']}{coarse}, {r['precision']}{domains}, {r['threads']} thread{'s' if r['threads'] > 1 else ''}"


def fitted_slope(points):
    """Least-squares slope of log(time) against log(vertices); None for fewer than two sizes."""
    if len(points) < 2:
        return None
    xs = [math.log(v) for v, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else None


def series(rows):
    """{series key: [row, ...] by size}."""
    out = {}
    for r in rows:
        out.setdefault(series_key(r), []).append(r)
    return out


def speedup(rows, r):
    """Median of the same case on one thread (the same sweep domains: the same numbers) / this one's (None
    for one thread or no partner)."""
    if r["threads"] == 1:
        return None
    for o in rows:
        if (o["model"], o["coarse_target"], o["precision"], o["domains"], o["vertices"], o["threads"]) == (
                r["model"], r["coarse_target"], r["precision"], r["domains"], r["vertices"], 1):
            return o["median_ms"] / r["median_ms"]
    return None


def make(exp_dir, out):
    rows = case_rows(exp_dir)
    by_series = series(rows)
    slopes = {k: (fitted_slope([(r["vertices"], r["median_ms"]) for r in v]),
                  fitted_slope([(r["vertices"], r["median_ms"]) for r in v if r["vertices"] >= 9000]))
              for k, v in by_series.items()}
    phase_names = ["coarse_solve", "mapping", "projection", "integration"]
    header = ["series", "surface vertices", "median ms", "p95 ms", "p95 / median", "2 threads speed-up",
              "slope (all sizes)", "slope (>= 10k)"] + [f"{p} ms" for p in phase_names]
    table = []
    for key, members in by_series.items():
        for r in members:
            s = speedup(rows, r)
            table.append([key, r["vertices"], tables.fmt(r["median_ms"], 3), tables.fmt(r["p95_ms"], 3),
                          tables.fmt(r["p95_ms"] / r["median_ms"], 2), tables.fmt(s, 2) if s else "",
                          tables.fmt(slopes[key][0], 3) if slopes[key][0] is not None else "",
                          tables.fmt(slopes[key][1], 3) if slopes[key][1] is not None else ""] +
                         [tables.fmt(r["phases"][p], 3) if p in r["phases"] else "" for p in phase_names])
    b = rows[0]["build"]
    tables.write_table(
        os.path.join(out, "tables"), "scaling", header, table,
        "Per-frame time of step() after the 50-frame load ramp (250 frames), 10 Gauss-Seidel iterations, cube "
        "surfaces of 682 to 99 848 vertices (experiments/scaling/). Slopes: least squares of log(median) on "
        "log(vertices). 2 threads speed-up: against one thread with the same sweep domains (bitwise the same "
        "result). Domains: the PBD parameter domains (the surface bisected, each domain swept whole by one "
        "thread, then the constraints across domains). Phases: medians of Model::last_phase_times (projection: pins and sweeps; integration: "
        "eqs. 31-32, 34-35 and the displacement output). "
        f"Measured on {b.get('cpu_model', '?')} ({b.get('hardware_threads', '?')} hardware threads), "
        f"{b['build_type']} build, {b['compiler']}, commit {b['git_commit']}; vector instructions "
        f"{sorted(set(r['isa'] for r in rows))}.")
    meshes = {}
    for r in rows:
        meshes.setdefault((r["vertices"], r["coarse_target"]), r)
    tables.write_table(
        os.path.join(out, "tables"), "scaling_mesh",
        ["surface vertices", "coarse target", "coarse nodes", "fine tets", "build s", "process peak MiB after build"],
        [[v, t, r["coarse_nodes"] or "", r["fine_tets"], tables.fmt(r["build_s"], 1) if r["build_s"] else "",
          tables.fmt(r["peak_mib"], 0) if r["peak_mib"] else ""] for (v, t), r in sorted(meshes.items())],
        "Hybrid mesh built from the cube surface (TetGen without a volume bound, coverage selection, coarse TetGen, "
        "control points), each size in its own process with the mesh cache off (scripts/scaling); the peak is the "
        "process's after the build (the second coarse target of a size is built while the first is held).")

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5), sharey=True)
    for ax, model in zip(axes, ["pbd", "hybrid"]):
        for key, members in by_series.items():
            if members[0]["model"] != model:
                continue
            v = [r["vertices"] for r in members]
            t = [r["median_ms"] for r in members]
            slope = slopes[key][0]
            ax.plot(v, t, marker="o", label=f"{key.split(', ', 1)[1]} (slope {slope:.2f})" if slope else key)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("surface vertices")
        ax.set_title(f"{model}: per-frame time, 10 iterations")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("median ms per frame")
    fig.tight_layout()
    os.makedirs(os.path.join(out, "figures"), exist_ok=True)
    fig.savefig(os.path.join(out, "figures", "scaling.png"), dpi=150)
    plt.close(fig)


if __name__ == "__main__":
    make(sys.argv[1] if len(sys.argv) > 1 else "results/scaling", sys.argv[2] if len(sys.argv) > 2 else "results")
    print("scaling tables and figure written")
