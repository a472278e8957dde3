"""analysis/doc_claims.py: the README's and the findings pages' summaries quote only
numbers of the tables they cite, and no page names a commit in its prose. The
committed pages pass; each rule is shown to fail on a small page made to break it.

Run by CTest (analysis_tests), or alone:
  /usr/bin/python3 -m unittest discover -s tests/analysis -p "test_doc_claims.py"
"""
import os
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import doc_claims  # noqa: E402


class CommittedPages(unittest.TestCase):
    def test_the_readme_and_every_page_keep_the_convention(self):
        problems = doc_claims.check(doc_claims.default_paths())
        self.assertEqual(problems, [], "\n".join(problems))

    def test_the_readme_is_a_door(self):
        with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
            lines = f.read().split("\n")
        self.assertLessEqual(len(lines), 200, "README.md: at most 200 lines")
        long = [n for n, line in enumerate(lines, 1) if len(line) > 300]
        self.assertEqual(long, [], "README.md: lines over 300 characters")

    def test_every_findings_page_exists(self):
        for name in doc_claims.FINDINGS_PAGES:
            self.assertTrue(os.path.isfile(os.path.join(ROOT, "docs", name)), name)


class QuotedNumbers(unittest.TestCase):
    def numbers(self, text):
        return [(c[0], c[1], c[2]) for c in doc_claims.quoted_numbers(text)]

    def test_forms(self):
        self.assertEqual(self.numbers("0.469 and 1.6e-3, 47 % and 17 800 tets"),
                         [(0.469, 3, False), (1.6e-3, 2, False), (47.0, 2, True), (17800.0, 3, False)])

    def test_factors_and_percentage_ranges(self):
        self.assertEqual(self.numbers("1.75x and 10x, 95-97 % and 3 to 4 %"),
                         [(1.75, 3, False), (10.0, 1, False), (95.0, 2, True), (97.0, 2, True), (3.0, 1, True),
                          (4.0, 1, True)])
        self.assertEqual(self.numbers("10k vertices, v1.2b"), [])

    def test_ranges_split_into_their_ends(self):
        self.assertEqual([c[0] for c in doc_claims.quoted_numbers("0.04-0.47 and 1.1e-4-1.6e-3")],
                         [0.04, 0.47, 1.1e-4, 1.6e-3])

    def test_what_is_not_a_claim(self):
        text = "eq. 19, table 1, section 1.4, Bouaziz et al. 2014, 10^5 vertices, [table 3.5](x.md)"
        self.assertEqual(doc_claims.quoted_numbers(text), [])

    def test_a_value_beside_a_reference_or_like_a_year_is_still_a_claim(self):
        self.assertEqual([c[0] for c in doc_claims.quoted_numbers("table 2, 1.91 ms; 0.2034 and 1.2000")],
                         [1.91, 0.2034, 1.2])

    def test_rounding_to_the_digits_quoted(self):
        table = [0.469, 15.6, 0.00156]
        for quoted in ("0.47", "0.469", "16", "15.6", "1.6e-3", "0.0016", "47 %"):
            claim = doc_claims.quoted_numbers(quoted)[0]
            self.assertTrue(doc_claims.matches(claim, table), quoted)
        for quoted in ("0.46", "0.4690001", "15.5", "1.5e-3", "4.7 %"):
            claim = doc_claims.quoted_numbers(quoted)[0]
            self.assertFalse(doc_claims.matches(claim, table), quoted)


class BrokenPages(unittest.TestCase):
    """Each rule on a temporary tree: docs/<findings page> and results/tables/t.md."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        os.makedirs(os.path.join(self.tmp.name, "docs"))
        os.makedirs(os.path.join(self.tmp.name, "results", "tables"))
        with open(os.path.join(self.tmp.name, "results", "tables", "t.md"), "w") as f:
            f.write("| case | error |\n|---|---|\n| pd | 0.00156 |\n| vbd | 0.469 |\n\nMeasured on a machine.\n")
        self.page = os.path.join(self.tmp.name, "docs", "suite.md")

    def tearDown(self):
        self.tmp.cleanup()

    def problems(self, text):
        with open(self.page, "w") as f:
            f.write(text)
        return doc_claims.check_findings_page(self.page)

    def test_a_page_that_keeps_the_convention(self):
        self.assertEqual(self.problems(
            "# Title\n\n## Summary\n\n- pd is 1.6e-3 off, vbd 0.47 ([t](../results/tables/t.md)).\n"
            "- Inline table ([below](#details)): 3.25.\n\n## Details\n\n| a |\n|---|\n| 3.25 |\n"
            "\nat 1a2b3c4 `in code` is fine: `1a2b3c4`\n".replace("at 1a2b3c4 ", "")), [])

    def test_no_summary_first(self):
        self.assertRegex(" ".join(self.problems("# Title\n\n## Method\n\ntext\n")), "not '## Summary'")

    def test_a_claim_without_a_table(self):
        self.assertRegex(" ".join(self.problems("# T\n\n## Summary\n\n- pd is 0.47 off.\n")), "cites no table")

    def test_a_number_the_table_does_not_hold(self):
        problems = self.problems("# T\n\n## Summary\n\n- pd is 0.48 off ([t](../results/tables/t.md)).\n")
        self.assertRegex(" ".join(problems), "0.48 is in none of the tables")

    def test_a_raw_result_file_is_not_a_table(self):
        os.makedirs(os.path.join(self.tmp.name, "results", "study", "case"))
        with open(os.path.join(self.tmp.name, "results", "study", "case", "probes.csv"), "w") as f:
            f.write("id,u\n1,0.0123\n")
        problems = self.problems("# T\n\n## Summary\n\n- 0.0123 ([raw](../results/study/case/probes.csv)).\n")
        self.assertRegex(" ".join(problems), "cites no table")

    def test_a_number_not_in_the_cited_section(self):
        problems = self.problems("# T\n\n## Summary\n\n- 3.26 ([s](#details)).\n\n## Details\n\n| 3.25 |\n")
        self.assertRegex(" ".join(problems), "3.26 is in none")

    def test_a_summary_longer_than_a_screen(self):
        body = "".join(f"- pd 0.47 ([t](../results/tables/t.md))\n" for _ in range(60))
        self.assertRegex(" ".join(self.problems("# T\n\n## Summary\n\n" + body)), "one screen")

    def test_a_commit_in_the_prose(self):
        problems = self.problems("# T\n\n## Summary\n\n- 0.47 ([t](../results/tables/t.md)).\n\n"
                                 "## More\n\nMeasured at 6ba9ded1 on Tuesday.\n")
        self.assertRegex(" ".join(problems), "names commit 6ba9ded1")

    def test_a_readme_claim(self):
        readme = os.path.join(self.tmp.name, "README.md")
        with open(readme, "w") as f:
            f.write("# R\n\nRun `tissuebench run 0.123`.\n\npd is 0.469 off ([t](results/tables/t.md)); "
                    "vbd 0.6.\n\n<!-- x:begin -->\n0.777\n<!-- x:end -->\n")
        problems = doc_claims.check_readme(readme)
        self.assertEqual(len(problems), 1, problems)
        self.assertRegex(problems[0], r"README.md:5: 0.6 is in none")


if __name__ == "__main__":
    unittest.main()
