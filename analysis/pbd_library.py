"""Against the PositionBasedDynamics library (docs/pbd_library_comparison.md): its per-frame time beside tissuebench's pbd model.

Usage: /usr/bin/python3 analysis/pbd_library.py [results/pbd_library] [results]
Reads the comparison's raw files (docs/pbd_library_comparison.md: how they were measured; the recipe
that built and ran the library is no longer in the repository): per size, results/pbd_library/<size>/
<case>/{run,timings}.json (tissuebench's pbd cases), library-t<threads>.json (the library's driver),
tissuebench_loaded_vertex.json, machine_load.csv, and results/pbd_library/library_build.json; writes
results/tables/pbd_library.{csv,md}: per size and
thread count the library's and tissuebench's (double and single precision) median and p95 ms per
frame after the load ramp and their ratio, then what each did (constraints, iterations, the loaded
vertex's displacement at the last frame).
"""
import csv
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import results_index  # noqa: E402
import table_io as tables  # noqa: E402


def load_json(path):
    with open(path) as f:
        return json.load(f)


def tissuebench_cases(size_dir):
    """{(precision, threads): {"run", "timings"}} of the size's pbd cases."""
    cases = {}
    for name in sorted(os.listdir(size_dir)):
        run_path = os.path.join(size_dir, name, "run.json")
        if not results_index.is_case_folder(os.path.join(size_dir, name)):
            continue  # not a case, or a killed run's staging folder
        run = load_json(run_path)
        if run["model"] != "pbd":
            continue
        p = run["parameters"]
        cases[(p.get("precision", "double"), int(p.get("threads", 1)))] = {
            "name": name, "run": run, "timings": load_json(os.path.join(size_dir, name, "timings.json")),
            "dir": os.path.join(size_dir, name)}
    return cases


def vertex_displacement(size_dir, case, vertex):
    """(position, displacement) of a vertex at the last frame of a tissuebench case, from
    tissuebench_loaded_vertex.json (extracted from surface.csv when the comparison ran)."""
    entry = load_json(os.path.join(size_dir, "tissuebench_loaded_vertex.json"))[case]
    assert entry["vertex"] == vertex, f"{size_dir}: tissuebench_loaded_vertex.json is for vertex {entry['vertex']}"
    return entry["position"], entry["displacement_m"]


def machine_load(size_dir):
    path = os.path.join(size_dir, "machine_load.csv")
    if not os.path.isfile(path):
        return {}
    with open(path) as f:
        return {r["case"]: max(float(r["load_before"]), float(r["load_after"])) for r in csv.DictReader(f)}


