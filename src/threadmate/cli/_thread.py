"""``threadmate thread``: the limits of size of a designation or spec, and its expanded spec."""

from __future__ import annotations

from typing import Any

import click

from ..geometry import ThreadSpec, load_spec, spec_from_designation
from ..geometry import thread_limits as _thread_limits
from ._common import SPEC_HELP, emit_json, is_spec_path
from ._main import cli
from ._options import condition_option

__all__ = ["thread", "thread_document"]

_DIAMETERS = ("major", "pitch_diameter", "minor")


def thread_document(text: str, condition: str = "mean") -> dict[str, Any]:
    """The ``--json`` document of ``threadmate thread`` for a designation or spec file.

    For a spec file the limits are the spec's single values, ``[v, v]``.
    """
    if is_spec_path(text):
        spec = load_spec(text)
        return {
            "units": spec.units,
            "pitch": spec.pitch,
            "designation": spec.designation,
            "condition": None,
            "hand": spec.hand,
            "bolt": _single_values(spec, "bolt"),
            "nut": _single_values(spec, "nut"),
            "spec": spec.to_dict(),
        }
    limits = _thread_limits(text)
    spec = spec_from_designation(text, condition=condition)
    doc = limits.to_dict()
    doc["condition"] = condition
    doc["spec"] = spec.to_dict()
    return doc


def _single_values(spec: ThreadSpec, name: str) -> dict[str, Any]:
    body = getattr(spec, name)
    out: dict[str, Any] = {k: [getattr(body, k), getattr(body, k)] for k in _DIAMETERS}
    for key in ("crest_fillet", "root_fillet"):
        out[key] = [getattr(body, key), getattr(body, key)]
    return out


def _format(doc: dict[str, Any]) -> str:
    units = doc["units"]
    places = 4 if units == "in" else 3
    lines = []
    title = doc.get("designation") or "thread spec"
    lines.append(f"{title}   (pitch {doc['pitch']:.{places + 2}g} {units}, {doc['hand']} hand)")
    head = f"{'':8}{'':16}{'min':>12}{'max':>12}   {'spec':>12}"
    lines.append(head)
    for body in ("bolt", "nut"):
        limits = doc[body]
        label = body
        if limits.get("tolerance_class"):
            label = f"{body} {limits['tolerance_class']}"
        for i, key in enumerate((*_DIAMETERS, "crest_fillet", "root_fillet")):
            lo, hi = limits[key]
            value = doc["spec"][body][key]
            lines.append(
                f"{label if i == 0 else '':8}{key.replace('_', ' '):16}"
                f"{lo:>12.{places}f}{hi:>12.{places}f}   {value:>12.{places + 1}f}"
            )
    spec = doc["spec"]
    cond = f" at {doc['condition']} material" if doc.get("condition") else ""
    lines.append(
        f"spec{cond}: bolt length {spec['bolt']['length']:g}, nut height "
        f"{spec['nut']['height']:g}, nut outer radius {spec['nut']['outer_radius']:g} {units}"
    )
    return "\n".join(lines)


@cli.command("thread", help=f"Limits of size of a thread pair and its expanded spec. {SPEC_HELP}")
@click.argument("designation", metavar="DESIGNATION|SPEC")
@condition_option
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def thread(designation: str, condition: str, as_json: bool) -> None:
    """Print the limits of size (designation) or the values (spec file) of a thread pair."""
    doc = thread_document(designation, condition)
    if as_json:
        emit_json(doc)
    else:
        click.echo(_format(doc))
