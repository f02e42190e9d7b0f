"""``threadmate sweep`` and ``threadmate library info|query|summary``: the contact-state
library over a roll/pitch/phase grid.

The commands' options and their calls into the library stage; the progress bar is
:mod:`._progress`'s, the text and JSON documents :mod:`._render_library`'s.
"""

from __future__ import annotations

import contextlib
import time
from pathlib import Path
from typing import Any

import click

from .._angles import phase_difference
from .._errors import InputError
from .._validate import check_workers
from ..contact import CONTINUATION_STEP, MAX_STEP, PHASE_TOLERANCE, TIGHTEN_STEP
from ..geometry import SpecParts
from ..library import DEFAULT_RANGES, MODELS
from ._common import SPEC_HELP, emit_json, resolve_spec, writable_directory
from ._main import cli
from ._options import (
    DEFAULTS_NOTE,
    RANGE_HELP,
    MeshFiles,
    check_grid_kind,
    chord_option,
    compliance_from_options,
    compliance_options,
    condition_option,
    echo_mesh_notes,
    max_starts_option,
    mesh_files_option,
    parts_option,
    polar_grid_options,
    workers_option,
)
from ._progress import progress_bar
from ._render_library import (
    echo_info,
    echo_query,
    echo_summary,
    echo_sweep,
    library_units,
    sweep_report,
    with_units,
)

# The library stage (pandas, pyarrow, the mechanics) is imported where it is used, so that
# --help and a refused option answer at once.
__all__ = ["sweep_command", "library_group"]


#: The mechanics-only options (the command's parameter names).
_MECHANICS_ONLY = (
    "force",
    "stiffness_text",
    "lateral_stiffness",
    "friction",
    "step",
    "phase_tolerance",
)


def _given(ctx: click.Context, name: str) -> bool:
    """Whether the user gave option ``name`` (not its default)."""
    source = ctx.get_parameter_source(name)
    return source is not None and source != click.core.ParameterSource.DEFAULT


def _flag(ctx: click.Context, name: str) -> str:
    """The flag of the command's parameter ``name`` (as click declares it)."""
    return next(p.opts[0] for p in ctx.command.params if p.name == name)


def _check_sweep_options(ctx: click.Context, model: str, workers: int | None) -> None:
    """Refuse misplaced sweep options and a bad worker count (one message, before the
    library stage loads); the API checks every value's range."""
    check_workers(workers)
    if model == "thesis":
        given = [_flag(ctx, name) for name in _MECHANICS_ONLY if _given(ctx, name)]
        if given:
            raise InputError(
                f"{given[0]} applies to --model mechanics only (the thesis's "
                "model uses the compliance centre, --compliance-z, alone)"
            )
        return
    if _given(ctx, "chunk_size"):
        raise InputError(
            "--chunk-size applies to --model thesis only (a mechanics chunk is "
            "one held tilt with all its phases)"
        )


