"""A reference you can trust (docs/reference_convergence.md): the fine FEM under refinement, element
order, load model and material law, and table 1's models against every level.

Usage: /usr/bin/python3 analysis/reference_convergence.py [results/reference_convergence] [results]

Reads results/reference_convergence/np<N>/reference_convergence/<scenario>/<case>/
(run.json, timings.json, top_surface.csv; scripts/reference_convergence writes
them), results/reference_convergence/failures.txt, and the paper's hybrid and
PBD runs of the paper experiment's cube scenarios (roles cube_pull and cube_push in
results/paper/experiment.json). Scenario names say the level, the
direction, the load and the force: ref-L<level>-<pull|push>-<point|disc>[-0.1N].

Every refinement level keeps the paper's surface vertices at the same
coordinates, so fields are compared at those vertices: a model's vertex is
matched to the reference's with equal rest coordinates (within 1e-12 m).
Writes results/tables/reference_convergence{,_cost,_neo_hookean,_table1}.{md,csv}
and results/figures/reference_convergence.png.
"""
import os
import re
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import metrics  # noqa: E402
import results_index  # noqa: E402
import table_io as tables  # noqa: E402

LOAD_POINT = np.array([0.0, 0.0, 0.1])
NEAR_LOAD = 0.01  # m: the "without a 1 cm disc around the load point" metrics leave out vertices this close
MATCH_TOLERANCE = 1e-12  # m
NAME = re.compile(r"^ref-L(\d+)-(pull|push)-(point|disc)(?:-([0-9.]+)N)?$")


def parse_scenario(name):
    """(level, direction, load, force in N) of a scenario name, or None."""
    m = NAME.match(name)
    if not m:
        return None
    return int(m.group(1)), m.group(2), m.group(3), float(m.group(4)) if m.group(4) else 1.0


def match_vertices(rest, rest_ref, tolerance=MATCH_TOLERANCE):
    """Row of rest_ref at the same coordinates as each row of rest (#V ints).

    Raises ValueError naming the first vertex with no counterpart within
    `tolerance` (a model run on another surface than the reference's levels).
    """
    rest = np.asarray(rest, float)
    rest_ref = np.asarray(rest_ref, float)
    key = {tuple(np.round(p / tolerance).astype(np.int64)): i for i, p in enumerate(rest_ref)}
    out = np.empty(len(rest), dtype=int)
    for i, p in enumerate(rest):
        base = np.round(p / tolerance).astype(np.int64)
        j = key.get(tuple(base))
        if j is None:  # rounding put it in a neighbouring cell: look around
            for d in np.ndindex(3, 3, 3):
                j = key.get(tuple(base + np.array(d) - 1))
                if j is not None:
                    break
        if j is None or np.linalg.norm(rest_ref[j] - p) > tolerance:
            raise ValueError(f"vertex {i} at {tuple(p)} has no reference vertex within {tolerance} m")
        out[i] = j
    return out


def load_vertex(rest):
    """Index of the vertex at the load point (the top centre is a vertex at every level)."""
    k = int(np.argmin(np.linalg.norm(rest - LOAD_POINT, axis=1)))
    if np.linalg.norm(rest[k] - LOAD_POINT) > MATCH_TOLERANCE:
        raise ValueError("no vertex at the load point")
    return k


def relative_change(u, u_ref, mask=None):
    """||u - u_ref|| / ||u_ref|| over the rows in mask (all if None)."""
    if mask is not None:
        u, u_ref = u[mask], u_ref[mask]
    return float(np.linalg.norm(u - u_ref) / np.linalg.norm(u_ref))


