"""``threadmate view``: the interactive page of a search or of a run.

A thin layer over :mod:`threadmate.view`: a search's JSON document becomes its page
(:func:`~threadmate.view.write_search_page`), a run's folder its ``report.html``
(:func:`~threadmate.view.write_run_page`), and ``--start`` computes one start's search
into the run's ``views/`` (:func:`~threadmate.view.write_start_page`).
"""

from __future__ import annotations

import math
from pathlib import Path

import click

from .._errors import InputError
from ._common import writable_output
from ._main import cli

__all__ = ["view_command"]


def _start(text: str | None) -> tuple[float, float, float] | None:
    """``--start R,P,PH``: three finite numbers (degrees)."""
    if text is None:
        return None
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise InputError(
            f"--start {text!r}: give the held roll, held pitch and start phase in degrees "
            "separated by commas, e.g. 0,-1,300"
        )
    return values[0], values[1], values[2]


@cli.command(
    "view",
    help="""Write the interactive page of a search or of a run (one HTML file that opens
in a browser with no network).

PATH is either a search's JSON document (threadmate search ... --json > SEARCH.json):
the page shows the bolt on the nut at every state of the turn under a slider, the touching
contacts with their force arrows and regions, and the compliance centre's height, the
bolt's tilt and the driver's torque against phase with the events and the snap marked;
it is written to -o, default SEARCH.html beside the document. Or PATH is a run's folder
(threadmate run -o DIR): DIR/report.html is written again, the report with its ranking
and class map interactive and every start linked to its search's page in DIR/views/;
--start R,P,PH first computes the search of that start (the run's thread pair,
compliance, chord and step) and writes its page there. Lengths in the spec's units,
angles in degrees, forces in N, torques in N m.""",
)
@click.argument("path", type=click.Path(path_type=Path), metavar="SEARCH.json|RUN_DIR")
@click.option(
    "-o",
    "--out",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="The page of a search: this .html file (default: the document's name with .html).",
)
@click.option(
    "--start",
    "start_text",
    default=None,
    metavar="R,P,PH",
    help="With a run's folder: also write the page of the start at held roll R, held "
    "pitch P and start phase PH (degrees, on the run's grid) into DIR/views/.",
)
def view_command(path: Path, out: Path | None, start_text: str | None) -> None:
    """The page of a search or of a run (see the command's help)."""
    start = _start(start_text)
    if path.is_dir():
        if out is not None:
            raise InputError("-o: a run's page is always DIR/report.html; leave -o out")
        from ..view import write_run_page, write_start_page

        if start is not None:
            click.echo(f"wrote {write_start_page(path, *start)}")
        click.echo(f"wrote {write_run_page(path)}")
        return
    if start is not None:
        raise InputError("--start: give a run's folder, not a search's document")
    if not path.exists():
        raise InputError(f"{path}: no such file or folder")
    target = path.with_suffix(".html") if out is None else out
    if target.suffix.lower() not in (".html", ".htm"):
        raise InputError(f"-o {target}: expected a file ending in .html")
    if target.resolve() == path.resolve():
        raise InputError(f"-o {target}: is the document itself; give another file")
    writable_output(target, "-o")
    from ..view import read_search_document, write_search_page

    doc = read_search_document(path)
    click.echo(f"wrote {write_search_page(doc, target)}")
