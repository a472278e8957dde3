"""The benchmark is open: a model outside the C++ tree scores from files alone.

examples/external_model/linear_fem.py (numpy, scipy) reads only the problem package
`tissuebench export` writes for two suite scenarios (the cube pulled on a disc, and
the L-block held at its base and grasped, the flap under gravity with its interior
probe), writes a submission, and `tissuebench
score` ranks it. It is the same model as the in-tree `fem` at `material: linear`
(the suite's case fem-linear), on the same mesh: its displacement at every
observation point (surface and interior) and its tool force equal the committed fem-linear run's to
rounding, and its score equals fem-linear's committed `rel L2 vs converged`
(results/tables/suite_scores.csv) to the table's three digits. So nothing the
scenario needs is missing from the package, and nothing of it is read wrongly.

Usage: external_model_test.py TISSUEBENCH SOURCE_DIR
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

CLI, SRC = sys.argv[1:3]
SCENARIOS = {"cube_pull_disc": "suite-cube-pull-disc", "l_block_grasp": "suite-l-block-grasp",
             "flap_gravity": "suite-flap-gravity"}
FAILURES = []


def check(ok, message):
    print(("ok: " if ok else "FAIL: ") + message, flush=True)
    if not ok:
        FAILURES.append(message)


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def vectors(records, key, columns):
    return {r[key]: np.array([float(r[c]) for c in columns]) for r in records}


def committed_score(role, case):
    for r in rows(os.path.join(SRC, "results", "tables", "suite_scores.csv")):
        if r["role"] == role and r["case"] == case:
            return float(r["rel L2 vs converged"])
    raise SystemExit(f"suite_scores.csv: no row {role},{case}")


def main():
    with tempfile.TemporaryDirectory(prefix="tb-external-") as tmp:
        for role, scenario in SCENARIOS.items():
            packages = os.path.join(tmp, "packages")
            subprocess.run([CLI, "export", os.path.join(SRC, "experiments", "suite.json"), "--scenario", role,
                            "--out", packages, "--quiet", "--mesh-cache", os.path.join(tmp, "cache")], check=True)
            package = os.path.join(packages, scenario)
            submission = os.path.join(tmp, "submissions", role)
            subprocess.run(["/usr/bin/python3", os.path.join(SRC, "examples", "external_model", "linear_fem.py"),
                            package, submission], check=True)
            # A fixed calibration figure: the score's times are not what is tested here.
            subprocess.run([CLI, "score", submission, "--package", package, "--calibration", "1"], check=True,
                           stdout=subprocess.DEVNULL)
            with open(os.path.join(submission, "score.json")) as f:
                score = json.load(f)
            committed = committed_score(role, "fem-linear")
            measured = score["rel_l2_converged"]
            check(float(f"{measured:.3g}") == committed,
                  f"{role}: rel L2 vs converged {measured:.6g}, fem-linear's committed {committed}")

            run = os.path.join(SRC, "results", "suite", scenario, "fem-linear")
            expected = vectors(rows(os.path.join(run, "top_surface.csv")), "vertex", ("ux", "uy", "uz"))
            expected = {f"s{v}": u for v, u in expected.items()}
            probes = os.path.join(run, "probes.csv")
            if os.path.exists(probes):  # the interior points p<n>: the last frame's row of each
                for r in rows(probes):
                    expected[f"p{r['probe']}"] = np.array([float(r[c]) for c in ("ux", "uy", "uz")])
            with open(os.path.join(package, "problem.json")) as f:
                last = json.load(f)["observation"]["frames"][-1]
            got = {r["id"]: np.array([float(r[c]) for c in ("ux", "uy", "uz")])
                   for r in rows(os.path.join(submission, "displacements.csv")) if int(r["frame"]) == last}
            common = sorted(set(expected) & set(got))
            check(len(common) == len(got) and len(common) > 100,
                  f"{role}: {len(common)} of the submission's {len(got)} points are fem-linear's observed vertices "
                  f"and probes")
            a = np.array([expected[i] for i in common])
            b = np.array([got[i] for i in common])
            relative = np.linalg.norm(a - b) / np.linalg.norm(a)
            check(relative < 1e-9, f"{role}: displacements vs fem-linear's, relative difference {relative:.2e}")

            reactions = os.path.join(run, "reactions.csv")
            if os.path.exists(reactions):
                tool_rows = [r for r in rows(reactions) if r["constraint"].startswith("tools[")]
                final = max(int(r["frame"]) for r in tool_rows)
                expected_force = vectors([r for r in tool_rows if int(r["frame"]) == final], "constraint",
                                         ("fx", "fy", "fz"))
                got_force = vectors(rows(os.path.join(submission, "forces.csv")), "tool", ("fx", "fy", "fz"))
                for k, force in enumerate(expected_force.values()):
                    mine = got_force[f"tool_{k}"]
                    difference = np.linalg.norm(mine - force) / np.linalg.norm(force)
                    check(difference < 1e-9, f"{role}: tool_{k} force {mine.tolist()} vs fem-linear's "
                                             f"{force.tolist()}, relative difference {difference:.2e}")
    print(f"external_model: {len(FAILURES)} failure(s)")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
