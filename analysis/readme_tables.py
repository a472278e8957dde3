"""Copies results/tables/*.md into README.md between its table markers, so the
README shows the tables the last reproduce run measured.

Usage: /usr/bin/python3 analysis/readme_tables.py [results/tables] [README.md]
"""
import os
import sys

BEGIN = "<!-- tables:begin (written by analysis/readme_tables.py) -->"
END = "<!-- tables:end -->"
SECTIONS = [
    ("table1", "Table 1: correlation of u_z with the fine FEM (cube top surface)"),
    ("table1_metrics", "Table 1, continued: the metrics correlation hides"),
    ("table2", "Table 2: per-frame time, cube"),
    ("table3", "Table 3: per-frame time, liver"),
    ("table3_metrics", "Table 3, continued: liver accuracy (beyond the paper)"),
    ("coarse_sweep", "Beyond the paper: the hybrid against its coarse mesh size (cube pull)"),
]


def update(tables_dir, readme):
    text = open(readme).read()
    if BEGIN not in text or END not in text:
        raise ValueError(f"{readme}: table markers not found")
    body = []
    for name, title in SECTIONS:
        with open(os.path.join(tables_dir, name + ".md")) as f:
            body.append(f"#### {title}\n\n{f.read().strip()}\n")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(readme, "w") as f:
        f.write(head + BEGIN + "\n\n" + "\n".join(body) + "\n" + END + tail)


if __name__ == "__main__":
    update(sys.argv[1] if len(sys.argv) > 1 else "results/tables", sys.argv[2] if len(sys.argv) > 2 else "README.md")
