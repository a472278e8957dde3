#!/usr/bin/python3
"""Writes the scenario files of the suite-reference convergence study
(docs/reference_convergence.md, "Every suite scenario") and
experiments/suite_reference_convergence.json, which lists them.

Each file is one suite scenario's reference problem (it extends the suite's
scenario file: same mesh recipe, material, support, loads, tools, probes and
observed vertices) on one refinement level with one element order, solved by
Newton on the neo-Hookean law (Bonet and Wood 2008, eq. 6.28) as one static
solve at the full load (no ramp: a hyperelastic static equilibrium does not
depend on the load path; the Newton solve takes its own load increments and
halves them when it fails). Level L: the surface's triangles split in four L
times, TetGen's volume bound divided by 8^L (experiments/mesh_recipe.cc); the
level-0 surface vertices stay, so every level is compared on them.

Solvers:
- fem_distributed (deal.II, Trilinos CG + ML AMG, MPI), P1 and P2, on every
  scenario. The liver and the flap (under gravity) were solved by the serial
  Newton (`fem`, solver newton, CHOLMOD; P1 levels 0 and 1 only) until
  fem_distributed took a body force; its level 1 was checked against the serial
  level 1 (docs/reference_convergence.md); case() keeps the serial solver for a
  role marked "serial".

Meshes read from files or generated with no volume bound (the liver, the
torus, the L-block: TetGen's quality bound alone) would only refine near the
surface: splitting the surface's triangles leaves the interior tets nearly as
large (the liver's level 1: 4.3x the nodes with no bound). Their levels >= 1
therefore get a volume bound of VOLUME_BOUND (the level-0 mesh's 95th
percentile tet volume, measured on the suite's mesh) / 8^L; level 0 keeps no
bound, so it is the suite's mesh (the same nodes and tets). Measured node
ratios level 1 / level 0: liver 5.7, torus 6.0, L-block 5.8 (8 would be an
exact halving of h).

The palpation (cube_palpation) runs its 31 frames as the suite does (PATH_DEPENDENT),
with the serial Newton, the only solver with the sphere's contact. Its level 1 takes
about 11 minutes since the contact's curvature is a low-rank downdate of the law's
supernodal factor (docs/equations.md); before, with an LDL^T factorisation wherever
the curvature made the tangent indefinite, it did not finish in 90 minutes, by this
route nor by implicit Euler held until settled (docs/reference_convergence.md).

What was planned and dropped, with its measured or estimated cost, is listed in
the doc's section.
"""
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))

CG_TOLERANCE = 1e-10

# role: (suite file, solver, P1 levels, P2 levels, load increments, level-0 fine
# nodes (the suite's mesh, for the estimated dofs that order the runs))
SCENARIOS = {
    "cube_pull_disc": ("cube-pull-disc.json", "distributed", [0, 1, 2], [0, 1], 5, 3114),
    # P2 under the push: level 0 did not finish (stopped after 552 s; the pull's took 79 s), so no level 1.
    "cube_push_disc": ("cube-push-disc.json", "distributed", [0, 1, 2], [0], 5, 3114),
    # P2 level 1 of the 5 % compression (about 1.4x10^6 dofs, 2 ranks): the study's one
    # solve above 10^6 dofs, and the only second P2 level at nu = 0.499.
    "truth_cube_5": ("truth-cube-05.json", "distributed", [0], [0, 1], 2, 7668),
    "truth_cube_12_5": ("truth-cube-125.json", "distributed", [0, 1], [0], 4, 7668),
    "truth_cube_18_25": ("truth-cube-1825.json", "distributed", [0, 1], [0], 5, 7668),
    "liver_grasp_gravity": ("liver-grasp-gravity.json", "distributed", [0, 1, 2], [0, 1], 10, 3404),
    "flap_gravity": ("flap-gravity.json", "distributed", [0, 1, 2], [0, 1], 10, 2297),
    "torus_grasp": ("torus-grasp.json", "distributed", [0, 1, 2], [0, 1], 4, 1067),
    "l_block_grasp": ("l-block-grasp.json", "distributed", [0, 1, 2], [0, 1], 4, 922),
    # The palpation: Newton's contact is in the serial solver only (sphere_obstacles.h),
    # and its answer depends on the path (a fold of the drag), so its frames are kept.
    "cube_palpation": ("cube-palpation.json", "serial", [0, 1], [], None, 3114),
}
# Scenarios solved along their frames as the suite runs them, not as one static solve
# at the full load: a contact path whose equilibrium past a fold depends on the path.
PATH_DEPENDENT = ("cube_palpation",)
# Level >= 1 volume bound of the meshes with none at level 0 (m^3): the 95th
# percentile of the level-0 tet volumes (the liver 14 415 tets, max 6.1e-8; the
# torus 4021, max 2.0e-7; the L-block 3119, max 7.3e-7).
VOLUME_BOUND = {"liver_grasp_gravity": 9.476e-09, "torus_grasp": 9.381e-08, "l_block_grasp": 3.024e-07}
# P2 has about 7 times the nodes of P1 on the same tets (the edge midpoints).
P2_NODE_FACTOR = 7
# The costly runs, last and in this order (what matters most first: the cube's
# P2 level 1 (~6x10^5 dofs), the Truth Cube's P2 at every strain (P1 locks), its P1
# level 1, then the P1 level-2 solves); the rest, cheapest first. The Truth Cube's Newton solves cost
# far more per dof than the cube's (nu = 0.499: about 120 CG iterations a Newton
# step on level 0 against 14 on the cube).
LARGE_ORDER = [("cube_pull_disc", 1, 2), ("truth_cube_5", 0, 2), ("truth_cube_12_5", 0, 2),
               ("truth_cube_18_25", 0, 2), ("truth_cube_18_25", 1, 1), ("truth_cube_12_5", 1, 1),
               ("cube_pull_disc", 2, 1),
               ("cube_push_disc", 2, 1),
               # The gravity scenarios, run after fem_distributed took a body force:
               # their P1 level 2 (three levels: an observed order), then P2 level 1.
               ("liver_grasp_gravity", 2, 1), ("flap_gravity", 2, 1), ("liver_grasp_gravity", 1, 2),
               ("flap_gravity", 1, 2),
               # Above 10^6 dofs: the Truth Cube's P2 level 1 at its smallest strain (2 load
               # increments, 8 Newton iterations on level 0).
               ("truth_cube_5", 1, 2),
               # The palpation's level 1 (Newton contact along 31 frames, CHOLMOD on 74 640 dofs).
               ("cube_palpation", 1, 1)]

