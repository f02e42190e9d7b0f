"""``threadmate run``: the main job end to end, on a built-in default."""

from __future__ import annotations

import dataclasses
import itertools
from pathlib import Path

import click

from .._errors import InputError
from .._validate import check_roll_spread, check_workers
from ..contact import CONTINUATION_STEP, TIGHTEN_STEP, UNSTABLE
from ..geometry import SpecParts
from ..pipeline import DEFAULT_DESIGNATION, RUN_GRID
from ._common import SPEC_HELP, echo_err, emit_json, resolve_spec, writable_directory
from ._main import cli
from ._options import (
    DEFAULTS_NOTE,
    RANGE_HELP,
    MeshFiles,
    chord_option,
    compliance_from_options,
    compliance_options,
    condition_option,
    echo_mesh_notes,
    max_starts_option,
    mesh_files_option,
    parts_option,
    roll_spread_option,
    workers_option,
)
from ._progress import progress_bar


def _values(text: str | None, option: str) -> list[float]:
    """A comma list of numbers (their range is the Compliance's to check)."""
    if text is None:
        return []
    try:
        # An empty item ('1,,2', ',', '') is a slip, not "nothing to compare".
        return [float(v) if v.strip() else float("") for v in text.split(",")]
    except ValueError:
        raise InputError(
            f"{option} {text!r}: give numbers separated by commas, e.g. 0.5,1,2"
        ) from None


