"""Writes the paper's tables into the documentation, from results/tables/, so the
README and the reproduction page show what the last reproduce run measured:

- README.md, between its table markers: one short table of the cases the paper
  reports, its values beside ours (short_block), each cell copied from a .csv;
- docs/paper_reproduction.md, between the same markers: every table in full
  (tables 1-3, their continuations and the coarse sweep), as results/tables/*.md.

analysis/reproduce.py calls update() after writing the tables into results/.

Usage: /usr/bin/python3 analysis/readme_tables.py [results/tables] [README.md] [docs/paper_reproduction.md]
(the defaults are those of this repository, whatever the working directory).
"""
import csv
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

BEGIN = "<!-- tables:begin (written by analysis/readme_tables.py) -->"
END = "<!-- tables:end -->"
# The full tables of docs/paper_reproduction.md: (results/tables/<name>.md, title).
SECTIONS = [
    ("table1", "Table 1: correlation of u_z with the fine FEM (cube top surface)"),
    ("table1_metrics", "Table 1, continued: the metrics correlation hides"),
    ("table2", "Table 2: per-frame time, cube"),
    ("table3", "Table 3: per-frame time, liver"),
    ("table3_metrics", "Table 3, continued: liver accuracy (beyond the paper)"),
    ("coarse_sweep", "Beyond the paper: the hybrid against its coarse mesh size (cube pull)"),
]
FULL = "docs/paper_reproduction.md#the-tables"  # where the README's short tables point


def read_csv(tables_dir, name):
    """results/tables/<name>.csv as (header, rows of strings)."""
    with open(os.path.join(tables_dir, name + ".csv"), newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def markdown(header, rows):
    cell = lambda c: str(c).replace("|", "\\|")  # noqa: E731
    md = "| " + " | ".join(cell(h) for h in header) + " |\n|" + "---|" * len(header) + "\n"
    return md + "".join("| " + " | ".join(cell(c) for c in r) + " |\n" for r in rows)


def column(tables_dir, name, key, value):
    """{row key: cell} of one column of results/tables/<name>.csv."""
    header, rows = read_csv(tables_dir, name)
    col = {h: i for i, h in enumerate(header)}
    return {r[col[key]].split(" vs ", 1)[0]: r[col[value]] for r in rows}


def short_block(tables_dir):
    """The README's one table: the cases the paper reports, its values beside ours:
    table 1's r(u_z) on the cube, tables 2 and 3's per-frame medians of the pull, each
    cell copied from results/tables/*.csv."""
    r_pull = column(tables_dir, "table1", "models", "pull (measured)")
    r_push = column(tables_dir, "table1", "models", "push (measured)")
    r_pull_paper = column(tables_dir, "table1", "models", "pull (paper)")
    r_push_paper = column(tables_dir, "table1", "models", "push (paper)")
    cube = column(tables_dir, "table2", "model", "pull median (ms)")
    cube_paper = column(tables_dir, "table2", "model", "pull paper (ms)")
    liver = column(tables_dir, "table3", "model", "pull median (ms)")
    liver_paper = column(tables_dir, "table3", "model", "pull paper (ms)")
    reported = [m for m in cube if r_pull_paper.get(m) or cube_paper.get(m) or liver_paper.get(m)]
    reference = next(iter(read_csv(tables_dir, "table1")[1]))[0].split(" vs ", 1)[1]
    body = [[m, r_pull.get(m, "(reference)" if m == reference else ""), r_pull_paper.get(m, ""),
             r_push.get(m, "(reference)" if m == reference else ""), r_push_paper.get(m, ""),
             cube.get(m, ""), cube_paper.get(m, ""), liver.get(m, ""), liver_paper.get(m, "")] for m in reported]
    head = ["model", "r(u_z) cube pull", "paper", "r(u_z) cube push", "paper", "cube pull (ms)", "paper",
            "liver pull (ms)", "paper"]
    note = (f"r(u_z): Pearson correlation of the top surface's vertical displacement with {reference}'s (table 1); "
            "ms: median per-frame time (tables 2 and 3; the paper's on its own machine). Every model, metric, "
            f"p95 and where it was measured: [the full tables]({FULL}).")
    return markdown(head, body) + "\n" + note + "\n"


def full_block(tables_dir):
    body = []
    for name, title in SECTIONS:
        with open(os.path.join(tables_dir, name + ".md")) as f:
            body.append(f"### {title}\n\n{f.read().strip()}\n")
    return "\n".join(body)


def replace_block(path, block):
    """Writes `block` between the markers of the file at `path`."""
    with open(path) as f:
        text = f.read()
    if BEGIN not in text or END not in text:
        raise ValueError(f"{path}: table markers not found")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(path, "w") as f:
        f.write(head + BEGIN + "\n\n" + block + "\n" + END + tail)


def update(tables_dir, readme=os.path.join(ROOT, "README.md"),
           reproduction=os.path.join(ROOT, "docs", "paper_reproduction.md")):
    replace_block(readme, short_block(tables_dir))
    replace_block(reproduction, full_block(tables_dir))


if __name__ == "__main__":
    args = sys.argv[1:]
    update(args[0] if args else os.path.join(ROOT, "results", "tables"), *args[1:3])