class Study:
    """Every case of the study: {np: {scenario: {case: case}}} and the fields."""

    def __init__(self, root):
        self.root = root
        self.runs = {}
        for entry in sorted(os.listdir(root)) if os.path.isdir(root) else []:
            m = re.match(r"^np(\d+)$", entry)
            exp = os.path.join(root, entry, "reference_convergence")
            if m and os.path.isdir(exp):
                self.runs[int(m.group(1))] = results_index.load_experiment(exp)
        if 1 not in self.runs:
            raise FileNotFoundError(f"{root}/np1/reference_convergence: no results (run scripts/reference_convergence)")
        self.failures = []
        path = os.path.join(root, "failures.txt")
        if os.path.isfile(path):
            with open(path) as f:
                self.failures = [line.strip() for line in f if line.strip()]
        self._fields = {}

    def case(self, scenario, case, np_=1):
        return self.runs.get(np_, {}).get(scenario, {}).get(case)

    def field(self, scenario, case, np_=1):
        """(rest #Vx3, u #Vx3) of a case's top surface, or None if it did not run."""
        key = (scenario, case, np_)
        if key not in self._fields:
            c = self.case(scenario, case, np_)
            self._fields[key] = None if c is None else metrics.read_displacements(
                os.path.join(c["folder"], "top_surface.csv"))[1:]
        return self._fields[key]

    def scenarios(self):
        return sorted(self.runs[1], key=lambda s: (parse_scenario(s) or (0,))[0])

    def failure(self, scenario, case):
        """The failure line of a case, or ''."""
        for line in self.failures:
            if line.startswith(f"{scenario} {case} "):
                return line.split(": ", 1)[-1]
        return ""


def on_paper_vertices(study, scenario, case, paper_rest, np_=1):
    """u of a case at the paper's top vertices (#V0 x 3), or None."""
    f = study.field(scenario, case, np_)
    if f is None:
        return None
    rest, u = f
    return u[match_vertices(paper_rest, rest)]


def scenario_name(level, direction, load, force=1.0):
    return f"ref-L{level}-{direction}-{load}" + ("" if force == 1.0 else f"-{force:g}N")


def levels_of(study, direction, load, case, force=1.0):
    return [lv for lv in range(10) if study.case(scenario_name(lv, direction, load, force), case)]


def paper_top(study):
    """The paper's top vertices: level 0's."""
    f = study.field(scenario_name(0, "pull", "point"), "fem-p1")
    if f is None:
        raise FileNotFoundError("the level-0 point pull (fem-p1) is missing")
    return f[0]


ORDERS = (("P1", "fem-p1"), ("P2", "fem-p2"))


def convergence_rows(study):
    """Per load, element order and level: dofs, load-point u_z, change against the
    finest solve of the same load (the most dofs, either order), on the paper's top
    vertices, with and without the vertices within 1 cm of the load point."""
    paper_rest = paper_top(study)
    far = np.linalg.norm(paper_rest - LOAD_POINT, axis=1) > NEAR_LOAD
    k = load_vertex(paper_rest)
    rows = []
    for load in ("point", "disc"):
        solves = [(study.case(scenario_name(lv, "pull", load), case)["run"]["model_report"]["dofs"], order, case, lv)
                  for order, case in ORDERS for lv in levels_of(study, "pull", load, case)]
        if not solves:
            continue
        _, f_order, f_case, f_level = max(solves)
        finest = on_paper_vertices(study, scenario_name(f_level, "pull", load), f_case, paper_rest)
        for order, case in ORDERS:
            for lv in levels_of(study, "pull", load, case):
                s = scenario_name(lv, "pull", load)
                u = on_paper_vertices(study, s, case, paper_rest)
                stats = study.case(s, case)["run"]["model_report"]
                rows.append({"load": load, "order": order, "level": lv, "dofs": stats["dofs"], "cells": stats["cells"],
                             "uz_load_mm": 1000 * u[k, 2], "finest": f"{f_order} L{f_level}",
                             "change": relative_change(u, finest), "change_far": relative_change(u, finest, far)})
    return rows


def cost_rows(study):
    """Per linear 1 N pull case and rank count: wall time by phase and peak memory."""
    rows = []
    for np_ in sorted(study.runs):
        for scenario in sorted(study.runs[np_]):
            p = parse_scenario(scenario)
            if not p or p[1] != "pull" or p[3] != 1.0:
                continue
            for case in ("fem-p1", "fem-p2"):
                c = study.case(scenario, case, np_)
                if c is None:
                    continue
                st = c["run"]["model_report"]
                sec = st["seconds"]
                proc = c["timings"].get("processes", {})
                diff = float("nan")
                if np_ != 1 and study.field(scenario, case, 1) is not None:
                    diff = relative_change(study.field(scenario, case, np_)[1], study.field(scenario, case, 1)[1])
                rows.append({"load": p[2], "order": case[-2:].upper(), "level": p[0], "np": np_, "dofs": st["dofs"],
                             "setup_s": c["timings"]["setup_ms"] / 1000, "solve_s": sec["solve_last_step"],
                             "wall_s": c["timings"]["setup_ms"] / 1000 + c["timings"]["step"]["median_ms"] / 1000,
                             "mesh_s": sec["mesh"], "assembly_s": sec["assembly"], "amg_s": sec["preconditioner"],
                             "cg": st["cg_iterations_last_step"], "peak_max_gib": proc.get("peak_rss_mib_max", 0) / 1024,
                             "peak_sum_gib": proc.get("peak_rss_mib_sum", 0) / 1024, "np_diff": diff})
    return sorted(rows, key=lambda r: (r["load"], r["order"], r["level"], r["np"]))


