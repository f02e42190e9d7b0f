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
from ..library import (
    CLASS_ORDER,
    SweepInterrupted,
    info,
    query,
    summary,
    sweep,
    write_figures,
)
from ._common import SPEC_HELP, emit_json, resolve_spec
from ._main import cli

__all__ = ["sweep_command", "library_group"]

_RANGE_HELP = ("START:STOP:STEP (STOP included when on the grid), a value, or a comma list, "
               "in degrees")


@contextlib.contextmanager
def _progress_bar(label: str) -> Iterator[Any]:
    """A rich bar on stderr fed by ``callback(done, total)``: done, rate, time left."""
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        ProgressColumn,
        TextColumn,
        TimeRemainingColumn,
    )
    from rich.text import Text

    class _Rate(ProgressColumn):
        def render(self, task):  # noqa: ANN001, ANN202 - rich's column protocol
            return Text(f"{task.speed:.1f}/s" if task.speed else "-/s")

    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), _Rate(),
               TimeRemainingColumn())
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
        else:
            bar.update(task, completed=done)

    try:
        yield callback
    finally:
        if bar is not None:
            bar.stop()


def _counts_line(counts: dict[str, int]) -> str:
    return ", ".join(f"{c} {counts.get(c, 0)}" for c in CLASS_ORDER if counts.get(c, 0)) \
        or "none yet"


@cli.command("sweep", help=f"""Build the contact-state library of a thread pair over a grid.

Runs the contact stages (see `threadmate contact`) for every roll x pitch x phase of the
grid (default the thesis's: roll and pitch -4..4 by 1, phase 0..355 by 5; 5,832
configurations) and writes the rows in chunks to LIBRARY, a Parquet dataset directory
with its metadata. Running the same command on an interrupted LIBRARY resumes it; a
LIBRARY of another spec, grid or setting is refused. Progress goes to stderr.

{SPEC_HELP}""")
@click.argument("spec_text", metavar="DESIGNATION|SPEC")
@click.option("--roll", "roll", default=None, metavar="RANGE",
              help=f"Roll values: {_RANGE_HELP} (default -4:4:1).")
@click.option("--pitch", "pitch", default=None, metavar="RANGE",
              help=f"Pitch values: {_RANGE_HELP} (default -4:4:1).")
@click.option("--phase", "phase", default=None, metavar="RANGE",
              help=f"Phase values, modulo 360: {_RANGE_HELP} (default 0:355:5).")
@click.option("-o", "--out", "out", required=True, type=click.Path(path_type=Path),
              help="Library directory (created, or resumed if it holds this sweep).")
@click.option("--workers", type=int, default=None,
              help="Worker processes (default: the CPUs available; 1 runs in-process).")
@click.option("--scheduler", default=None, metavar="ADDRESS|local|pool",
              help="Dask scheduler address, 'local' for a Dask LocalCluster, or 'pool' for "
                   "the process pool (default: Dask's scheduler-address setting if set, "
                   "else the pool). Dask: pip install threadmate[dask].")
@click.option("--chord", type=float, default=None,
              help="Chord tolerance of the meshes in the spec's units "
                   "(default 5e-6 in, 1.27e-4 mm).")
@click.option("--compliance-z", type=float, default=0.0, show_default=True,
              help="Compliance centre on the bolt axis, bolt frame (0: the tip centre).")
@click.option("--chunk-size", type=int, default=None,
              help="Configurations per chunk, i.e. per Parquet part (default: automatic).")
@click.option("--condition", type=click.Choice(["mean", "max", "min"]), default="mean",
              show_default=True, help="Material condition at which a designation expands.")
@click.option("--json", "as_json", is_flag=True,
              help="Print one JSON document on stdout instead of text.")
