"""Writing tables (.md and .csv) and the notes every table carries."""
from collections import Counter
import csv
import io
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
LOAD_CASES = ["pull", "push"]  # the paper's two load cases: the columns of tables 1-3
# The role of each of the paper's scenarios (experiments/paper.json gives them; the
# runner writes them into experiment.json): {body: {load case: role}}.
ROLES = {"cube": {"pull": "cube_pull", "push": "cube_push"}, "liver": {"pull": "liver_pull", "push": "liver_push"}}


def paper_values():
    """analysis/paper_values.json: the paper's published numbers (data, not code)."""
    with open(os.path.join(HERE, "paper_values.json")) as f:
        return json.load(f)


def paper_value(paper, table, case, load_case):
    """The paper's value of `table` for a case (via paper_model_of_case), or None."""
    model = paper["paper_model_of_case"].get(case)
    return paper[table].get(model, {}).get(load_case) if model else None


def fmt(x, digits=3):
    if isinstance(x, str):
        return x
    if x is None or x != x:
        return "n/a"
    return f"{x:.{digits}f}"


def write_table(out_dir, name, header, rows, notes=""):
    """Writes name.md and name.csv."""
    os.makedirs(out_dir, exist_ok=True)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    with open(os.path.join(out_dir, name + ".csv"), "w") as f:
        f.write(buf.getvalue())
    md = markdown_table(header, rows) + "\n"
    if notes:
        md += "\n" + notes.strip() + "\n"
    with open(os.path.join(out_dir, name + ".md"), "w") as f:
        f.write(md)


def markdown_table(header, rows):
    """A Markdown table (no trailing newline); '|' in a cell is escaped."""
    md = "| " + " | ".join(h.replace("|", "\\|") for h in header) + " |\n|" + "---|" * len(header)
    return md + "".join("\n| " + " | ".join(str(c).replace("|", "\\|") for c in r) + " |" for r in rows)


def machine_note(cases, threads="one thread"):
    """Machine, build and thread count of the runs (read from each run.json); where the
    cases were run on more than one machine, build or commit, each is named with how
    many cases it ran (a table's footer never claims one commit for all)."""
    def machine(b):
        return (f"{b.get('cpu_model', '?')} ({b.get('hardware_threads', '?')} hardware threads), "
                f"{b.get('build_type', '?')} build, {b.get('compiler', '?')}")
    builds = [c["run"]["build"] for c in cases.values()]
    machines = Counter(machine(b) for b in builds)
    commits = Counter(b.get("git_commit", "?") for b in builds)

    def listed(counter, what):
        if len(counter) == 1:
            return f"{what} {next(iter(counter))}"
        return f"{what}s " + ", ".join(f"{k} ({n} case{'s' if n > 1 else ''})" for k, n in sorted(counter.items()))
    on = listed(machines, "machine").removeprefix("machine ")
    note = f"Measured on {on}, {listed(commits, 'commit')}; {threads}."
    busy = busy_cases(cases)
    if busy:
        # Named by group ("role/case" keys: a role all of whose cases were busy is named once).
        groups = {}
        for name in cases:
            groups.setdefault(name.split("/")[0] if "/" in name else name, []).append(name)
        named = []
        for group, names in groups.items():
            loads = [busy[n] for n in names if n in busy]
            if len(loads) == len(names) > 1:
                named.append(f"{group} (all {len(names)} cases, load {min(loads):.1f}-{max(loads):.1f})")
            else:
                named += [f"{n} (load {busy[n]:.1f})" for n in names if n in busy]
        note += (f" On a busy machine (the 1-minute load average more than {BUSY_LOAD_MARGIN} above the hardware threads at the case's setup or "
                 "last frame: its times inflated by the other work): " + ", ".join(named) + ".")
    return note


# Margin above the hardware threads before a case is called busy. The 1-minute load
# average counts the case's own threads: a two-thread case alone on two hardware threads
# reads 1.91-2.02 (every such case in results/, 2026-11-29), which is not other work;
# the margin is twice that spread. A build beside a case adds about 0.5-2. The flag asks
# whether the machine was oversubscribed (more runnable threads than hardware threads),
# not whether anything else ran: a one-thread case beside one other thread is not flagged.
BUSY_LOAD_MARGIN = 0.2


def busy_cases(cases):
    """{case name: its highest load} for the cases whose run recorded a 1-minute load
    average above the machine's hardware threads plus BUSY_LOAD_MARGIN (timings.json
    load_average_1min, written since the runner records it; older cases are not judged)."""
    busy = {}
    for name, c in cases.items():
        load = c.get("timings", {}).get("load_average_1min") or {}
        values = [v for v in load.values() if isinstance(v, (int, float))]
        threads = c["run"]["build"].get("hardware_threads")
        if values and threads and max(values) > threads + BUSY_LOAD_MARGIN:
            busy[name] = max(values)
    return busy


def case_table(cases):
    """A Markdown table of every case: its model and the parameters the scenario set
    (from run.json), one row a case."""
    rows = []
    for name, c in cases.items():
        run = c["run"]
        given = run.get("parameters_given", run.get("parameters", {}))
        rows.append([name, run.get("model", name), ", ".join(f"{k} {v}" for k, v in sorted(given.items()))])
    return markdown_table(["case", "model", "parameters the scenario set"], rows)


def ordered_for_paper(names, paper, table):
    """Cases the paper has a value for first (in the paper's order), then the rest."""
    in_paper = [c for m in paper[table] for c in names if paper["paper_model_of_case"].get(c) == m]
    return in_paper + [c for c in names if c not in in_paper]