def neo_rows(study):
    """Linear against neo-Hookean (P1, same mesh and load): top-surface relative
    difference ||u_lin - u_neo|| / ||u_neo|| and the load-point u_z of both."""
    rows = []
    for scenario in study.scenarios():
        p = parse_scenario(scenario)
        if not p:
            continue
        level, direction, load, force = p
        if "neo-p1" not in [c for c in study.runs[1][scenario]] and not study.failure(scenario, "neo-p1"):
            continue
        lin = study.field(scenario, "fem-p1")
        neo = study.field(scenario, "neo-p1")
        row = {"force": force, "direction": direction, "load": load, "level": level}
        if lin is None or neo is None:
            row["failed"] = study.failure(scenario, "neo-p1") or "missing"
            rows.append(row)
            continue
        k = load_vertex(lin[0])
        st = study.case(scenario, "neo-p1")["run"]["model_report"]
        row.update({"uz_linear_mm": 1000 * lin[1][k, 2], "uz_neo_mm": 1000 * neo[1][k, 2],
                    "difference": relative_change(lin[1], neo[1]),
                    "difference_far": relative_change(lin[1], neo[1], np.linalg.norm(lin[0] - LOAD_POINT, axis=1) > NEAR_LOAD),
                    "newton": st["newton_iterations_last_step"], "increments": st["load_increments_last_step"],
                    "halvings": st["increment_halvings_last_step"], "seconds": st["seconds"]["solve_last_step"]})
        rows.append(row)
    return sorted(rows, key=lambda r: (-r["force"], r["direction"] != "pull", r["load"], r["level"]))


def table1_rows(study, paper_dir):
    """The paper's hybrid and PBD (the paper experiment's scenarios in roles
    cube_pull and cube_push) against every point-load reference level and order, at
    the paper's top vertices. No rows without a paper results folder."""
    rows = []
    if not os.path.isdir(paper_dir):
        return rows
    paper = results_index.Experiment(paper_dir)
    for direction in ("pull", "push"):
        cases = paper.by_role(tables.ROLES["cube"][direction])
        models = {}
        for model in ("hybrid", "pbd", "fem-direct"):
            if model in cases:
                models[model] = metrics.read_displacements(os.path.join(cases[model]["folder"], "top_surface.csv"))[1:]
        for order, case in ORDERS:
            for lv in levels_of(study, direction, "point", case):
                s = scenario_name(lv, direction, "point")
                ref_rest, ref_u = study.field(s, case)
                for model, (rest, u) in models.items():
                    m = metrics.extended(u, ref_u[match_vertices(rest, ref_rest)], rest, LOAD_POINT, NEAR_LOAD)
                    rows.append({"direction": direction, "model": model, "reference": f"{order} L{lv}",
                                 "dofs": study.case(s, case)["run"]["model_report"]["dofs"], **m})
    return rows


