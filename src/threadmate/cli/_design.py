"""``threadmate sensor`` and ``threadmate program``: the design stage over mechanics
libraries (docs/design.md).

Two commands, as the network's are split by question (``path``, ``recommend``): ``sensor``
answers whether a sensor can tell the snap from the other jumps, for one or several
compliances side by side (its figure compares them); ``program`` gives the settings to
load on the controller for the one compliance chosen, whose snap threshold it takes from
the same computation.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from .._errors import InputError
from .._validate import FIGURE_FORMATS
from ._common import emit_json, writable_output, write_failed
from ._main import cli
from ._progress import progress_words

# The design stage (networkx, pandas, matplotlib) is imported where it is used, so that
# --help and a refused option answer at once.

__all__ = ["program_command", "sensor_command"]


def _once(libraries: tuple[str, ...]) -> None:
    """Refuse a library given twice: its compliance would be shown twice."""
    seen: set[Path] = set()
    for lib in libraries:
        key = Path(lib).resolve()
        if key in seen:
            raise InputError(f"library {lib} given twice: give each compliance's library once")
        seen.add(key)


def _incomplete_note(library: str, graph: Any) -> str | None:
    g = graph.graph
    if g.get("complete", True):
        return None
    words = progress_words(library, g["done"], g["configurations"])
    return f"library {library}: {words}; the figures are of the starts done"


@cli.command("sensor")
@click.argument("libraries", nargs=-1, required=True, type=click.Path())
@click.option(
    "--plot",
    type=click.Path(),
    default=None,
    help="Write the figure (snap clicks against each search's largest other jump, with the "
    "threshold; one row per library) to this .png/.pdf/.svg.",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def sensor_command(libraries: tuple[str, ...], plot: str | None, as_json: bool) -> None:
    """Can a sensor tell the snap from the other jumps? For each of LIBRARIES (one
    compliance each): every start's search, its snap's click against the largest drop of
    any other jump in the same search (and the same for the tilt spring's moment and the
    driver's torque), the threshold that separates them with its margins, or the
    statement that none does with the searches the best threshold decides wrongly; and
    the driver-torque signature before the snap. Lengths in the spec's units, torques
    and moments in N m.
    """
    _once(libraries)
    fig = None
    if plot is not None:
        if Path(plot).suffix.lower() not in FIGURE_FORMATS:
            raise InputError(f"--plot {plot}: expected a file ending in .png, .pdf or .svg")
        fig = writable_output(plot, "--plot")
    from ..design import format_snap_detection, plot_snap_detection, snap_detection
    from ..library import load
    from ..network import build_network

    found = []
    for lib in libraries:
        rows = load(lib)
        graph = build_network(rows)
        det = snap_detection(graph, rows)
        note = _incomplete_note(lib, graph)
        if note:
            det.notes.insert(0, note)
        found.append((lib, det))
    if fig is not None:
        try:
            plot_snap_detection(
                [d for _, d in found], fig, [lib for lib, _ in found] if len(found) > 1 else None
            )
        except OSError as exc:
            raise write_failed(fig, exc) from None
    if as_json:
        first = found[0][1].to_dict()
        emit_json(
            {
                "units": first["units"],
                "figure": str(fig) if fig is not None else None,
                "settings": [{"library": lib, **det.to_dict()} for lib, det in found],
            }
        )
        return
    for lib, det in found:
        click.echo(f"## {lib}\n")
        click.echo(format_snap_detection(det))
    if fig is not None:
        click.echo(f"wrote {fig}")


@cli.command("program")
@click.argument("library", type=click.Path())
@click.option(
    "--turn-margin",
    type=float,
    default=None,
    help="Degrees added to the largest turn to the snap for the turn limit (default: the "
    "grid's start-phase step).",
)
@click.option(
    "--torque-margin",
    type=float,
    default=0.25,
    show_default=True,
    help="Share added to the largest driver torque for the torque limit.",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def program_command(
    library: str, turn_margin: float | None, torque_margin: float, as_json: bool
) -> None:
    """What to program on the controller for the compliance of LIBRARY: the turn limit
    after which to give up, the torque limit, where to lift and retry for starts that
    never snap (the network's active plans as robot moves), and the snap as a sensor
    threshold; each figure with the rule it comes from.
    """
    from .._validate import check_range

    if turn_margin is not None:
        check_range("turn_margin", turn_margin, 0.0, 720.0, units="deg")
    check_range("torque_margin", torque_margin, 0.0, 10.0)
    from ..design import controller_program, format_controller_program, snap_detection
    from ..library import load
    from ..network import build_network

    rows = load(library)
    graph = build_network(rows, active=True)
    prog = controller_program(
        graph,
        snap_detection(graph, rows),
        turn_margin=turn_margin,
        torque_margin=torque_margin,
    )
    note = _incomplete_note(library, graph)
    if note:
        prog.notes.insert(0, note)
    if as_json:
        emit_json({"library": library, **prog.to_dict()})
        return
    click.echo(format_controller_program(prog))
