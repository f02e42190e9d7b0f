"""``threadmate sweep`` and ``threadmate library info|query|summary``: the contact-state
library over a roll/pitch/phase grid."""

from __future__ import annotations

import contextlib
import math
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import click

from .._errors import InputError
from .._validate import check_workers
from ..contact import CONTINUATION_STEP, MAX_STEP, PHASE_TOLERANCE, Compliance
from ..library import MODELS
from ._common import SPEC_HELP, Parts, emit_json, resolve_spec, writable_directory
from ._main import cli
from ._options import (
    DEFAULTS_NOTE,
    MeshFiles,
    chord_option,
    compliance_from_options,
    compliance_options,
    condition_option,
    echo_mesh_notes,
    max_starts_option,
    mesh_files_option,
    parts_option,
)

# The library stage (pandas, pyarrow, the mechanics) is imported where it is used, so that
# --help and a refused option answer at once.
__all__ = ["sweep_command", "library_group"]

_RANGE_HELP = (
    "START:STOP:STEP (STOP included when on the grid), a value, or a comma list, in degrees"
)


@contextlib.contextmanager
def _progress_bar(label: str) -> Iterator[Any]:
    """A rich bar on stderr fed by ``callback(done, total)``: done, rate, time left."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        ProgressColumn,
        Task,
        TextColumn,
        TimeRemainingColumn,
    )
    from rich.text import Text

    class _Rate(ProgressColumn):
        def render(self, task: Task) -> Text:
            return Text(f"{task.speed:.1f}/s" if task.speed else "-/s")

    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        _Rate(),
        TimeRemainingColumn(),
    )
    # The bar starts with the first report, i.e. once the request is validated, so that a
    # refused request prints its one error line and nothing else.
    bar: Progress | None = None
    task = None

    def callback(done: int, total: int) -> None:
        nonlocal bar, task
        if bar is None:
            bar = Progress(*columns, console=Console(file=sys.stderr), transient=False)
            bar.start()
            # Configurations resumed from disk fill the bar but do not count in the rate.
            task = bar.add_task(label, total=total, completed=done)
        elif task is not None:  # set with the bar
            bar.update(task, completed=done)

    try:
        yield callback
    finally:
        if bar is not None:
            bar.stop()


def _counts_line(counts: dict[str, int]) -> str:
    from ..library import CLASS_ORDER

    known = [c for c in CLASS_ORDER if counts.get(c, 0)]
    others = [c for c in counts if c not in CLASS_ORDER and counts[c]]
    return ", ".join(f"{c} {counts[c]}" for c in known + others) or "none yet"


def _roles_line(counts: dict[str, int]) -> str:
    from ..contact import ROLES

    return ", ".join(f"{r} {counts[r]}" for r in ROLES if counts.get(r, 0)) or "none"


def progress_words(library: str | Path, done: int, total: int, model: str = "mechanics") -> str:
    """``"4 of 8 starts done"``, and for an incomplete library whether its sweep still
    runs (the process holding its lock) or was interrupted."""
    from ..library import lock_holder

    noun = "starts" if model == "mechanics" else "configurations"
    words = f"{done} of {total} {noun} done"
    if done >= total:
        return words
    holder = lock_holder(library)
    if holder is not None:
        return (
            f"{words}: INCOMPLETE, a sweep (process {holder['pid']} on {holder['host']}, "
            f"since {holder['started']}) is still writing it"
        )
    return f"{words}: INCOMPLETE, its sweep was interrupted (run the same sweep to finish it)"


#: The mechanics-only options (the command's parameter names).
_MECHANICS_ONLY = (
    "force",
    "stiffness_text",
    "lateral_stiffness",
    "friction",
    "step",
    "phase_tolerance",
)


def _units(model: str, length: str) -> dict[str, str]:
    """The units of a library's JSON documents."""
    if model == "mechanics":
        return {
            "length": length,
            "angle": "deg",
            "force": "N",
            "torque": "N m",
            "potential": "mJ",
            "work": "mJ",
        }
    return {"length": length, "angle": "deg"}


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
    help=f"Held roll values: {_RANGE_HELP} (default -4:4:1).",
)
@click.option(
    "--pitch",
    "pitch",
    default=None,
    metavar="RANGE",
    help=f"Held pitch values: {_RANGE_HELP} (default -4:4:1).",
)
@click.option(
    "--phase",
    "phase",
    default=None,
    metavar="RANGE",
    help=f"Phase values, modulo 360: {_RANGE_HELP} (default 0:355:5).",
)
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
    help=f"Mechanics: continuation step in degrees of phase (> 0, at most {MAX_STEP:g}).",
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
@click.option(
    "--workers",
    type=int,
    default=None,
    help="Worker processes (default: the CPUs available; 1 runs in-process).",
)
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
    parts: Parts,
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
    from ..library import Grid

    Grid.parse(roll, pitch, phase)  # a bad range is refused before the library stage loads
    from ..library import METADATA_FILE, SweepInterrupted, info, sweep

    existed = (out / METADATA_FILE).is_file()
    resumed: dict[str, int] = {}
    start = time.perf_counter()
    try:
        with _progress_bar("sweep") as bar:

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
    report = {
        "library": str(out),
        "model": doc["model"],
        "units": _units(doc["model"], doc["units"]),
        "grid": doc["grid"],
        "configurations": doc["configurations"],
        "resumed": existed or bool(resumed.get("done")),
        "done_before": int(resumed.get("done", 0)),
        "done": doc["done"],
        "complete": doc["complete"],
        "parts": doc["parts"],
        "wall_s": wall,
        "classifications": doc["classifications"],
    }
    if doc["model"] == "mechanics":
        report["compliance"] = meta["compliance"]
        report["continuation"] = meta["continuation"]
        report["states"] = doc["states"]
    report["mesh"] = meta.get("mesh")
    echo_mesh_notes(meta.get("mesh"), doc["units"])
    if as_json:
        emit_json(report)
        return
    click.echo(f"Library {out} ({doc['model']} model): {doc['grid']}")
    what = "rest states reached" if doc["model"] == "mechanics" else "states"
    click.echo(
        f"  {doc['done']} of {doc['configurations']} done in {wall:.1f} s; "
        f"{what}: {_counts_line(doc['classifications'])}"
    )
    if doc["states"]:
        click.echo(
            f"  {doc['states']['total']} contact states: {_roles_line(doc['states']['by_role'])}"
        )


