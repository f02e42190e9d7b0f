"""``threadmate thread``: the limits of size of a designation or spec, and its expanded spec."""

from __future__ import annotations

from typing import Any

import click

from ..geometry import SpecParts, ThreadSpec, thread_limits as _thread_limits
from ._common import SPEC_HELP, emit_json, is_spec_path, parts_document, resolve_spec
from ._main import cli
from ._options import condition_option, parts_option

__all__ = ["thread", "thread_document"]

_DIAMETERS = ("major", "pitch_diameter", "minor")


def thread_document(
    text: str, condition: str = "mean", parts: SpecParts | None = None
) -> dict[str, Any]:
    """The ``--json`` document of ``threadmate thread`` for a designation or spec file.

    For a spec file the limits are the spec's single values, ``[v, v]``. ``parts`` holds
    the bolt's point, the nut's countersink and their lengths in the spec's units.
    """
    if is_spec_path(text):
        spec = resolve_spec(text, condition, parts)
        return {
            "units": spec.units,
            "pitch": spec.pitch,
            "designation": spec.designation,
            "condition": None,
            "hand": spec.hand,
            "bolt": _single_values(spec, "bolt"),
            "nut": _single_values(spec, "nut"),
            "spec": spec.to_dict(),
            "parts": parts_document(spec),
        }
    limits = _thread_limits(text)
    spec = resolve_spec(text, condition, parts)
    doc = limits.to_dict()
    doc["condition"] = condition
    doc["spec"] = spec.to_dict()
    doc["parts"] = parts_document(spec)
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
    lines += _parts_lines(doc["parts"], units)
    return "\n".join(lines)


def _parts_lines(parts: dict[str, Any], units: str) -> list[str]:
    """The point and the countersink in words, with the lengths (angles in degrees)."""
    point, sink = parts["point"], parts["countersink"]
    if point["form"] == "flat":
        tip = "flat (the thesis's)"
    else:
        shape = (
            f"{point['angle']:g} deg from the axis"
            if point["form"] == "chamfer"
            else f"radius {point['radius']:.6g} {units}"
        )
        tip = (
            f"{point['form']}, {shape}, to a {point['diameter']:.6g} {units} tip, "
            f"{point['height']:.6g} {units} high"
        )
    if sink is None:
        bore = "none (a flat, sharp-edged bore: the thesis's)"
    else:
        bore = (
            f"{sink['angle']:g} deg included, {sink['diameter']:.6g} {units} at the face, "
            f"{sink['depth']:.6g} {units} deep"
        )
    return [
        f"bolt point: {tip}; bolt length {parts['bolt_length']:.6g} {units}",
        f"nut countersink: {bore}; nut height {parts['nut_height']:.6g} {units}",
    ]


@cli.command("thread", help=f"Limits of size of a thread pair and its expanded spec. {SPEC_HELP}")
@click.argument("designation", metavar="DESIGNATION|SPEC")
@condition_option
@parts_option
@click.option("--json", "as_json", is_flag=True, help="Print one JSON document on stdout.")
def thread(designation: str, condition: str, as_json: bool, parts: SpecParts) -> None:
    """Print the limits of size (designation) or the values (spec file) of a thread pair."""
    doc = thread_document(designation, condition, parts)
    if as_json:
        emit_json(doc)
    else:
        click.echo(_format(doc))
