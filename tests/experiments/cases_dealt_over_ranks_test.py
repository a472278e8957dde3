"""Cases dealt out over MPI ranks (docs/usage.md, "Many cases over MPI ranks").

`mpirun -n 2 tissuebench run tests/experiments/mpi_dealt.json` against one process:
each case dealt to one rank is written by that rank alone and is byte for byte the
one-process result (every file but timings.json and run.json, which hold times and
the machine); the distributed FEM, run by both ranks together, agrees to 1e-8; both
ranks wrote cases; the case that fails (the hybrid with exact_fine_fem control points takes no grasp) is
reported by rank 0's summary and leaves its .failed.json, and the other cases of
its rank still run; no staging folder is left.

Usage: cases_dealt_over_ranks_test.py MPIEXEC TISSUEBENCH SOURCE_DIR
"""
import filecmp
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

mpiexec, cli, source = sys.argv[1:4]
experiment = os.path.join(source, "tests", "experiments", "mpi_dealt.json")
DEALT = ["fem", "embedded", "pbd", "hybrid", "vbd"]
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)


with tempfile.TemporaryDirectory() as tmp:
    runs = {}
    for ranks in (1, 2):
        command = ([mpiexec, "-n", "2"] if ranks == 2 else []) + [
            cli, "run", experiment, "--out", os.path.join(tmp, f"np{ranks}"),
            "--mesh-cache", os.path.join(tmp, f"cache{ranks}")]
        runs[ranks] = subprocess.run(command, capture_output=True, text=True, timeout=600)
        # One case fails (hybrid-exact): the exit status says so, rank 0's summary counts it.
        check(runs[ranks].returncode != 0, f"np{ranks}: exit status 0 though a case failed")
        check("6 of 7 cases written" in runs[ranks].stderr,
              f"np{ranks}: no '6 of 7 cases written' in stderr:\n{runs[ranks].stderr}")
    folder = {n: os.path.join(tmp, f"np{n}", "mpi-dealt", "mpi-dealt") for n in (1, 2)}
    check(os.path.exists(os.path.join(folder[2], "hybrid-exact.failed.json")), "np2: no hybrid-exact.failed.json")
    check(os.path.exists(os.path.join(folder[2], "mesh", "summary.json")), "np2: the mesh folder was not written")
    writers = set()
    for case in DEALT:
        timings = json.load(open(os.path.join(folder[2], case, "timings.json")))
        processes = timings["processes"]
        check(processes["ranks"] == 1 and processes["processes"] == 2,
              f"{case}: timings.json processes {processes}, expected one rank of two")
        writers.add(processes["dealt_to_process"])
        check(timings["peak_memory_mib"] > 0, f"{case}: peak memory {timings['peak_memory_mib']}")
        names = sorted(os.listdir(os.path.join(folder[1], case)))
        check(names == sorted(os.listdir(os.path.join(folder[2], case))), f"{case}: different files")
        for name in names:
            if name in ("timings.json", "run.json"):
                continue
            same = filecmp.cmp(os.path.join(folder[1], case, name), os.path.join(folder[2], case, name), shallow=False)
            check(same, f"{case}/{name}: differs between one process and a rank of two")
        print(f"{case}: dealt to rank {processes['dealt_to_process']}, files identical to one process")
    check(writers == {0, 1}, f"the dealt cases were written by ranks {sorted(writers)}, not by both")
    fields = [np.genfromtxt(os.path.join(folder[n], "fem-distributed", "surface.csv"), delimiter=",",
                            skip_header=1)[:, 4:7] for n in (1, 2)]
    difference = np.linalg.norm(fields[1] - fields[0]) / np.linalg.norm(fields[0])
    print(f"fem-distributed: two ranks together against one, relative difference {difference:.2e}")
    check(difference < 1e-8, f"fem-distributed: np 2 differs from np 1 by {difference:.2e}")
    ranks = json.load(open(os.path.join(folder[2], "fem-distributed", "timings.json")))["processes"]["ranks"]
    check(ranks == 2, f"fem-distributed: timings.json says {ranks} ranks, expected 2 (run together)")
    left = [os.path.join(d, f) for d, subdirs, files in os.walk(tmp) for f in subdirs + files
            if ".tmp" in f or ".old" in f]
    check(not left, f"staging folders left: {left}")

for failure in failures:
    print("FAILED:", failure)
sys.exit(1 if failures else 0)