def case(solver, degree, steps):
    """The reference case; steps None: the solver's default load increments (as the suite's)."""
    if solver == "serial":
        parameters = {"solver": "newton", "material_law": "neo_hookean"}
        if steps is not None:
            parameters["newton_load_steps"] = steps
        return {"name": "newton-p1", "model": "fem", "parameters": parameters}
    return {"name": "neo-p%d" % degree, "model": "fem_distributed",
            "parameters": {"degree": degree, "material_law": "neo_hookean", "load_steps": steps,
                           "cg_tolerance": CG_TOLERANCE}}


def unramped(items):
    """The suite's loads or tools at full value from the first frame."""
    out = []
    for item in items:
        item = dict(item)
        if "ramp_frames" in item:
            item["ramp_frames"] = 0
        out.append(item)
    return out


def resolved_suite(path):
    """The suite scenario's own keys and those of the files it extends (a dict merge,
    as the runner's `extends`: objects merge key by key, anything else replaces)."""
    j = json.load(open(path))
    if "extends" not in j:
        return j
    base = resolved_suite(os.path.normpath(os.path.join(os.path.dirname(path), j["extends"])))

    def merge(a, b):
        if isinstance(a, dict) and isinstance(b, dict):
            r = dict(a)
            for k, v in b.items():
                r[k] = merge(a.get(k), v) if k in a else v
            return r
        return b

    return merge(base, {k: v for k, v in j.items() if k != "extends"})


def scenario(role, level, degree):
    file, solver, _, _, steps, _ = SCENARIOS[role]
    suite = resolved_suite(os.path.join(ROOT, "experiments", "scenarios", "suite", file))
    s = {"extends": "../suite/" + file, "name": "sref-%s-L%d-p%d" % (role.replace("_", "-"), level, degree)}
    s["description"] = ("Suite-reference convergence (docs/reference_convergence.md, 'Every suite scenario'): %s "
                        "refined %d times, P%d, Newton neo-Hookean (%s), %s"
                        % (role, level, degree, "serial fem, CHOLMOD" if solver == "serial" else "fem_distributed",
                           "along the suite's frames" if role in PATH_DEPENDENT else "one static solve at the full load"))
    s["mesh"] = {"refine_levels": level}
    if level > 0 and role in VOLUME_BOUND:
        s["mesh"]["fine_tetgen"] = {"max_volume": VOLUME_BOUND[role]}
    if role not in PATH_DEPENDENT:
        if suite.get("load"):
            s["load"] = {"ramp_frames": 0}
        for key in ("loads", "tools"):
            if suite.get(key):
                s[key] = unramped(suite[key])
        s["frames"] = {"max": 1, "static": 1, "steady_tolerance": None}
    s["models"] = [case(solver, degree, steps)]
    return s


def estimated_dofs(role, level, degree):
    nodes = SCENARIOS[role][5] * 8 ** level * (P2_NODE_FACTOR if degree == 2 else 1)
    return 3 * nodes


def write(path, j):
    with open(path, "w") as f:
        json.dump(j, f, indent=2)
        f.write("\n")


def main():
    runs = []
    for role, (_, _, p1, p2, _, _) in SCENARIOS.items():
        runs += [(role, level, 1) for level in p1] + [(role, level, 2) for level in p2]
    # Cheapest first: an interrupted study has its small levels whole.
    runs.sort(key=lambda r: (LARGE_ORDER.index(r) if r in LARGE_ORDER else -1, estimated_dofs(*r), r))
    for stale in os.listdir(HERE):  # the files of runs no longer planned
        if stale.startswith("sref-") and stale.endswith(".json"):
            os.remove(os.path.join(HERE, stale))
    files = []
    for role, level, degree in runs:
        s = scenario(role, level, degree)
        name = s["name"] + ".json"
        write(os.path.join(HERE, name), s)
        files.append("scenarios/suite_reference/" + name)
    experiment = {
        "name": "suite_reference_convergence",
        "description": "Every suite scenario's Newton neo-Hookean reference under refinement (levels 0-2, P1 and "
        "P2), cheapest first; written by experiments/scenarios/suite_reference/generate.py, run by "
        "scripts/suite_reference_convergence; docs/reference_convergence.md, 'Every suite scenario'",
        "scenarios": files,
    }
    write(os.path.join(ROOT, "experiments", "suite_reference_convergence.json"), experiment)
    print("%d scenario files" % len(files))


if __name__ == "__main__":
    main()
