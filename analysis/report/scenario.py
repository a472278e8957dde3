"""One page per suite scenario (role): the Pareto plot of error against median frame time
with the budgets and the two bands (the reference's own error, the law-to-law gap), the
scenario's leaderboard rows and scores, the reference's deformation in 3D with each
budget winner's error map on it, the tools' forces and the probes' errors."""
import math

import numpy as np

import leaderboard
import plots
import sources
from markup import Html, esc, figure, table, tag

MM = 1000.0


def value_text(v):
    return f"{v:g}" if isinstance(v, (int, float)) and not isinstance(v, bool) else str(v)


def hover(row, case, column):
    """A point's hover text: case, model, error, times, then every parameter of its run.json
    (those the suite set marked *)."""
    run = case["run"]
    given = run.get("parameters_given", {})
    lines = [f"<b>{row['case']}</b>: {run['model']}", f"{column}: {row[column]}",
             f"median {row['median (ms)']} ms, p95 {row['p95 (ms)']} ms, settled: {row['settled']}",
             "parameters (* set by the suite):"]
    lines += [f"{'*' if k in given else ''}{k} = {value_text(v)}" for k, v in sorted(run.get("parameters", {}).items())]
    return "<br>".join(lines)


def pareto_figure(suite, role, colours):
    """The scenario's ranked cases (no reference) on error against their median frame (timings.json)."""
    column, y_title = suite.accuracy(role)
    cases = suite.cases(role)
    points = []
    for row in suite.role_scores(role):
        name = row["case"]
        if name not in cases or suite.exp.is_reference(name) or not math.isfinite(sources.number(row[column])):
            continue
        case = cases[name]
        points.append({"case": name, "model": case["run"]["model"], "error": sources.number(row[column]),
                       "time_ms": case["timings"]["step"]["median_ms"], "settled": row["settled"] == "yes",
                       "hover": hover(row, case, column)})
    if not points:  # a plot of the bands alone would pass for a result
        raise sources.ResultsError(f"{role}: no ranked case has a finite '{column}' in suite_scores.csv")
    bands = [b for b in (suite.reference_band(role), suite.law_band(role)) if b is not None]
    title = f"{role}: error against time per frame (x: not settled)"
    return plots.pareto(points, bands, leaderboard.BUDGETS_MS, title, y_title, colours), bands


def pareto_caption(bands):
    budgets = ", ".join(f"{b:g}" for b in leaderboard.BUDGETS_MS)
    shaded = "; ".join(b[2] for b in bands) or "no band (neither is estimated here)"
    return (f"Each point a ranked case (named on the Pareto front; hover: its parameters from run.json); dotted: "
            f"the budgets ({budgets} ms); shaded: {shaded}. An error of 0 is drawn at {plots.ERROR_FLOOR:g}. Below "
            "a band's top the reference (its own discretisation) or the law (another standard neo-Hookean law) "
            "cannot tell the models apart.")


def surface_view(suite, role):
    """The reference's deformed observed surface in 3D coloured by |u|, or by each budget
    winner's |u - u_ref| (mm; a menu), or a paragraph saying why there is none."""
    cases = suite.cases(role)
    ref_name = suite.exp.require_reference()
    ids, rest, u_ref = sources.surface(cases[ref_name])
    if rest is None:
        return tag("p", "No 3D view: this scenario's mesh is third-party geometry (README 'Data'), whose "
                   "coordinates are never stored; its observed surface is kept by vertex index only "
                   f"({len(ids)} vertices), so the errors are in the tables above but cannot be drawn on it.")
    views = [(f"{ref_name}: |u|", np.linalg.norm(u_ref, axis=1) * MM, "|u| (mm)")]
    skipped = []
    for name, budgets in sorted(suite.winners(role).items(), key=lambda kv: min(kv[1])):
        w_ids, _, u = sources.surface(cases[name])
        if not np.array_equal(w_ids, ids):
            skipped.append(name)
            continue
        within = ", ".join(f"{b:g}" for b in budgets)
        views.append((f"{name} (best within {within} ms): |u - u_ref|", np.linalg.norm(u - u_ref, axis=1) * MM,
                      "|u - u_ref| (mm)"))
    title = f"{ref_name}'s deformed observed surface ({len(ids)} vertices); the menu: each budget winner's error"
    note = f" Not drawn (other vertices than the reference's): {', '.join(skipped)}." if skipped else ""
    return figure(f"{role}-surface-3d", plots.surface((rest + u_ref) * MM, views, title),
                  "Coloured by the reference's displacement or, chosen in the menu, by a budget winner's distance "
                  "from it at each vertex, drawn on the reference's deformed surface." + note)


