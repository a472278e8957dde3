"""The documentation stays true to the repository: every relative link in README.md
and docs/*.md resolves to a file of the repository (and an `#anchor` to a heading of
that file), and every test a page cites by name (`Suite.Test`, `Suite.*` or
`Class.test_name`) exists under tests/. Each checker is also tested on temporary
files, so that a broken link or a renamed test is shown to fail.

Run by CTest (analysis_tests), or alone:
  /usr/bin/python3 -m unittest discover -s tests/analysis -p "test_doc_links.py"
"""
import glob
import os
import re
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

FENCE = re.compile(r"^(```|~~~).*?^\1[^\n]*$", re.M | re.S)
CODE_SPAN = re.compile(r"(`+)(.+?)\1", re.S)
# [text](target) and ![alt](target), an optional "title" after the target.
INLINE_LINK = re.compile(r"!?\[(?:[^\[\]\\]|\\.|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE_DEFINITION = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s.*)?$", re.M)
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$", re.M)
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def documentation_files(root=ROOT):
    """README.md and docs/*.md of the repository."""
    return [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "*.md")))


def without_code(text):
    """The text with fenced code blocks and inline code spans removed (links there are
    examples, not links); line breaks are kept, so line numbers stay right."""
    text = FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    return CODE_SPAN.sub(lambda m: "\n" * m.group(0).count("\n"), text)


def slug(heading):
    """GitHub's anchor of a heading: its text as rendered (links become their text,
    code spans their content), lower-cased, every character but letters, digits,
    '_', '-' and spaces dropped, spaces turned into '-'."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)
    text = CODE_SPAN.sub(lambda m: m.group(2), text)
    text = re.sub(r"<[^>]+>", "", text)
    return re.sub(r"[^\w\- ]", "", text.strip().lower()).replace(" ", "-")


def anchors(path):
    """Every heading anchor of a Markdown file, with GitHub's -1, -2 ... suffixes for
    repeated headings."""
    with open(path, encoding="utf-8") as f:
        text = FENCE.sub("", f.read())
    seen, out = {}, set()
    for m in HEADING.finditer(text):
        base = slug(m.group(2))
        n = seen.get(base, 0)
        out.add(base if n == 0 else f"{base}-{n}")
        seen[base] = n + 1
    return out


def links(path):
    """(line number, target) of every link and image in a Markdown file, outside code."""
    with open(path, encoding="utf-8") as f:
        text = without_code(f.read())
    found = [(m.start(1), m.group(1)) for m in INLINE_LINK.finditer(text)]
    found += [(m.start(1), m.group(1)) for m in REFERENCE_DEFINITION.finditer(text)]
    return sorted((text.count("\n", 0, start) + 1, target) for start, target in found)


def broken_links(path, root=ROOT):
    """'file:line: target: why' for every relative link of `path` that does not
    resolve to a file or folder inside `root`, or to a heading of its file."""
    problems = []
    here = os.path.dirname(os.path.abspath(path))
    for line, target in links(path):
        if SCHEME.match(target) or target.startswith("//"):
            continue  # not relative: a web address
        file_part, _, anchor = target.partition("#")
        resolved = os.path.normpath(os.path.join(here, file_part)) if file_part else os.path.abspath(path)
        where = f"{os.path.relpath(path, root)}:{line}: {target}"
        if os.path.commonpath([resolved, os.path.abspath(root)]) != os.path.abspath(root):
            problems.append(f"{where}: leaves the repository")
        elif not os.path.exists(resolved):
            problems.append(f"{where}: no such file")
        elif anchor:
            if not resolved.endswith(".md") or os.path.isdir(resolved):
                problems.append(f"{where}: an anchor into a file that is not Markdown")
            elif anchor not in anchors(resolved):
                problems.append(f"{where}: no heading #{anchor} in {os.path.relpath(resolved, root)}")
    return problems


CITED_TEST = re.compile(r"`([A-Z]\w*)\.(\*|[A-Z]\w*|test_\w*)`")
CPP_TEST = re.compile(r"\b(?:TEST|TEST_F|TEST_P|TYPED_TEST|TYPED_TEST_P)\(\s*(\w+)\s*,\s*(\w+)\s*\)")
PY_CLASS = re.compile(r"^class (\w+)\b", re.M)
PY_TEST = re.compile(r"^    def (test_\w+)\(", re.M)


def defined_tests(tests_dir):
    """{(suite or class, test name)} of every GoogleTest and Python test under tests_dir."""
    tests = set()
    for path in glob.glob(os.path.join(tests_dir, "**", "*"), recursive=True):
        if path.endswith((".cc", ".h")):
            with open(path, encoding="utf-8") as f:
                tests |= {(m.group(1), m.group(2)) for m in CPP_TEST.finditer(f.read())}
        elif path.endswith(".py"):
            with open(path, encoding="utf-8") as f:
                text = f.read()
            classes = [(m.start(), m.group(1)) for m in PY_CLASS.finditer(text)]
            for m in PY_TEST.finditer(text):
                owner = [name for start, name in classes if start < m.start()]
                if owner:
                    tests.add((owner[-1], m.group(1)))
    return tests


def missing_tests(path, tests):
    """'file:line: Suite.Test' for every test `path` cites that `tests` does not hold
    (`Suite.*`: no test of that suite)."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    suites = {suite for suite, _ in tests}
    problems = []
    for m in CITED_TEST.finditer(text):
        suite, name = m.group(1), m.group(2)
        if (name == "*" and suite not in suites) or (name != "*" and (suite, name) not in tests):
            problems.append(f"{os.path.relpath(path, ROOT)}:{text.count(chr(10), 0, m.start()) + 1}: "
                            f"{suite}.{name}")
    return problems


