"""Two threads against one, from interleaved benchmark repetitions (docs/scaling.md,
docs/realtime_nonlinear.md).

Usage: /usr/bin/python3 analysis/thread_speedup.py [results/benchmarks/thread_speedup.json] [results]
Reads a Google Benchmark JSON with repetitions randomly interleaved (scripts/thread_speedup:
BM_PbdFrameScaling and BM_HybridFrameScaling; scripts/nonlinear_speedup: BM_NonlinearStepperFrame)
and writes, for the frame-scaling benchmarks, results/tables/thread_speedup.{csv,md}: per series
(model, coarse mesh, precision, domains) and surface size, the median and the minimum frame time
of the repetitions at 1 and 2 threads, their coefficients of variation, and the speed-up as the
ratio of the medians and of the minima. The VM's second CPU is shared: two-thread repetitions
fall into a fast and a slow cluster (20-30 % apart), so the medians' ratio depends on how many
land in the slow one, and the minima's ratio says what the code does when both CPUs are its own.
For the real-time nonlinear steppers the same, per solver and tet count, into
results/tables/nonlinear_thread_speedup.{csv,md}, a repetition's time being its median frame
(the benchmark's p50_ms counter); and the cost's log-log slope against the tets, least squares
over the sizes of a series, into results/tables/nonlinear_cost_slope.{csv,md}.
"""
import json
import math
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import table_io as tables  # noqa: E402

TARGET = 1.7  # the scaling study's target: two threads at least 1.7 x one thread at 10 000 vertices and above
SLOPE_TARGET = 1.1  # the real-time nonlinear steppers' cost against the tets: fitted slope at most this
MODELS = {"BM_PbdFrameScaling": "pbd", "BM_HybridFrameScaling": "hybrid", "BM_NonlinearStepperFrame": "nonlinear"}
# BM_NonlinearStepperFrame's first argument (experiments/benchmarks/model_benchmarks.cc) and what
# its `work` counts for each.
NONLINEAR_SOLVERS = {0: ("vbd", "sweep"), 1: ("xpbd", "sub-step"), 2: ("pd quasi-Newton", "iteration"),
                     3: ("pd local-global", "iteration"), 4: ("vbd, scalar kernels", "sweep")}


def parse_name(run_name):
    """('pbd' | 'hybrid', {argument: int}) of a frame-scaling benchmark's run name, or None."""
    parts = run_name.split("/")
    if parts[0] not in MODELS:
        return None
    args = {}
    for p in parts[1:]:
        if ":" in p:
            key, value = p.split(":", 1)
            args[key] = int(value)
    return MODELS[parts[0]], args


def nonlinear_label(args):
    """A BM_NonlinearStepperFrame series: solver, work a frame, node order."""
    solver, unit = NONLINEAR_SOLVERS.get(args["xpbd"], (f"solver {args['xpbd']}", "unit"))
    work = args["work"]
    label = f"{solver}, {work} {unit}{'s' if work != 1 else ''}"
    if args["xpbd"] == 1 and work == 1:
        label += " of 1 ms"  # the benchmark's one sub-step is a 1 ms step (model_benchmarks.cc)
    return label + ("" if args.get("zorder", 1) else ", TetGen's order")


def repetitions(benchmarks, family="frame_scaling"):
    """{(series, size): {threads: {repetition index: ms}}} of the individual repetitions
    (aggregates skipped). family "frame_scaling": series = (model, coarse target or None,
    precision, domains), size its surface vertices, time the repetition's mean frame;
    "nonlinear": series its nonlinear_label, size the tets, time its median frame (p50_ms)."""
    runs = {}
    for b in benchmarks:
        if b.get("run_type") != "iteration":
            continue
        parsed = parse_name(b["run_name"])
        if parsed is None or (parsed[0] == "nonlinear") != (family == "nonlinear"):
            continue
        model, args = parsed
        if b.get("time_unit") != "ms":
            raise ValueError(f"{b['name']}: time unit {b.get('time_unit')}, expected ms")
        if family == "nonlinear":
            if "p50_ms" not in b:
                raise ValueError(f"{b['name']}: no p50_ms counter (a benchmark built before it was added)")
            key = (nonlinear_label(args), int(b["tets"]))
            ms = float(b["p50_ms"])
        else:
            key = ((model, args.get("coarse"), "single" if args["single"] else "double", args["domains"]),
                   int(b["surface_vertices"]))
            ms = float(b["real_time"])
        by_rep = runs.setdefault(key, {}).setdefault(args["threads"], {})
        by_rep[int(b.get("repetition_index", 0))] = ms
    return runs


def cv(values):
    return statistics.pstdev(values) / statistics.mean(values) if len(values) > 1 else 0.0


def series_label(series):
    if isinstance(series, str):
        return series
    model, coarse, precision, domains = series
    return f"{model}" + (f", coarse {coarse}" if coarse else "") + f", {precision}, {domains} domains"


def slope(sizes, times):
    """The least-squares slope of log(time) against log(size)."""
    x = [math.log(v) for v in sizes]
    y = [math.log(t) for t in times]
    mx, my = statistics.mean(x), statistics.mean(y)
    return sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)