def sweep_command(spec_text: str, roll: str | None, pitch: str | None, phase: str | None,
                  out: Path, workers: int | None, scheduler: str | None, chord: float | None,
                  compliance_z: float, chunk_size: int | None, condition: str,
                  as_json: bool) -> None:
    """Sweep the grid into a library."""
    if workers is not None and workers < 1:
        raise InputError(f"--workers {workers} must be at least 1")
    if chunk_size is not None and chunk_size < 1:
        raise InputError(f"--chunk-size {chunk_size} must be at least 1")
    spec = resolve_spec(spec_text, condition)
    start = time.perf_counter()
    try:
        with _progress_bar("sweep") as callback:
            sweep(spec, roll, pitch, phase, out=out, workers=workers, scheduler=scheduler,
                  chunk_size=chunk_size, chord=chord, compliance_z=compliance_z,
                  progress=callback)
    except SweepInterrupted as exc:
        raise click.ClickException(str(exc)) from None
    except KeyboardInterrupt:
        if out.is_dir():
            with contextlib.suppress(Exception):
                doc = info(out)
                click.echo(f"threadmate: {doc['done']} of {doc['configurations']} "
                           f"configurations are saved in {out}; run the same command to "
                           "resume", err=True)
        raise
    wall = time.perf_counter() - start
    doc = info(out)
    report = {
        "library": str(out),
        "units": doc["units"],
        "grid": doc["grid"],
        "configurations": doc["configurations"],
        "done": doc["done"],
        "complete": doc["complete"],
        "parts": doc["parts"],
        "wall_s": wall,
        "classifications": doc["classifications"],
    }
    if as_json:
        emit_json(report)
        return
    click.echo(f"Library {out}: {doc['grid']}")
    click.echo(f"  {doc['done']} of {doc['configurations']} done in {wall:.1f} s; "
               f"{_counts_line(doc['classifications'])}")


@cli.group("library")
def library_group() -> None:
    """Read a contact-state library without recomputing (info, query, summary)."""


def _library_arg() -> Any:
    return click.argument("library", metavar="LIBRARY", type=click.Path(path_type=Path))


@library_group.command("info")
@_library_arg()
@click.option("--json", "as_json", is_flag=True,
              help="Print one JSON document on stdout instead of text.")
def info_command(library: Path, as_json: bool) -> None:
    """What a library holds: spec, grid, settings, progress and counts."""
    doc = info(library)
    if as_json:
        emit_json(doc)
        return
    meta = doc["metadata"]
    spec = meta["spec"]
    mesh, contact = meta["mesh"], meta["contact"]
    name = spec.get("designation") or "custom spec"
    click.echo(f"Library {doc['path']} (threadmate {meta['threadmate_version']})")
    click.echo(f"  spec: {name}, pitch {spec['pitch']:g} {doc['units']}, "
               f"{spec.get('hand', 'right')} hand, bolt PD {spec['bolt']['pitch_diameter']:g},"
               f" nut PD {spec['nut']['pitch_diameter']:g}")
    click.echo(f"  grid: {doc['grid']}")
    dev = mesh.get("max_deviation")
    click.echo(f"  mesh: chord {mesh['chord']:g} {doc['units']}"
               + (f", max deviation {dev:.3g} {doc['units']}" if dev is not None else ""))
    click.echo(f"  contact: compliance_z {contact['compliance_z']:g} {doc['units']}, "
               f"analyser {contact.get('analyzer', '?')}")
    state = "complete" if doc["complete"] else "incomplete: run the same sweep to resume"
    click.echo(f"  done: {doc['done']} of {doc['configurations']} in {doc['parts']} parts "
               f"({state})")
    click.echo(f"  states: {_counts_line(doc['classifications'])}")


def _fmt(v: Any) -> str:
    return f"{v:.6f}" if isinstance(v, float) and math.isfinite(v) else "-"


@library_group.command("query")
@_library_arg()
@click.option("--roll", type=float, required=True, help="Roll in degrees.")
@click.option("--pitch", type=float, required=True, help="Pitch in degrees.")
@click.option("--phase", type=float, required=True, help="Phase in degrees (modulo 360).")
@click.option("--json", "as_json", is_flag=True,
              help="Print one JSON document on stdout instead of text.")