def rows_of(root):
    rows = []
    for size in sorted(os.listdir(root)):
        size_dir = os.path.join(root, size)
        if not os.path.isdir(size_dir):
            continue  # each size's folder holds its library-t<threads>.json (others are skipped below)
        tb = tissuebench_cases(size_dir)
        load = machine_load(size_dir)
        for threads in (1, 2):
            lib_path = os.path.join(size_dir, f"library-t{threads}.json")
            if not os.path.isfile(lib_path) or ("double", threads) not in tb:
                continue
            lib = load_json(lib_path)
            d, s = tb[("double", threads)], tb.get(("single", threads))
            run = d["run"]
            assert lib["omp_max_threads"] == threads, lib_path
            assert lib["vertices"] == run["mesh"]["surface_vertices"], "not the same surface"
            assert lib["triangles"] == run["mesh"]["surface_triangles"], "not the same surface"
            assert lib["frames"] == run["frames"], "not the same frame count"
            position, u_tb = vertex_displacement(size_dir, d["name"], lib["load_vertex"])
            assert max(abs(a - b) for a, b in zip(position, lib["load_vertex_position"])) < 1e-12, "loaded vertex"
            tb_step, lib_frame = d["timings"]["step_after_ramp"], lib["frame_after_ramp"]
            s_step = s["timings"]["step_after_ramp"] if s else None
            timers = lib.get("library_timers_after_ramp_mean_ms", {})
            rows.append({
                "scenario": size, "vertices": lib["vertices"], "threads": threads,
                "library_median_ms": lib_frame["median_ms"], "library_p95_ms": lib_frame["p95_ms"],
                "tb_double_median_ms": tb_step["median_ms"], "tb_double_p95_ms": tb_step["p95_ms"],
                "tb_single_median_ms": s_step["median_ms"] if s_step else None,
                "tb_single_p95_ms": s_step["p95_ms"] if s_step else None,
                "ratio_double": lib_frame["median_ms"] / tb_step["median_ms"],
                # The fastest frames, the least disturbed by other jobs on a shared machine.
                "library_min_ms": min(lib["frame_ms"][lib["ramp_frames"]:]), "tb_double_min_ms": tb_step["min_ms"],
                "ratio_double_min": min(lib["frame_ms"][lib["ramp_frames"]:]) / tb_step["min_ms"],
                "ratio_single": lib_frame["median_ms"] / s_step["median_ms"] if s_step else None,
                "timed_frames": lib_frame["count"], "tb_timed_frames": tb_step["count"],
                "library_projection_share": (timers["position constraints projection"] / timers["simulation step"]
                                             if "simulation step" in timers else None),
                "library_groups": lib["constraint_groups"],
                "library_distance": lib["distance_constraints"], "library_dihedral": lib["dihedral_constraints"],
                "tb_stretch": lib["edges"], "tb_bending": lib["interior_edges"],
                "library_iterations": lib["iterations"], "tb_iterations": int(run["parameters"]["iterations"]),
                "tb_iterations_recorded": sorted(set(d["timings"].get("solver_iterations_per_frame", []))),
                "frames": lib["frames"], "fixed_vertices": lib["fixed_vertices"],
                "load_N": lib["force_N"][2], "load_vertex": lib["load_vertex"],
                "library_uz_mm": 1e3 * lib["load_vertex_displacement_m"][2], "tb_uz_mm": 1e3 * u_tb[2],
                "library_max_u_mm": 1e3 * lib["max_displacement_m"], "tb_max_u_mm": 1e3 * run["max_displacement_m"],
                "load_library": load.get(f"library-t{threads}"), "load_tb": load.get("tissuebench"),
                "tb_build": run["build"], "tb_isa": run.get("model_report", {}).get("instruction_set", "?"),
            })
    return sorted(rows, key=lambda r: (r["vertices"], r["threads"]))


