"""Every start's search read as a sensor would meet it: its jumps, its snap, their signals.

A library's network (:mod:`threadmate.network`) holds each start's passive search as a
chain of transitions. This module walks each chain once, from the start's rest state to
the snap (an in-phase state proved by screwing in), to where the library's continuation
stopped, or round a cycle once, and keeps the events a wrist sensor and the driver could
notice on the way: every **jump** (a fold of the branch that does not end in the thread:
the bolt tipping off the bore's edge, rolling over a crest, or landing in phase but
jamming when screwed in) and the **snap**. For each event it keeps four signals, all
from the library's rows and the compliance, none from a new search:

- ``click``: the fall of the compliance centre a sensor sees (the library's ``click``
  column: from the highest the bolt stands within the last degree of turn to the
  landing; its ``drop`` where the library holds no click), spec length units;
- ``moment_change``: the change of the moment the compliance's tilt spring passes to the
  tool, ``k_r |(tilt - held) after - (tilt - held) before|`` (N m; tilts in radians);
- ``torque_change``: the change of the driver's torque across the event,
  ``|T after - T before|`` (N m);
- ``lateral_force_change``: the change of the lateral force the tool takes at the
  compliance centre, ``|sum lambda_i n_i,xy after - before|`` over the contacts' normal
  forces (N; the model's equilibrium is frictionless, so the friction forces are not in
  it). It needs the library's rows (contact forces and normals stay there, not in the
  network); without them it is NaN.

The axial force is not among them: the model presses the bolt with a constant axial force
(docs/mechanics.md, "The system"), so at rest before and after any jump the tool carries
the same axial load; see docs/design.md, "The snap a sensor sees".
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any

import networkx as nx
import numpy as np
import pandas as pd

from .._angles import FULL_TURN
from ..contact import ERROR_CLASS, IN_PHASE, UNSTABLE
from ..network import snap_click, starts

__all__ = ["EVENT_SIGNALS", "SearchEvents", "search_events"]

#: The signals of an event: name, unit (``length``: the spec's), and what it is.
EVENT_SIGNALS: dict[str, tuple[str, str]] = {
    "click": ("length", "fall of the compliance centre a sensor sees at the event"),
    "moment_change": (
        "N m",
        "change of the tilt spring's moment on the tool across the event, "
        "k_r |(tilt - held) after - (tilt - held) before|",
    ),
    "torque_change": (
        "N m",
        "change of the driver's torque across the event, |T after - T before|",
    ),
    "lateral_force_change": (
        "N",
        "change of the lateral force the tool takes at the compliance centre, "
        "|sum lambda_i n_i,xy after - before| (normal forces: the equilibrium is frictionless)",
    ),
}


def _snapped(node: dict[str, Any]) -> bool:
    """In phase and proved by screwing in: the end of a search (as the network has it)."""
    return node.get("classification") == IN_PHASE and bool(node.get("engaged"))


def _largest(*values: float) -> float:
    """The largest of ``values``, NaN meaning none."""
    finite = [v for v in values if not math.isnan(v)]
    return max(finite) if finite else math.nan


def _finite(x: Any) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        return math.nan
    return v if math.isfinite(v) else math.nan


@dataclass(frozen=True)
class SearchEvents:
    """The searches of one library and the events on them.

    Attributes
    ----------
    searches : pandas.DataFrame
        One row per start at rest (starts that failed or whose descent did not reach a
        rest state are left out): ``node``, ``held_roll``, ``held_pitch``, ``phase``
        (deg), ``snaps`` (the search reaches the snap within the library's horizon),
        ``snap_turn`` (deg from the start to the snap, NaN none), ``snap_event`` (the
        snap's source state, '' none), ``jumps`` (non-snap jumps on the way), and per
        signal of :data:`EVENT_SIGNALS` ``snap_<signal>`` and ``jump_<signal>`` (the
        largest over the search's non-snap jumps; NaN: none); ``torque_before_snap``,
        ``torque_after_snap`` (N m), ``torque_peak`` (the largest driver torque met up to
        the snap or the library's horizon, N m) and ``torque_peak_high_friction`` (the
        same at the rest states on the way, their friction part scaled to
        ``high_friction``).
    events : pandas.DataFrame
        One row per distinct jump or snap transition met: ``source``, ``target``,
        ``kind`` (``jump`` or ``snap``), ``held_roll``, ``held_pitch``, ``phase`` (deg),
        ``landing`` (class of the state landed on), ``drop`` (length), the signals,
        ``torque_before``, ``torque_after`` (N m) and ``searches`` (how many starts'
        searches pass it).
    units : str
        The spec's length unit.
    compliance : dict
        The library's compliance (:meth:`threadmate.contact.Compliance.to_dict`).
    phase_step : float
        The largest gap between two neighbouring start phases of the grid (deg).
    high_friction : float
        The friction coefficient ``torque_peak_high_friction`` is taken at.
    starts : int
        Starts of the library (at rest or not).
    branch_fall : float
        The steepest mean fall of the compliance centre per degree of turn along a
        continuous branch the searches pass (length per degree, NaN: none): the library
        holds a branch's ends, not its steepest degree.
    """

    searches: pd.DataFrame
    events: pd.DataFrame
    units: str
    compliance: dict[str, Any]
    phase_step: float
    high_friction: float
    starts: int
    branch_fall: float = math.nan


def _phase_step(grid: dict[str, Any]) -> float:
    """The largest gap between neighbouring start phases of a grid (deg, around the turn)."""
    phases = sorted(float(p) for p in grid.get("phase", []))
    if len(phases) < 2:
        return FULL_TURN
    gaps = [b - a for a, b in zip(phases, phases[1:], strict=False)]
    gaps.append(phases[0] + FULL_TURN - phases[-1])
    return float(max(gaps))


def _lateral_forces(rows: pd.DataFrame | None) -> dict[str, tuple[float, float]]:
    """Per state id, the lateral part of the contacts' normal forces ``sum lambda_i
    n_i,xy`` (N): what the tool holding the compliance centre takes (with the sign
    reversed)."""
    if rows is None:
        return {}
    out: dict[str, tuple[float, float]] = {}
    for sid, forces, normals in zip(
        rows["state_id"], rows["contact_forces"], rows["contact_normals"], strict=True
    ):
        f = np.asarray(forces, dtype=float)
        n = np.asarray(normals, dtype=float).reshape(-1, 3)
        if f.size == 0 or n.shape[0] != f.size:
            out[sid] = (math.nan, math.nan)
            continue
        fx, fy = (f[:, None] * n[:, :2]).sum(axis=0)
        out[sid] = (float(fx), float(fy))
    return out


def search_events(
    graph: nx.DiGraph, rows: pd.DataFrame | None = None, *, high_friction: float = 0.20
) -> SearchEvents:
    """Walk every start's passive search of ``graph`` once and keep its events.

    Parameters
    ----------
    graph : networkx.DiGraph
        A library's network (:func:`threadmate.network.build_network`; active moves, if
        any, are passed over).
    rows : pandas.DataFrame, optional
        The library's rows (:func:`threadmate.library.load`), for the lateral force;
        without them ``lateral_force_change`` is NaN.
    high_friction : float
        The friction coefficient at which the driver's torque is also given (default
        0.20, the top of the VDI 2230 range of thread friction). The model's equilibrium
        is frictionless and friction enters only the driver's torque
        (docs/mechanics.md), so at a rest state the torque at another friction is the
        frictionless part plus the friction part scaled by the ratio of the
        coefficients: exact in the model, not an estimate.

    Returns
    -------
    SearchEvents
    """
    compliance = json.loads(graph.graph["compliance"])
    k_roll = float(compliance["stiffness"]["roll"])
    k_pitch = float(compliance["stiffness"]["pitch"])
    mu = float(compliance["friction"])
    scale = high_friction / mu if mu > 0 else math.nan
    nodes = graph.nodes
    lateral = _lateral_forces(rows)

    def passive_next(n: str) -> tuple[str, dict[str, Any]] | None:
        for _, v, d in graph.out_edges(n, data=True):
            if not d.get("active"):
                return v, d
        return None

    def torque(n: str) -> float:
        return _finite(nodes[n].get("driver_torque"))

    def torque_high(n: str) -> float:
        d = nodes[n]
        t, f = _finite(d.get("driver_torque")), _finite(d.get("friction_torque"))
        if math.isnan(t) or math.isnan(f) or math.isnan(scale):
            return t
        return t - f + f * scale

    def spring(n: str) -> tuple[float, float]:
        d = nodes[n]
        return (
            k_roll * math.radians(float(d["roll"]) - float(d["held_roll"])),
            k_pitch * math.radians(float(d["pitch"]) - float(d["held_pitch"])),
        )

    events: dict[tuple[str, str], dict[str, Any]] = {}

    def event(u: str, v: str, e: dict[str, Any]) -> dict[str, Any]:
        key = (u, v)
        if key not in events:
            click = _finite(e.get("click"))
            if math.isnan(click):
                click = _finite(e.get("drop"))
            (mu0, mv0), (mu1, mv1) = spring(u), spring(v)
            t0, t1 = torque(u), torque(v)
            d = nodes[u]
            events[key] = {
                "source": u,
                "target": v,
                "kind": e["kind"],
                "held_roll": float(d["held_roll"]),
                "held_pitch": float(d["held_pitch"]),
                "phase": float(d["phase"]),
                "landing": str(nodes[v].get("classification", "")),
                "drop": _finite(e.get("drop")),
                "click": click,
                "moment_change": math.hypot(mu1 - mu0, mv1 - mv0),
                "torque_change": abs(t1 - t0),
                "lateral_force_change": math.hypot(
                    *(
                        b - a
                        for a, b in zip(
                            lateral.get(u, (math.nan, math.nan)),
                            lateral.get(v, (math.nan, math.nan)),
                            strict=True,
                        )
                    )
                ),
                "torque_before": t0,
                "torque_after": t1,
                "searches": 0,
            }
        return events[key]

    table = []
    total = 0
    branch_fall = math.nan
    for (roll, pitch, phase), start in sorted(starts(graph).items()):
        total += 1
        d0 = nodes[start]
        if d0.get("classification") in (ERROR_CLASS, UNSTABLE):
            continue  # a failed start, or a descent that did not reach a rest state
        seen: set[str] = set()
        n, turn = start, 0.0
        peak, peak_high = torque(start), torque_high(start)
        snap: dict[str, Any] | None = None
        jumps: list[dict[str, Any]] = []
        while not _snapped(nodes[n]) and n not in seen:
            seen.add(n)
            step = passive_next(n)
            if step is None:  # the library's horizon, or a failed continuation
                break
            v, e = step
            peak = _largest(peak, _finite(e.get("torque_peak")), torque(v))
            peak_high = _largest(peak_high, torque_high(v))
            turn += float(e.get("turn", 0.0))
            if e["kind"] == "turning" and float(e.get("turn", 0.0)) > 0:
                branch_fall = _largest(branch_fall, _finite(e.get("drop")) / float(e["turn"]))
            # (A snap into phase without a jump has nothing for a sensor to tell.)
            if e["kind"] == "jump" or (e["kind"] == "snap" and math.isfinite(snap_click(e))):
                ev = event(n, v, e)
                ev["searches"] += 1
                if e["kind"] == "snap":
                    snap = ev
                else:
                    jumps.append(ev)
            n = v
        row: dict[str, Any] = {
            "node": start,
            "held_roll": float(roll),
            "held_pitch": float(pitch),
            "phase": float(phase),
            "snaps": _snapped(nodes[n]),
            # A start already in the thread has nothing to search: turn 0, no click.
            "snap_turn": turn if _snapped(nodes[n]) else math.nan,
            "snap_event": snap["source"] if snap else "",
            "jumps": len(jumps),
            "torque_before_snap": snap["torque_before"] if snap else math.nan,
            "torque_after_snap": snap["torque_after"] if snap else math.nan,
            "torque_peak": peak,
            "torque_peak_high_friction": peak_high,
        }
        for name in EVENT_SIGNALS:
            row[f"snap_{name}"] = snap[name] if snap else math.nan
            values = [j[name] for j in jumps if not math.isnan(j[name])]
            row[f"jump_{name}"] = max(values) if values else math.nan
        table.append(row)
    columns = [
        "node",
        "held_roll",
        "held_pitch",
        "phase",
        "snaps",
        "snap_turn",
        "snap_event",
        "jumps",
        *(f"snap_{s}" for s in EVENT_SIGNALS),
        *(f"jump_{s}" for s in EVENT_SIGNALS),
        "torque_before_snap",
        "torque_after_snap",
        "torque_peak",
        "torque_peak_high_friction",
    ]
    event_columns = [
        "source",
        "target",
        "kind",
        "held_roll",
        "held_pitch",
        "phase",
        "landing",
        "drop",
        *EVENT_SIGNALS,
        "torque_before",
        "torque_after",
        "searches",
    ]
    return SearchEvents(
        pd.DataFrame(table, columns=columns),
        pd.DataFrame(list(events.values()), columns=event_columns),
        str(graph.graph["units"]),
        compliance,
        _phase_step(json.loads(graph.graph["grid"])),
        float(high_friction),
        total,
        branch_fall,
    )