@cli.group("library")
def library_group() -> None:
    """Read a contact-state library without recomputing (info, query, summary)."""


def _library_arg() -> Any:
    return click.argument("library", metavar="LIBRARY", type=click.Path(path_type=Path))


def _with_units(doc: dict[str, Any]) -> dict[str, Any]:
    """A reader's document with ``units`` as a mapping of quantity to unit."""
    return {**doc, "units": _units(doc["model"], doc["units"])}


def _compliance_line(c: dict[str, Any], units: str) -> str:
    return Compliance.from_dict(c).describe(units)


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
        emit_json(_with_units(doc))
        return
    meta = doc["metadata"]
    spec = meta["spec"]
    mesh, contact = meta["mesh"], meta["contact"]
    name = spec.get("designation") or "custom spec"
    u = doc["units"]
    click.echo(
        f"Library {doc['path']} ({doc['model']} model; threadmate {meta['threadmate_version']})"
    )
    click.echo(
        f"  spec: {name}, pitch {spec['pitch']:g} {u}, "
        f"{spec.get('hand', 'right')} hand, bolt PD {spec['bolt']['pitch_diameter']:g},"
        f" nut PD {spec['nut']['pitch_diameter']:g}"
    )
    click.echo(f"  grid: {doc['grid']}")
    dev = mesh.get("max_deviation")
    click.echo(
        f"  mesh: chord {mesh['chord']:g} {u}"
        + (f", max deviation {dev:.3g} {u}" if dev is not None else "")
    )
    if doc["model"] == "mechanics":
        click.echo(f"  compliance: {_compliance_line(meta['compliance'], u)}")
        cont = meta.get("continuation", {})
        click.echo(
            f"  continuation: step {cont.get('step', float('nan')):g} deg, events "
            f"located to {cont.get('phase_tolerance', float('nan')):g} deg"
        )
    else:
        click.echo(
            f"  contact: compliance_z {contact['compliance_z']:g} {u}, "
            f"analyser {contact.get('analyzer', '?')}"
        )
    words = progress_words(library, doc["done"], doc["configurations"], doc["model"])
    parts = f"{doc['parts']} part" + ("" if doc["parts"] == 1 else "s")
    click.echo(f"  {words}, in {parts}" + (" (complete)" if doc["complete"] else ""))
    what = "rest states reached" if doc["model"] == "mechanics" else "states"
    click.echo(f"  {what}: {_counts_line(doc['classifications'])}")
    if doc["states"]:
        st = doc["states"]
        click.echo(f"  all {st['total']} contact states by role: {_roles_line(st['by_role'])}")
        click.echo(f"  by class: {_counts_line(st['by_class'])}")