@cli.command(
    "sweep",
    help=f"""Build the contact-state library of a thread pair over a grid.

Every roll x pitch x phase of the grid (default the thesis's: roll and pitch -4..4 by 1,
phase 0..355 by 5; 5,832 configurations) is a start: the held tilt of the tool and the
phase at which the bolt is dropped. With --model mechanics (the default; see `threadmate
settle` and `threadmate search`) the library holds, for each start, the rest state the
bolt reaches under the axial force and the compliance, the unstable states passed on the
way, and the counter-clockwise search continued from it grid phase by grid phase, with
the jumps and the snap located between grid phases; each state with its passive
transition (settling, turning, jump or snap) and the driver's work along it (mJ). With
--model thesis it holds the thesis's fixed-pivot stages per configuration (see
`threadmate contact`), with the thesis's classes. The compliance and continuation
settings are stored in the library.

With --tilt and --direction the grid is polar instead: held tilts by size (the angle
between bolt and nut axes) and direction (the azimuth in the nut's frame, from +X toward
+Y, toward which the bolt's axis leans), e.g. --tilt 0:4:0.5 --direction 0:360:22.5;
size 0 is one upright held tilt. Each held tilt's roll and pitch are computed exactly
from its size and direction (docs/design.md) and every row carries them.

Rows are written in chunks to LIBRARY, a Parquet dataset directory with its metadata.
Running the same command on an interrupted LIBRARY resumes it (saying how many
configurations were already done); a LIBRARY of another spec, grid, model or setting is
refused, and so is a second sweep of a LIBRARY that a sweep is writing (naming its
process). A grid past --max-starts is refused at once, with its count and the time it
would take. Progress goes to stderr. Forces in N, stiffness in N m/rad, lateral stiffness in
N/m, lengths in the spec's units, angles in degrees.

{DEFAULTS_NOTE}

{SPEC_HELP}""",
)
@click.argument("spec_text", metavar="DESIGNATION|SPEC")
@click.option(
    "--roll",
    "roll",
    default=None,
    metavar="RANGE",
    help=f"Held roll values: {RANGE_HELP} (default {DEFAULT_RANGES['roll']}).",
)
@click.option(
    "--pitch",
    "pitch",
    default=None,
    metavar="RANGE",
    help=f"Held pitch values: {RANGE_HELP} (default {DEFAULT_RANGES['pitch']}).",
)
@click.option(
    "--phase",
    "phase",
    default=None,
    metavar="RANGE",
    help=f"Phase values, modulo 360: {RANGE_HELP} (default {DEFAULT_RANGES['phase']}).",
)
@polar_grid_options
@click.option(
    "-o",
    "--out",
    "out",
    required=True,
    type=click.Path(path_type=Path),
    help="Library directory (created, or resumed if it holds this sweep).",
)
@click.option(
    "--model",
    type=click.Choice(list(MODELS)),
    default="mechanics",
    show_default=True,
    help="mechanics: rest states, settling and the simulated search; thesis: the "
    "thesis's fixed-pivot stages.",
)
@compliance_options
@click.option(
    "--step",
    type=float,
    default=CONTINUATION_STEP,
    show_default=True,
    help=f"Mechanics: continuation step in degrees of phase (> 0, at most {MAX_STEP:g}; "
    f"the screw-in proofs and clockwise starts step by at most {TIGHTEN_STEP:g}).",
)
@click.option(
    "--phase-tolerance",
    type=float,
    default=PHASE_TOLERANCE,
    show_default=True,
    help="Mechanics: how closely jumps and the snap are located in phase "
    "(degrees, > 0, at most --step).",
)
@click.option(
    "--screw",
    "clockwise",
    is_flag=True,
    help="Mechanics: also turn every start clockwise directly (threadmate screw, one turn) "
    "and record whether it engages, rides or jams (columns clockwise, clockwise_phase).",
)
@workers_option
@click.option(
    "--scheduler",
    default=None,
    metavar="ADDRESS|local|pool",
    help="Dask scheduler address, 'local' for a Dask LocalCluster, or 'pool' for "
    "the process pool (default: Dask's scheduler-address setting if set, "
    "else the pool). Dask: pip install threadmate[dask].",
)
@chord_option
@click.option(
    "--chunk-size",
    type=int,
    default=None,
    help="Thesis model: configurations per chunk, i.e. per Parquet part (default: "
    "automatic). A mechanics chunk is one held tilt.",
)
@max_starts_option
@condition_option
@parts_option
@mesh_files_option
@click.option(
    "--json", "as_json", is_flag=True, help="Print one JSON document on stdout instead of text."
)
@click.pass_context
def sweep_command(
    ctx: click.Context,
    spec_text: str,
    roll: str | None,
    pitch: str | None,
    phase: str | None,
    tilt: str | None,
    direction: str | None,
    out: Path,
    model: str,
    force: float,
    stiffness_text: str,
    lateral_stiffness: float | None,
    friction: float,
    compliance_z: float,
    step: float,
    phase_tolerance: float,
    clockwise: bool,
    workers: int | None,
    scheduler: str | None,
    chord: float | None,
    chunk_size: int | None,
    max_starts: int | None,
    condition: str,
    as_json: bool,
    parts: SpecParts,
    meshes: MeshFiles,
) -> None:
    """Sweep the grid into a library."""
    _check_sweep_options(ctx, model, workers)
    if clockwise and model != "mechanics":
        raise InputError("--screw is for the mechanics model only")
    compliance = compliance_from_options(
        force, stiffness_text, lateral_stiffness, friction, compliance_z
    )
    spec = resolve_spec(spec_text, condition, parts)
    writable_directory(out, "-o")
    check_grid_kind(roll, pitch, tilt, direction)
    from ..library import make_grid

    # A bad range, or a square and a polar grid mixed, is refused before the stage loads.
    make_grid(roll, pitch, phase, tilt, direction)
    from ..library import METADATA_FILE, SweepInterrupted, info, sweep

    existed = (out / METADATA_FILE).is_file()
    resumed: dict[str, int] = {}
    start = time.perf_counter()
    try:
        with progress_bar("sweep") as bar:

            def callback(done: int, total: int) -> None:
                if not resumed:
                    # The first report comes once the library is opened and checked.
                    resumed.update(done=done, total=total)
                    if existed or done:
                        click.echo(
                            f"threadmate: resuming {out}: {done} of {total} "
                            "configurations were already done",
                            err=True,
                        )
                bar(done, total)

            sweep(
                spec,
                roll,
                pitch,
                phase,
                out=out,
                workers=workers,
                scheduler=scheduler,
                chunk_size=chunk_size,
                chord=chord,
                model=model,
                compliance=compliance,
                step=step,
                phase_tolerance=phase_tolerance,
                progress=callback,
                clockwise=clockwise,
                max_starts=max_starts,
                tilt=tilt,
                direction=direction,
                **meshes.arguments(),
            )
    except SweepInterrupted as exc:
        raise click.ClickException(str(exc)) from None
    except OSError as exc:  # the system refused a write (a full disk): what is kept, and how on
        saved = ""
        with contextlib.suppress(Exception):
            doc = info(out)
            saved = (
                f"; {doc['done']} of {doc['configurations']} configurations are saved "
                "there: make room and run the same command to resume"
            )
        raise InputError(f"cannot write {out}: {exc.strerror or exc}{saved}") from None
    except KeyboardInterrupt:
        if out.is_dir():
            with contextlib.suppress(Exception):
                doc = info(out)
                click.echo(
                    f"threadmate: {doc['done']} of {doc['configurations']} "
                    f"configurations are saved in {out}; run the same command to "
                    "resume",
                    err=True,
                )
        raise
    wall = time.perf_counter() - start
    doc = info(out)
    meta = doc["metadata"]
    report = sweep_report(out, doc, existed, resumed, wall)
    echo_mesh_notes(meta.get("mesh"), doc["units"])
    if as_json:
        emit_json(report)
        return
    echo_sweep(out, doc, wall)


