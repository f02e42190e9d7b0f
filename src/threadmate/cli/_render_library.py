"""The library commands' text and JSON documents: ``sweep``'s report, ``library info``,
``library query`` and ``library summary`` as a reader sees them (the commands in
:mod:`._library` read the options and call the library stage)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from .._text import number_text
from ..contact import Compliance
from ._progress import progress_words

__all__ = [
    "echo_info",
    "echo_query",
    "echo_summary",
    "echo_sweep",
    "library_units",
    "sweep_report",
    "with_units",
]


def _counts_line(counts: dict[str, int]) -> str:
    from ..library import CLASS_ORDER

    known = [c for c in CLASS_ORDER if counts.get(c, 0)]
    others = [c for c in counts if c not in CLASS_ORDER and counts[c]]
    return ", ".join(f"{c} {counts[c]}" for c in known + others) or "none yet"


def _roles_line(counts: dict[str, int]) -> str:
    from ..contact import ROLES

    return ", ".join(f"{r} {counts[r]}" for r in ROLES if counts.get(r, 0)) or "none"


def library_units(model: str, length: str) -> dict[str, str]:
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


def with_units(doc: dict[str, Any]) -> dict[str, Any]:
    """A reader's document with ``units`` as a mapping of quantity to unit."""
    return {**doc, "units": library_units(doc["model"], doc["units"])}


def _compliance_line(c: dict[str, Any], units: str) -> str:
    return Compliance.from_dict(c).describe(units)


def sweep_report(
    out: Path, doc: dict[str, Any], existed: bool, resumed: dict[str, int], wall: float
) -> dict[str, Any]:
    """``sweep``'s JSON document: the library ``doc`` (:func:`threadmate.library.info`) as
    the sweep left it, whether it resumed (``resumed``: the first progress report) and
    its wall time in seconds."""
    meta = doc["metadata"]
    report = {
        "library": str(out),
        "model": doc["model"],
        "units": library_units(doc["model"], doc["units"]),
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
    return report


def echo_sweep(out: Path, doc: dict[str, Any], wall: float) -> None:
    """``sweep``'s text: the library, what is done and the states reached."""
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


def echo_info(library: Path, doc: dict[str, Any]) -> None:
    """``library info``'s text: spec, grid, mesh, settings, progress and counts."""
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


def echo_query(doc: dict[str, Any]) -> None:
    """``library query``'s text: the configuration and its stored state."""
    g = doc["grid"]
    moved = " (moved to the nearest grid state)" if doc["moved_to_grid"] else ""
    held = "HELD " if doc["model"] == "mechanics" else ""
    click.echo(
        f"{held}ROLL = {g['roll']:g}   {held}PITCH = {g['pitch']:g}   PHASE = "
        f"{g['phase']:g}   config_id {doc['config_id']}{moved}"
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
        f"compliance centre height {number_text(rec['centre_z'])} {u}"
    )
    points, normals = rec["contact_points"] or [], rec["contact_normals"] or []
    for i, (regions, force) in enumerate(
        zip(rec["contact_regions"] or [], rec["contact_forces"] or [], strict=False)
    ):
        p = " ".join(number_text(v) for v in points[3 * i : 3 * i + 3])
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
            f"{work:.6g} mJ, drop {number_text(rec['drop'])} {u}"
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
        origin = " ".join(number_text(rec[f"{s}_origin_{a}"]) for a in "xyz")
        click.echo(f"{s}: turn {rec[f'{s}_angle']:.4f} deg, bolt origin {origin} {u}")
        for i in (1, 2, 3):
            if rec[f"{s}_c{i}_pairs"]:
                p = " ".join(number_text(rec[f"{s}_c{i}_{a}"]) for a in "xyz")
                click.echo(
                    f"  contact {i}: {p}  pairs {rec[f'{s}_c{i}_pairs']}  "
                    f"{rec[f'{s}_c{i}_bolt_region']}/{rec[f'{s}_c{i}_nut_region']}"
                )
    click.echo(
        f"interference {number_text(rec['interference'])} {u}, origin drop "
        f"{number_text(rec['origin_drop'])} {u}, pivot offset "
        f"{number_text(rec['pivot_offset'])} {u}"
    )


def echo_summary(library: Path, doc: dict[str, Any]) -> None:
    """``library summary``'s text: counts of the classes, the states by role, the passive
    transitions, the region combinations and the figures written."""
    from ..contact import ROLES

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
