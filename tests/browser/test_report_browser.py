"""The report (analysis/report/build.py) in a real browser: built from the committed
results into a temporary folder, every page opened over file:// by headless Chromium
through selenium, and checked: no console error (a browser log entry of level SEVERE),
every plot (a .js-plotly-plot element) drawn with at least one trace, and a screenshot
that is not blank. The checkers are tested on synthetic input, and a broken page (a
JavaScript error, an empty plot, nothing drawn) is shown to fail.

Run by CTest (report_browser, label "full"), or alone:
  /usr/bin/python3 tests/browser/test_report_browser.py [-v]
With --screenshots DIR it writes DIR/index.png and DIR/cube_pull_disc.png (1400 x 900)
instead of testing (results/figures/report/ holds the committed ones).
"""
import argparse
import io
import os
import shutil
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path[:0] = [os.path.join(ROOT, "analysis", "report"), os.path.join(ROOT, "analysis")]
import build  # noqa: E402

CHROMEDRIVER = "/usr/bin/chromedriver"
WINDOW = (1400, 900)
OPTIONS = ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
           "--disable-background-networking", "--disable-component-update", "--disable-sync")
DRAW_TIMEOUT_S = 30
BLANK_SHARE = 0.01  # a screenshot is blank when fewer pixels than this differ from its commonest colour
SCREENSHOT_PAGES = ("index.html", "cube_pull_disc.html")


def console_errors(entries):
    """The messages of the browser log entries ({level, message, ...}) of level SEVERE."""
    return [e.get("message", "") for e in entries if e.get("level") == "SEVERE"]


def is_blank(png, share=BLANK_SHARE):
    """Whether a PNG (bytes) is one colour over all but `share` of its pixels."""
    import matplotlib.image
    image = matplotlib.image.imread(io.BytesIO(png), format="png")  # H x W x 3 or 4, floats in [0, 1]
    rgb = np.round(image[..., :3] * 255).astype(np.int64).reshape(-1, 3)
    counts = np.bincount((rgb[:, 0] << 16) | (rgb[:, 1] << 8) | rgb[:, 2])  # pixels of each 24-bit colour
    return 1.0 - counts.max() / len(rgb) < share


class Browser:
    """Headless Chromium through chromedriver, a fresh profile, the browser log kept."""

    def __init__(self):
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
        self.profile = tempfile.mkdtemp(prefix="report-chromium-")
        options = webdriver.ChromeOptions()
        for o in OPTIONS + (f"--user-data-dir={self.profile}",):
            options.add_argument(o)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        self.driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
        self.driver.set_window_size(*WINDOW)

    def close(self):
        self.driver.quit()
        shutil.rmtree(self.profile, ignore_errors=True)

    def open(self, path, timeout=DRAW_TIMEOUT_S):
        """Opens a page and waits until its script says every figure is drawn; returns
        (problems [str], screenshot PNG bytes)."""
        from selenium.common.exceptions import TimeoutException
        from selenium.webdriver.support.ui import WebDriverWait
        d = self.driver
        d.get("file://" + os.path.abspath(path))
        problems = []
        try:
            WebDriverWait(d, timeout).until(
                lambda d: d.execute_script("return document.body.getAttribute('data-figures')") == "drawn")
        except TimeoutException:
            problems.append(f"its figures were not drawn within {timeout} s")
        expected = d.execute_script("return document.querySelectorAll('script[data-figure]').length")
        traces = d.execute_script("return Array.prototype.map.call(document.querySelectorAll('.js-plotly-plot'),"
                                  " function (p) { return p.data ? p.data.length : 0; })")
        if len(traces) != expected:
            problems.append(f"{len(traces)} plots drawn of {expected}")
        problems += [f"plot {i} has no trace" for i, n in enumerate(traces) if n < 1]
        problems += [f"console error: {m}" for m in console_errors(d.get_log("browser"))]
        png = d.get_screenshot_as_png()
        if is_blank(png):
            problems.append("its screenshot is blank")
        return problems, png


