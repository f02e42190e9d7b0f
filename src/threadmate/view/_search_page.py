"""The page of a search: the bolt on the nut along the turn, and what the sensors see.

Input is the search's JSON document (``threadmate search --json``:
:meth:`threadmate.contact.SearchResult.to_dict` with the thread pair under ``spec`` and
the meshes under ``mesh``). The page shows, for every state of the search (every
continuation step and both sides of each event):

- the 3-D scene in the nut's frame F: the nut, the bolt at the state's pose, its touching
  contacts and the normal force on the bolt at each as an arrow;
- the compliance centre's height, the tilt of the bolt axis and the driver's torque
  against phase, the events and the snap marked, a cursor at the state shown;
- a slider over the states; clicking a point of the plots or an event's button moves it.
"""

from __future__ import annotations

import html
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from .._errors import InputError
from .._io import atomic_write_text, read_utf8
from .._json import parse_json
from ..geometry import ThreadSpec
from ._display import display_meshes
from ._html import page, script

__all__ = [
    "ARROW_PITCHES",
    "read_search_document",
    "search_page",
    "search_view_data",
    "write_search_page",
]

#: Length of a force arrow carrying the whole axial load, in pitches.
ARROW_PITCHES = 1.5
#: Keys a search document must hold for its page (and ``spec``, unless the thread pair is
#: given apart).
_KEYS = ("units", "parameters", "start", "states", "events", "snap")


def read_search_document(path: str | os.PathLike[str]) -> dict[str, Any]:
    """The JSON document ``threadmate search --json`` wrote to ``path``, checked.

    Raises
    ------
    InputError
        The file is missing, not JSON, or not a search's document with its thread pair.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file (give a search's JSON document)")
    try:
        doc = parse_json(read_utf8(path, InputError))
    except ValueError as exc:
        raise InputError(f"{path}: not a JSON document ({exc})") from None
    check_search_document(doc, str(path), with_spec=True)
    return dict(doc)


def check_search_document(
    doc: Any, where: str = "search document", *, with_spec: bool = False
) -> None:
    """Refuse a document that is not a search's, naming what is missing (``spec`` too
    when ``with_spec``)."""
    if not isinstance(doc, dict):
        raise InputError(f"{where}: expected a JSON object (a search's document)")
    missing = [k for k in (*_KEYS, *(("spec",) if with_spec else ())) if k not in doc]
    if missing:
        hint = (
            " (written before searches carried their thread pair: run the search again "
            "for its JSON document)"
            if missing == ["spec"]
            else " (give the JSON document of threadmate search)"
        )
        raise InputError(f"{where}: not a search's document, no {', '.join(missing)}{hint}")
    states = doc["states"]
    if not isinstance(states, list) or not states:
        raise InputError(f"{where}: the search holds no state to show")
    for i, s in enumerate(states):
        if not isinstance(s, dict) or not all(
            k in s for k in ("phase", "origin", "rotation", "centre", "contacts")
        ):
            raise InputError(f"{where}: state {i} lacks its pose or its contacts")


def _touching(state: dict[str, Any]) -> list[dict[str, Any]]:
    """The touching contacts of a state's document (as ``MechanicalState.touching``)."""
    out = []
    for c in state["contacts"]:
        force = c.get("force")
        loaded = force is not None and math.isfinite(force) and force > 0.0
        if c.get("gap", 0.0) == 0.0 or loaded:
            out.append(c)
    return out


def _number(value: Any) -> float | None:
    return float(value) if value is not None and math.isfinite(float(value)) else None


