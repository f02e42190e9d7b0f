"""``threadmate planar``: the flush bolt on the nut at one phase (the thesis's chapter 2)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from .._errors import InputError
from .._validate import check_phase
from ..geometry import SpecParts
from ._common import (
    SPEC_HELP,
    emit_json,
    resolve_spec,
    writable_output,
    write_failed,
)
from ._main import cli
from ._options import condition_option, parts_option

if TYPE_CHECKING:
    from ..geometry import ThreadSpec
    from ..planar import CriticalPhase, PlanarState

__all__ = ["planar"]

#: The default phase: the thesis's example (section 2.4.1), where the bolt rests on two
#: contacts for any common thread (the in-phase window is a few degrees either side of 0).
DEFAULT_PHASE = 30.0


def _pivot_path(plot: Path) -> Path:
    return plot.with_name(f"{plot.stem}-pivot{plot.suffix}")


@cli.command(
    "planar",
    help=f"""Contact of the bolt standing flush on the nut at one phase.

The bolt (roll = pitch = 0, tip face in the nut's top plane) is turned to PHASE degrees,
counter-clockwise seen from above. Prints the contact points where the bolt's tip outline
crosses the nut's top outline (angle theta in the fixed frame, x, y, the regions in
contact, the common normal), the contact angle, the pivot axis, the in-phase window and
the critical phases at which a contact changes regions. Lengths are in the spec's units,
angles in degrees.

{SPEC_HELP}""",
)
@click.argument("spec_text", metavar="DESIGNATION|SPEC")
@click.option(
    "--phase",
    type=float,
    default=DEFAULT_PHASE,
    show_default=True,
    help="Bolt phase in degrees (taken modulo 360). The default is the thesis's "
    "example phase, where two contacts show.",
)
@condition_option
@parts_option
@click.option(
    "--json", "as_json", is_flag=True, help="Print one JSON document on stdout instead of text."
)
@click.option(
    "--plot",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Write the contact-region combination disk (one turn of phase) to this "
    ".png or .svg file, and the pivot-axis chart beside it as "
    "<stem>-pivot<suffix> unless --pivot-plot names another file.",
)
@click.option(
    "--pivot-plot",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Write the pivot-axis-versus-phase chart to this .png or .svg file.",
)
def planar(
    spec_text: str,
    phase: float,
    condition: str,
    as_json: bool,
    plot: Path | None,
    pivot_plot: Path | None,
    parts: SpecParts,
) -> None:
    """Report the planar contact state (see the command's help)."""
    check_phase("phase", phase)  # the API's one limit of a phase, before the stage loads
    if plot is not None or pivot_plot is not None:
        from ..planar import figure_format  # matplotlib, for a figure asked for
    # Refuse bad figure names before any work, so that nothing is half done.
    if plot is not None:
        figure_format(plot)
        writable_output(plot, "--plot")
    pivot_option = "--pivot-plot"
    if plot is not None and pivot_plot is None:
        pivot_plot, pivot_option = _pivot_path(plot), "--plot"
    if pivot_plot is not None:
        figure_format(pivot_plot)
        writable_output(pivot_plot, pivot_option)
        if plot is not None and plot.resolve() == pivot_plot.resolve():
            raise InputError(f"--plot and --pivot-plot name the same file: {plot}")
    spec = resolve_spec(spec_text, condition, parts)
    from ..planar import (  # scipy and matplotlib, once the input is read
        critical_phases,
        in_phase_window,
        planar_state,
        plot_pivot_axes,
        plot_region_disk,
    )

    # The planar model is the thesis's: the thread sections flush at the end faces. A
    # point or countersink is not in it; say so rather than let it pass for them.
    notes = []
    if spec.bolt.point.form != "flat" or spec.nut.countersink is not None:
        notes.append(
            "the planar analysis is the thesis's model of flat ends (the thread sections "
            "flush); the bolt's point and the nut's countersink are not in it (settle and "
            "search model them)"
        )
    state = planar_state(spec, phase)
    window = in_phase_window(spec)
    critical = critical_phases(spec)
    figures: list[Path] = []
    for path, draw in ((plot, plot_region_disk), (pivot_plot, plot_pivot_axes)):
        if path is not None:
            try:
                figures.append(draw(spec, path))
            except OSError as exc:
                raise write_failed(path, exc) from None
    if as_json:
        doc: dict[str, Any] = {"units": spec.units}
        if spec.designation:
            doc["designation"] = spec.designation
        doc.update(state.to_dict())
        doc["in_phase_window"] = [list(w) for w in window]
        doc["critical_phases"] = [c.to_dict() for c in critical]
        doc["figures"] = [str(f) for f in figures]
        doc["notes"] = notes
        emit_json(doc)
        return
    _echo_text(spec, state, window, critical, figures)
    for note in notes:
        click.echo(f"note: {note}", err=True)


def _echo_text(
    spec: ThreadSpec,
    state: PlanarState,
    window: list[tuple[float, float]],
    critical: list[CriticalPhase],
    figures: list[Path],
) -> None:
    u = spec.units
    name = spec.designation or "spec"
    click.echo(f"{name}: bolt flush on nut at phase {state.phase:g} deg")
    spans = ", ".join(f"[{a:.4f}, {b:.4f}]" for a, b in window) or "none"
    click.echo(f"  in-phase window (deg): {spans}")
    if state.in_phase and not state.contacts:
        click.echo("  in phase: the outlines do not overlap; the bolt can drop into the nut")
    else:
        if state.line_contact:
            click.echo("  at the window's edge: equal flanks coincide (line contact); its ends:")
        click.echo(f"  contact angle: {state.contact_angle:.4f} deg")
        click.echo(f"  pivot axis length: {state.pivot_axis_length:.6g} {u}")
        for i, c in enumerate(state.contacts):
            click.echo(
                f"  contact {i % 2 + 1}: theta {c.theta:.4f} deg, x {c.x:.6g} {u}, "
                f"y {c.y:.6g} {u}, bolt {c.bolt_region} / nut {c.nut_region}, "
                f"normal (0, 0, 1)"
            )
    click.echo("  critical phases (deg):")
    for cp in critical:
        before = "in phase" if cp.before is None else f"{cp.before[0]}/{cp.before[1]}"
        after = "in phase" if cp.after is None else f"{cp.after[0]}/{cp.after[1]}"
        click.echo(f"    {cp.phase:9.4f}  contact {cp.contact}: {before} -> {after}")
    for f in figures:
        click.echo(f"  wrote {f}")
