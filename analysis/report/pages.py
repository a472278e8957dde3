"""The report's pages other than the scenarios' (scenario.py) and the Truth Cube's
(truthcube.py): the index (what tissuebench is, the verdict per budget, links), the
paper's tables beside its values, and the scaling and thread plots. Each body function
returns (markup, [tables whose notes say where the numbers were measured])."""
import os
import re

import plots
import sources
import table_io
from markup import Html, esc, figure, link, table, tag

INTRO = ("tissuebench measures the accuracy and the speed of real-time soft-tissue deformation models on the "
         "same scenarios, against the same reference (Newton's neo-Hookean answer on the same fine mesh), so that "
         "a researcher choosing a model for a surgical simulator can see what each one costs a frame and how far "
         "it is from the elastic solution. It began as a reproduction of Tan, Zheng and Zhou (2021)'s hybrid "
         "model (a coarse linear FEM pinning a fine PBD surface) and runs it beside the models the field uses "
         "(FEM, PBD and XPBD, condensed, embedded, VBD, volumetric XPBD, projective dynamics) behind one interface.")
# The paper's tables: (csv name, paper_values.json key, what a row's first cell names).
PAPER_TABLES = (("table1", "table1_correlation_top_surface", "Pearson r of u_z over the cube's top surface"),
                ("table2", "table2_ms_per_frame", "the cube: ms per frame"),
                ("table3", "table3_liver_ms_per_frame", "the liver: ms per frame"))
PAPER_FIGURES = ("figure1", "figure4", "figure5")


def linked_rows(rows, pages):
    """Table rows whose first cell (a role, maybe flagged) links to the role's page."""
    return [[link(pages[sources.role_of(r[0])], r[0]) if sources.role_of(r[0]) in pages else r[0]] + r[1:]
            for r in rows]


def index_body(suite, pages, others):
    """pages: {role: file}; others: [(file, title, what)] of the other pages."""
    board = [[r[h] for h in suite.board_header] for r in suite.board.values()]
    converged = [[r[h] for h in suite.converged_header] for r in suite.converged.values()]
    scenario_links = Html(", ".join(link(f, role) for role, f in pages.items()))
    items = "".join(f"<li>{link(f, t)}: {esc(w)}</li>" for f, t, w in others)
    parts = [tag("p", INTRO),
             tag("h2", "The verdict per budget"),
             tag("p", "Per scenario, the most accurate model whose median frame fits 0.1, 1 and 16 ms, and its "
                      "error (relative L2 of the observed surface against the scenario's reference; on the Truth "
                      "Cube the RMS bead error in mm); in brackets a more accurate one missing the budget by less "
                      "than 1.5 times. The last column: the reference's own estimated discretisation error, below "
                      "which models differ on what the reference cannot resolve (docs/suite.md)."),
             table(suite.board_header, linked_rows(board, pages)),
             tag("h3", "Against the converged field"),
             tag("p", "The same cells ranked against the finest run of the reference study, where it has one."),
             table(suite.converged_header, linked_rows(converged, pages)),
             tag("h2", "Pages"),
             Html(f"<p>One page per scenario: {scenario_links}.</p><ul>{items}</ul>")]
    return Html("\n".join(esc(p) for p in parts)), ["leaderboard"]


def paper_checks(name, key, header, rows, paper):
    """[(label, measured, paper value)] of the cells the paper has a value for, and the
    sentences where the table's paper column differs from analysis/paper_values.json."""
    pairs, differ = [], []
    for row in rows:
        case = row[0].split(" vs ")[0]
        for load in table_io.LOAD_CASES:
            value = table_io.paper_value(paper, key, case, load)
            if value is None:
                continue
            measured = next(i for i, h in enumerate(header) if h.startswith(load) and "paper" not in h)
            quoted = next(i for i, h in enumerate(header) if h.startswith(load) and "paper" in h)
            pairs.append((f"{case} {load}", sources.number(row[measured]), value))
            if sources.number(row[quoted]) != value:
                differ.append(f"{name}.csv gives {row[quoted]} for {case} {load}, paper_values.json {value}")
    return pairs, differ