def make(root, out_root):
    rows = rows_of(root)
    if not rows:
        raise SystemExit(f"no library and tissuebench results under {root} (docs/pbd_library_comparison.md)")
    lib_build = load_json(os.path.join(root, "library_build.json"))
    b = rows[0]["tb_build"]
    f = tables.fmt
    header = ["surface vertices", "threads", "library median ms", "library p95 ms",
              "tissuebench double median ms", "tissuebench double p95 ms",
              "tissuebench single median ms", "tissuebench single p95 ms",
              "library / tissuebench double (median)", "library / tissuebench single (median)",
              "library / tissuebench double (fastest frame)", "load average (library / tissuebench runs)"]
    body = [[r["vertices"], r["threads"], f(r["library_median_ms"]), f(r["library_p95_ms"]),
             f(r["tb_double_median_ms"]), f(r["tb_double_p95_ms"]), f(r["tb_single_median_ms"]),
             f(r["tb_single_p95_ms"]), f(r["ratio_double"], 2), f(r["ratio_single"], 2), f(r["ratio_double_min"], 2),
             f"{f(r['load_library'], 1)} / {f(r['load_tb'], 1)}"] for r in rows]
    work_header = ["surface vertices", "distance / stretch constraints (library / tissuebench)",
                   "dihedral / bending constraints (library / tissuebench)", "library constraint groups",
                   "iterations (library / tissuebench)", "fixed vertices", "load N", "frames",
                   "loaded vertex u_z at the last frame, mm (library / tissuebench double)",
                   "max displacement mm (library / tissuebench double)", "library projection share of its step"]
    work = [[r["vertices"], f"{r['library_distance']} / {r['tb_stretch']}", f"{r['library_dihedral']} / {r['tb_bending']}",
             r["library_groups"], f"{r['library_iterations']} / {r['tb_iterations']}", r["fixed_vertices"],
             f(r["load_N"], 5), r["frames"], f"{f(r['library_uz_mm'], 2)} / {f(r['tb_uz_mm'], 2)}",
             f"{f(r['library_max_u_mm'], 2)} / {f(r['tb_max_u_mm'], 2)}", f(r["library_projection_share"], 2)]
            for r in rows if r["threads"] == 1]
    csv_header = list(k for k in rows[0] if k not in ("tb_build",))
    csv_rows = [[r[k] if not isinstance(r[k], list) else " ".join(map(str, r[k])) for k in csv_header] for r in rows]
    tables.write_table(os.path.join(out_root, "tables"), "pbd_library", csv_header, csv_rows)

    def thread_spread(key):
        by_size = {}
        for r in rows:
            by_size.setdefault(r["vertices"], []).append(r[key])
        spread = max(max(v) - min(v) for v in by_size.values())
        return "0 mm (the same numbers)" if spread == 0 else f"{spread:.3g} mm"

    def md_table(h, rs):
        return ("| " + " | ".join(h) + " |\n|" + "---|" * len(h) + "\n" +
                "".join("| " + " | ".join(str(c) for c in r) + " |\n" for r in rs))

    md = (
        "# The PositionBasedDynamics library against tissuebench's pbd model\n\n"
        f"Machine: {b.get('cpu_model', '?')}, {b.get('hardware_threads', '?')} hardware threads; **check the "
        "load-average column**: about 1 is a quiet machine (the measured process itself), more means other jobs "
        "shared the cores and only the ratios are comparable. Measured as docs/pbd_library_comparison.md describes (tables by `analysis/pbd_library.py`). "
        "Per frame, after the 50-frame load ramp: median and p95 over "
        f"{', '.join(sorted({str(r['timed_frames']) for r in rows}, key=int))} frames. The library "
        f"({lib_build['source'].rstrip('/').split('/')[-1]} {lib_build['version']}, commit "
        f"{lib_build['commit'][:12]}; {lib_build['build_type']}, `{lib_build['cxx_flags']}`, "
        f"{lib_build['compiler']}, double, Eigen {lib_build['eigen'].split('(')[-1].rstrip(')')}) "
        "is timed over the driver's whole frame: the load and damping on the velocities, then "
        "`TimeStepController::step` (1 sub-step, 10 position iterations, 0 velocity iterations, no gravity, no "
        "collision detection). Tissuebench "
        f"({b['build_type']}, {b['compiler']}, commit {b['git_commit']}, {rows[0]['tb_isa']} kernels) is timed by "
        "its runner (timings.json, step_after_ramp): the whole pbd model step. Threads: the library's "
        "OMP_NUM_THREADS, tissuebench's `threads` parameter (its sweep here colour by colour, `domains` 1; its "
        "spatial domains are faster on 2 threads: docs/scaling.md). On a shared machine the 2-thread rows measure "
        "the contention as much as the solvers: a 2-thread process seldom has both cores, and every colour ends "
        "in a barrier (docs/pbd_library_comparison.md). The fastest-frame ratio is the one "
        "least disturbed by other jobs.\n\n"
        + md_table(header, body) +
        "\n## Same work?\n\n"
        "Both read the same OBJ surface (tissuebench's `mesh/fine_surface.obj`), fix the same bottom vertices "
        "(inverse mass 0), lump the same masses (density 1000 x enclosed volume, shared by one third of the "
        "incident triangle area), load the vertex nearest the top centre with the scenario's force (1 N on the "
        "682-vertex cube, scaled by 682 / vertices above it as in the scaling experiment), ramped over 50 frames, "
        "time step 10 ms, damping 0.05 of the velocity per frame, stiffness 1, 10 Gauss-Seidel iterations. "
        "Tissuebench's constraint counts are those of its rule (its constraint kinds' build, "
        "models/numerics/pbd/stretch_kind.cc and bending_kind.cc: one "
        "stretch constraint per edge, one bending constraint per edge with two triangles), counted on the same "
        "OBJ by the driver; the library's are the constraints its addClothConstraints (method 1) and "
        "addBendingConstraints (method 1) created.\n\n"
        + md_table(work_header, work) +
        "\nThe displacements need not agree: the library's DihedralConstraint (Bridson's gradients of "
        "arccos(n1 . n2), a fixed group order every iteration) is not tissuebench's eq. (19) bending projection "
        "swept alternately forward and backward. Between 1 and 2 threads the loaded vertex's u_z differs by at most "
        f"{thread_spread('library_uz_mm')} in the library and {thread_spread('tb_uz_mm')} in "
        "tissuebench.\n"
    )
    with open(os.path.join(out_root, "tables", "pbd_library.md"), "w") as fh:
        fh.write(md)
    return md


if __name__ == "__main__":
    root = sys.argv[1] if len(sys.argv) > 1 else "results/pbd_library"
    out = sys.argv[2] if len(sys.argv) > 2 else "results"
    print(make(root, out))
