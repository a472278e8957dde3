"""The HTML of the report's pages, none of their content.

page(...) -> a whole page (str); table(header, rows) -> an HTML table; figure(div_id, fig)
-> a placeholder div and the figure's JSON, which the page's one script draws with
Plotly.newPlot once plotly.js (copied beside the pages) has loaded. When every figure of
a page is drawn the script sets <body data-figures="drawn"> (the browser test waits for it).
Text is escaped here; a Html string is markup already.
"""
import html
import json
import re

import plotly.utils

PLOTLY_JS = "plotly.js"


class Html(str):
    """Markup, put into a page as it is (other strings are escaped)."""


def esc(text):
    return text if isinstance(text, Html) else Html(html.escape(str(text)))


def link(href, text):
    return Html(f'<a href="{html.escape(href)}">{esc(text)}</a>')


def tag(name, content, cls=None):
    attr = f' class="{cls}"' if cls else ""
    return Html(f"<{name}{attr}>{esc(content)}</{name}>")


def join(parts, sep=""):
    return Html(sep.join(esc(p) for p in parts))


def table(header, rows, cls="data"):
    """An HTML table of string cells (a Html cell is put in as it is)."""
    head = "".join(f"<th>{esc(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{esc(c)}</td>" for c in row) + "</tr>\n" for row in rows)
    return Html(f'<div class="scroll"><table class="{cls}"><thead><tr>{head}</tr></thead>\n<tbody>\n{body}'
                '</tbody></table></div>')


def figure_json(fig):
    """The figure's data and layout as JSON, keys sorted (the same figure, the same text), with
    '<' escaped so that no string in it can close the <script> holding it."""
    text = json.dumps(fig.to_plotly_json(), cls=plotly.utils.PlotlyJSONEncoder, sort_keys=True,
                      separators=(",", ":"))
    return text.replace("<", "\\u003c")


def figure(div_id, fig, caption=""):
    """A figure's placeholder and its JSON; the id is fixed by the caller (the same inputs give
    the same page), kept to letters, digits, '_' and '-'."""
    div_id = re.sub(r"[^A-Za-z0-9_-]", "", div_id)
    cap = f"<figcaption>{esc(caption)}</figcaption>" if caption else ""
    return Html(f'<figure><div class="plot" id="{div_id}"></div>{cap}'
                f'<script type="application/json" data-figure="{div_id}">{figure_json(fig)}</script></figure>')


DRAW = """<script>
(function () {
  var blocks = document.querySelectorAll('script[type="application/json"][data-figure]');
  var drawn = Array.prototype.map.call(blocks, function (block) {
    var fig = JSON.parse(block.textContent);
    return Plotly.newPlot(block.getAttribute('data-figure'), fig.data, fig.layout,
                          {responsive: true, displaylogo: false});
  });
  Promise.all(drawn).then(function () { document.body.setAttribute('data-figures', 'drawn'); });
})();
</script>"""

STYLE = """body { font-family: sans-serif; margin: 0 auto; max-width: 1320px; padding: 0 16px 32px; color: #222; }
nav { padding: 10px 0; border-bottom: 1px solid #ccc; margin-bottom: 8px; font-size: 14px; line-height: 1.7; }
nav a { margin-right: 10px; white-space: nowrap; }
h1 { font-size: 24px; margin: 10px 0 6px; } h2 { font-size: 19px; margin-top: 26px; }
p, li { line-height: 1.45; max-width: 1100px; }
table.data { border-collapse: collapse; font-size: 13px; margin: 8px 0; }
table.data th, table.data td { border: 1px solid #ccc; padding: 3px 6px; text-align: left; vertical-align: top; }
table.data th { background: #f0f0f0; }
figure { margin: 8px 0 16px; } figcaption { font-size: 13px; color: #444; max-width: 1100px; }
.plot { width: 100%; height: 520px; } .plot.tall { height: 640px; }
.grid { display: grid; grid-template-columns: repeat(auto-fit, minmax(420px, 1fr)); gap: 8px; }
.grid .plot { height: 460px; }
img.static { max-width: 100%; border: 1px solid #ddd; }
.scroll { overflow-x: auto; }
.note { color: #555; font-size: 13px; } footer { margin-top: 28px; border-top: 1px solid #ccc; padding-top: 8px; }
"""


def page(title, nav, body, measured):
    """A whole page: nav ([(href, text)]), the body's markup, and where its numbers were
    measured ([sentences], said once, at the foot); plotly.js is loaded only where a figure is."""
    script = (f'<script src="{PLOTLY_JS}" charset="utf-8"></script>\n'
              if 'data-figure="' in body else "")
    links = join([link(h, t) for h, t in nav], " ")
    foot = (Html("<footer><p class=\"note\"><b>Where these numbers were measured.</b> " + join(measured, " ")
                 + "</p></footer>") if measured else "")
    return (f'<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n<title>{esc(title)}</title>\n'
            f"<style>\n{STYLE}</style>\n{script}</head>\n<body>\n<nav>{links}</nav>\n<main>\n<h1>{esc(title)}</h1>\n"
            f"{body}\n</main>\n{foot}\n{DRAW}\n</body>\n</html>\n")
