"""``threadmate envelope``: the capture envelope of a compliance (the design stage)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from .._errors import InputError
from .._validate import FIGURE_FORMATS, check_workers
from ..geometry import SpecParts
from ._common import SPEC_HELP, emit_json, resolve_spec, writable_output, write_failed
from ._main import cli
from ._options import (
    COMPLIANCE_PARAMETERS,
    DEFAULTS_NOTE,
    DIRECTION_HELP,
    chord_option,
    compliance_from_options,
    compliance_options,
    condition_option,
    envelope_grid_options,
    parts_option,
    workers_option,
)
from ._progress import progress_bar

__all__ = ["envelope_command"]

#: The options a library fixes for itself (the command's parameter names).
_LIBRARY_OWN = (*COMPLIANCE_PARAMETERS, "tilt", "direction", "phase", "chord", "condition")


def _given(ctx: click.Context, name: str) -> bool:
    source = ctx.get_parameter_source(name)
    return source is not None and source != click.core.ParameterSource.DEFAULT


def _is_library(text: str) -> bool:
    """A folder is read as a library (the design stage says so if it is none)."""
    return Path(text).is_dir()


@cli.command(
    "envelope",
    help=f"""The capture envelope of a compliance: what misalignment it tolerates.

For each direction of misalignment relative to the nut's thread start ({DIRECTION_HELP}),
the largest held tilt at which every start phase snaps within one turn, and those at
which 95 % and 50 % of them do; the tolerated misalignment is the worst direction's.
Each is located by bisection in tilt size between the grid's sizes, to --tolerance, every
phase evaluated at each size probed; then the turn, work, click and peak torque of the
starts inside. SOURCE is a polar library (threadmate sweep --tilt ... --direction ...),
whose compliance, grid and settings are its own, or a designation or spec, swept along
the directions on demand (nothing stored). Progress goes to stderr. Angles in degrees,
forces in N, stiffness in N m/rad, work in mJ, torque in N m.

{DEFAULTS_NOTE}

{SPEC_HELP}""",
)
@click.argument("source", metavar="LIBRARY|DESIGNATION|SPEC")
@compliance_options
@envelope_grid_options("Spec", "0:4:0.5", "0:360:22.5", "0:340:20", 0.05)
@workers_option
@chord_option
@condition_option
@parts_option
@click.option("--plot", default=None, help="Write the polar figure to this .png/.pdf/.svg.")
@click.option(
    "--output",
    "-o",
    "output",
    default=None,
    help="Also write the JSON document to this file.",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
@click.pass_context
def envelope_command(
    ctx: click.Context,
    source: str,
    force: float,
    stiffness_text: str,
    lateral_stiffness: float | None,
    friction: float,
    compliance_z: float,
    tilt: str | None,
    direction: str | None,
    phase: str | None,
    tolerance: float,
    workers: int | None,
    chord: float | None,
    condition: str,
    parts: SpecParts,
    plot: str | None,
    output: str | None,
    as_json: bool,
) -> None:
    """The capture envelope (see the help text)."""
    check_workers(workers)
    figure = _out_file(plot, "--plot", tuple(FIGURE_FORMATS)) if plot else None
    document = _out_file(output, "-o", (".json",)) if output else None
    library = _is_library(source)
    args: dict[str, Any] = {"tolerance": tolerance, "workers": workers}
    if library:
        given = [p for p in ctx.command.params if p.name in _LIBRARY_OWN and _given(ctx, p.name)]
        if given or parts.given:
            flag = given[0].opts[0] if given else "the parts' options"
            raise InputError(
                f"{flag}: {source} is a library, whose compliance, grid, mesh and parts are "
                "its own; give a designation or spec to choose them"
            )
        target: Any = source
    else:
        from ..library import PolarGrid

        PolarGrid.parse(tilt, direction, phase or "0")  # a bad range, before any work
        target = resolve_spec(source, condition, parts)
        args.update(
            compliance=compliance_from_options(
                force, stiffness_text, lateral_stiffness, friction, compliance_z
            ),
            tilt=tilt,
            direction=direction,
            phase=phase,
            chord=chord,
        )
    from ..design import envelope, plot_envelope

    with progress_bar("envelope (held tilts)") as bar:
        env = envelope(target, progress=bar, **args)
    doc = env.to_dict()
    from .._io import atomic_write_text
    from .._json import json_text

    for path, write in (
        (document, lambda p: atomic_write_text(p, json_text(doc))),
        (figure, lambda p: plot_envelope(env, p)),
    ):
        if path is not None:
            try:
                write(path)
            except OSError as exc:  # a full disk
                raise write_failed(path, exc) from None
    if as_json:
        doc["figure"] = str(figure) if figure is not None else None
        emit_json(doc)
        return
    _echo(env)
    for path in (document, figure):
        if path is not None:
            click.echo(f"wrote {path}")


def _out_file(path: str, option: str, suffixes: tuple[str, ...]) -> Path:
    out = Path(path)
    if out.suffix.lower() not in suffixes:
        raise InputError(f"{option} {path}: expected a file ending in {' or '.join(suffixes)}")
    return writable_output(out, option)


def _num(value: float | None, fmt: str) -> str:
    from .._text import number_text

    return number_text(value, fmt)


def _echo(env: Any) -> None:
    """The envelope as text: the sentence, the table by direction, what lies inside."""
    c = env.compliance
    k = c["stiffness"]
    click.echo(
        f"Compliance F {c['force']:g} N, k {k['roll']:g}/{k['pitch']:g} N m/rad, friction "
        f"{c['friction']:g}: {env.summary_line()}."
    )
    t = env.tolerated
    click.echo(
        f"95 % of phases snap up to {t['95%']['tilt']:.2f} deg and 50 % up to "
        f"{t['50%']['tilt']:.2f} deg {env.where()} (bisected to {env.tolerance:g} deg)."
    )
    click.echo("")
    click.echo("| direction deg | 100 % deg | 95 % deg | 50 % deg | turn mean deg | click min |")
    click.echo("|---|---|---|---|---|---|")
    for x in env.directions:
        tt = x["tilt"]
        mark = {lv: (">=" if x["beyond_range"][lv] else "") for lv in tt}
        click.echo(
            f"| {x['direction']:g} | {mark['100%']}{tt['100%']:.2f} | {mark['95%']}"
            f"{tt['95%']:.2f} | {mark['50%']}{tt['50%']:.2f} | "
            f"{_num(x['inside']['turn_mean'], '.0f')} | "
            f"{_num(x['inside']['click_min'], '.2e')} |"
        )
    i = env.inside
    click.echo("")
    click.echo(
        f"Inside the tolerated misalignment ({i['starts']} starts): turn to the snap "
        f"{_num(i['turn_mean'], '.0f')} deg mean, {_num(i['turn_worst'], '.0f')} worst; work "
        f"{_num(i['work_mean'], '.3g')} mJ mean, {_num(i['work_worst'], '.3g')} worst; click "
        f"{_num(i['click_mean'], '.2e')} {env.units} mean, {_num(i['click_min'], '.2e')} "
        f"smallest; peak torque {_num(i['torque_peak'], '.3g')} N m."
    )
    click.echo(f"{env.probes} held tilts computed in {env.seconds:.0f} s.")
    for note in env.notes:
        click.echo(f"note: {note}")
