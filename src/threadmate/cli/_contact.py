"""``threadmate contact``: first, second and third contact of a tilted bolt on its nut.

The thesis's fixed-pivot procedure, classified by its criteria of section 4.2 (see
:mod:`threadmate.contact`); the physical model is ``threadmate settle`` / ``search``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import click

from .._text import number_text
from .._validate import MAX_LENGTH, MAX_TILT, check_configuration
from ..geometry import SpecParts, check_chord
from ._common import SPEC_HELP, emit_json, resolve_spec
from ._main import cli
from ._options import (
    MeshFiles,
    chord_option,
    condition_option,
    echo_mesh_notes,
    mesh_files_option,
    mesh_summary,
    parts_option,
)

if TYPE_CHECKING:
    from ..contact import ContactResult

__all__ = ["contact"]


def _fmt(v: float, width: int = 11) -> str:
    return f"{number_text(v):>{width}}"


def _text(result: ContactResult) -> str:
    """The thesis's Figure 4.1 fields, stage by stage, and the classification."""
    u = result.units
    lines = [
        f"ROLL = {result.roll:g}   PITCH = {result.pitch:g}   PHASE = {result.phase:g}"
        f"   (degrees; lengths in {u}, fixed frame)",
        f"Classification: {result.classification}   "
        f"({result.n_contacts} contact(s) at the last stage reached)",
    ]
    labels = {"first": "1st contact", "second": "2nd contact", "third": "3rd contact"}
    for stage in result.stages:
        lines.append("")
        if not stage.found:
            lines.append(f"{labels[stage.name]}: none found")
            continue
        turn = "" if stage.name == "first" else f"   turn = {stage.angle:.4f} deg"
        lines.append(f"{labels[stage.name]}:{turn}   ({stage.queries} collision queries)")
        ox, oy, oz = stage.found_origin
        lines.append(f"  BOLT origin: {_fmt(ox)} {_fmt(oy)} {_fmt(oz)}")
        lines.append("  Contact point locations:")
        lines.append(
            f"    {'X':>11} {'Y':>11} {'Z':>11}  {'pairs':>5}  {'bolt/nut':<16}"
            f" {'normal (nut -> bolt)'}"
        )
        for c in stage.contacts:
            x, y, z = c.point
            n = " ".join(f"{v:7.4f}" for v in c.normal)
            lines.append(f"    {_fmt(x)} {_fmt(y)} {_fmt(z)}  {c.pairs:5d}  {c.regions:<16} {n}")
    lines.append("")
    lines.append(
        f"Interference at the 3rd contact: {_fmt(result.interference, 0)} {u}   "
        f"origin drop 2nd -> 3rd: {_fmt(result.origin_drop, 0)} {u}"
    )
    lines.append(
        f"Pivot axis to compliance centre: {_fmt(result.pivot_offset, 0)} {u}   "
        f"rolling pivot axis: {'yes' if result.rolling else 'no'}   "
        f"collision queries: {result.queries}"
    )
    final = result.final_pose
    if final is not None:
        r, p, ph = final.angles()
        lines.append(
            f"Final orientation: roll {r:.4f}  pitch {p:.4f}  phase {ph:.4f} deg; "
            f"origin z {final.origin[2]:.6f} {u}"
        )
    return "\n".join(lines)


@cli.command(
    "contact",
    help=f"""First, second and third contact of a tilted bolt on the nut:
the thesis's fixed-pivot procedure.

The bolt, tilted by ROLL and PITCH and spun to PHASE (degrees, conventions.md), comes down
on the nut until it first touches, turns about the nut's tangent there until a second
contact, then about the pivot axis through the two until a third, each found by bisection
to 1e-7 in of travel. This is the thesis's FIXED-PIVOT procedure: each stage turns about
an axis fixed in space and the compliance holding the bolt is ignored, so the poses are not
rest states. The physical model (rest states under load and compliance) is the mechanics:
threadmate settle / threadmate search.

Prints per stage the contact points, triangle pairs, regions in contact, common normals,
the bolt origin and turn angle, and the classification by the thesis's own criteria of its
section 4.2: unstable (two-point: the third contact needed an embedding deeper than the
drop of the bolt origin from the 2nd to the 3rd stage), quasi-stable (two-point: the pivot
axis passes within pitch/10 of the compliance centre), stable (three-point), in-phase (the
bolt dropped into the nut), no-contact. Also reports the thesis's rolling sign: a pivot
contact gained triangle pairs once the turn about the pivot axis began. Lengths are in the
spec's units.

{SPEC_HELP}""",
)
@click.argument("spec_text", metavar="DESIGNATION|SPEC")
@click.option(
    "--roll",
    type=float,
    required=True,
    help=f"Tilt about fixed X in degrees (within +/-{MAX_TILT:g}).",
)
@click.option(
    "--pitch",
    type=float,
    required=True,
    help=f"Tilt about fixed Y in degrees (within +/-{MAX_TILT:g}).",
)
@click.option(
    "--phase",
    type=float,
    required=True,
    help="Spin of the bolt about its axis in degrees (counter-clockwise from above).",
)
@chord_option
@click.option(
    "--compliance-z",
    type=float,
    default=0.0,
    show_default=True,
    help=f"Compliance centre on the bolt axis, bolt frame, in the spec's units "
    f"(0: the tip centre; within +/-{MAX_LENGTH:g}).",
)
@condition_option
@parts_option
@mesh_files_option
@click.option(
    "--json", "as_json", is_flag=True, help="Print one JSON document on stdout instead of text."
)
def contact(
    spec_text: str,
    roll: float,
    pitch: float,
    phase: float,
    chord: float | None,
    compliance_z: float,
    condition: str,
    as_json: bool,
    parts: SpecParts,
    meshes: MeshFiles,
) -> None:
    """Run the three contact stages for one configuration."""
    check_configuration(roll, pitch, phase)
    spec = resolve_spec(spec_text, condition, parts)
    check_chord(spec, chord)  # the meshes' own range, before any mesh is built
    # The analyser checks the compliance centre and the meshes before it builds anything.
    from ..contact import ContactAnalyzer  # the mechanics (trimesh, numba), once input is read

    analyzer = ContactAnalyzer(spec, chord=chord, compliance_z=compliance_z, **meshes.arguments())
    echo_mesh_notes(analyzer.mesh_info, spec.units)
    result = analyzer.analyze(roll, pitch, phase)
    if as_json:
        emit_json({**result.to_dict(), "mesh": analyzer.mesh_info})
    else:
        click.echo(_text(result))
        if meshes.given:
            click.echo(mesh_summary(analyzer.mesh_info, spec.units))
