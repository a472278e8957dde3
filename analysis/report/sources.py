"""What the report reads from the committed results, each missing input a one-line
ResultsError naming its file (results_index.main prints it).

- read_csv(path) -> (header [str], rows [[str]]); number(cell) -> float (NaN for n/a).
- machine_notes(md path) -> [str]: the "Measured ..." sentences under a table.
- Suite(results, reference_errors): the suite's cases (results_index.Experiment of
  RESULTS/suite) with the tables they are scored in (RESULTS/tables: suite_scores,
  leaderboard, leaderboard_converged, law_sensitivity) and each scenario's reference
  error (experiments/suite_reference_errors.json), all by role.
- surface(case) -> (ids #V, rest #V x 3 m or None, u #V x 3 m): a case's observed surface;
  tool_forces(case) -> {tool: (frames #F, forces #F x 3 N)}; probes(case) -> #P x 3 m or None.
"""
import csv
import math
import os
import re

import numpy as np

import law_sensitivity
import leaderboard
import metrics
import results_index
from results_index import ResultsError

# suite_scores.csv's column of what a scenario ranks by (leaderboard.accuracy_key).
ACCURACY_COLUMNS = {"rel_l2": "rel L2 vs reference", "bead_rms_mm": "bead RMS (mm)"}
# A machine note: "Measured [when] on ...", to a full stop before a space or the end (version
# numbers, loads and commits keep their dots), then the busy-machine sentence where there is one.
MEASURED = re.compile(r"Measured (?:\S+ )?on .*?\.(?=\s|$)(?:\s+On a busy machine .*?\.(?=\s|$))?")


def require(path, how="the command that writes it"):
    """path, or a ResultsError naming it."""
    if not os.path.isfile(path):
        raise ResultsError(f"{path}: missing ({how})")
    return path