def write_tables(study, paper_dir, out):
    tdir = os.path.join(out, "tables")
    conv = convergence_rows(study)
    tables.write_table(
        tdir, "reference_convergence",
        ["load", "order", "level", "dofs", "cells", "u_z at load point (mm)", "change vs finest",
         "change vs finest, outside 1 cm", "finest"],
        [[r["load"], r["order"], r["level"], r["dofs"], r["cells"], tables.fmt(r["uz_load_mm"], 2),
          tables.fmt(r["change"], 4), tables.fmt(r["change_far"], 4), r["finest"]] for r in conv],
        "Cube, 1 N pull at the top centre: the paper's point force, or the same force as a uniform traction on a "
        "5 mm disc. Level L: the paper's surface split in four L times, the TetGen volume bound / 8^L (level 0 is "
        "the paper's mesh). Linear FEM, distributed (one MPI rank), CG relative tolerance 1e-10. 'change vs finest': "
        "||u_L - u_finest|| / ||u_finest|| over the paper's 121 top-surface vertices, against the finest solve of the "
        "same load (the most dofs, either element order: column 'finest'); 'outside 1 cm': the vertices farther than 1 cm from the load point (116 of 121).")
    cost = cost_rows(study)
    tables.write_table(
        tdir, "reference_convergence_cost",
        ["load", "order", "level", "ranks", "dofs", "wall (s)", "mesh (s)", "assembly (s)", "AMG setup (s)",
         "CG solve (s)", "CG iterations", "peak memory, max rank (GiB)", "peak memory, all ranks (GiB)",
         "np vs np=1 difference"],
        [[r["load"], r["order"], r["level"], r["np"], r["dofs"], tables.fmt(r["wall_s"], 1), tables.fmt(r["mesh_s"], 1),
          tables.fmt(r["assembly_s"], 1), tables.fmt(r["amg_s"], 1), tables.fmt(r["solve_s"], 1), r["cg"],
          tables.fmt(r["peak_max_gib"], 2), tables.fmt(r["peak_sum_gib"], 2),
          "" if r["np"] == 1 else f"{r['np_diff']:.1e}"] for r in cost],
        "Wall time of setup and solve as the runner measured them (setup: reading the cached mesh into the model, "
        "the distributed mesh, dofs, assembly, AMG; solve: CG), peak resident memory per process "
        "(getrusage, the whole process: meshes, deal.II, Trilinos). Each case ran in its own process. "
        + machine(study) + " The two cores were shared with other jobs, so the times are noisy.")
    neo = neo_rows(study)
    tables.write_table(
        tdir, "reference_convergence_neo_hookean",
        ["force (N)", "direction", "load", "level", "u_z at load, linear (mm)", "u_z at load, neo-Hookean (mm)",
         "relative difference", "relative difference, outside 1 cm", "Newton iterations", "load increments",
         "increments halved", "solve (s)"],
        [[tables.fmt(r["force"], 1), r["direction"], r["load"], r["level"]]
         + ([tables.fmt(r["uz_linear_mm"], 3), tables.fmt(r["uz_neo_mm"], 3), tables.fmt(r["difference"], 4),
             tables.fmt(r["difference_far"], 4), r["newton"], r["increments"], r["halvings"],
             tables.fmt(r["seconds"], 1)] if "failed" not in r else ["failed: " + r["failed"]] + [""] * 7)
         for r in neo],
        "Linear against compressible neo-Hookean FEM (P1, same lambda and mu: E = 3 kPa, nu = 0.45), same mesh and "
        "load. Relative difference: ||u_lin - u_neo|| / ||u_neo|| over the level's top-surface vertices. Newton "
        "with load increments (10 at 1 N, 2 at 0.1 N; halved on failure), relative residual 1e-9.")
    t1 = table1_rows(study, paper_dir)
    tables.write_table(
        tdir, "reference_convergence_table1",
        ["direction", "model", "reference", "reference dofs", "r(u_z)", "relative L2", "|u| ratio at load point",
         "r(u_z), outside 1 cm", "relative L2, outside 1 cm"],
        [[r["direction"], r["model"], r["reference"], r["dofs"], tables.fmt(r["corr_uz"]), tables.fmt(r["rel_l2"]),
          tables.fmt(r["load_ratio"]), tables.fmt(r["corr_uz_far"]), tables.fmt(r["rel_l2_far"])] for r in t1],
        "Table 1's models (results/paper/cube-<pull|push>/: hybrid, PBD and the paper-sized fem-direct, all on the "
        "paper's mesh) against the linear point-load reference at every level and element order, at the paper's "
        "121 top-surface vertices (matched by rest coordinates); 'outside 1 cm': the 116 vertices farther than 1 cm from "
        "the load point, away from the point load's singularity.")
    return conv, cost, neo, t1


