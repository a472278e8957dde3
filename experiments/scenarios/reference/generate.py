#!/usr/bin/python3
"""Writes the scenario files of the reference-convergence study (issue 13) and
experiments/reference_convergence.json, which lists them.

Every scenario is the paper's cube (experiments/scenarios/cube-pull.json: same
surface, TetGen bounds, material, support), refined `refine_levels` times (the
surface's triangles split in four per level, the volume bound / 8), under the
paper's point force or the same force as a uniform traction on a 5 mm disc, as
one static solve (no ramp). Cases: the linear FEM with P1 and P2 elements and
the neo-Hookean FEM with P1, all distributed (mpirun -np N): P1 on levels 0-3
(level 3: 10.3 million tets, the >= 10^6-dof solve), P2 and the neo-Hookean on
levels 0-1. The 0.1 N scenarios stop at level 1.

Dropped when the study was first run (2 shared, heavily loaded cores, about
100 minutes of wall time for the whole study), judged from the smaller levels:
- P2 on level 2 (planned; about 4.9 million dofs, as many as P1 on level 3 with
  about twice the matrix entries per row): P2 on level 1 (612,255 dofs) took
  20 s assembly, 17 s AMG setup and 61 s of CG (108 iterations) at 1.9 GiB, so
  level 2 would need about 8x that per case, six cases (pull/push, point/disc,
  np 1 and 2), and likely more memory than the machine has beside P1 level 3.
- The neo-Hookean on level 2 (planned for the disc loads and the 1 N point
  pull): on level 0 (9342 dofs) the 1 N point pull took 37 Newton iterations
  (547 CG iterations, an AMG setup per Newton step) in 10.2 s; level 2 has about
  64x the dofs, so each of the five cases would take of the order of an hour.
- Level 3 runs last (pull before push) so that what does not fit is the last
  to go.

Run it again after editing; the files are committed as written.
"""
import copy
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))

LEVELS = [0, 1, 2, 3]
P2_LEVELS = [0, 1]
NEO_LEVELS = [0, 1]  # all loads
NEO_LEVEL_2 = []  # none: see the docstring
DISC_RADIUS = 0.005  # m
CG_TOLERANCE = 1e-10
# Load increments of the neo-Hookean solve (halved on a failed Newton solve).
NEO_LOAD_STEPS = {1.0: 10, 0.1: 2}


def case(name, parameters):
    return {"name": name, "model": "fem_distributed", "parameters": dict({"cg_tolerance": CG_TOLERANCE}, **parameters)}


def scenario(base, level, direction, force, load):
    s = copy.deepcopy(base)
    sign = "pull" if direction > 0 else "push"
    tag = "" if force == 1.0 else "-%gN" % force
    s["name"] = "ref-L%d-%s-%s%s" % (level, sign, load, tag)
    s["description"] = (
        "Reference convergence (issue 13): the paper's cube refined %d times, %g N %s (%s) at the top centre%s"
        % (level, force, sign, "+z" if direction > 0 else "-z", ", a uniform traction on a %g mm disc" % (1000 * DISC_RADIUS) if load == "disc" else "")
    )
    s["mesh"]["refine_levels"] = level
    s["load"] = {"point": [0, 0, 0.1], "force": [0, 0, direction * force], "ramp_frames": 0}
    if load == "disc":
        s["load"]["disc_radius"] = DISC_RADIUS
    s["frames"] = {"max": 1, "static": 1}
    models = []
    if force == 1.0:
        models.append(case("fem-p1", {"degree": 1}))
        if level in P2_LEVELS:
            models.append(case("fem-p2", {"degree": 2}))
    else:
        models.append(case("fem-p1", {"degree": 1}))
    if level in NEO_LEVELS or (level == 2 and (load, force, direction) in NEO_LEVEL_2):
        models.append(case("neo-p1", {"degree": 1, "material_law": "neo_hookean", "load_steps": NEO_LOAD_STEPS[force]}))
    s["models"] = models
    return s


def main():
    base = json.load(open(os.path.join(ROOT, "experiments", "scenarios", "cube-pull.json")))
    files = []
    # Level 3 last (pull before push): the study runs the scenarios in this order.
    for group in ([lv for lv in LEVELS if lv < 3], [lv for lv in LEVELS if lv >= 3]):
        for force in (1.0, 0.1):
            for direction in (1, -1):
                for load in ("point", "disc"):
                    for level in group:
                        neo = level in NEO_LEVELS or (level == 2 and (load, force, direction) in NEO_LEVEL_2)
                        if force != 1.0 and not neo:
                            continue  # at 0.1 N only the neo-Hookean comparison
                        s = scenario(base, level, direction, force, load)
                        name = s["name"] + ".json"
                        with open(os.path.join(HERE, name), "w") as f:
                            json.dump(s, f, indent=2)
                            f.write("\n")
                        files.append("scenarios/reference/" + name)
    experiment = {
        "name": "reference_convergence",
        "description": "Issue 13: the fine FEM reference under refinement (P1, P2), point and disc loads, linear and "
        "neo-Hookean; written by experiments/scenarios/reference/generate.py, run by scripts/reference_convergence",
        "scenarios": files,
    }
    with open(os.path.join(ROOT, "experiments", "reference_convergence.json"), "w") as f:
        json.dump(experiment, f, indent=2)
        f.write("\n")
    print("%d scenario files" % len(files))


if __name__ == "__main__":
    main()