def read_csv(path):
    """(header, rows) of a committed table; a missing or empty one is a ResultsError."""
    with open(require(path, "a committed table: regenerate it with the script named in its .md"), newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ResultsError(f"{path}: empty table (no header)")
    return rows[0], rows[1:]


def read_dicts(path):
    """The rows of a committed table as {column: cell}."""
    header, rows = read_csv(path)
    return [dict(zip(header, r)) for r in rows]


def number(cell):
    """A table cell as a float: NaN for n/a, an empty cell or text."""
    try:
        return float(cell)
    except (TypeError, ValueError):
        return math.nan


def machine_notes(md_path):
    """The "Measured ..." sentences of a table's notes (its .md below the table), in order, once each."""
    with open(require(md_path, "a committed table's notes"), encoding="utf-8") as f:
        text = " ".join(line.strip() for line in f if not line.startswith("|"))  # no table, one line
    return list(dict.fromkeys(m.group(0) for m in MEASURED.finditer(text)))


def surface(case):
    """(ids #V, rest #V x 3 m or None, u #V x 3 m) of a case's top_surface.csv (metrics.read_displacements)."""
    path = require(os.path.join(case["folder"], "top_surface.csv"), "written by tissuebench run")
    try:
        return metrics.read_displacements(path)
    except ValueError as e:
        raise ResultsError(str(e)) from None


def tool_forces(case):
    """{tool key: (frames #F ints, forces #F x 3 N)} of a case's reactions.csv, the support
    left out (it is not an instrument); {} when the case wrote none."""
    path = os.path.join(case["folder"], "reactions.csv")
    if not os.path.isfile(path):
        return {}
    _, rows = leaderboard.read_csv_rows(path)
    out = {}
    for key in sorted({r[1] for r in rows if r[1] != "support"}):
        mine = sorted((int(r[0]), [float(v) for v in r[3:6]]) for r in rows if r[1] == key)
        out[key] = (np.array([f for f, _ in mine]), np.array([v for _, v in mine]).reshape(-1, 3))
    return out


def probes(case):
    """#P x 3 probe displacements (m) of a case, None when it wrote no probes.csv."""
    return leaderboard.probe_displacements(case["folder"])


def role_of(cell):
    """The role in a leaderboard's first cell ("cube_pull_disc (times of 2 cases from a busy machine)")."""
    return cell.split(" ")[0]


class Suite:
    """The suite's results and tables, by role.

    roles: [role] in suite_scores.csv's order; exp: results_index.Experiment of RESULTS/suite;
    board, converged: {role: {column: cell}} of leaderboard.csv, leaderboard_converged.csv;
    tables: RESULTS/tables.
    """

    def __init__(self, results, reference_errors=leaderboard.REFERENCE_ERRORS):
        self.tables = os.path.join(results, "tables")
        self.scores = read_dicts(os.path.join(self.tables, "suite_scores.csv"))
        self.roles = list(dict.fromkeys(s["role"] for s in self.scores))
        self.board_header, board = read_csv(os.path.join(self.tables, "leaderboard.csv"))
        self.board = {role_of(r[0]): dict(zip(self.board_header, r)) for r in board}
        self.converged_header, converged = read_csv(os.path.join(self.tables, "leaderboard_converged.csv"))
        self.converged = {role_of(r[0]): dict(zip(self.converged_header, r)) for r in converged}
        self.law = read_dicts(os.path.join(self.tables, "law_sensitivity.csv"))
        self.declared = leaderboard.read_reference_errors(reference_errors)
        self.exp = results_index.Experiment(os.path.join(results, "suite"))
        self.exp.require_reference()
        for role in self.roles:
            if role not in self.board:
                raise ResultsError(f"{self.tables}/leaderboard.csv: no row for {role} (suite_scores.csv has it)")

    def cases(self, role):
        """{case: case dict} of the scenario in `role`."""
        return self.exp.by_role(role)

    def accuracy(self, role):
        """(suite_scores column, axis title) of what `role` ranks by."""
        key = leaderboard.accuracy_key(role)
        return ACCURACY_COLUMNS[key], ("bead RMS error (mm)" if key == "bead_rms_mm"
                                       else "relative L2 error against the reference")

    def role_scores(self, role):
        """suite_scores.csv's rows of `role` ({column: cell}), in the table's order."""
        return [s for s in self.scores if s["role"] == role]

    def winners(self, role):
        """{case: [budgets in ms]}: the case each budget cell of the leaderboard names first."""
        names = sorted(self.cases(role), key=len, reverse=True)  # "pd-5" before "pd"
        out = {}
        for budget in leaderboard.BUDGETS_MS:
            cell = self.board[role][f"best within {budget:g} ms"]
            name = next((n for n in names if cell.startswith(n + " ")), None)
            if name is not None:
                out.setdefault(name, []).append(budget)
        return out

    def reference_band(self, role):
        """(low, high, text) of the reference's own estimated error on the ranking's axis, or None:
        below `high` (a relative L2) the reference cannot tell models apart; on the Truth Cube the
        reference's bead RMS and that of the converged field."""
        entry = self.declared.get(role)
        if not entry or entry.get("field_error") is None:
            return None
        text = "reference's own error (est.): " + leaderboard.reference_error_text(entry)
        if leaderboard.accuracy_key(role) == "bead_rms_mm":
            beads = entry.get("qoi", {}).get("bead_rms_mm", {})
            if beads.get("finest_value") is None:
                return None
            return min(beads["value"], beads["finest_value"]), max(beads["value"], beads["finest_value"]), text
        return 0.0, entry["field_error"], text

    def law_band(self, role):
        """(low, high, text) of the law-to-law gap on the ranking's axis, or None: the largest
        difference of two nonlinear laws' surface fields (law_sensitivity.law_gap), on the
        Truth Cube the spread of their bead RMS errors."""
        if leaderboard.accuracy_key(role) == "bead_rms_mm":
            laws = {r["compared"]: number(r["value"]) for r in self.law
                    if r["role"] == role and r["quantity"] == law_sensitivity.BEADS
                    and r["compared"] in ("coupled", "isochoric", "stable")}
            values = [v for v in laws.values() if math.isfinite(v)]
            if len(values) < 2:
                return None
            return min(values), max(values), f"law-to-law gap: bead RMS {min(values):.3g}-{max(values):.3g} mm"
        pairs = {r["compared"]: number(r["value"]) for r in self.law if r["role"] == role
                 and r["quantity"] == "surface field"}
        gap = law_sensitivity.law_gap(pairs)
        return None if not math.isfinite(gap) else (0.0, gap, f"law-to-law gap: {gap:.3g}")
