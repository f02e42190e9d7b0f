"""``threadmate design``: the compliance that tolerates the most misalignment, and whether
it holds over what varies (the design stage; docs/design.md, "The design search")."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from .._errors import InputError
from .._validate import FIGURE_FORMATS, check_workers
from ..geometry import SpecParts
from ._common import SPEC_HELP, echo_err, emit_json, resolve_spec, writable_output, write_failed
from ._main import cli
from ._options import (
    RANGE_HELP,
    chord_option,
    condition_option,
    envelope_grid_options,
    parts_option,
    workers_option,
)

__all__ = ["design_command"]


def _bounds(text: str, flag: str, units: str) -> tuple[float, float]:
    """``LO:HI`` (or one value: both bounds) as two numbers; their order and signs are the
    API's to check."""
    parts = [p.strip() for p in text.split(":")]
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) not in (1, 2):
        raise InputError(f"{flag} {text!r}: give the bounds as LO:HI in {units}, e.g. 2:40")
    return (values[0], values[-1])


def _centre(text: str) -> float | str:
    try:
        return float(text)
    except ValueError:
        return text


@cli.command(
    "design",
    help=f"""The compliance that tolerates the most misalignment.

Within the bounds on the axial force (N) and the rotational stiffness (N m/rad), the
setting whose capture envelope tolerates the largest misalignment in its worst direction
(every start phase snaps within one turn), ties broken by the mean turn to the snap, the
mean work and the peak torque. The envelope depends on force and stiffness only through
k/F, so the search runs over that ratio (log-spaced, then halved around the best), each
ratio at the least force the bounds allow. Each setting is evaluated with a coarse
envelope (--direction, --phase, --tilt, --tolerance), which ranks them; the optimum is
then measured again at the envelope's own grid, the figure the summary gives (in any
direction; --no-confirm skips it), and --fine measures the robustness cases at that grid
too. Then the optimum is re-evaluated at maximum and minimum
material and at friction 0.08 and 0.20 (VDI 2230), with a sentence on whether it holds;
where it does not, the setting evaluated whose worst case tolerates the most is named too.
The bolt is held upright, as the nut's thread-start azimuth is unknown to the robot;
with --azimuth-known a pre-tilt is searched and recommended when it tolerates more.
Progress goes to stderr.

{SPEC_HELP}""",
)
@click.argument("spec_text", metavar="DESIGNATION|SPEC")
@click.option(
    "--force",
    "force_text",
    default="2:40",
    show_default=True,
    metavar="LO:HI",
    help="Bounds on the axial force, in N.",
)
@click.option(
    "--stiffness",
    "stiffness_text",
    default="0.1:10",
    show_default=True,
    metavar="LO:HI",
    help="Bounds on the rotational stiffness about X and Y, in N m/rad.",
)
@click.option(
    "--compliance-z",
    "compliance_z",
    default="0",
    show_default=True,
    metavar="Z|RANGE",
    help="Compliance centre on the bolt axis (bolt frame, spec units); a range or list "
    "(START:STOP:STEP, a comma list) is searched value by value.",
)
@click.option(
    "--friction",
    type=float,
    default=None,
    help="Thread friction coefficient (default: the Compliance's, 0.15).",
)
@click.option(
    "--lateral-stiffness",
    type=float,
    default=None,
    help="Lateral stiffness of the compliance centre in N/m (default: held at x = y = 0).",
)
@click.option(
    "--torque-limit",
    type=float,
    default=None,
    help="Driver torque limit in N m: a start whose peak torque passes it does not snap.",
)
@click.option(
    "--may-exceed",
    "may_exceed",
    type=float,
    default=1.0,
    show_default=True,
    metavar="FACTOR",
    help="How far (a factor on k/F) the search may go beyond the bounds when the best lies "
    "at one: the force stays at its bound, the stiffness goes beyond; 1: never.",
)
@click.option(
    "--ratios",
    type=int,
    default=None,
    help="Ratios k/F of the first log-spaced grid over the bounds (default 5).",
)
@click.option(
    "--refinements",
    type=int,
    default=None,
    help="Halvings of the grid step around the best (default 4).",
)
@envelope_grid_options("Coarse envelope", "0:4:1", "0:360:45", "0:340:40", None)
@click.option(
    "--no-confirm",
    "no_confirm",
    is_flag=True,
    help="Leave the optimum at the coarse envelope instead of measuring it again at the "
    "envelope's own grid (16 directions, 18 phases, 0.05 deg): minutes less, and the "
    "summary's figure then holds only in the coarse grid's directions.",
)
@click.option(
    "--fine",
    is_flag=True,
    help="Measure the robustness cases at the envelope's own grid too: two full envelopes "
    "more (the material conditions).",
)
@click.option(
    "--azimuth-known",
    "azimuth_known",
    is_flag=True,
    help="The nut's thread-start azimuth is known to the robot: search a pre-tilt at the "
    "optimum (sizes --pretilt-sizes toward the coarse directions), each judged by the "
    "envelope measured around it; recommended only when it tolerates more than upright.",
)
@click.option(
    "--pretilt-sizes",
    "pretilt_sizes",
    default="1,2",
    show_default=True,
    metavar="RANGE",
    help=f"Pre-tilt sizes searched with --azimuth-known: {RANGE_HELP}.",
)
@click.option(
    "--no-robustness",
    "no_robustness",
    is_flag=True,
    help="Skip the re-evaluation over material conditions and friction.",
)
@workers_option
@chord_option
@condition_option
@parts_option
@click.option("--plot", default=None, help="Write tolerated tilt against k/F to this file.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def design_command(
    spec_text: str,
    force_text: str,
    stiffness_text: str,
    compliance_z: str,
    friction: float | None,
    lateral_stiffness: float | None,
    torque_limit: float | None,
    may_exceed: float,
    ratios: int | None,
    refinements: int | None,
    tilt: str | None,
    direction: str | None,
    phase: str | None,
    tolerance: float | None,
    no_confirm: bool,
    fine: bool,
    azimuth_known: bool,
    pretilt_sizes: str,
    no_robustness: bool,
    workers: int | None,
    chord: float | None,
    condition: str,
    parts: SpecParts,
    plot: str | None,
    as_json: bool,
) -> None:
    """The design search (see the help text)."""
    check_workers(workers)
    figure = None
    if plot is not None:
        if Path(plot).suffix.lower() not in FIGURE_FORMATS:
            raise InputError(f"--plot {plot}: expected a file ending in .png, .pdf or .svg")
        figure = writable_output(plot, "--plot")
    force = _bounds(force_text, "--force", "N")
    stiffness = _bounds(stiffness_text, "--stiffness", "N m/rad")
    spec = resolve_spec(spec_text, condition, parts)
    from ._common import is_spec_path

    material = None
    if not is_spec_path(spec_text):
        # The same parts at each material condition.
        material = {c: resolve_spec(spec_text, c, parts) for c in ("max", "min")}
    from ..design import best_compliance, format_compliance_design, plot_compliance_design

    given: dict[str, Any] = {
        k: v
        for k, v in (
            ("ratios", ratios),
            ("refinements", refinements),
            ("tilt", tilt),
            ("direction", direction),
            ("phase", phase),
            ("tolerance", tolerance),
        )
        if v is not None
    }
    design = best_compliance(
        spec,
        force=force,
        stiffness=stiffness,
        compliance_z=_centre(compliance_z),
        friction=friction,
        lateral_stiffness=lateral_stiffness,
        torque_limit=torque_limit,
        may_exceed=may_exceed,
        confirm=not no_confirm,
        fine=fine,
        robust=not no_robustness,
        azimuth_known=azimuth_known,
        pretilt_sizes=pretilt_sizes,
        material=material,
        workers=workers,
        chord=chord,
        progress=lambda text: echo_err(f"design: {text}"),
        **given,
    )
    if figure is not None:
        try:
            plot_compliance_design(design, figure)
        except OSError as exc:
            raise write_failed(figure, exc) from None
    if as_json:
        doc = design.to_dict()
        doc["figure"] = str(figure) if figure is not None else None
        emit_json(doc)
        return
    click.echo(format_compliance_design(design))
    if figure is not None:
        click.echo(f"wrote {figure}")
