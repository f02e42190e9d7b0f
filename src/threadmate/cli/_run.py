"""``threadmate run``: the main job end to end, on a built-in default."""

from __future__ import annotations

from pathlib import Path

import click

from .._errors import InputError
from ..network import ResistanceParams
from ..pipeline import DEFAULT_DESIGNATION, run_pipeline
from ._common import SPEC_HELP, emit_json, resolve_spec
from ._library import _RANGE_HELP, _progress_bar
from ._main import cli


@cli.command("run", help=f"""Run the whole pipeline for DESIGNATION|SPEC into DIR.

Sweeps (or resumes, or reuses) DIR/library, builds the network, recommends the SRCC
pitch and writes DIR/network.graphml, DIR/recommendation.json, DIR/figures/ and
DIR/report.md. Default: {DEFAULT_DESIGNATION} on the thesis's grid. {SPEC_HELP}""")
@click.argument("spec_text", metavar="[DESIGNATION|SPEC]", required=False,
                default=DEFAULT_DESIGNATION)
@click.option("-o", "--out", type=click.Path(path_type=Path), default=Path("threadmate-run"),
              show_default=True, help="Output folder.")
@click.option("--roll", default=None, help=f"Roll grid: {_RANGE_HELP} (default -4:4:1).")
@click.option("--pitch", default=None, help=f"Pitch grid: {_RANGE_HELP} (default -4:4:1).")
@click.option("--phase", default=None, help=f"Phase grid: {_RANGE_HELP} (default 0:360:5).")
@click.option("--workers", type=int, default=None, help="Worker processes (default: all cores).")
@click.option("--scheduler", default=None, help="Dask scheduler address, or 'local'.")
@click.option("--chord", type=float, default=None, help="Mesh chord tolerance (spec units).")
@click.option("--roll-spread", type=float, default=None,
              help="Roll errors to expect, +/- degrees (default: the whole grid).")
@click.option("--condition", type=click.Choice(["mean", "max", "min"]), default="mean",
              show_default=True, help="Material condition at which a designation expands.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def run_command(spec_text: str, out: Path, roll: str | None, pitch: str | None,
                phase: str | None, workers: int | None, scheduler: str | None,
                chord: float | None, roll_spread: float | None, condition: str,
                as_json: bool) -> None:
    """The main job (help text above)."""
    if workers is not None and workers < 1:
        raise InputError(f"--workers {workers} must be at least 1")
    if roll_spread is not None and not (0 <= roll_spread <= 45):
        raise InputError(f"--roll-spread {roll_spread:g} must be within 0..45 degrees")
    if out.exists() and not out.is_dir():
        raise InputError(f"-o {out} exists and is not a folder")
    spec = resolve_spec(spec_text, condition)
    with _progress_bar("sweep") as callback:
        result = run_pipeline(spec, out, roll=roll, pitch=pitch, phase=phase, workers=workers,
                              scheduler=scheduler, chord=chord, roll_spread=roll_spread,
                              params=ResistanceParams(), progress=callback)
    if as_json:
        emit_json(result.to_dict())
        return
    click.echo(f"wrote {result.out}/: library/, network.graphml, network.json, "
               f"recommendation.json, figures/ ({len(result.figures)}), report.md")
    click.echo("states: " + ", ".join(f"{k} {v}" for k, v in result.counts.items()))
    click.echo(result.note)
