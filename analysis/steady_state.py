"""Steady-state studies (docs/liver_steady_state.md): which cases of an experiment (a sweep, e.g.
experiments/liver_steady.json, or a plain list of scenarios, e.g.
experiments/shapes_steady.json) meet the runner's steady-state test, at which frame,
how far from it the others end, whether the surface they settle in is inverted
anywhere, their accuracy against the experiment's reference and their per-frame cost.

Usage: /usr/bin/python3 analysis/steady_state.py [results/liver_steady] [results]
Reads results/<experiment>/<point>/<case>/ (each point's factor values are in
experiment.json); writes results/tables/<experiment>.{csv,md} (one row per point and
case) and results/tables/<experiment>_summary.{csv,md} (per case and factor setting,
the base scenarios side by side). A case without results is listed as "no result".
"""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import metrics  # noqa: E402
import results_index  # noqa: E402
from table_io import fmt, machine_note, write_table  # noqa: E402


def read_triangles(obj_path):
    """The triangles (#F x 3, 0-based) of an OBJ surface."""
    faces = []
    with open(obj_path) as f:
        for line in f:
            if line.startswith("f "):
                faces.append([int(t.split("/")[0]) - 1 for t in line.split()[1:4]])
    return np.array(faces, dtype=int)


def inverted_triangles(case, triangles):
    """Surface triangles of a case whose normal has turned more than 90 degrees from
    its rest normal (a crumpled or folded surface can meet the steady-state test too)."""
    surface_csv = os.path.join(case["folder"], "surface.csv")
    ids, _, u = metrics.read_displacements(surface_csv)
    if not (ids == np.arange(len(ids))).all():
        raise ValueError(f"{surface_csv}: vertices not in surface order")
    rest = results_index.observed_rest(case, "surface.csv")
    x = rest + u

    def normals(p):
        return np.cross(p[triangles[:, 1]] - p[triangles[:, 0]], p[triangles[:, 2]] - p[triangles[:, 0]])
    return int((np.einsum("ij,ij->i", normals(x), normals(rest)) < 0).sum())


def point_rows(exp_dir):
    """One dict per (point, case other than the reference), in experiment.json's order."""
    exp = results_index.Experiment(exp_dir)
    ref = exp.require_reference()
    rows = []
    for entry in exp.listed_points:
        sweep = entry.get("sweep") or {}
        scenario = entry["name"]
        cases = exp.scenarios.get(scenario, {})
        for case in entry["cases"]:
            if case == ref:
                continue
            row = {"scenario": scenario, "base": sweep.get("base", scenario), "case": case,
                   "values": sweep.get("values", {}), "ok": case in cases}
            if case in cases:
                c = cases[case]
                run, t = c["run"], c["timings"]
                row["steady"] = run.get("reached_steady_state", True)
                row["steady_frame"] = run.get("steady_frame", -1)
                row["frames"] = run.get("frames")
                max_u = run.get("max_displacement_m") or float("nan")
                row["last_change"] = run.get("last_frame_change_m", float("nan")) / max_u
                row["tolerance"] = (run.get("scenario_resolved") or {}).get("frames", {}).get("steady_tolerance")
                row["median_ms"] = (t.get("step_after_ramp") or t["step"])["median_ms"]
                row["metrics"] = exp.metrics(scenario, case) if ref in cases else None
                row["parameters"] = run.get("parameters", {})
                mesh_obj = os.path.join(exp.root, scenario, "mesh", "fine_surface.obj")
                row["inverted"] = (inverted_triangles(c, read_triangles(mesh_obj))
                                   if os.path.isfile(mesh_obj) else None)
            else:
                row["failure"] = exp.failure(scenario, case)
            rows.append(row)
    return exp, rows


def factor_labels(rows):
    labels = []
    for r in rows:
        for k in r["values"]:
            if k not in labels:
                labels.append(k)
    return labels


def make(exp_dir, out_root):
    exp, rows = point_rows(exp_dir)
    labels = factor_labels(rows)
    name = exp.name
    out_dir = os.path.join(out_root, "tables")
    table = []
    for r in rows:
        head = [r["base"], r["case"]] + [str(r["values"].get(k, "")) for k in labels]
        if not r["ok"]:
            table.append(head + ["no result"] + [""] * 7)
            continue
        m = r["metrics"] or {}
        table.append(head + [
            str(r["steady_frame"]) if r["steady"] else f"no ({r['frames']})",
            f"{r['last_change']:.1e}",
            fmt(m.get("corr_uz")), fmt(m.get("rel_l2")), fmt(m.get("load_ratio")),
            "n/a" if r["inverted"] is None else str(r["inverted"]), fmt(r["median_ms"], 2)])
    ref = exp.require_reference()
    some = next((c for s in exp.scenarios.values() for c in s.values()), None)
    write_table(out_dir, name,
                ["scenario", "case"] + labels + ["steady at frame", "last change / max |u|", "r(u_z)",
                                                 "relative L2", "|u| ratio at load", "inverted triangles",
                                                 "median ms"], table,
                f"Each case of experiments/{name}.json, against {ref} on the observed vertices. 'steady at frame': the frame at which the runner's test (max per-vertex change "
                "in a frame <= steady_tolerance x max |u|) was met, or 'no (frames run)'; 'last change / max |u|': "
                "the last frame's change over the largest displacement (the test's quantity; the tolerance is "
                f"{rows[0].get('tolerance') if rows else ''}); accuracy of a case that did not settle is its last "
                "frame's. inverted triangles: surface triangles whose normal turned more than 90 degrees from rest (a "
                "crumpled surface can be steady too). median ms: step() per frame after the load ramp. " + (machine_note({"x": some}) if some
                                                                                  else ""))

    # Summary: per case and factor setting, the pull and push outcomes side by side.
    summary = {}
    bases = []
    for r in rows:
        key = (r["case"],) + tuple(str(r["values"].get(k, "")) for k in labels)
        summary.setdefault(key, {})[r["base"]] = r
        if r["base"] not in bases:
            bases.append(r["base"])
    stable = []
    for key, by_base in summary.items():
        row = list(key)
        for b in bases:
            r = by_base.get(b)
            if r is None or not r["ok"]:
                row += ["no result", "", ""]
            else:
                m = r["metrics"] or {}
                row += [str(r["steady_frame"]) if r["steady"] else "no", fmt(m.get("rel_l2")),
                        "n/a" if r["inverted"] is None else str(r["inverted"])]
        stable.append(row)
    header = ["case"] + labels
    for b in bases:
        header += [f"{b} steady at", f"{b} rel. L2", f"{b} inverted"]
    write_table(out_dir, name + "_summary", header, stable,
                "Per case and setting, the frame at which each base scenario met the steady-state test ('no': "
                "not within the frame budget), its relative L2 error against the reference and its inverted "
                "triangles.")
    n_steady = sum(1 for r in rows if r["ok"] and r["steady"])
    return n_steady, len(rows)


if __name__ == "__main__":
    exp_dir = sys.argv[1] if len(sys.argv) > 1 else "results/liver_steady"
    out_root = sys.argv[2] if len(sys.argv) > 2 else "results"
    steady, total = make(exp_dir, out_root)
    print(f"steady-state tables of {exp_dir} written: {steady} of {total} cases steady")
