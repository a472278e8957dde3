#!/usr/bin/python3
"""Writes the scenario files of the reference-convergence study
(docs/reference_convergence.md) and experiments/reference_convergence.json, which
lists them.

Every scenario is the paper's cube (it extends experiments/scenarios/cube-pull.json
through ref.base.json: same surface, TetGen bounds, material, support, and what it
changes is all the file says), refined `refine_levels` times (the
surface's triangles split in four per level, the volume bound / 8), under the
paper's point force or the same force as a uniform traction on a 5 mm disc, as
one static solve (no ramp). Cases: the linear FEM with P1 and P2 elements and
the neo-Hookean FEM with P1, all distributed (mpirun -np N), on these levels:

  1 N           P1 (linear)   P2 (linear)   P1 neo-Hookean
  pull, point   0 1 2 3       0 1           0 1
  pull, disc    0 1 2         0 1           0
  push, point   0 1 2         0             0
  push, disc    0             0             0
  0.1 N: the neo-Hookean cases and their linear P1 counterparts.

Level 3 (10.3 million tets, 4.87 million P1 dofs) is the study's >= 10^6-dof solve.
Scenarios are listed, and run, level by level.

Planned but dropped when the study was first run (2 cores shared with other
jobs at a load average near 7, about 100 minutes of wall time for the study),
judged from the smaller levels:
- P2 on level 2 (about 4.9 million dofs, as many as P1 on level 3 with about
  twice the matrix entries per row): P2 on level 1 (612,255 dofs) took 20 s
  assembly, 17 s AMG setup and 61 s of CG (108 iterations) at 1.9 GiB with one
  rank; level 2 would be about 8x that per case.
- The neo-Hookean on level 2 (planned for the disc loads and the 1 N point
  pull) and on level 1 except the point pulls: on level 0 (9342 dofs) the 1 N
  point pull took 37 Newton iterations (547 CG iterations, an AMG setup per
  Newton step) in 10.2 s, on level 1 over 5 minutes under that load; level 2
  would take of the order of an hour per case.
- Level 3 under the disc load and pushed, level 2 pushed under the disc, P2 on
  level 1 pushed, and level 1 pushed under the disc (used by nothing once the
  neo-Hookean level 1 push went): each level-3 solve takes tens of minutes here
  and the one that stays (the point pull, np 1 and 2) is the one the study set out
  to run and table 1 compares with. The disc load's finest solves are P1 on level
  2 and P2 on level 1 (605,541 and 612,255 dofs).

"""
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))

# Levels of each case per (direction, load), at 1 N; 0.1 N: the neo-Hookean ones.
P1_LEVELS = {("pull", "point"): [0, 1, 2, 3], ("pull", "disc"): [0, 1, 2], ("push", "point"): [0, 1, 2],
             ("push", "disc"): [0]}
P2_LEVELS = {("pull", "point"): [0, 1], ("pull", "disc"): [0, 1], ("push", "point"): [0], ("push", "disc"): [0]}
NEO_LEVELS = {("pull", "point"): [0, 1], ("pull", "disc"): [0], ("push", "point"): [0], ("push", "disc"): [0]}
DISC_RADIUS = 0.005  # m
CG_TOLERANCE = 1e-10
# Load increments of the neo-Hookean solve (halved on a failed Newton solve).
NEO_LOAD_STEPS = {1.0: 10, 0.1: 2}


def case(name, parameters):
    return {"name": name, "model": "fem_distributed", "parameters": dict({"cg_tolerance": CG_TOLERANCE}, **parameters)}


# What every reference scenario changes in the paper's cube (ref.base.json): one
# static solve, no ramp; the steady-state tolerance back to its default (null
# removes cube-pull.json's value).
BASE = {
    "extends": "../cube-pull.json",
    "description": "The reference scenarios' common settings (ref-L*.json extend it): the paper's cube "
    "(cube-pull.json) as one static solve, no load ramp",
    "load": {"ramp_frames": 0},
    "frames": {"max": 1, "static": 1, "steady_tolerance": None},
}


def scenario(level, direction, force, load):
    sign = "pull" if direction > 0 else "push"
    tag = "" if force == 1.0 else "-%gN" % force
    s = {"extends": "ref.base.json", "name": "ref-L%d-%s-%s%s" % (level, sign, load, tag)}
    s["description"] = (
        "Reference convergence (docs/reference_convergence.md): the paper's cube refined %d times, %g N %s (%s) at the top centre%s"
        % (level, force, sign, "+z" if direction > 0 else "-z", ", a uniform traction on a %g mm disc" % (1000 * DISC_RADIUS) if load == "disc" else "")
    )
    s["mesh"] = {"refine_levels": level}
    s["load"] = {"force": [0, 0, direction * force]}
    if load == "disc":
        s["load"]["disc_radius"] = DISC_RADIUS
    key = ("pull" if direction > 0 else "push", load)
    models = [case("fem-p1", {"degree": 1})]
    if force == 1.0 and level in P2_LEVELS[key]:
        models.append(case("fem-p2", {"degree": 2}))
    if level in NEO_LEVELS[key]:
        models.append(case("neo-p1", {"degree": 1, "material_law": "neo_hookean", "load_steps": NEO_LOAD_STEPS[force]}))
    s["models"] = models
    return s


def write(path, j):
    with open(path, "w") as f:
        json.dump(j, f, indent=2)
        f.write("\n")


def main():
    write(os.path.join(HERE, "ref.base.json"), BASE)
    files = []
    for level in range(4):
        for force in (1.0, 0.1):
            for direction in (1, -1):
                for load in ("point", "disc"):
                    key = ("pull" if direction > 0 else "push", load)
                    if level not in (P1_LEVELS[key] if force == 1.0 else NEO_LEVELS[key]):
                        continue  # at 0.1 N only the neo-Hookean comparison
                    s = scenario(level, direction, force, load)
                    name = s["name"] + ".json"
                    write(os.path.join(HERE, name), s)
                    files.append("scenarios/reference/" + name)
    experiment = {
        "name": "reference_convergence",
        "description": "The fine FEM reference under refinement (P1, P2), point and disc loads, linear and "
        "neo-Hookean; written by experiments/scenarios/reference/generate.py, run by scripts/reference_convergence; docs/reference_convergence.md",
        "scenarios": files,
    }
    write(os.path.join(ROOT, "experiments", "reference_convergence.json"), experiment)
    print("%d scenario files" % len(files))


if __name__ == "__main__":
    main()