def paper_body(tables, figures):
    """figures: [file] of the committed figures copied beside the page."""
    paper = table_io.paper_values()
    parts = [tag("p", f"Tables 1-3 of {paper['source']}, measured here beside the paper's values "
                      f"(analysis/paper_values.json; the paper's machine: {paper['machine']}).")]
    timing = []
    for name, key, what in PAPER_TABLES:
        header, rows = sources.read_csv(os.path.join(tables, name + ".csv"))
        pairs, differ = paper_checks(name, key, header, rows, paper)
        parts += [tag("h2", f"Table {name[-1]}: {what}"), table(header, rows)]
        if differ:
            parts.append(tag("p", "Differs from paper_values.json: " + "; ".join(differ) + "."))
        if name == "table1":
            parts.append(figure("paper-table1", plots.bars(
                [p[0] for p in pairs], [("measured", [p[1] for p in pairs]), ("paper", [p[2] for p in pairs])],
                "Table 1: measured against the paper", "Pearson r")))
        else:
            timing += [(f"{name}: {p[0]}",) + p[1:] for p in pairs]
    parts.append(figure("paper-timing", plots.bars(
        [p[0] for p in timing], [("measured", [p[1] for p in timing]), ("paper", [p[2] for p in timing])],
        "Tables 2 and 3: ms per frame, measured against the paper (another machine: compare the order)",
        "ms per frame", log_y=True)))
    parts.append(tag("h2", "The paper's figures, as reproduced"))
    parts += [Html(f'<p><img class="static" src="{f}" alt="{esc(f)}"><br><span class="note">{esc(f)}</span></p>')
              for f in figures]
    return Html("\n".join(esc(p) for p in parts)), ["table2", "table3"]


def series_of(header, rows, x, y, key="series"):
    """[(series, [x], [y], {})] of a table's rows, in their order; rows without a y are left out."""
    col = {h: i for i, h in enumerate(header)}
    out = {}
    for r in rows:
        value = sources.number(r[col[y]])
        if value == value:
            xs, ys = out.setdefault(r[col[key]], ([], []))
            xs.append(sources.number(r[col[x]]))
            ys.append(value)
    return [(name, xs, ys, {}) for name, (xs, ys) in out.items()]


def styled(series, colours, suffix="", dash=None):
    """series_of's series named name + suffix, each drawn in its name's colour (colours: plots.colours),
    dashed as `dash` says (None: solid)."""
    out = []
    for name, xs, ys, _ in series:
        line = {"color": colours[name]} if dash is None else {"color": colours[name], "dash": dash}
        out.append((name + suffix, xs, ys, {"line": line, "marker": {"color": colours[name]}}))
    return out


def target(header):
    """The speed-up target a thread table's last column names ("medians >= 1.7x" -> 1.7)."""
    m = re.search(r">= ([0-9.]+)x", header[-1])
    return float(m.group(1)) if m else None


def scaling_body(tables):
    read = {n: sources.read_csv(os.path.join(tables, n + ".csv"))
            for n in ("scaling", "thread_speedup", "nonlinear_thread_speedup", "nonlinear_cost_slope")}
    header, rows = read["scaling"]
    parts = [tag("p", "How a frame's cost grows with the mesh, and what a second thread buys "
                      "(docs/scaling.md, docs/realtime_nonlinear.md)."),
             tag("h2", "The hybrid and PBD from 682 to 99 848 surface vertices (scaling.csv)"),
             figure("scaling-median", plots.lines(series_of(header, rows, "surface vertices", "median ms"),
                                                  "Median time per frame", "surface vertices", "median ms",
                                                  log_x=True, log_y=True, hlines=[(16, "16 ms")]), "Click a legend "
                    "entry to hide its series."),
             figure("scaling-speedup", plots.lines(series_of(header, rows, "surface vertices", "2 threads speed-up"),
                                                   "Two threads against one, same sweep domains", "surface vertices",
                                                   "speed-up", log_x=True, hlines=[(1, "1x")]))]
    for name, x, what in (("thread_speedup", "surface vertices", "The hybrid and PBD, interleaved repetitions"),
                          ("nonlinear_thread_speedup", "tets", "VBD and XPBD on the cube's fine volume")):
        header, rows = read[name]
        goal = target(header)
        colours = plots.colours(r[0] for r in rows)
        medians = styled(series_of(header, rows, x, "speed-up (medians)"), colours)
        minima = styled(series_of(header, rows, x, "speed-up (minima)"), colours, " (minima)", "dot")
        hlines = [(goal, f"target {goal:g}x")] if goal else []
        parts += [tag("h2", f"{what} ({name}.csv)"),
                  figure(f"{name}-speedup", plots.lines(medians + minima, "Two-thread speed-up", x, "speed-up",
                                                        log_x=True, hlines=hlines)),
                  table(header, rows)]
    header, rows = read["nonlinear_thread_speedup"]
    colours = plots.colours(r[0] for r in rows)
    cost = (styled(series_of(header, rows, "tets", "1 thread median ms"), colours, ", 1 thread") +
            styled(series_of(header, rows, "tets", "2 threads median ms"), colours, ", 2 threads", "dot"))
    header, rows = read["nonlinear_cost_slope"]
    parts += [tag("h2", "Cost against size (nonlinear_cost_slope.csv)"),
              figure("nonlinear-cost", plots.lines(cost, "Median frame against tets", "tets", "median ms",
                                                   log_x=True, log_y=True)),
              table(header, rows),
              Html("<details><summary>scaling.csv in full</summary>" + table(*read["scaling"]) + "</details>")]
    return Html("\n".join(esc(p) for p in parts)), list(read)
