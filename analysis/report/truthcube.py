"""The Truth Cube's page: the CT-tracked beads measured against each model's predicted
positions. The measured table is third-party data read from the data directory as
analysis/truth_cube.py reads it (--data-dir, else $TISSUEBENCH_DATA, else ../shared);
without it the page says so and shows the committed tables alone."""
import os
import sys

import numpy as np

import leaderboard
import plots
import sources
import truth_cube
from markup import Html, esc, figure, table, tag
from results_index import ResultsError


def roles(suite):
    return [r for r in suite.roles if r.startswith(leaderboard.TRUTH_CUBE_ROLE_PREFIX)]


def suite_bars(suite):
    """Bead RMS (mm) of every case, grouped by the suite's Truth Cube scenarios (suite_scores.csv)."""
    tc = roles(suite)
    names = list(dict.fromkeys(s["case"] for r in tc for s in suite.role_scores(r)))
    series = []
    for role in tc:
        by_case = {s["case"]: sources.number(s["bead RMS (mm)"]) for s in suite.role_scores(role)}
        series.append((role, [by_case.get(n, float("nan")) for n in names]))
    return figure("truth-cube-suite-rms", plots.bars(names, series, "The suite: RMS bead error of every case",
                                                     "bead RMS (mm)"))


def bead_figures(suite, beads):
    """Per Truth Cube role: measured against predicted vertical bead displacement (mm) of every case
    (the reference and the budget winners shown, the others a click away in the legend); then
    the beads of the largest strain coloured by the reference's error."""
    ref_name = suite.exp.require_reference()
    out, last = [], None
    for role in roles(suite):
        shown = {ref_name} | set(suite.winners(role))
        series, lo, hi = [], 0.0, 0.0
        for name, case in suite.cases(role).items():
            read = truth_cube.case_beads(case, beads.positions, beads.strains)
            if read is None:
                continue
            rest, measured, predicted = read
            if name == ref_name:
                last = (role, read)
            du, dp = measured[:, 2] - rest[:, 2], predicted[:, 2] - rest[:, 2]
            lo, hi = min(lo, du.min(), dp.min()), max(hi, du.max(), dp.max())
            series.append((name, du, dp, {"visible": True if name in shown else "legendonly",
                                          "marker": {"size": 4}}))
        out.append(figure(f"{role}-beads", plots.lines(
            series, f"{role}: vertical bead displacement, predicted against measured (every bead)",
            "measured u_z (mm)", "predicted u_z (mm)", mode="markers")
            .add_scatter(x=[lo, hi], y=[lo, hi], mode="lines", name="measured = predicted",
                         line={"color": "black", "width": 1})))
    if last is not None:
        role, (rest, measured, predicted) = last
        error = np.linalg.norm(predicted - measured, axis=1)
        out.append(figure("truth-cube-beads-3d", plots.surface(
            measured, [(ref_name, error, "mm")], f"{role}: the {len(error)} beads at their measured positions, "
            f"coloured by |predicted - measured| of {ref_name}"), "Bead positions in the model's frame (mm)."))
    return out


def body(suite, data_flag):
    """(markup, [tables whose notes say where the numbers were measured])."""
    tables = suite.tables
    header, rows = sources.read_csv(os.path.join(tables, "truth_cube.csv"))
    parts = [tag("p", "The Truth Cube (Kerdok et al. 2003): a silicone cube whose 343 embedded beads were "
                      "tracked by CT while a plate compressed it by 5, 12.5 and 18.25 %. Each model's beads are "
                      "its displacement at the beads' rest positions (probes.csv) added to them, against the "
                      "measured positions (docs/truth_cube.md)."),
             tag("h2", "The suite's Truth Cube scenarios"), suite_bars(suite)]
    try:
        beads = leaderboard.Beads(data_flag)
    except ResultsError as e:
        print(f"report: truth_cube.html without the beads: {e}", file=sys.stderr)
        parts.append(tag("p", f"The measured bead table is not in the data directory ({e}); the bead plots "
                              "need it (README 'Data'). The tables below are the committed ones."))
    else:
        parts += bead_figures(suite, beads)
    parts += [tag("h2", "Bonded and sliding plates (truth_cube.csv)"),
              tag("p", "The Truth Cube experiment (experiments/truth_cube.json), scored by analysis/truth_cube.py."),
              table(header, rows)]
    by_case = {}
    for r in rows:
        by_case.setdefault(f"{r[1]} {r[0]} %", {})[r[2]] = sources.number(r[3])
    names = list(dict.fromkeys(r[2] for r in rows))
    parts.append(figure("truth-cube-experiment-rms", plots.bars(
        names, [(k, [v.get(n, float("nan")) for n in names]) for k, v in by_case.items()],
        "truth_cube.csv: RMS bead error by plate and strain", "bead RMS (mm)")))
    return Html("\n".join(esc(p) for p in parts)), ["truth_cube", "suite_scores"]