class Checkers(unittest.TestCase):
    """The checkers on synthetic input: no browser."""

    @staticmethod
    def png(image):
        import matplotlib.image
        buf = io.BytesIO()
        matplotlib.image.imsave(buf, image, format="png")
        return buf.getvalue()

    def test_one_colour_is_blank(self):
        self.assertTrue(is_blank(self.png(np.ones((90, 140, 3)))))

    def test_a_speck_is_still_blank(self):
        image = np.ones((90, 140, 3))
        image[10:12, 10:12] = 0  # 4 pixels of 12 600
        self.assertTrue(is_blank(self.png(image)))

    def test_a_drawing_is_not_blank(self):
        image = np.ones((90, 140, 3))
        image[20:60, 30:100, 0] = np.linspace(0, 1, 70)  # a gradient over a fifth of the image
        self.assertFalse(is_blank(self.png(image)))

    def test_only_severe_entries_are_errors(self):
        log = [{"level": "WARNING", "message": "slow"}, {"level": "INFO", "message": "hello"},
               {"level": "SEVERE", "message": "Uncaught ReferenceError: x is not defined"}]
        self.assertEqual(console_errors(log), ["Uncaught ReferenceError: x is not defined"])
        self.assertEqual(console_errors(log[:2]), [])


class ReportInBrowser(unittest.TestCase):
    """Every page of the report built from the committed results, and broken pages beside them."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="report-")
        cls.pages = build.make(os.path.join(ROOT, "results"), cls.tmp)
        cls.browser = Browser()

    @classmethod
    def tearDownClass(cls):
        cls.browser.close()
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_every_page_draws_without_error(self):
        failed = {}
        for name in self.pages:
            problems, _ = self.browser.open(os.path.join(self.tmp, name))
            if problems:
                failed[name] = problems
        self.assertEqual(failed, {})

    def broken(self, name, body):
        """Problems of a page made with the report's own markup (plotly.js beside it)."""
        import markup
        import plotly.graph_objects as go
        fig = markup.figure("ok", go.Figure(go.Scatter(x=[1, 2], y=[2, 1])))
        path = os.path.join(self.tmp, name)
        with open(path, "w") as f:
            f.write(markup.page(name, [], markup.Html(fig + body), []))
        return self.browser.open(path, timeout=5)[0]

    def test_a_javascript_error_fails(self):
        problems = self.broken("broken_script.html", "<script>notDefinedAnywhere();</script>")
        self.assertTrue(any("console error" in p and "notDefinedAnywhere" in p for p in problems), problems)

    def test_a_plot_without_traces_fails(self):
        import markup
        import plotly.graph_objects as go
        problems = self.broken("empty_plot.html", markup.figure("empty", go.Figure()))
        self.assertIn("plot 1 has no trace", problems)

    def test_figures_left_undrawn_fail(self):
        problems = self.broken("undrawn.html", '<script type="application/json" data-figure="nowhere">{}</script>')
        self.assertTrue(any("not drawn" in p for p in problems), problems)

    def test_a_blank_page_fails(self):
        path = os.path.join(self.tmp, "blank.html")
        with open(path, "w") as f:
            f.write('<!DOCTYPE html><html><body data-figures="drawn"></body></html>')
        self.assertIn("its screenshot is blank", self.browser.open(path, timeout=5)[0])


def screenshots(out):
    """Builds the report into a temporary folder and writes OUT/<page>.png of SCREENSHOT_PAGES."""
    tmp = tempfile.mkdtemp(prefix="report-")
    browser = Browser()
    try:
        build.make(os.path.join(ROOT, "results"), tmp)
        os.makedirs(out, exist_ok=True)
        for name in SCREENSHOT_PAGES:
            problems, png = browser.open(os.path.join(tmp, name))
            if problems:
                sys.exit(f"{name}: " + "; ".join(problems))
            with open(os.path.join(out, name.replace(".html", ".png")), "wb") as f:
                f.write(png)
            print(f"{out}/{name.replace('.html', '.png')}")
    finally:
        browser.close()
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(add_help=False)
    parser.add_argument("--screenshots", metavar="DIR")
    args, rest = parser.parse_known_args()
    if args.screenshots:
        screenshots(args.screenshots)
    else:
        unittest.main(argv=[sys.argv[0]] + rest)