def slope_rows(runs):
    """Per series with three or more sizes: the fitted slope of the median time on 1 and 2 threads."""
    by_series = {}
    for (series, size), by_threads in runs.items():
        by_series.setdefault(series_label(series), {})[size] = by_threads
    rows = []
    for label, sizes in sorted(by_series.items()):
        if len(sizes) < 3:
            continue
        row = [label, ", ".join(str(v) for v in sorted(sizes))]
        for threads in (1, 2):
            points = [(v, statistics.median(t[threads].values())) for v, t in sorted(sizes.items()) if threads in t]
            row.append(tables.fmt(slope(*zip(*points)), 2) if len(points) >= 3 else "")
        row.append("yes" if all(r and float(r) <= SLOPE_TARGET for r in row[2:4]) else "no")
        rows.append(row)
    return rows


def rows_of(runs):
    rows = []
    for (series, vertices), by_threads in sorted(runs.items(), key=lambda kv: (series_label(kv[0][0]), kv[0][1])):
        if 1 not in by_threads or 2 not in by_threads:
            continue
        one, two = list(by_threads[1].values()), list(by_threads[2].values())
        m1, m2 = statistics.median(one), statistics.median(two)
        rows.append([series_label(series), vertices, len(one), tables.fmt(m1), tables.fmt(min(one)),
                     tables.fmt(cv(one), 3), tables.fmt(m2), tables.fmt(min(two)), tables.fmt(cv(two), 3),
                     tables.fmt(m1 / m2, 2), tables.fmt(min(one) / min(two), 2), "yes" if m1 / m2 >= TARGET else "no"])
    return rows


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else "results/benchmarks/thread_speedup.json"
    out = sys.argv[2] if len(sys.argv) > 2 else "results"
    try:
        with open(src) as f:
            data = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        sys.exit(f"thread_speedup: cannot read {src}: {e}")
    benchmarks = data.get("benchmarks", [])
    try:
        scaling = rows_of(repetitions(benchmarks))
        nonlinear_runs = repetitions(benchmarks, "nonlinear")
    except (KeyError, ValueError) as e:
        sys.exit(f"thread_speedup: {src}: {e}")
    nonlinear = rows_of(nonlinear_runs)
    if not scaling and not nonlinear:
        sys.exit(f"thread_speedup: {src} has no frame-scaling benchmark with both 1 and 2 threads")
    ctx = data.get("context", {})
    machine = (f"Measured {ctx.get('date', '?')} on {ctx.get('tissuebench_cpu_model', '?')} "
               f"({ctx.get('num_cpus', '?')} CPUs), {ctx.get('tissuebench_build_type', '?')} build, "
               f"{ctx.get('tissuebench_compiler', '?')}, commit {ctx.get('tissuebench_git_commit', '?')}, "
               f"load average {', '.join(tables.fmt(x, 2) for x in ctx.get('load_avg', []))} at the start.")
    columns = ["repetitions", "1 thread median ms", "1 thread min ms", "1 thread cv", "2 threads median ms",
               "2 threads min ms", "2 threads cv", "speed-up (medians)", "speed-up (minima)", f"medians >= {TARGET}x"]
    tables_dir = os.path.join(out, "tables")
    if scaling:
        notes = (f"Google Benchmark frame-scaling benchmarks (10 iterations a frame, after 20 frames of the ramped "
                 f"top-centre load), repetitions randomly interleaved so that one and two threads alternate; "
                 f"median and minimum of the repetitions' mean frame time (wall clock); speed-up: the ratio "
                 f"of the medians and of the minima (the second CPU of the VM is shared: two-thread "
                 f"repetitions fall into a fast and a slow cluster). Target {TARGET}x (docs/scaling.md, "
                 f"'Against the targets'). " + machine)
        tables.write_table(tables_dir, "thread_speedup", ["series", "surface vertices"] + columns, scaling, notes)
        print(f"thread_speedup: {len(scaling)} rows -> {os.path.join(tables_dir, 'thread_speedup.md')}")
    if nonlinear:
        notes = (f"BM_NonlinearStepperFrame (experiments/benchmarks/model_benchmarks.cc): the paper cube's fine "
                 f"volume at TetGen's volume bounds for the tet counts shown, under the 1 N pull, frames after the "
                 f"first; repetitions randomly interleaved; a repetition's time is its median frame (counter "
                 f"p50_ms, wall clock); median and minimum over the repetitions; speed-up: the ratio of the "
                 f"medians and of the minima. Target {TARGET}x (docs/realtime_nonlinear.md). " + machine)
        tables.write_table(tables_dir, "nonlinear_thread_speedup", ["series", "tets"] + columns, nonlinear, notes)
        slopes = slope_rows(nonlinear_runs)
        if slopes:
            tables.write_table(tables_dir, "nonlinear_cost_slope",
                               ["series", "tets", "slope, 1 thread", "slope, 2 threads", f"both <= {SLOPE_TARGET}"],
                               slopes, "Least-squares slope of log(median frame) against log(tets), from "
                               "nonlinear_thread_speedup's medians. " + machine)
        print(f"thread_speedup: {len(nonlinear)} rows -> {os.path.join(tables_dir, 'nonlinear_thread_speedup.md')}")


if __name__ == "__main__":
    main()
