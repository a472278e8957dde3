"""Writes the paper's tables into the documentation, from results/tables/, so the
README and the reproduction page show what the last reproduce run measured:

- README.md, between its table markers: short versions of tables 1-3 (table 1's
  correlations beside the relative L2 error, the per-frame medians of tables 2 and
  3, table 3's correlations), each cell copied from the table's .csv;
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
from table_io import paper_values  # noqa: E402

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


def notes(tables_dir, name):
    """The note under results/tables/<name>.md's table (its last paragraph)."""
    with open(os.path.join(tables_dir, name + ".md")) as f:
        return f.read().strip().split("\n\n")[-1]


def measured_on(tables_dir, name):
    """'Measured on <cpu> ..., commit ...; one thread.' from a timing table's note."""
    text = notes(tables_dir, name)
    start = text.find("Measured on ")
    end = text.find("one thread.", start)
    return text[start:end + len("one thread.")] if start >= 0 and end >= 0 else ""


def markdown(header, rows):
    cell = lambda c: str(c).replace("|", "\\|")  # noqa: E731
    md = "| " + " | ".join(cell(h) for h in header) + " |\n|" + "---|" * len(header) + "\n"
    return md + "".join("| " + " | ".join(cell(c) for c in r) + " |\n" for r in rows)


def metric_rows(tables_dir, name, metric):
    """{model: (pull, push)} of one metric of a *_metrics table."""
    header, rows = read_csv(tables_dir, name)
    col = {h: i for i, h in enumerate(header)}
    return {r[col["model"]]: (r[col["pull"]], r[col["push"]]) for r in rows if r[col["metric"]] == metric}


def short_table1(tables_dir):
    header, rows = read_csv(tables_dir, "table1")
    l2 = metric_rows(tables_dir, "table1_metrics", "relative L2 error")
    reference = rows[0][0].split(" vs ", 1)[1]
    body = []
    for r in rows:
        model = r[0].split(" vs ", 1)[0]
        body.append([model, r[1], r[2], r[3], r[4], *l2.get(model, ("", ""))])
    title = f"Table 1, cube: Pearson r of u_z on the top surface against {reference}, and the relative L2 error"
    note = ("Correlation is blind to scale, so the relative L2 error (||u - u_ref|| / ||u_ref||) stands beside it; "
            f"the load-point ratio and the maximum error are in the [full table]({FULL}).")
    head = ["model", "r pull", "paper", "r push", "paper", "rel. L2 pull", "rel. L2 push"]
    return title, markdown(head, body), note, reference


def short_timing(tables_dir, name, reference=None):
    """Per case: the pull's and the push's median and the paper's value; with a
    reference (table 3), also r(u_z) from <name>_metrics."""
    header, rows = read_csv(tables_dir, name)
    col = {h: i for i, h in enumerate(header)}
    r_uz = metric_rows(tables_dir, name + "_metrics", "r(u_z)") if reference else {}
    body = []
    for r in rows:
        model = r[col["model"]]
        row = [model, r[col["pull median (ms)"]], r[col["pull paper (ms)"]], r[col["push median (ms)"]],
               r[col["push paper (ms)"]]]
        if reference:
            row += ["(reference)", ""] if model == reference else list(r_uz.get(model, ("", "")))
        body.append(row)
    head = ["model", "pull (ms)", "paper", "push (ms)", "paper"] + (["r pull", "r push"] if reference else [])
    return markdown(head, body)


def short_block(tables_dir):
    paper = paper_values()
    machine = measured_on(tables_dir, "table3")
    machine = "measured as table 2" if machine == measured_on(tables_dir, "table2") else machine
    t1_title, t1, t1_note, reference = short_table1(tables_dir)
    sections = [
        (t1_title, t1, t1_note),
        ("Table 2, cube: per-frame time", short_timing(tables_dir, "table2"),
         f"Median per-frame time of `step()`; the paper's on an {paper['machine']}. "
         f"{measured_on(tables_dir, 'table2')} p95, setup and every case's parameters: [full table]({FULL})."),
        ("Table 3, liver: per-frame time, and r of u_z over the whole surface (beyond the paper)",
         short_timing(tables_dir, "table3", reference),
         f"Median per-frame time, {machine}; r against {reference}. '(not steady)': the frame budget "
         f"ended before the steady-state test was met. p95 and the other metrics: [full table]({FULL})."),
    ]
    return "\n".join(f"#### {title}\n\n{table}\n{note}\n" for title, table, note in sections)


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