def _check_grid_phase(phase: float, taken: float, library: Path) -> None:
    """Refuse a ``--phase`` that is not one of the library's grid phases (modulo 360),
    naming them: the stability map and the counts exist at grid phases only."""
    if abs((taken - phase + 180.0) % 360.0 - 180.0) <= 1e-6:
        return
    from ..library import info

    phases = [f"{v:g}" for v in info(library)["metadata"]["grid"]["phase"]]
    shown = phases if len(phases) <= 12 else [*phases[:6], "...", phases[-1]]
    raise InputError(
        f"--phase {phase:g} is not a phase of the library's grid ({', '.join(shown)} deg; "
        f"{len(phases)} phases): give one of them, e.g. the nearest, {taken:g}"
    )


def _fmt(v: Any) -> str:
    return f"{v:.6f}" if isinstance(v, float) and math.isfinite(v) else "-"


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
        emit_json(_with_units(doc))
        return
    g = doc["grid"]
    snap = " (snapped to the nearest grid state)" if doc["snapped"] else ""
    held = "HELD " if doc["model"] == "mechanics" else ""
    click.echo(
        f"{held}ROLL = {g['roll']:g}   {held}PITCH = {g['pitch']:g}   PHASE = "
        f"{g['phase']:g}   config_id {doc['config_id']}{snap}"
    )
    rec = doc["record"]
    if rec is None:
        click.echo("Not computed yet: the library's sweep is unfinished (run it again to resume).")
        return
    if doc["model"] == "mechanics":
        _echo_state(rec, doc["units"])
    else:
        _echo_thesis(rec, doc["units"])


def _echo_state(rec: dict[str, Any], u: str) -> None:
    """The rest state a mechanics drop reaches, its contacts and its passive transition."""
    click.echo(
        f"Rest state: {rec['classification']}   ({rec['n_contacts']} contact(s); "
        f"regions {rec['region_combination'] or '-'})   state {rec['state_id']}"
    )
    if rec["error"]:
        click.echo(f"Error: {rec['error']}")
        return
    click.echo(
        f"Bolt tilt: roll {rec['roll']:.4f}  pitch {rec['pitch']:.4f} deg;  "
        f"compliance centre height {_fmt(rec['centre_z'])} {u}"
    )
    points, normals = rec["contact_points"] or [], rec["contact_normals"] or []
    for i, (regions, force) in enumerate(
        zip(rec["contact_regions"] or [], rec["contact_forces"] or [], strict=False)
    ):
        p = " ".join(_fmt(v) for v in points[3 * i : 3 * i + 3])
        n = " ".join(f"{v:8.5f}" for v in normals[3 * i : 3 * i + 3])
        click.echo(f"  contact {i + 1}: {p}  normal {n}  force {force:.4f} N  {regions}")
    click.echo(
        f"Potential {rec['potential']:.6g} mJ;  driver torque "
        f"{rec['driver_torque']:.6g} N m (friction {rec['friction_torque']:.6g} N m)"
    )
    if rec["next_id"]:
        work = rec["work_friction"] + rec["work_potential"]
        click.echo(
            f"Next: {rec['transition']} ({rec['transition_label']}) to "
            f"{rec['next_id']} after {rec['transition_turn']:.4f} deg, work "
            f"{work:.6g} mJ, drop {_fmt(rec['drop'])} {u}"
        )
    else:
        click.echo("Next: none (the search ends here)")