def force_figures(suite, role):
    """One figure per tool of the reference: |F| (N) at each frame of every case measuring it."""
    cases = suite.cases(role)
    ref_name = suite.exp.require_reference()
    out = []
    for key in sources.tool_forces(cases[ref_name]):
        series = []
        for name, case in cases.items():
            forces = sources.tool_forces(case).get(key)
            if forces is None:
                continue
            style = {"line": {"color": "black", "width": 3}} if name == ref_name else {}
            series.append((name, forces[0], np.linalg.norm(forces[1], axis=1), style))
        out.append(figure(f"{role}-force-{key}", plots.lines(
            series, f"{key}: force on the tool at each frame", "frame", "|F| (N)", mode="lines")))
    return out


def probe_figure(suite, role):
    """|u - u_ref| (mm) at each probe of each case that wrote probes.csv (over 4 probes: RMS and max), or None."""
    cases = suite.cases(role)
    ref_name = suite.exp.require_reference()
    u_ref = sources.probes(cases[ref_name])
    if u_ref is None:
        return None
    names, errors = [], []
    for name, case in cases.items():
        u = sources.probes(case)
        if name == ref_name or u is None:
            continue
        names.append(name)
        errors.append(np.linalg.norm(u - u_ref, axis=1) * MM)
    if not names:
        return None
    errors = np.array(errors)  # cases x probes
    if errors.shape[1] <= 4:
        series = [(f"probe {p}", errors[:, p]) for p in range(errors.shape[1])]
    else:
        series = [(f"RMS over {errors.shape[1]} probes", np.sqrt(np.mean(errors ** 2, axis=1))),
                  ("max", errors.max(axis=1))]
    return figure(f"{role}-probes", plots.bars(names, series, "Probe displacement error against the reference",
                                                "|u - u_ref| (mm)", log_y=True))


def row_table(header, row):
    return table(header, [[row[h] for h in header]]) if row else tag("p", "No row for this scenario.")


def page_body(suite, role, colours):
    """The body of a scenario's page (markup)."""
    cases = suite.cases(role)
    ref = cases[suite.exp.require_reference()]
    resolved = ref["run"].get("scenario_resolved", {})
    pareto, bands = pareto_figure(suite, role, colours)
    column, _ = suite.accuracy(role)
    scores = suite.role_scores(role)
    header = [h for h in scores[0] if h != "role"]
    parts = [
        tag("p", f"Scenario {suite.exp.scenario_name(role)} ({resolved.get('file', '')}): "
                 f"{resolved.get('description', '')}. Ranked by {column}; {len(cases)} cases."),
        tag("h2", "Time against accuracy"),
        figure(f"{role}-pareto", pareto, pareto_caption(bands)),
        tag("h2", "The leaderboard's rows"),
        tag("p", "Against the reference on the same mesh (leaderboard.csv):"),
        row_table(suite.board_header, suite.board.get(role)),
        tag("p", "Against the converged field (leaderboard_converged.csv):"),
        row_table(suite.converged_header, suite.converged.get(role)),
        tag("h2", "Every case (suite_scores.csv)"),
        table(header, [[s[h] for h in header] for s in scores]),
        tag("h2", "The reference's deformation and the budget winners' errors"),
        surface_view(suite, role),
    ]
    forces = force_figures(suite, role)
    if forces:
        parts += [tag("h2", "Tool forces")] + forces
    probes = probe_figure(suite, role)
    if probes is not None:
        parts += [tag("h2", "Probe errors"), probes]
    return Html("\n".join(esc(p) for p in parts))