def search_view_data(
    doc: dict[str, Any], *, spec: ThreadSpec | None = None, chord: float | None = None
) -> dict[str, Any]:
    """What the page of a search draws, as plain data (the page's ``tm-data`` element).

    Parameters
    ----------
    doc : dict
        The search's JSON document (``threadmate search --json``, or
        :meth:`threadmate.contact.SearchResult.to_dict`).
    spec : ThreadSpec, optional
        The thread pair (default: the document's ``spec``; one of them is needed).
    chord : float, optional
        The meshes' chord (default: the document's, else the spec's default).

    Returns
    -------
    dict
        ``units``, ``title``, ``states`` (per state: ``phase``, ``origin``, ``rotation``
        row-major, ``height``, ``tilt``, ``torque``, ``classification``, ``regions``,
        ``contacts``), ``events`` (with the index of the state after each), ``snap``
        (index or None), ``bolt`` and ``nut`` (display meshes: ``x``, ``y``, ``z``, ``i``,
        ``j``, ``k``; the bolt in B, the nut in F), ``arrow`` (length of an arrow per N).
    """
    check_search_document(doc, with_spec=spec is None)
    spec = ThreadSpec.from_dict(doc["spec"]) if spec is None else spec
    mesh = doc.get("mesh") or {}
    parts = [mesh.get(k) for k in ("bolt", "nut")] if isinstance(mesh, dict) else []
    from_cad = any(isinstance(p, dict) and not p.get("generated", False) for p in parts)
    if chord is None and parts and isinstance(parts[0], dict) and parts[0].get("generated"):
        chord = parts[0].get("chord")
    u = spec.units
    states = []
    nut_points: list[list[float]] = []
    bolt_points: list[list[float]] = []
    for index, s in enumerate(doc["states"]):
        try:
            rot = np.asarray(s["rotation"], dtype=float).reshape(3, 3)
            origin = np.asarray(s["origin"], dtype=float).reshape(3)
            float(s["phase"]), float(s["centre"][2])
            for c in s["contacts"]:
                np.asarray(c["point"], dtype=float).reshape(3)
                np.asarray(c["normal"], dtype=float).reshape(3)
        except (ValueError, TypeError, KeyError, IndexError) as exc:
            raise InputError(
                f"search document: state {index} has no pose or contact of the search's "
                f"form ({type(exc).__name__}: {exc})"
            ) from None
        contacts = []
        for c in _touching(s):
            p = np.asarray(c["point"], dtype=float)
            nut_points.append(p.tolist())
            bolt_points.append((rot.T @ (p - origin)).tolist())
            contacts.append(
                {
                    "point": p.tolist(),
                    "normal": [float(v) for v in c["normal"]],
                    "force": _number(c.get("force")),
                    "regions": f"{c.get('bolt_region', '')}/{c.get('nut_region', '')}",
                }
            )
        states.append(
            {
                "phase": float(s["phase"]),
                "origin": origin.tolist(),
                "rotation": rot.ravel().tolist(),
                "height": float(s["centre"][2]),
                "tilt": math.degrees(math.acos(min(1.0, max(-1.0, float(rot[2, 2]))))),
                "torque": _number(s.get("driver_torque")),
                "classification": s.get("classification", ""),
                "kind": s.get("kind", ""),
                "regions": s.get("region_combination", ""),
                "contacts": contacts,
            }
        )
    phases = [s["phase"] for s in states]
    way = 1.0 if len(phases) < 2 or phases[-1] >= phases[0] else -1.0
    events = []
    for e in doc["events"]:
        # The state just after the event, as turned (the landing of a jump).
        after = next(
            (i for i, ph in enumerate(phases) if way * (ph - float(e["phase"])) >= 0.0),
            len(phases) - 1,
        )
        events.append(
            {
                "phase": float(e["phase"]),
                "kind": e.get("kind", ""),
                "before": e.get("before", ""),
                "after": e.get("after", ""),
                "drop": _number(e.get("drop")),
                "click": _number(e.get("click")),
                "state": after,
            }
        )
    snap = doc.get("snap")
    snap_state = None
    if isinstance(snap, dict):
        snap_state = next((e["state"] for e in events if e["kind"] == "snap"), len(states) - 1)
    bolt, nut = display_meshes(spec, nut_points, bolt_points, chord=chord)
    start = doc["start"]
    params = doc["parameters"]
    force = float(params.get("force", 1.0))
    name = spec.designation or f"spec (pitch {spec.pitch:g} {u})"
    sense = "counter-clockwise" if spec.handedness > 0 else "clockwise"
    return {
        "units": u,
        "title": (
            f"{name}: {sense} search from roll {start['roll']:g}, pitch "
            f"{start['pitch']:g}, phase {start['phase']:g} deg"
        ),
        "sense": sense,
        "subtitle": _subtitle(doc, u, force)
        + (
            " The search ran on meshes from CAD; the page draws the spec's own meshes."
            if from_cad
            else ""
        ),
        "force": force,
        "pitch": spec.pitch,
        "arrow": ARROW_PITCHES * spec.pitch / force,
        "states": states,
        "events": events,
        "snap": snap_state,
        "bolt": _mesh_data(bolt.vertices, bolt.faces, bolt.source_faces),
        "nut": _mesh_data(nut.vertices, nut.faces, nut.source_faces),
    }