def _echo_thesis(rec: dict[str, Any], u: str) -> None:
    """The thesis's stages of one configuration."""
    click.echo(
        f"Classification: {rec['classification']}   ({rec['n_contacts']} contact(s); "
        f"regions {rec['region_combination'] or '-'})"
    )
    if rec["error"]:
        click.echo(f"Error: {rec['error']}")
    for s in ("first", "second", "third"):
        if not rec[f"{s}_found"]:
            click.echo(f"{s}: none found")
            continue
        origin = " ".join(_fmt(rec[f"{s}_origin_{a}"]) for a in "xyz")
        click.echo(f"{s}: turn {rec[f'{s}_angle']:.4f} deg, bolt origin {origin} {u}")
        for i in (1, 2, 3):
            if rec[f"{s}_c{i}_pairs"]:
                p = " ".join(_fmt(rec[f"{s}_c{i}_{a}"]) for a in "xyz")
                click.echo(
                    f"  contact {i}: {p}  pairs {rec[f'{s}_c{i}_pairs']}  "
                    f"{rec[f'{s}_c{i}_bolt_region']}/{rec[f'{s}_c{i}_nut_region']}"
                )
    click.echo(
        f"interference {_fmt(rec['interference'])} {u}, origin drop "
        f"{_fmt(rec['origin_drop'])} {u}, pivot offset {_fmt(rec['pivot_offset'])} {u}"
    )


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
    from ..contact import ROLES
    from ..library import summary, write_figures

    doc = summary(library, phase=phase)
    if phase is not None:
        _check_grid_phase(phase, doc["at_phase"]["phase"], library)
    if figdir is not None:
        doc["figures"] = {k: str(v) for k, v in write_figures(library, figdir, phase).items()}
    doc["units"] = _units(doc["model"], doc["units"])
    doc["complete"] = doc["done"] >= doc["configurations"]
    if as_json:
        emit_json(doc)
        return
    done = doc["done"]
    mech = doc["model"] == "mechanics"
    words = progress_words(library, done, doc["configurations"], doc["model"])
    click.echo(f"{doc['library']} ({doc['model']} model): {doc['grid']}; {words}")
    if not doc["complete"]:
        click.echo("The counts below are of those done only.")
    if mech:
        click.echo("Rest state reached by the drop at each start:")
    for c, n in doc["counts"].items():
        click.echo(f"  {c:<13}{n:>8}  {100 * doc['fractions'][c]:5.1f} %")
    if done:
        among = "the rest classes" if mech else "the three states"
        click.echo(
            f"  most common of {among}: {doc['most_common']}; least common: {doc['least_common']}"
        )
    at = doc["at_phase"]
    click.echo(f"At phase {at['phase']:g} deg: {_counts_line(at['counts'])}")
    if mech and doc.get("states"):
        st = doc["states"]
        click.echo(f"All {st['total']} contact states (role: classes):")
        for role in [r for r in ROLES if r in st["by_role_and_class"]]:
            click.echo(
                f"  {role:<14}{st['by_role'][role]:>8}  "
                f"{_counts_line(st['by_role_and_class'][role])}"
            )
        moves = st.get("transitions", {})
        if moves:
            click.echo(
                "Passive transitions (kind: labels): "
                + "; ".join(
                    f"{k} {', '.join(f'{lab} {n}' for lab, n in v.items())}"
                    for k, v in moves.items()
                )
            )
    click.echo("Contact-region combinations (bolt/nut per contact):")
    for combo, n in list(doc["region_combinations"].items())[:15]:
        click.echo(f"  {n:>8}  {combo}")
    if len(doc["region_combinations"]) > 15:
        click.echo(f"  ... {len(doc['region_combinations']) - 15} more (see --json)")
    for name, path in doc.get("figures", {}).items():
        click.echo(f"Figure {name}: {path}")