@cli.group("library")
def library_group() -> None:
    """Read a contact-state library without recomputing (info, query, summary)."""


def _library_arg() -> Any:
    return click.argument("library", metavar="LIBRARY", type=click.Path(path_type=Path))


@library_group.command("info")
@_library_arg()
@click.option(
    "--json", "as_json", is_flag=True, help="Print one JSON document on stdout instead of text."
)
def info_command(library: Path, as_json: bool) -> None:
    """What a library holds: spec, grid, model, settings, progress and counts."""
    from ..library import info

    doc = info(library)
    if as_json:
        emit_json(with_units(doc))
        return
    echo_info(library, doc)


def _check_grid_phase(phase: float, taken: float, library: Path) -> None:
    """Refuse a ``--phase`` that is not one of the library's grid phases (modulo 360),
    naming them: the stability map and the counts exist at grid phases only."""
    if abs(phase_difference(taken, phase)) <= 1e-6:
        return
    from ..library import info

    phases = [f"{v:g}" for v in info(library)["metadata"]["grid"]["phase"]]
    shown = phases if len(phases) <= 12 else [*phases[:6], "...", phases[-1]]
    raise InputError(
        f"--phase {phase:g} is not a phase of the library's grid ({', '.join(shown)} deg; "
        f"{len(phases)} phases): give one of them, e.g. the nearest, {taken:g}"
    )


@library_group.command("query")
@_library_arg()
@click.option("--roll", type=float, required=True, help="(Held) roll in degrees.")
@click.option("--pitch", type=float, required=True, help="(Held) pitch in degrees.")
@click.option("--phase", type=float, required=True, help="Phase in degrees (modulo 360).")
@click.option(
    "--nearest",
    is_flag=True,
    help="Take the nearest grid configuration when the one asked for is off the "
    "grid (without it, such a request is refused with the nearest named).",
)
@click.option(
    "--json", "as_json", is_flag=True, help="Print one JSON document on stdout instead of text."
)
def query_command(
    library: Path, roll: float, pitch: float, phase: float, nearest: bool, as_json: bool
) -> None:
    """The stored contact state of a configuration of the grid: the thesis's stages, or
    the rest state the mechanics' drop reaches."""
    from ..library import query  # it checks the configuration (threadmate._validate)

    doc = query(library, roll, pitch, phase, nearest=nearest)
    if as_json:
        emit_json(with_units(doc))
        return
    echo_query(doc)


@library_group.command("summary")
@_library_arg()
@click.option(
    "--phase",
    type=float,
    default=None,
    help="Phase of the stability map and of the per-phase counts (degrees; "
    "default the first grid phase).",
)
@click.option(
    "-o",
    "--out",
    "figdir",
    type=click.Path(path_type=Path),
    default=None,
    help="Write the figures (stability map, phase strips, region combinations) "
    "as PNG into this directory.",
)
@click.option(
    "--json", "as_json", is_flag=True, help="Print one JSON document on stdout instead of text."
)
def summary_command(library: Path, phase: float | None, figdir: Path | None, as_json: bool) -> None:
    """Counts of the classes over the configurations (the mechanics: of the rest state
    each drop reaches, and of all states by role), region combinations, figures."""
    if figdir is not None:
        writable_directory(figdir, "-o")
    from ..library import summary, write_figures

    doc = summary(library, phase=phase)
    if phase is not None:
        _check_grid_phase(phase, doc["at_phase"]["phase"], library)
    if figdir is not None:
        doc["figures"] = {k: str(v) for k, v in write_figures(library, figdir, phase).items()}
    doc["units"] = library_units(doc["model"], doc["units"])
    doc["complete"] = doc["done"] >= doc["configurations"]
    if as_json:
        emit_json(doc)
        return
    echo_summary(library, doc)
