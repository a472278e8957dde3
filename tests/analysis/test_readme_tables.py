"""analysis/readme_tables.py: the README's short tables and docs/paper_reproduction.md's
full ones are what the script writes from the committed results/tables/, cell for cell."""
import csv
import os
import shutil
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
import readme_tables  # noqa: E402

TABLES = os.path.join(ROOT, "results", "tables")


class ReadmeTables(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.readme = shutil.copy(os.path.join(ROOT, "README.md"), self.tmp.name)
        os.makedirs(os.path.join(self.tmp.name, "docs"))
        self.doc = shutil.copy(os.path.join(ROOT, "docs", "paper_reproduction.md"),
                               os.path.join(self.tmp.name, "docs"))

    def tearDown(self):
        self.tmp.cleanup()

    def read(self, path):
        with open(path, encoding="utf-8") as f:
            return f.read()

    def test_the_committed_pages_are_what_the_script_writes(self):
        readme_tables.update(TABLES, self.readme, self.doc)
        self.assertEqual(self.read(self.readme), self.read(os.path.join(ROOT, "README.md")),
                         "README.md's tables differ from results/tables: run analysis/readme_tables.py")
        self.assertEqual(self.read(self.doc), self.read(os.path.join(ROOT, "docs", "paper_reproduction.md")),
                         "docs/paper_reproduction.md's tables differ: run analysis/readme_tables.py")

    def test_every_short_cell_is_a_cell_of_the_full_tables(self):
        block = readme_tables.short_block(TABLES)
        cells = set()
        for name in ("table1", "table1_metrics", "table2", "table3", "table3_metrics"):
            with open(os.path.join(TABLES, name + ".csv"), newline="") as f:
                for row in csv.reader(f):
                    cells |= set(row) | {c.split(" vs ")[0] for c in row}
        for line in block.splitlines():
            if line.startswith("| ") and not line.startswith("| model"):
                for cell in line.strip("| ").split(" | "):
                    self.assertIn(cell.strip(), cells | {"", "(reference)"}, line)

    def test_the_full_tables_are_the_committed_markdown(self):
        full = readme_tables.full_block(TABLES)
        for name, title in readme_tables.SECTIONS:
            self.assertIn(f"### {title}\n\n" + self.read(os.path.join(TABLES, name + ".md")).strip(), full)

    def test_missing_markers_are_an_error(self):
        with open(self.readme, "w") as f:
            f.write("# no markers\n")
        with self.assertRaisesRegex(ValueError, "table markers not found"):
            readme_tables.update(TABLES, self.readme, self.doc)


if __name__ == "__main__":
    unittest.main()