class RepositoryDocumentation(unittest.TestCase):
    def test_every_relative_link_resolves(self):
        files = documentation_files()
        self.assertIn(os.path.join(ROOT, "docs", "equations.md"), files)
        problems = [p for path in files for p in broken_links(path)]
        self.assertEqual(problems, [], "broken links:\n" + "\n".join(problems))

    def test_every_cited_test_exists(self):
        tests = defined_tests(os.path.join(ROOT, "tests"))
        problems = [p for path in documentation_files() for p in missing_tests(path, tests)]
        self.assertEqual(problems, [], "tests cited but not defined:\n" + "\n".join(problems))


class LinkChecker(unittest.TestCase):
    """The checker itself, on a small tree of temporary files."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = self.tmp.name
        os.makedirs(os.path.join(self.root, "docs"))
        os.makedirs(os.path.join(self.root, "src"))
        self.write("src/code.h", "// a header\n")
        self.write("docs/other.md", "# Other page\n\n## Results: four causes\n\n## Same\n\n## Same\n\n"
                   "### `code.h`, eqs. (19)-(30)\n")

    def tearDown(self):
        self.tmp.cleanup()

    def write(self, name, text):
        with open(os.path.join(self.root, name), "w", encoding="utf-8") as f:
            f.write(text)
        return os.path.join(self.root, name)

    def check(self, text):
        return broken_links(self.write("docs/page.md", text), self.root)

    def test_links_that_resolve_pass(self):
        self.assertEqual(self.check(
            "# Page\n\nSee [other](other.md), [a header](../src/code.h), ![an image](../src/code.h),\n"
            "[a section](other.md#results-four-causes), [the second Same](other.md#same-1),\n"
            "[code in a heading](other.md#codeh-eqs-19-30), [here](#page), [the web](https://example.org/x),\n"
            "[a folder](../src) and [a title](other.md \"Other\").\n\n[ref]: other.md\n"), [])

    def test_a_missing_file_fails_naming_the_line_and_target(self):
        problems = self.check("# Page\n\ntext\n[gone](missing.md) and [fine](other.md)\n")
        self.assertEqual(len(problems), 1)
        self.assertIn("docs/page.md:4: missing.md: no such file", problems[0])

    def test_a_missing_anchor_fails(self):
        problems = self.check("# Page\n\n[no such section](other.md#results) [nor here](#nowhere)\n")
        self.assertEqual(len(problems), 2)
        self.assertTrue(any("other.md#results: no heading #results in docs/other.md" in p for p in problems))
        self.assertTrue(any("#nowhere: no heading #nowhere in docs/page.md" in p for p in problems))

    def test_a_third_same_heading_is_not_there(self):
        self.assertEqual(len(self.check("[x](other.md#same-2)\n")), 1)

    def test_a_reference_definition_and_an_image_are_checked(self):
        problems = self.check("![figure](../results/missing.png)\n\n[ref]: ../src/gone.h\n")
        self.assertEqual(len(problems), 2)

    def test_a_link_out_of_the_repository_fails(self):
        outside = os.path.basename(self.root)
        problems = self.check(f"[up](../../{outside}/src/code.h) [out](../../etc)\n")
        self.assertEqual(len(problems), 1)
        self.assertIn("leaves the repository", problems[0])

    def test_links_in_code_are_examples_not_links(self):
        self.assertEqual(self.check("`[x](missing.md)`\n\n```\n[y](missing.md)\n```\n"), [])

    def test_anchors_follow_github(self):
        self.assertEqual(slug("Bending constraint, eqs. (19)-(30)"), "bending-constraint-eqs-19-30")
        self.assertEqual(slug("XPBD (Macklin, Mueller, Chentanez 2016)"), "xpbd-macklin-mueller-chentanez-2016")
        self.assertEqual(slug("Can table 1 be reproduced?"), "can-table-1-be-reproduced")
        self.assertEqual(slug("[Data](README.md) and `u_z`"), "data-and-u_z")


class CitedTestChecker(unittest.TestCase):
    def test_defined_tests_are_found_and_a_missing_one_fails(self):
        with tempfile.TemporaryDirectory() as root:
            os.makedirs(os.path.join(root, "tests"))
            with open(os.path.join(root, "tests", "a_test.cc"), "w") as f:
                f.write("TEST(Suite, Kept) {}\nTYPED_TEST(Laws, Typed) {}\nTEST_F(Fixture, WithFixture) {}\n")
            with open(os.path.join(root, "tests", "test_b.py"), "w") as f:
                f.write("class Checks(unittest.TestCase):\n    def test_kept(self):\n        pass\n")
            tests = defined_tests(os.path.join(root, "tests"))
            self.assertEqual(tests, {("Suite", "Kept"), ("Laws", "Typed"), ("Fixture", "WithFixture"),
                                     ("Checks", "test_kept")})
            page = os.path.join(root, "page.md")
            with open(page, "w") as f:
                f.write("`Suite.Kept`, `Laws.*`, `Checks.test_kept`, `README.md`, `Version.h`\n"
                        "`Suite.Renamed` and `Gone.*` and `Checks.test_gone`\n")
            problems = missing_tests(page, tests)
            self.assertEqual([p.split(": ", 1)[1] for p in problems], ["Suite.Renamed", "Gone.*", "Checks.test_gone"])


if __name__ == "__main__":
    unittest.main()