def _subtitle(doc: dict[str, Any], u: str, force: float) -> str:
    snap = doc.get("snap")
    p = doc["parameters"]
    k = p.get("stiffness") or {}
    said = (
        f"snap at phase {snap['phase']:.2f} deg after {snap['turn']:.2f} deg, click "
        f"{snap['click']:.4g} {u}"
        if isinstance(snap, dict)
        else f"no snap within {doc.get('turns', 1):g} turn(s)"
    )
    return (
        f"{said}. Axial force {force:g} N, stiffness {k.get('roll', '?')}/{k.get('pitch', '?')} "
        f"N m/rad, friction {p.get('friction', '?')}. Lengths in {u}, angles in degrees, "
        "torque in N m; the scene is in the nut's frame F (origin at the centre of the nut's "
        "top face, +Z out of the nut toward the bolt)."
    )


def _mesh_data(v: np.ndarray, f: np.ndarray, source: int) -> dict[str, Any]:
    r = np.round(v, 7)
    return {
        "x": r[:, 0].tolist(),
        "y": r[:, 1].tolist(),
        "z": r[:, 2].tolist(),
        "i": f[:, 0].tolist(),
        "j": f[:, 1].tolist(),
        "k": f[:, 2].tolist(),
        "source_faces": source,
    }


def _body(data: dict[str, Any]) -> str:
    u = data["units"]
    n = len(data["states"])
    buttons = "".join(
        f'<button type="button" class="tm-event" data-state="{e["state"]}">'
        f"{html.escape(e['kind'])} at {e['phase']:.2f}&deg;</button>"
        for e in data["events"]
    )
    return f"""
<h1>{html.escape(data["title"])}</h1>
<p class="tm-sub">{html.escape(data["subtitle"])}</p>
<div class="tm-controls">
  <label for="tm-slider">state along the turn</label>
  <input type="range" id="tm-slider" min="0" max="{n - 1}" step="1" value="0"
    aria-label="state along the turn (phase)">
  <button type="button" id="tm-prev" aria-label="previous state">&#9664;</button>
  <button type="button" id="tm-next" aria-label="next state">&#9654;</button>
  {buttons}
  <button type="button" id="tm-zoom">zoom to the contacts</button>
</div>
<div id="tm-readout" aria-live="polite"></div>
<div class="tm-main">
  <div class="tm-panel" id="tm-scene" role="img"
    aria-label="bolt and nut in the nut's frame F ({u})"></div>
  <div class="tm-panel" id="tm-plots" role="img"
    aria-label="height, tilt and driver torque against phase"></div>
</div>
<h2>Contacts of the state shown</h2>
<div id="tm-contacts"></div>
<p class="tm-note">Arrows: the normal force of the nut on the bolt at each touching contact,
{data["arrow"] * data["force"]:.3g} {u} long for the whole axial load of {data["force"]:g} N.
Meshes drawn thinned away from the contacts (bolt {len(data["bolt"]["i"])} of
{data["bolt"]["source_faces"]} triangles, nut {len(data["nut"]["i"])} of
{data["nut"]["source_faces"]}), at full detail within {0.6 * data["pitch"]:.3g} {u} of
every contact. Phase increases counter-clockwise seen from above (+Z).</p>
"""


def search_page(
    doc: dict[str, Any], *, spec: ThreadSpec | None = None, chord: float | None = None
) -> str:
    """The HTML page of a search (see the module docstring); parameters as
    :func:`search_view_data`'s."""
    data = search_view_data(doc, spec=spec, chord=chord)
    return page(data["title"], _body(data), {"tm-data": data}, [script("_search.js")])


def write_search_page(
    doc: dict[str, Any],
    path: str | os.PathLike[str],
    *,
    spec: ThreadSpec | None = None,
    chord: float | None = None,
) -> Path:
    """Write the page of a search to ``path`` (atomically) and return the path."""
    return atomic_write_text(path, search_page(doc, spec=spec, chord=chord))
