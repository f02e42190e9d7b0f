"""The page of a run: report.html beside report.md, and the pages of its starts.

``report.html`` holds the report's text with interactive figures in place of two of its
pictures (the settings ranked; the class map over the held tilts, any start phase) and
the others inline, and a table of every start. A start links to its search's page in
``views/`` (``views/search-r<roll>-p<pitch>-ph<phase>.html``, with the search's JSON
document beside it): ``threadmate run`` writes the page of the start its click signature
shows, :func:`write_start_page` (``threadmate view RUN_DIR --start R,P,PH``) any other's.
A start without a page says the command that writes it. Everything is inline: the page
opens with no network, and its links are relative, so the folder may be moved whole.
"""

from __future__ import annotations

import base64
import csv
import html
import math
import os
from pathlib import Path
from typing import Any

from .._errors import InputError
from .._io import atomic_write_text, read_utf8
from .._json import json_text, parse_json
from ..geometry import ThreadSpec
from ..library import METADATA_FILE
from ._html import page, script
from ._report_html import report_html
from ._search_page import write_search_page

__all__ = ["start_page_name", "write_run_page", "write_start_page", "write_start_views"]

#: The run's folder of start pages.
VIEWS = "views"
#: The report's pictures drawn interactively instead (their keys in the report).
_INTERACTIVE = {"recommendation": "tm-ranking", "library stability map": "tm-classmap"}


def start_page_name(roll: float, pitch: float, phase: float) -> str:
    """The file name (without suffix) of a start's page: ``search-r+0-p-1-ph300``."""
    return f"search-r{roll:+g}-p{pitch:+g}-ph{phase:g}"


def write_start_views(views: str | os.PathLike[str], doc: dict[str, Any], spec: ThreadSpec) -> Path:
    """Write a start's search document (``NAME.json``) and page (``NAME.html``) into the
    folder ``views``; return the page's path."""
    start = doc["start"]
    name = start_page_name(start["roll"], start["pitch"], start["phase"])
    views = Path(views)
    page = write_search_page(doc, views / f"{name}.html", spec=spec)
    atomic_write_text(views / f"{name}.json", json_text(doc))
    return page


def _library(run: Path) -> Path:
    """The run's library: ``library``, or with several compliances the first
    ``library-F<force>-k<stiffness>`` in name order."""
    found = [run / "library", *sorted(run.glob("library-F*-k*"))]
    for lib in found:
        if (lib / METADATA_FILE).is_file():
            return lib
    raise InputError(
        f"{run}: not a threadmate run folder (no library/{METADATA_FILE}; give the output "
        "folder of threadmate run)"
    )


def _read_json(path: Path) -> Any:
    try:
        return parse_json(read_utf8(path, InputError))
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: cannot read it ({exc})") from None


def write_start_page(run: str | os.PathLike[str], roll: float, pitch: float, phase: float) -> Path:
    """Compute the search from one start of a run and write its page into the run's
    ``views/`` folder (with its JSON document), then rewrite ``report.html`` so that it
    links to it.

    The search uses the run's library settings: its thread pair, compliance, chord and
    continuation step (with several compliances, the first library's in name order; the
    page names its compliance). Returns the page's path.

    Raises
    ------
    InputError
        ``run`` is not a run folder, the start is not one of its grid's, or the run was
        swept on meshes from CAD (give them to ``threadmate search`` with its page
        instead).
    """
    from ..contact import Compliance, Mechanics, contact_scene, search

    run = Path(run)
    meta = _read_json(_library(run) / METADATA_FILE)
    grid = meta.get("grid") or {}
    for value, axis in ((roll, "roll"), (pitch, "pitch"), (phase, "phase")):
        values = [float(v) for v in grid.get(axis, [])]
        if not any(math.isclose(value, v, abs_tol=1e-9) for v in values):
            shown = ", ".join(f"{v:g}" for v in values)
            raise InputError(
                f"the start's {axis} {value:g} deg is not on the run's grid ({axis}: {shown})"
            )
    mesh = meta.get("mesh") or {}
    if isinstance(mesh.get("bolt"), dict) or isinstance(mesh.get("nut"), dict):
        raise InputError(
            f"{run} was swept on meshes from CAD: draw a start with threadmate search on "
            "the same meshes, which writes its page too"
        )
    spec = ThreadSpec.from_dict(meta["spec"])
    cont = meta.get("continuation") or {}
    mech = Mechanics(
        spec,
        Compliance.from_dict(meta["compliance"]),
        scene=contact_scene(spec, chord=mesh.get("chord")),
    )
    result = search(
        mech,
        roll,
        pitch,
        phase,
        step=float(cont["step"]),
        phase_tolerance=float(cont["phase_tolerance"]),
    )
    doc = {**result.to_dict(), "mesh": mech.scene.mesh_info, "spec": spec.to_dict()}
    path = write_start_views(run / VIEWS, doc, spec)
    if (run / "report.md").is_file():
        write_run_page(run)
    return path


