"""Every number the README and the findings pages' summaries quote is a number of the
table they cite; no commit hash in the prose.

The convention (docs/design.md, "Findings pages"):

- A findings page (FINDINGS_PAGES) opens with its answer: its first second-level
  heading is `## Summary`, and everything from the top of the page to the end of that
  section fits one screen (SUMMARY_MAX_LINES lines, SUMMARY_MAX_WORDS words).
- Each item of a summary (a list item or a paragraph) cites at least one table: a link
  to a table under results/ (`results/tables/leaderboard.md`, a study's
  `results/<study>/tables/*.md` or `.csv`; not a raw result file), or to a heading of a page (`#anchor`,
  `page.md#anchor`) whose section holds a Markdown table.
- Every number an item quotes is a number of a table it cites, rounded to the
  significant digits quoted (`0.47` is the table's 0.469; `47 %` its 0.469 or 46.9;
  `1.75x` its 1.75).
  Not claims, and so not checked: numbers in code spans (commands, parameter values:
  `iterations 10`), in link texts, in named references (eq. 19, table 1, section 1.4),
  years (1990-2039), orders of magnitude written 10^n, and integers up to
  SMALL_INTEGER (counts such as two threads or 10 iterations).
- README.md: every paragraph or list item that quotes a number is a claim, checked
  the same way (its generated tables are checked by their own tests).
- Neither README.md nor docs/*.md names a commit in its prose: where and when a number
  was measured is said once, under its table.

Run alone: /usr/bin/python3 analysis/doc_claims.py [README.md docs/suite.md ...]
(prints each problem as `file:line: message`; exit status 1 if any).
"""
import math
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

FINDINGS_PAGES = [
    "paper_reproduction.md", "variants.md", "liver_steady_state.md", "shapes.md", "xpbd.md", "suite.md",
    "realtime_nonlinear.md", "scaling.md", "pbd_library_comparison.md", "reference_convergence.md",
    "truth_cube.md", "determinism.md", "robustness.md", "prediction_leaderboard.md",
]
SUMMARY_HEADING = "Summary"
SUMMARY_MAX_LINES = 45
SUMMARY_MAX_WORDS = 500
SMALL_INTEGER = 20