def machine(study):
    c = study.case(scenario_name(0, "pull", "point"), "fem-p1")
    b = c["run"].get("build", {}) if c else {}
    if not b:
        return ""
    return (f"Measured on {b.get('cpu_model', '?')} ({b.get('hardware_threads', '?')} hardware threads), "
            f"{b.get('build_type', '?')} build, {b.get('compiler', '?')}, one thread per rank.")


def figure(conv, cost, t1, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(11, 8.5))
    style = {("point", "P1"): ("C0", "o", "-"), ("point", "P2"): ("C0", "s", "--"),
             ("disc", "P1"): ("C1", "o", "-"), ("disc", "P2"): ("C1", "s", "--")}
    for (load, order), (color, marker, ls) in style.items():
        rows = [r for r in conv if r["load"] == load and r["order"] == order]
        if not rows:
            continue
        d = [r["dofs"] for r in rows]
        label = f"{load} load, {order}"
        ax[0, 0].plot(d, [r["uz_load_mm"] for r in rows], color=color, marker=marker, ls=ls, label=label)
        coarse = [r for r in rows if r["change"] > 0]  # all but the finest solve itself
        if coarse:
            ax[0, 1].plot([r["dofs"] for r in coarse], [r["change"] for r in coarse], color=color, marker=marker,
                          ls=ls, label=label + ", all")
            ax[0, 1].plot([r["dofs"] for r in coarse], [r["change_far"] for r in coarse], color=color, marker=marker,
                          ls=":", mfc="none", label=label + ", outside 1 cm")
    ax[0, 0].set(xscale="log", xlabel="dofs", ylabel="u_z at the load point (mm)",
                 title="load-point displacement, 1 N pull")
    ax[0, 1].set(xscale="log", yscale="log", xlabel="dofs", ylabel="relative change vs finest level",
                 title="top-surface field against the finest level")
    for (np_, color) in ((1, "C2"), (2, "C3")):
        for order, marker in (("P1", "o"), ("P2", "s")):
            rows = [r for r in cost if r["np"] == np_ and r["order"] == order and r["load"] == "point"]
            if rows:
                ax[1, 0].plot([r["dofs"] for r in rows], [r["wall_s"] for r in rows], color=color, marker=marker,
                              label=f"{order}, {np_} rank(s): wall s")
                ax[1, 0].plot([r["dofs"] for r in rows], [r["peak_sum_gib"] for r in rows], color=color,
                              marker=marker, ls=":", mfc="none", label=f"{order}, {np_} rank(s): peak GiB")
    ax[1, 0].set(xscale="log", yscale="log", xlabel="dofs", title="cost (point pull): wall time and peak memory")
    refs = []
    for r in t1:
        if r["reference"] not in refs:
            refs.append(r["reference"])
    for model, color in (("hybrid", "C4"), ("pbd", "C5")):
        for key, ls, what in (("corr_uz", "-", "r(u_z)"), ("corr_uz_far", "--", "r(u_z) outside 1 cm")):
            rows = [r for r in t1 if r["model"] == model and r["direction"] == "pull"]
            ax[1, 1].plot([refs.index(r["reference"]) for r in rows], [r[key] for r in rows], color=color, ls=ls,
                          marker="o", label=f"{model}: {what}")
    ax[1, 1].set_xticks(range(len(refs)))
    ax[1, 1].set_xticklabels(refs, rotation=30)
    ax[1, 1].set(title="table 1 (pull) against each reference", xlabel="reference (point load)")
    for a in ax.flat:
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=7)
    fig.tight_layout()
    os.makedirs(os.path.join(out, "figures"), exist_ok=True)
    fig.savefig(os.path.join(out, "figures", "reference_convergence.png"), dpi=130)
    plt.close(fig)


def make(root, out, paper_dir=None):
    study = Study(root)
    conv, cost, neo, t1 = write_tables(study, paper_dir or os.path.join(out, "paper"), out)
    figure(conv, cost, t1, out)
    return study


if __name__ == "__main__":
    root = sys.argv[1] if len(sys.argv) > 1 else "results/reference_convergence"
    out = sys.argv[2] if len(sys.argv) > 2 else "results"
    results_index.main(lambda: make(root, out), "reference_convergence")
    print("reference convergence tables and figure written")