def query_command(library: Path, roll: float, pitch: float, phase: float,
                  as_json: bool) -> None:
    """The stored contact state nearest a configuration (snapped to the grid)."""
    doc = query(library, roll, pitch, phase)
    if as_json:
        emit_json(doc)
        return
    g = doc["grid"]
    snap = " (snapped to the nearest grid state)" if doc["snapped"] else ""
    click.echo(f"ROLL = {g['roll']:g}   PITCH = {g['pitch']:g}   PHASE = {g['phase']:g}"
               f"   config_id {doc['config_id']}{snap}")
    rec = doc["record"]
    if rec is None:
        click.echo("Not computed yet: the library's sweep is unfinished (run it again to "
                   "resume).")
        return
    click.echo(f"Classification: {rec['classification']}   ({rec['n_contacts']} contact(s); "
               f"regions {rec['region_combination'] or '-'})")
    if rec["error"]:
        click.echo(f"Error: {rec['error']}")
    u = doc["units"]
    for s in ("first", "second", "third"):
        if not rec[f"{s}_found"]:
            click.echo(f"{s}: none found")
            continue
        origin = " ".join(_fmt(rec[f"{s}_origin_{a}"]) for a in "xyz")
        click.echo(f"{s}: turn {rec[f'{s}_angle']:.4f} deg, bolt origin {origin} {u}")
        for i in (1, 2, 3):
            if rec[f"{s}_c{i}_pairs"]:
                p = " ".join(_fmt(rec[f"{s}_c{i}_{a}"]) for a in "xyz")
                click.echo(f"  contact {i}: {p}  pairs {rec[f'{s}_c{i}_pairs']}  "
                           f"{rec[f'{s}_c{i}_bolt_region']}/{rec[f'{s}_c{i}_nut_region']}")
    click.echo(f"interference {_fmt(rec['interference'])} {u}, origin drop "
               f"{_fmt(rec['origin_drop'])} {u}, pivot offset {_fmt(rec['pivot_offset'])} {u}")


@library_group.command("summary")
@_library_arg()
@click.option("--phase", type=float, default=None,
              help="Phase of the stability map and of the per-phase counts (degrees; "
                   "default the first grid phase).")
@click.option("-o", "--out", "figdir", type=click.Path(path_type=Path), default=None,
              help="Write the figures (stability map, phase strips, region combinations) "
                   "as PNG into this directory.")
@click.option("--json", "as_json", is_flag=True,
              help="Print one JSON document on stdout instead of text.")
def summary_command(library: Path, phase: float | None, figdir: Path | None,
                    as_json: bool) -> None:
    """Counts of unstable, quasi-stable and stable states, region combinations, figures."""
    if phase is not None and not math.isfinite(phase):
        raise InputError(f"--phase {phase:g} is not a finite angle")
    from ..library import load

    rows = load(library, columns=["roll", "pitch", "phase", "classification", "n_contacts",
                                  "region_combination"])
    doc = summary(rows, phase=phase if phase is not None else rows.attrs["threadmate"]
                  ["grid"]["phase"][0])
    if figdir is not None:
        doc["figures"] = {k: str(v) for k, v in write_figures(rows, figdir, phase).items()}
    if as_json:
        emit_json(doc)
        return
    done = doc["done"]
    click.echo(f"{doc['library']}: {doc['grid']}; {done} done")
    for c in CLASS_ORDER:
        n = doc["counts"][c]
        click.echo(f"  {c:<13}{n:>8}  {100 * doc['fractions'][c]:5.1f} %")
    if done:
        click.echo(f"  most common of the three states: {doc['most_common']}; least common: "
                   f"{doc['least_common']}")
    at = doc["at_phase"]
    click.echo(f"At phase {at['phase']:g} deg: {_counts_line(at['counts'])}")
    click.echo("Contact-region combinations (bolt/nut per contact):")
    for combo, n in list(doc["region_combinations"].items())[:15]:
        click.echo(f"  {n:>8}  {combo}")
    if len(doc["region_combinations"]) > 15:
        click.echo(f"  ... {len(doc['region_combinations']) - 15} more (see --json)")
    for name, path in doc.get("figures", {}).items():
        click.echo(f"Figure {name}: {path}")
