"""The pages' shell: one HTML file with plotly.js, the page's data and its script inline.

Nothing is fetched when a page opens: plotly.js comes from the ``plotly`` package
(:func:`plotly.offline.get_plotlyjs`), the data as JSON in ``<script
type="application/json">`` elements, the page's own script from this package.
"""

from __future__ import annotations

import functools
import html
from importlib import resources
from typing import Any

from .._json import json_text

__all__ = ["embedded_json", "page", "script"]

_STYLE = """
:root { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; }
body { margin: 0 1rem 1rem; color: #1d2733; background: #fff; font-size: 15px; }
h1 { font-size: 1.25rem; margin: 0.6rem 0 0.2rem; }
h2 { font-size: 1.1rem; margin: 1.2rem 0 0.4rem; }
p.tm-sub { margin: 0.1rem 0 0.5rem; color: #4a5866; font-size: 0.9rem; }
.tm-main { display: grid; grid-template-columns: minmax(0, 1.15fr) minmax(0, 1fr); gap: 0.8rem; }
@media (max-width: 900px) { .tm-main { grid-template-columns: 1fr; } }
.tm-panel { border: 1px solid #d9dee4; border-radius: 6px; min-height: 420px; }
#tm-scene, #tm-plots { height: 62vh; min-height: 420px; }
.tm-controls { display: flex; flex-wrap: wrap; align-items: center; gap: 0.6rem;
  margin: 0.6rem 0; }
.tm-controls input[type=range] { flex: 1 1 320px; }
.tm-controls button { font: inherit; padding: 0.15rem 0.6rem; }
#tm-readout { font-variant-numeric: tabular-nums; min-width: 22rem; }
table { border-collapse: collapse; font-size: 0.88rem; margin: 0.3rem 0; }
th, td { border: 1px solid #d9dee4; padding: 0.15rem 0.45rem; text-align: right; }
th { background: #f3f5f7; }
td.tm-text, th.tm-text { text-align: left; }
.tm-note { color: #4a5866; font-size: 0.85rem; }
.tm-report img { max-width: 100%; }
.tm-report { max-width: 70rem; }
a.tm-start { cursor: pointer; }
"""


@functools.cache
def plotly_js() -> str:
    """plotly.js, minified, from the installed ``plotly`` package."""
    from plotly.offline import get_plotlyjs

    return str(get_plotlyjs())


def script(name: str) -> str:
    """A script shipped beside this module (``name``: a file in the package)."""
    return resources.files(__package__).joinpath(name).read_text(encoding="utf-8")


def embedded_json(element_id: str, value: Any) -> str:
    """``value`` as a ``<script type="application/json">`` element a page's script reads
    (NaN and infinities as null; ``<`` escaped, so no text in it can close the element)."""
    text = json_text(value, indent=None, end="").replace("<", "\\u003c")
    return f'<script type="application/json" id="{element_id}">{text}</script>'


def page(title: str, body: str, data: dict[str, Any], scripts: list[str]) -> str:
    """A whole HTML page: ``body`` (markup), the JSON elements of ``data`` (id -> value),
    plotly.js and ``scripts`` (each a script's text), every one inline."""
    blocks = "\n".join(embedded_json(k, v) for k, v in data.items())
    code = "\n".join(f"<script>\n{s}\n</script>" for s in scripts)
    return (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>{html.escape(title)}</title>\n<style>{_STYLE}</style>\n"
        f"<script>{plotly_js()}</script>\n</head>\n<body>\n{body}\n{blocks}\n{code}\n"
        "</body>\n</html>\n"
    )
