"""tissuebench.read_results(folder): an experiment's results folder, as `tissuebench run`
writes it (<out>/<experiment>/: experiment.json, <scenario>/<case>/run.json,
timings.json, top_surface.csv ...), as pandas DataFrames. Read with the analysis's
own index and metrics (analysis/results_index.py, analysis/metrics.py), so a table
made here agrees with the committed ones.
"""
import sys
from dataclasses import dataclass

from ._paths import ANALYSIS_DIR  # written by the build (python/CMakeLists.txt): the repository's analysis/


def _results_index():
    """analysis/results_index.py, which imports its neighbours (metrics) by name."""
    if ANALYSIS_DIR not in sys.path:
        sys.path.append(ANALYSIS_DIR)
    import results_index
    return results_index


@dataclass
class Results:
    """What read_results returns.

    name, description, reference: the experiment's (experiment.json; reference None
    when it declares none)
    cases:   one row per case listed or found: scenario, case, model, dynamic, frames,
             steady_frame, reached_steady_state, max_displacement_m, setup_ms,
             step_median_ms, step_p95_ms (every frame), step_after_ramp_median_ms,
             peak_memory_mib, error (the runner's message for a failed case, else None;
             a failed case has no other value)
    metrics: one row per case and its scenario's reference (not the reference itself):
             scenario, case, reference, corr_uz, corr_mag, rel_l2, max_error (m),
             load_ratio, on the observed vertices (top_surface.csv; metrics.compare)
    frames:  one row per frame of every case: scenario, case, frame, step_ms,
             solver_iterations (timings.json)
    """
    name: str
    description: str
    reference: object
    cases: object
    metrics: object
    frames: object


def read_results(folder):
    """The results folder of one experiment (e.g. results/paper, runs/small) as Results.
    Raises tissuebench.Error, one line naming the folder, when it holds no results."""
    import pandas as pd

    from ._tissuebench import Error
    index = _results_index()
    try:
        e = index.Experiment(folder)
    except index.ResultsError as err:
        raise Error(str(err)) from None
    cases, metrics, frames = [], [], []
    for scenario, listed in e.listed_cases.items():
        for case in listed:
            error = e.failure(scenario, case)
            if error is not None and case not in e.scenarios.get(scenario, {}):
                cases.append({"scenario": scenario, "case": case, "error": error})
    for scenario, found in e.scenarios.items():
        for case, c in found.items():
            run, timings = c["run"], c["timings"]
            cases.append({
                "scenario": scenario, "case": case, "model": run["model"], "dynamic": run["dynamic"],
                "frames": run["frames"], "steady_frame": run["steady_frame"],
                "reached_steady_state": run["reached_steady_state"],
                "max_displacement_m": run["max_displacement_m"], "setup_ms": timings["setup_ms"],
                "step_median_ms": timings["step"]["median_ms"], "step_p95_ms": timings["step"]["p95_ms"],
                "step_after_ramp_median_ms": timings["step_after_ramp"]["median_ms"],
                "peak_memory_mib": timings.get("peak_memory_mib"), "error": None})
            for frame, (ms, iterations) in enumerate(zip(timings["step_ms_per_frame"],
                                                         timings["solver_iterations_per_frame"])):
                frames.append({"scenario": scenario, "case": case, "frame": frame, "step_ms": ms,
                               "solver_iterations": iterations})
            if e.reference and case != e.reference and e.reference in found:
                metrics.append({"scenario": scenario, "case": case, "reference": e.reference,
                                **e.metrics(scenario, case)})
    order = ["scenario", "case", "model", "dynamic", "frames", "steady_frame", "reached_steady_state",
             "max_displacement_m", "setup_ms", "step_median_ms", "step_p95_ms", "step_after_ramp_median_ms",
             "peak_memory_mib", "error"]
    listed_order = {(s, c): k for k, (s, c) in enumerate(
        (s, c) for s, names in e.listed_cases.items() for c in names)}
    cases.sort(key=lambda row: listed_order.get((row["scenario"], row["case"]), len(listed_order)))
    return Results(
        name=e.name, description=e.description, reference=e.reference,
        cases=pd.DataFrame(cases, columns=order),
        metrics=pd.DataFrame(metrics, columns=["scenario", "case", "reference", "corr_uz", "corr_mag", "rel_l2",
                                               "max_error", "load_ratio"]),
        frames=pd.DataFrame(frames, columns=["scenario", "case", "frame", "step_ms", "solver_iterations"]))
