"""Regenerates every table and figure from raw results.

Usage: /usr/bin/python3 analysis/reproduce.py [results/paper] [results]
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import coarse_sweep  # noqa: E402
import figures  # noqa: E402
import readme_tables  # noqa: E402
import tables  # noqa: E402

if __name__ == "__main__":
    exp_dir = sys.argv[1] if len(sys.argv) > 1 else "results/paper"
    out = sys.argv[2] if len(sys.argv) > 2 else "results"
    tables.make_tables(exp_dir, os.path.join(out, "tables"))
    figures.make_figures(exp_dir, os.path.join(out, "figures"))
    sweep_dir = os.path.join(os.path.dirname(exp_dir), "coarse_sweep")
    if os.path.isdir(sweep_dir):
        coarse_sweep.make(sweep_dir, out)
    readme = os.path.join(os.path.dirname(HERE), "README.md")
    if os.path.abspath(out) == os.path.join(os.path.dirname(HERE), "results"):
        readme_tables.update(os.path.join(out, "tables"), readme)  # README shows the committed results
    print(f"tables in {out}/tables, figures in {out}/figures")
