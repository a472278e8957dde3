#!/usr/bin/python3
"""From Python: sweep one model's parameter on a suite scenario, plot its error against
its time per frame, and score a model written in Python, in one script.

    export PYTHONPATH=$PWD/build/python
    /usr/bin/python3 examples/python/sweep_and_score.py OUT [--frames 100]

1. The sweep: projective dynamics (`pd`, the suite's case) on the pulled cube
   (experiments/suite.json, role cube_pull_disc) at 1, 2, 5 and 10 iterations a frame,
   each run with `tissuebench.Run` for --frames frames; its error is the relative L2 of
   its displacement at the role's observation points against the converged answer
   (analysis/observation_points.py score_observations; on this mesh the points are
   surface vertices s<v>, read directly), its time the median of the runner's own
   per-frame timing (`run.step_ms`). Writes OUT/sweep.csv and OUT/sweep.png (log-log).
2. The Python model: the role's problem package (`tissuebench export`), the numpy
   linear FEM of examples/external_model/linear_fem.py run on it, and `tissuebench
   score`: writes OUT/submission/ with its score.json.
Prints one line per step; tests/python/test_examples.py runs it and checks its output.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

import tissuebench  # before numpy: it chooses OpenBLAS's kernels as the program does

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import observation_points  # noqa: E402

ROLE = "cube_pull_disc"
ITERATIONS = [1, 2, 5, 10]


def error_at_points(run, ids):
    """The relative L2 against the converged field at the role's points (vertices of this mesh)."""
    values = run.displacement[[int(i[1:]) for i in ids]]
    return observation_points.score_observations(ROLE, values)["rel_l2_converged"]


def sweep(frames):
    rows = []
    ids = observation_points.read_role(ROLE)["surface"]["id"]
    for iterations in ITERATIONS:
        experiment = tissuebench.load(os.path.join(ROOT, "experiments", "suite.json"),
                                      overrides={"models.pd.parameters.iterations": iterations,
                                                 "frames.max": frames})
        run = tissuebench.Run(experiment.scenario(ROLE), "pd")
        run.run()
        row = {"iterations": iterations, "frames": run.frames, "median_ms": float(np.median(run.step_ms)),
               "rel_l2_converged": error_at_points(run, ids)}
        print(f"sweep: pd, {iterations} iteration(s): {row['frames']} frames, median {row['median_ms']:.3f} ms, "
              f"rel L2 vs converged {row['rel_l2_converged']:.4f}", flush=True)
        rows.append(row)
    return rows


def plot(rows, path, frames):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.loglog([r["median_ms"] for r in rows], [r["rel_l2_converged"] for r in rows], "o-")
    for r in rows:
        ax.annotate(f"{r['iterations']} it", (r["median_ms"], r["rel_l2_converged"]), textcoords="offset points",
                    xytext=(4, 4))
    ax.set_xlabel("median frame time (ms)")
    ax.set_ylabel("relative L2 vs the converged field")
    ax.set_title(f"pd on {ROLE}, after {frames} frames")
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def score_python_model(cli, out):
    packages = os.path.join(out, "packages")
    subprocess.run([cli, "export", os.path.join(ROOT, "experiments", "suite.json"), "--scenario", ROLE,
                    "--out", packages, "--quiet"], check=True)
    package = os.path.join(packages, "suite-cube-pull-disc")
    submission = os.path.join(out, "submission")
    subprocess.run([sys.executable, os.path.join(ROOT, "examples", "external_model", "linear_fem.py"), package,
                    submission], check=True)
    subprocess.run([cli, "score", submission, "--package", package, "--calibration", "100"], check=True,
                   stdout=subprocess.DEVNULL)
    with open(os.path.join(submission, "score.json")) as f:
        score = json.load(f)
    print(f"score: {score['method']}: rel L2 vs converged {score['rel_l2_converged']:.4f}", flush=True)
    return score


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", help="folder for sweep.csv, sweep.png and the submission")
    parser.add_argument("--frames", type=int, default=100, help="frames each pd run steps (default 100)")
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "experiments", "tissuebench"),
                        help="the tissuebench program (default the build's)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = sweep(args.frames)
    with open(os.path.join(args.out, "sweep.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    plot(rows, os.path.join(args.out, "sweep.png"), args.frames)
    score_python_model(args.cli, args.out)


if __name__ == "__main__":
    try:
        main()
    except tissuebench.Error as e:
        sys.exit(f"sweep_and_score: {e}")
