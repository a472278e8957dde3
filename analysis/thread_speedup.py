"""Two threads against one, from interleaved benchmark repetitions (docs/scaling.md).

Usage: /usr/bin/python3 analysis/thread_speedup.py [results/benchmarks/thread_speedup.json] [results]
Reads the Google Benchmark JSON scripts/thread_speedup wrote (BM_PbdFrameScaling and
BM_HybridFrameScaling, repetitions randomly interleaved) and writes
results/tables/thread_speedup.{csv,md}: per series (model, coarse mesh, precision, domains) and
surface size, the median and the minimum frame time of the repetitions at 1 and 2 threads,
their coefficients of variation, and the speed-up as the ratio of the medians and of the
minima. The VM's second CPU is shared: two-thread repetitions fall into a fast and a slow
cluster (20-30 % apart), so the medians' ratio depends on how many land in the slow one,
and the minima's ratio says what the code does when both CPUs are its own.
"""
import json
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import table_io as tables  # noqa: E402

TARGET = 1.7  # the scaling study's target: two threads at least 1.7 x one thread at 10 000 vertices and above
MODELS = {"BM_PbdFrameScaling": "pbd", "BM_HybridFrameScaling": "hybrid"}


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


def repetitions(benchmarks):
    """{(series, vertices): {threads: {repetition index: ms}}} of the individual repetitions
    (aggregates skipped). series = (model, coarse target or None, precision, domains)."""
    runs = {}
    for b in benchmarks:
        if b.get("run_type") != "iteration":
            continue
        parsed = parse_name(b["run_name"])
        if parsed is None:
            continue
        model, args = parsed
        if b.get("time_unit") != "ms":
            raise ValueError(f"{b['name']}: time unit {b.get('time_unit')}, expected ms")
        series = (model, args.get("coarse"), "single" if args["single"] else "double", args["domains"])
        key = (series, int(b["surface_vertices"]))
        by_rep = runs.setdefault(key, {}).setdefault(args["threads"], {})
        by_rep[int(b.get("repetition_index", 0))] = float(b["real_time"])
    return runs


def cv(values):
    return statistics.pstdev(values) / statistics.mean(values) if len(values) > 1 else 0.0


def series_label(series):
    model, coarse, precision, domains = series
    return f"{model}" + (f", coarse {coarse}" if coarse else "") + f", {precision}, {domains} domains"


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
    rows = rows_of(repetitions(data.get("benchmarks", [])))
    if not rows:
        sys.exit(f"thread_speedup: {src} has no frame-scaling benchmark with both 1 and 2 threads")
    ctx = data.get("context", {})
    notes = (f"Google Benchmark frame-scaling benchmarks (10 iterations a frame, after 20 frames of the ramped "
             f"top-centre load), repetitions randomly interleaved so that one and two threads alternate; "
             f"median and minimum of the repetitions' mean frame time (wall clock); speed-up: the ratio "
             f"of the medians and of the minima (the second CPU of the VM is shared: two-thread "
             f"repetitions fall into a fast and a slow cluster). Target {TARGET}x (docs/scaling.md, 'Against the targets'). "
             f"Measured {ctx.get('date', '?')} on {ctx.get('tissuebench_cpu_model', '?')} "
             f"({ctx.get('num_cpus', '?')} CPUs), {ctx.get('tissuebench_build_type', '?')} build, "
             f"{ctx.get('tissuebench_compiler', '?')}, commit {ctx.get('tissuebench_git_commit', '?')}, "
             f"load average {', '.join(tables.fmt(x, 2) for x in ctx.get('load_avg', []))} at the start.")
    tables.write_table(os.path.join(out, "tables"), "thread_speedup",
                       ["series", "surface vertices", "repetitions", "1 thread median ms", "1 thread min ms",
                        "1 thread cv", "2 threads median ms", "2 threads min ms", "2 threads cv",
                        "speed-up (medians)", "speed-up (minima)", f"medians >= {TARGET}x"], rows, notes)
    print(f"thread_speedup: {len(rows)} rows -> {os.path.join(out, 'tables', 'thread_speedup.md')}")


if __name__ == "__main__":
    main()