def _starts(run: Path, units: str) -> list[dict[str, Any]]:
    path = run / "starts.csv"
    if not path.is_file():
        raise InputError(f"{run}: no starts.csv (run threadmate run into it first)")
    out = []
    with path.open(encoding="utf-8", newline="") as fh:
        for row in csv.DictReader(fh):

            def num(key: str, r: dict[str, str] = row) -> float | None:
                text = r.get(key, "")
                try:
                    v = float(text)
                except ValueError:
                    return None
                return v if math.isfinite(v) else None

            roll, pitch, phase = num("held_roll_deg"), num("held_pitch_deg"), num("phase_deg")
            if roll is None or pitch is None or phase is None:
                continue
            name = start_page_name(roll, pitch, phase)
            out.append(
                {
                    "roll": roll,
                    "pitch": pitch,
                    "phase": phase,
                    "classification": row.get("classification", ""),
                    "snapped": row.get("snapped") == "True",
                    "turn": num("turn_deg"),
                    "work": num("work_mJ"),
                    "click": num(f"click_{units}"),
                    "page": (
                        f"{VIEWS}/{name}.html" if (run / VIEWS / f"{name}.html").is_file() else None
                    ),
                    "command": f"threadmate view {run.name} --start {roll:g},{pitch:g},{phase:g}",
                }
            )
    return out


def _figure_markup(run: Path, starts: list[dict[str, Any]]) -> Any:
    signature = next((s for s in starts if s["page"]), None)

    def image(alt: str, target: str) -> str:
        if alt in _INTERACTIVE:
            div = _INTERACTIVE[alt]
            extra = ""
            if div == "tm-classmap":
                extra = (
                    '<label for="tm-phase">start phase (deg) </label>'
                    '<select id="tm-phase"></select> '
                    '<span class="tm-note">click a start to open its search</span>'
                )
            return f'{extra}<div class="tm-panel" id="{div}" style="height:440px"></div>'
        path = run / target
        if not path.is_file() or path.suffix.lower() != ".png":
            return f'<p class="tm-note">({html.escape(target)} not found)</p>'
        data = base64.b64encode(path.read_bytes()).decode("ascii")
        img = f'<img alt="{html.escape(alt)}" src="data:image/png;base64,{data}">'
        if alt == "click signature" and signature is not None:
            img += (
                f'<p><a class="tm-start" href="{signature["page"]}">open this search '
                "interactively</a></p>"
            )
        return img

    return image


def _starts_table(starts: list[dict[str, Any]], units: str) -> str:
    def cell(v: float | None, fmt: str) -> str:
        return "-" if v is None else format(v, fmt)

    rows = []
    for i, s in enumerate(starts):
        target = s["page"] or "#tm-start-note"
        label = "open" if s["page"] else "how to open"
        rows.append(
            f"<tr><td>{s['roll']:g}</td><td>{s['pitch']:g}</td><td>{s['phase']:g}</td>"
            f'<td class="tm-text">{html.escape(s["classification"])}</td>'
            f"<td>{'yes' if s['snapped'] else 'no'}</td><td>{cell(s['turn'], '.1f')}</td>"
            f"<td>{cell(s['click'], '.4g')}</td><td>{cell(s['work'], '.3g')}</td>"
            f'<td class="tm-text"><a class="tm-start" data-start="{i}" href="{target}">'
            f"{label}</a></td></tr>"
        )
    return (
        "<h2>Every start</h2>"
        '<p class="tm-note">Each start links to its search\'s page: the bolt on the nut at '
        "every state of the turn, its contacts, and height, tilt and torque against phase."
        "</p>"
        '<div id="tm-start-note" class="tm-note" aria-live="polite"></div>'
        "<details open><summary>starts table</summary><table><tr><th>held roll deg</th>"
        '<th>held pitch deg</th><th>start phase deg</th><th class="tm-text">class</th>'
        f"<th>snaps</th><th>turn deg</th><th>click {units}</th><th>work mJ</th>"
        '<th class="tm-text">search</th></tr>' + "".join(rows) + "</table></details>"
    )


def write_run_page(run: str | os.PathLike[str]) -> Path:
    """Write ``report.html`` into the run folder ``run`` from its report.md,
    recommendation.json, starts.csv, library metadata and ``views/``; return its path.

    Raises
    ------
    InputError
        ``run`` is not a finished run's folder.
    """
    run = Path(run)
    if not run.is_dir():
        raise InputError(f"{run}: no such folder (give the output folder of threadmate run)")
    meta = _read_json(_library(run) / METADATA_FILE)
    for name in ("report.md", "recommendation.json", "starts.csv"):
        if not (run / name).is_file():
            raise InputError(f"{run}: no {name} (the run has not finished: run it again)")
    units = str(meta.get("units", "in"))
    rec = _read_json(run / "recommendation.json")
    starts = _starts(run, units)
    report = read_utf8(run / "report.md", InputError)
    body = report_html(report, _figure_markup(run, starts))
    body = f'<div class="tm-report">{body}{_starts_table(starts, units)}</div>'
    data = {
        "units": units,
        "settings": rec.get("settings", []),
        "best": rec.get("recommended"),
        "starts": starts,
    }
    title = report.splitlines()[0].lstrip("# ").strip() if report else "threadmate run"
    return atomic_write_text(
        run / "report.html", page(title, body, {"tm-data": data}, [script("_run.js")])
    )
