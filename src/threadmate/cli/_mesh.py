"""``threadmate mesh``: write the bolt and nut of a thread pair as binary STL files."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from .._errors import InputError
from .._io import atomic_path
from ..geometry import SpecParts
from ._common import (
    SPEC_HELP,
    emit_json,
    resolve_spec,
    writable_directory,
    writable_output,
    write_failed,
)
from ._main import cli
from ._options import chord_option, condition_option, parts_option

__all__ = ["mesh", "mesh_document"]


def mesh_document(
    text: str,
    out_dir: str | Path,
    chord: float | None = None,
    condition: str = "mean",
    parts: SpecParts | None = None,
    force: bool = False,
) -> dict[str, Any]:
    """Tessellate a designation or spec file into ``out_dir/bolt.stl`` and ``nut.stl``.

    Both files are written through temporary files and renamed only once both are
    complete, so a failure leaves neither half-written. A ``bolt.stl`` or ``nut.stl``
    already in ``out_dir`` is refused unless ``force``. Returns the ``--json`` document.
    """
    out = writable_directory(out_dir)
    paths = {"bolt": out / "bolt.stl", "nut": out / "nut.stl"}
    for path in paths.values():  # a folder in the way of a file (the other would land)
        writable_output(path)
    there = [str(p) for p in paths.values() if p.exists()]
    if there and not force:
        raise InputError(
            f"-o {out_dir}: {' and '.join(there)} already "
            f"{'exist' if len(there) > 1 else 'exists'}; pass --force to overwrite"
        )
    spec = resolve_spec(text, condition, parts)
    from ..geometry import stl_header, thread_meshes, write_stl  # trimesh, once input is read

    bolt, nut = thread_meshes(spec, chord)
    try:
        # Both land under temporary names first; the renames happen only after both writes.
        with atomic_path(paths["bolt"]) as tmp_bolt, atomic_path(paths["nut"]) as tmp_nut:
            for tmp, name, tb in ((tmp_bolt, "bolt", bolt), (tmp_nut, "nut", nut)):
                write_stl(tb.mesh, tmp, stl_header(name, spec, tb.chord))
    except OSError as exc:
        raise write_failed(out, exc) from None
    return {
        "units": spec.units,
        "designation": spec.designation,
        "chord": bolt.chord,
        "bolt": {
            "path": str(paths["bolt"]),
            "triangles": bolt.triangles,
            "max_deviation": bolt.max_deviation,
        },
        "nut": {
            "path": str(paths["nut"]),
            "triangles": nut.triangles,
            "max_deviation": nut.max_deviation,
        },
    }


@cli.command(
    "mesh",
    help="Write the bolt and nut as binary STL (DIR/bolt.stl, DIR/nut.stl), "
    f"each in its own frame. {SPEC_HELP}",
)
@click.argument("designation", metavar="DESIGNATION|SPEC")
@click.option(
    "-o",
    "--output",
    "out_dir",
    required=True,
    type=click.Path(file_okay=False, path_type=Path),
    help="Folder for bolt.stl and nut.stl (created if missing).",
)
@click.option(
    "--force", is_flag=True, help="Overwrite a bolt.stl or nut.stl already in the folder."
)
@chord_option
@condition_option
@parts_option
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def mesh(
    designation: str,
    out_dir: Path,
    force: bool,
    chord: float | None,
    condition: str,
    as_json: bool,
    parts: SpecParts,
) -> None:
    """Tessellate a thread pair and write its two STL files."""
    doc = mesh_document(designation, out_dir, chord, condition.lower(), parts, force)
    if as_json:
        emit_json(doc)
        return
    units = doc["units"]
    click.echo(f"{doc['designation'] or 'thread spec'}: chord {doc['chord']:g} {units}")
    for name in ("bolt", "nut"):
        part = doc[name]
        click.echo(
            f"  {name:4} {part['path']}  {part['triangles']} triangles, "
            f"max deviation {part['max_deviation']:.3g} {units}"
        )