@cli.command(
    "run",
    help=f"""Run the whole pipeline for DESIGNATION|SPEC into DIR.

Sweeps (or resumes, or reuses) the mechanics library DIR/library, builds the network,
recommends the SRCC setting and writes DIR/network.graphml, DIR/starts.csv,
DIR/recommendation.json, DIR/sensor.json and DIR/program.json (the snap a sensor sees,
what to program), DIR/figures/, DIR/report.md and DIR/report.html (the report as an
interactive page; the search of the start its click signature shows in DIR/views/).
DIR must be new, empty or a previous run's folder (resumed, its files written again).
Default: {DEFAULT_DESIGNATION} on held roll {RUN_GRID["roll"]}, pitch {RUN_GRID["pitch"]},
phase {RUN_GRID["phase"]} (degrees). {SPEC_HELP} {DEFAULTS_NOTE}""",
)
@click.argument(
    "spec_text", metavar="[DESIGNATION|SPEC]", required=False, default=DEFAULT_DESIGNATION
)
@click.option(
    "-o",
    "--out",
    type=click.Path(path_type=Path),
    default=Path("threadmate-run"),
    show_default=True,
    help="Output folder.",
)
@click.option(
    "--roll", default=None, help=f"Held roll grid: {RANGE_HELP} (default {RUN_GRID['roll']})."
)
@click.option(
    "--pitch", default=None, help=f"Held pitch grid: {RANGE_HELP} (default {RUN_GRID['pitch']})."
)
@click.option(
    "--phase", default=None, help=f"Start phase grid: {RANGE_HELP} (default {RUN_GRID['phase']})."
)
@compliance_options
@click.option(
    "--compare-stiffness",
    default=None,
    metavar="K1,K2,...",
    help="Also compare these rotational stiffnesses [N m/rad] (one library each).",
)
@click.option(
    "--compare-force",
    default=None,
    metavar="F1,F2,...",
    help="Also compare these axial forces [N] (one library each).",
)
@click.option(
    "--step",
    type=float,
    default=CONTINUATION_STEP,
    show_default=True,
    help=f"Continuation step of the search [deg]; its screw-in proofs and clockwise starts "
    f"step by at most {TIGHTEN_STEP:g}.",
)
@click.option(
    "--screw",
    "clockwise",
    is_flag=True,
    help="Also turn every start clockwise directly (threadmate screw); the report gives "
    "the share that engages against the held tilt.",
)
@workers_option
@click.option("--scheduler", default=None, help="Dask scheduler address, or 'local'.")
@chord_option
@roll_spread_option
@max_starts_option
@condition_option
@parts_option
@mesh_files_option
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def run_command(
    spec_text: str,
    out: Path,
    roll: str | None,
    pitch: str | None,
    phase: str | None,
    force: float,
    stiffness_text: str,
    lateral_stiffness: float | None,
    friction: float,
    compliance_z: float,
    compare_stiffness: str | None,
    compare_force: str | None,
    step: float,
    clockwise: bool,
    workers: int | None,
    scheduler: str | None,
    chord: float | None,
    roll_spread: float | None,
    max_starts: int | None,
    condition: str,
    as_json: bool,
    parts: SpecParts,
    meshes: MeshFiles,
) -> None:
    """The main job (help text above)."""
    # The API's checks of the cheap options, before the stages load (the pipeline checks
    # them again, and every other value, before it sweeps).
    check_workers(workers)
    check_roll_spread(roll_spread)
    writable_directory(out, "-o")
    base = compliance_from_options(force, stiffness_text, lateral_stiffness, friction, compliance_z)
    forces = _values(compare_force, "--compare-force")
    stiffnesses: list[float | tuple[float, float]] = list(
        _values(compare_stiffness, "--compare-stiffness")
    )
    compliances = [base]
    for f, k in itertools.product(forces or [base.force], stiffnesses or [base.stiffness]):
        c = dataclasses.replace(base, force=f, stiffness=k)
        if c not in compliances:
            compliances.append(c)
    spec = resolve_spec(spec_text, condition, parts)
    for c in compliances:
        c.check_for(spec.pitch)
    from ..library import Grid

    # A bad range is refused before the stages load (the pipeline checks it again).
    given = {"roll": roll, "pitch": pitch, "phase": phase}
    Grid.parse(*(RUN_GRID[k] if v is None else v for k, v in given.items()))
    # One core compiles the kernels (on a machine whose cache is empty) while this one
    # loads the stages and prepares the sweep.
    from ..contact import warm_kernels_aside

    warm_kernels_aside()
    from ..pipeline import check_run_folder, run_pipeline  # every stage, once the options are read

    try:  # a folder of the user's is not written into (a previous run's is resumed)
        check_run_folder(out)
    except InputError as exc:
        raise InputError(f"-o {exc}") from None

    try:
        with progress_bar("sweep") as callback:
            result = run_pipeline(
                spec,
                out,
                roll=roll,
                pitch=pitch,
                phase=phase,
                compliances=compliances,
                workers=workers,
                scheduler=scheduler,
                chord=chord,
                roll_spread=roll_spread,
                step=step,
                progress=callback,
                clockwise=clockwise,
                max_starts=max_starts,
                **meshes.arguments(),
            )
    except OSError as exc:  # the system refused a write (a full disk)
        raise InputError(
            f"cannot write {exc.filename or out}: {exc.strerror or exc} (every file written "
            "is whole: make room and run the same command to go on)"
        ) from None
    echo_mesh_notes(result.meshes, spec.units)
    unsettled = result.counts.get(f"starts {UNSTABLE}", 0)  # a start's class when not at rest
    if unsettled:
        echo_err(
            f"threadmate: warning: {unsettled} start(s) did not reach a rest state (the "
            "descent did not converge): left out of the ranking; report.md lists them"
        )
    if as_json:
        emit_json(result.to_dict())
        return
    best = result.recommended
    click.echo(
        f"wrote {result.out}/: {len(result.libraries)} librar"
        f"{'y' if len(result.libraries) == 1 else 'ies'}, network.graphml, "
        f"network.json, starts.csv, recommendation.json, "
        f"{', '.join(p.name for p in result.design.values())}, figures/ "
        f"({len(result.figures)}), report.md, report.html"
        + (f", views/ ({len(result.pages) - 1})" if len(result.pages) > 1 else "")
    )
    tol = result.tolerated
    if tol is not None:
        k = tol["stiffness"]
        fails = tol["first_failure"]
        click.echo(
            f"F = {tol['force']:g} N, k = {k['roll']:g}/{k['pitch']:g} N m/rad, held upright: "
            f"every start phase snaps up to {tol['tilt']:.2f} deg of misalignment in the "
            "grid's directions"
            + (f" (less than {fails:.2f} deg in the worst)" if fails is not None else "")
            + "; read off the grid (threadmate envelope locates it)"
        )
    click.echo(
        f"recommended pre-tilt (nut azimuth known): held pitch {best['held_pitch']:+g} deg; "
        f"{best['share_snap']:.0%} of starts snap within one turn"
    )
    for note in result.notes:
        click.echo(f"note: {note}")