FENCE = re.compile(r"^(```|~~~).*?^\1[^\n]*$", re.M | re.S)
CODE_SPAN = re.compile(r"(`+)(.+?)\1", re.S)
LINK = re.compile(r"!?\[((?:[^\[\]\\]|\\.|\[[^\]]*\])*)\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
COMMENT = re.compile(r"<!--.*?-->", re.S)
# A commit named in prose: 7 to 40 hex digits with at least one digit and one letter.
COMMIT = re.compile(r"\b(?=[0-9a-f]*[0-9])(?=[0-9a-f]*[a-f])[0-9a-f]{7,40}\b")
# A reference by name: eq. 19, eqs. 12-30, section 1.4, table 2 (a list of integers or
# dotted section numbers after it, never a measured value such as "table 2, 1.91 ms").
NAMED_REFERENCE = re.compile(
    r"\b(?:eqs?\.?|equations?|sections?|tables?|figures?|figs?\.?|steps?-|chapters?|issues?|PR|stop)"
    r"\s*#?\(?\d+(?:\.\d+)*\)?(?:(?:\s*-\s*|\s+(?:and|to)\s+)\(?\d+(?:\.\d+)*\)?)*", re.I)
YEAR = re.compile(r"(?<![\d.])(?:19[9]\d|20[0-3]\d)(?![\d.]\d)")
POWER = re.compile(r"\b10\^-?\d+|\b\d+(?:\.\d+)?\s*[x*]\s*10\^-?\d+")
# A number as written: digits grouped by spaces in thousands (17 800), a decimal part,
# an exponent; an x after it is a factor (1.75x); a following % makes it a percentage,
# and the first end of a range whose second is one (95-97 %).
NUMBER = re.compile(r"(?<![\w.])(\d{1,3}(?: \d{3})+|\d+)(\.\d+)?(e[-+]?\d+)?x?(?![\w]|\.\d)(\s?%)?")
PERCENT_RANGE_END = re.compile(r"\s*(?:-|to)\s*\d[\d.]*(?:e[-+]?\d+)?\s?%")


# A block a script writes between markers (<!-- name:begin ... --> ... <!-- name:end -->):
# its tables are checked by their own tests, and their notes say where and when they
# were measured, commit included.
GENERATED = re.compile(r"<!-- (\w+):begin.*?<!-- \1:end -->", re.S)


def without_generated(text):
    """The text with generated blocks blanked (line breaks kept)."""
    return GENERATED.sub(lambda m: "\n" * m.group(0).count("\n"), text)


def without_code(text):
    """The text with fenced blocks, HTML comments and code spans blanked (line breaks kept)."""
    blank = lambda m: "\n" * m.group(0).count("\n")  # noqa: E731
    return CODE_SPAN.sub(blank, COMMENT.sub(blank, FENCE.sub(blank, text)))


def quoted_numbers(text):
    """[(value, significant digits, is_percent, as written)] of the claims in `text`
    (already without code), skipping link texts and targets, named references, years
    and powers of ten."""
    text = LINK.sub(" ", text)
    for pattern in (NAMED_REFERENCE, POWER, YEAR):
        text = pattern.sub(" ", text)
    out = []
    for m in NUMBER.finditer(text):
        integer, fraction, exponent, percent = m.group(1), m.group(2) or "", m.group(3) or "", m.group(4)
        percent = percent or PERCENT_RANGE_END.match(text, m.end())
        digits = integer.replace(" ", "")
        written = digits + fraction + exponent
        value = float(written)
        mantissa = (digits + fraction[1:]).lstrip("0")
        if not fraction:
            mantissa = mantissa.rstrip("0")
        out.append((value, max(len(mantissa), 1), bool(percent), m.group(0).strip()))
    return out


def table_numbers(text):
    """Every number in a table's text (the table, its notes), as floats."""
    return [float(m.group(1).replace(" ", "") + (m.group(2) or "") + (m.group(3) or ""))
            for m in NUMBER.finditer(text)]


def round_sig(x, digits):
    if x == 0 or not math.isfinite(x):
        return x
    return round(x, digits - 1 - int(math.floor(math.log10(abs(x)))))


def matches(claim, numbers):
    """Whether a quoted number (quoted_numbers' tuple) is one of `numbers` rounded to the
    digits quoted; a percentage also matches a fraction x100."""
    value, digits, percent, _ = claim
    if value == 0:
        return any(round_sig(v, digits) == 0 or abs(v) < 10 ** -digits for v in numbers)
    for v in numbers:
        for scaled in ((v, v * 100) if percent else (v,)):
            r = round_sig(abs(scaled), digits)
            if math.isclose(r, value, rel_tol=1e-9):
                return True
    return False


def is_exempt(claim):
    value, _, percent, written = claim
    return not percent and value.is_integer() and "." not in written and "e" not in written \
        and value <= SMALL_INTEGER


def blocks(text):
    """[(first line number, block text)] of the paragraphs and list items of Markdown
    text already without code: headings, table rows and blank lines end a block; a new
    list item starts one."""
    out, current, start = [], [], 0
    for number, line in enumerate(text.split("\n"), 1):
        stripped = line.strip()
        item = re.match(r"^\s*(?:[-*+]|\d+\.)\s+", line)
        if not stripped or HEADING.match(line) or stripped.startswith("|") or item:
            if current:
                out.append((start, "\n".join(current)))
                current = []
            if item and not HEADING.match(line):
                current, start = [line], number
            continue
        if not current:
            start = number
        current.append(line)
    if current:
        out.append((start, "\n".join(current)))
    return out


def slug(heading):
    """GitHub's anchor of a heading (as tests/analysis/test_doc_links.py computes it)."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)
    text = CODE_SPAN.sub(lambda m: m.group(2), text)
    text = re.sub(r"<[^>]+>", "", text)
    return re.sub(r"[^\w\- ]", "", text.strip().lower()).replace(" ", "-")


def section_tables(path, anchor):
    """The Markdown table rows under the heading `anchor` of `path` (up to the next
    heading of the same or a higher level), or None if no such heading."""
    with open(path, encoding="utf-8") as f:
        lines = FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), f.read()).split("\n")
    seen, level, rows = {}, None, []
    for line in lines:
        m = HEADING.match(line)
        if m:
            base = slug(m.group(2))
            n = seen.get(base, 0)
            seen[base] = n + 1
            name = base if n == 0 else f"{base}-{n}"
            if level is not None and len(m.group(1)) <= level:
                break
            if level is None and name == anchor:
                level = len(m.group(1))
            continue
        if level is not None and line.strip().startswith("|"):
            rows.append(line)
    return None if level is None else "\n".join(rows)


def cited_tables(block, page):
    """{target: numbers} of the tables a block cites: files under results/ (a .md table
    with its .csv beside it) and headings whose section holds a table. Targets that are
    neither are left out."""
    out = {}
    for m in LINK.finditer(block):
        target = m.group(2)
        if re.match(r"^[a-z]+:", target):
            continue
        path, _, anchor = target.partition("#")
        full = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
        if path and os.sep + "results" + os.sep in full and os.sep + "tables" + os.sep in full \
                and os.path.isfile(full) and full.endswith((".md", ".csv")):
            text = ""
            for twin in {full, os.path.splitext(full)[0] + ".md", os.path.splitext(full)[0] + ".csv"}:
                if os.path.isfile(twin):
                    with open(twin, encoding="utf-8") as f:
                        text += f.read() + "\n"
            out[target] = table_numbers(text)
        elif anchor and full.endswith(".md") and os.path.isfile(full):
            rows = section_tables(full, anchor)
            if rows:
                out[target] = table_numbers(rows)
    return out


def check_block(page, line, block, require_citation):
    """Problems of one claim block: no table cited, or a number no cited table holds."""
    claims = [c for c in quoted_numbers(block) if not is_exempt(c)]
    if not claims and not require_citation:
        return []
    tables = cited_tables(block, page)
    where = f"{os.path.relpath(page, ROOT)}:{line}"
    if not tables:
        if claims or require_citation:
            first = f" (it quotes {claims[0][3]})" if claims else ""
            return [f"{where}: a claim that cites no table{first}: link the results/ table or the "
                    "section whose table holds its numbers"]
        return []
    numbers = [v for values in tables.values() for v in values]
    return [f"{where}: {c[3]} is in none of the tables it cites ({', '.join(sorted(tables))})"
            for c in claims if not matches(c, numbers)]


def summary_section(text):
    """(first line, last line, section text) of the page's `## Summary` (1-based, the
    heading's line first), or None if the first second-level heading is another."""
    lines = text.split("\n")
    start = None
    for i, line in enumerate(lines):
        m = HEADING.match(line)
        if m and len(m.group(1)) == 2:
            if start is None:
                if m.group(2).strip() != SUMMARY_HEADING:
                    return None
                start = i
            else:
                return start + 1, i, "\n".join(lines[start:i])
    return (start + 1, len(lines), "\n".join(lines[start:])) if start is not None else None


def commit_problems(path, text):
    prose = without_code(text)
    out = []
    for number, line in enumerate(prose.split("\n"), 1):
        for m in COMMIT.finditer(LINK.sub(lambda l: l.group(1), line)):
            out.append(f"{os.path.relpath(path, ROOT)}:{number}: names commit {m.group(0)} in its prose: "
                       "say where and when once, under the table")
    return out


def check_findings_page(path):
    with open(path, encoding="utf-8") as f:
        text = without_generated(f.read())
    rel = os.path.relpath(path, ROOT)
    section = summary_section(without_code(text))
    if section is None:
        return [f"{rel}:1: the first second-level heading is not '## {SUMMARY_HEADING}'"]
    first, last, body = section
    problems = []
    head = without_code(text).split("\n")[:last]
    words = len(" ".join(head).split())
    if last > SUMMARY_MAX_LINES or words > SUMMARY_MAX_WORDS:
        problems.append(f"{rel}:{first}: the page's opening and summary take {last} lines and {words} words; "
                        f"one screen is at most {SUMMARY_MAX_LINES} lines and {SUMMARY_MAX_WORDS} words")
    for line, block in blocks(body):
        problems += check_block(path, first + line - 1, block, require_citation=True)
    return problems + commit_problems(path, text)


def check_readme(path):
    with open(path, encoding="utf-8") as f:
        text = without_generated(f.read())
    prose = without_code(text)
    problems = []
    for line, block in blocks(prose):
        problems += check_block(path, line, block, require_citation=False)
    return problems + commit_problems(path, text)


def check(paths):
    problems = []
    for path in paths:
        name = os.path.basename(path)
        if name == "README.md":
            problems += check_readme(path)
        elif name in FINDINGS_PAGES:
            problems += check_findings_page(path)
        else:
            with open(path, encoding="utf-8") as f:
                problems += commit_problems(path, f.read())
    return problems


def default_paths():
    docs = os.path.join(ROOT, "docs")
    return [os.path.join(ROOT, "README.md")] + sorted(
        os.path.join(docs, n) for n in os.listdir(docs) if n.endswith(".md"))


def main(argv):
    paths = [os.path.abspath(p) for p in argv] or default_paths()
    problems = check(paths)
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
