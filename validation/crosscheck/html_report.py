"""``report.html`` of a cross-check: the text and tables of ``report.md``, its pictures, and
the collapse mechanism as an interactive 3D view, all opened from disk without a network.

The 3D view is pyvista's export to vtk.js (``mechanism_3d.html``: trame-vtk's offline viewer
with the scene embedded, no CDN), shown in the report in an ``iframe``; the markdown becomes
HTML through Python-Markdown with its ``tables`` extension.
"""

from __future__ import annotations

import html
import logging
import os
import tempfile
from pathlib import Path

logger = logging.getLogger(__name__)

STYLE = """
body { font-family: sans-serif; max-width: 1100px; margin: 2em auto; line-height: 1.45;
       color: #222; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: left; }
th { background: #eee; }
img { max-width: 100%; border: 1px solid #ddd; margin: 0.5em 0; }
iframe { width: 100%; height: 640px; border: 1px solid #bbb; }
code { background: #f4f4f4; padding: 0 0.2em; }
"""


WASM_DIR = "VTK_WASM_DIR_OVERRIDE"
"""trame-vtklocal's variable naming a folder of VTK WebAssembly files; the export needs none."""


def write_mechanism_html(plotter, path: Path) -> Path:
    """The plotter's scene as a standalone vtk.js page (pyvista's trame export).

    The export starts trame's server in this process once; the server's vtklocal module
    would download VTK's WebAssembly build from the network at start unless
    :data:`WASM_DIR` names a folder, so an empty one is named for that start (the vtk.js
    page uses no WebAssembly).
    """
    trame = getattr(plotter, "trame", None)
    export = trame.export_html if trame is not None and hasattr(trame, "export_html") else None
    with tempfile.TemporaryDirectory() as empty:
        before = os.environ.get(WASM_DIR)
        os.environ.setdefault(WASM_DIR, empty)
        try:
            (export or plotter.export_html)(path)
        finally:
            if before is None:
                os.environ.pop(WASM_DIR, None)
    plotter.close()
    return path


def view_section(view: Path | None, why_not: str) -> str:
    """The report's section with the interactive 3D view, or why there is none."""
    head = "<h2>Collapse mechanism in 3D</h2>\n"
    if view is None:
        return head + f"<p>No interactive view: {html.escape(why_not)}.</p>\n"
    name = html.escape(view.name)
    return (
        head + "<p>Drag to turn, scroll to zoom (the view is also "
        f'<a href="{name}">a page of its own</a>). Colour: block speed relative to the '
        "fastest block [-]; grey wire: the structure at rest.</p>\n"
        f'<iframe src="{name}" title="collapse mechanism in 3D"></iframe>\n'
    )


def write_html_report(markdown_text: str, path: Path, view: Path | None, why_not: str) -> Path:
    """``report.html``: ``markdown_text`` as HTML with the 3D view after its short summary.

    Parameters
    ----------
    markdown_text : str
        The text of ``report.md`` (its pictures are relative paths beside ``path``).
    path : Path
        Where to write.
    view : Path or None
        The 3D view's page beside ``path``; None writes ``why_not`` in its place.
    """
    import markdown

    body = markdown.markdown(markdown_text, extensions=["tables"], output_format="html")
    marker = "<h2>Verdict</h2>"
    section = view_section(view, why_not)
    body = body.replace(marker, section + marker, 1) if marker in body else body + section
    first = markdown_text.splitlines()[0] if markdown_text else "report"
    title = first.lstrip("# ").replace("`", "").strip()
    page = (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>{html.escape(title)}</title>\n<style>{STYLE}</style>\n</head>\n"
        f"<body>\n{body}\n</body>\n</html>\n"
    )
    path.write_text(page, encoding="utf-8")
    return path
