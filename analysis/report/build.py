"""The static results report: writes OUT/ (HTML pages, plotly.js beside them, the paper's
figures) from the committed results alone, to open in a browser over file:// (no server,
no network).

Usage: /usr/bin/python3 analysis/report/build.py [--results results] [--out report]
       [--data-dir DIR] [--reference-errors FILE]

Pages: index.html (the verdict per budget), <role>.html per suite scenario (scenario.py),
truth_cube.html (truthcube.py), paper.html and scaling.html (pages.py); the modules
beside this one: sources (what is read), plots (the figures), markup (the HTML).
plotly.js is Debian's (python3-plotly), copied at each build. A missing input is one
line naming its file, exit status 2 (results_index.main). docs/report.md says more.
"""
import argparse
import glob
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.dirname(HERE)]

import plotly.offline  # noqa: E402

import leaderboard  # noqa: E402
import markup  # noqa: E402
import pages  # noqa: E402
import plots  # noqa: E402
import results_index  # noqa: E402
import scenario  # noqa: E402
import sources  # noqa: E402
import truthcube  # noqa: E402
from results_index import ResultsError  # noqa: E402

OTHER_PAGES = (("truth_cube.html", "Truth Cube", "the beads, measured against predicted"),
               ("paper.html", "Paper", "the paper's tables 1-3 beside its values, and its figures as reproduced"),
               ("scaling.html", "Scaling", "frame time against mesh size, and the thread speed-ups"))


def machine_notes(tables, names):
    """'<tables>: <note>' for each distinct machine note of the named tables (RESULTS/tables/<name>.md)."""
    by_note = {}
    for name in names:
        for note in sources.machine_notes(os.path.join(tables, name + ".md")):
            by_note.setdefault(note, []).append(name)
    return [", ".join(n + ".csv" for n in found) + ": " + note for note, found in by_note.items()]


def paper_figures(results):
    """The committed figures 1, 4, 5 (RESULTS/figures/figure1*.png, ...), sorted."""
    found = []
    for prefix in pages.PAPER_FIGURES:
        mine = sorted(glob.glob(os.path.join(results, "figures", prefix + "*.png")))
        if not mine:
            raise ResultsError(f"{results}/figures/{prefix}*.png: missing (bash scripts/reproduce writes it)")
        found += mine
    return found


def bodies(results, data_flag, reference_errors):
    """{file: (title, body markup, [tables of its machine notes])} of every page."""
    suite = sources.Suite(results, reference_errors)
    role_pages = {role: f"{role}.html" for role in suite.roles}
    colours = plots.colours(c["run"]["model"] for r in suite.roles for c in suite.cases(r).values())
    out = {"index.html": ("tissuebench: the results",) + pages.index_body(suite, role_pages, OTHER_PAGES)}
    for role, name in role_pages.items():
        out[name] = (f"Scenario {role}", scenario.page_body(suite, role, colours), ["suite_scores"])
    figures = [os.path.join("figures", os.path.basename(f)) for f in paper_figures(results)]
    out["truth_cube.html"] = ("The Truth Cube's beads",) + truthcube.body(suite, data_flag)
    out["paper.html"] = ("The paper's tables 1-3 and figures",) + pages.paper_body(suite.tables, figures)
    out["scaling.html"] = ("Scaling and threads",) + pages.scaling_body(suite.tables)
    nav = [("index.html", "Home")] + [(f, r) for r, f in role_pages.items()] + [(f, t) for f, t, _ in OTHER_PAGES]
    return {name: markup.page(title, nav, body, machine_notes(suite.tables, notes))
            for name, (title, body, notes) in out.items()}


def make(results, out, data_flag=None, reference_errors=leaderboard.REFERENCE_ERRORS):
    """Writes the report into out (its earlier pages and figures replaced); returns the pages' names."""
    html = bodies(results, data_flag, reference_errors)  # everything read before anything is written
    figures = paper_figures(results)
    os.makedirs(os.path.join(out, "figures"), exist_ok=True)
    for old in glob.glob(os.path.join(out, "*.html")) + glob.glob(os.path.join(out, "figures", "*.png")):
        os.remove(old)
    for name, text in html.items():
        with open(os.path.join(out, name), "w", encoding="utf-8") as f:
            f.write(text)
    with open(os.path.join(out, markup.PLOTLY_JS), "w", encoding="utf-8") as f:
        f.write(plotly.offline.get_plotlyjs())
    for f in figures:
        shutil.copyfile(f, os.path.join(out, "figures", os.path.basename(f)))
    return sorted(html)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--results", default="results", help="the committed results (tables, suite, figures)")
    p.add_argument("--out", default="report")
    p.add_argument("--data-dir", default=None, help="where the Truth Cube's bead table is (analysis/truth_cube.py)")
    p.add_argument("--reference-errors", default=leaderboard.REFERENCE_ERRORS,
                   help="each scenario's reference error (experiments/suite_reference_errors.json)")
    a = p.parse_args()
    written = results_index.main(lambda: make(a.results, a.out, a.data_dir, a.reference_errors), "report")
    print(f"report: {len(written)} pages in {a.out}/ (open {a.out}/index.html)")


if __name__ == "__main__":
    main()
