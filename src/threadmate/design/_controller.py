"""What to program on the controller, each figure derived from a library and said how.

- **Turn limit**: the largest turn to the snap among the searches that snap, plus a margin
  of one start-phase step of the grid (a start between two grid phases reaches the next
  grid phase within that gap, and from there mostly joins that grid start's search), with
  the share of the starts it catches, recounted from the searches.
- **Torque limit**: the largest driver torque up to the snap (the library's peak over the
  search's transitions and rest states) and the same at the top of the friction range
  (the rest states' friction torque scaled to ``high_friction``: exact in the model, whose
  equilibrium is frictionless), the larger of the two raised by a stated margin.
- **Starts that never snap**: lift and retry, at the held tilt the network's active plans
  (``--active``: change the held tilt by a grid step, lift and re-drop) lead to, each plan
  written as plain robot moves; without plans, at the held tilt that catches the most
  starts within the turn limit.
- **The snap as a sensor threshold**: the model presses with a constant axial force, so its
  axial force does not change across the snap; what a wrist sensor sees is the fall of the
  compliance centre, the change of the tilt spring's moment and of the driver's torque
  (:func:`~threadmate.design.snap_detection`), confirmed as the model proves a snap: turned
  clockwise, the bolt descends at the lead.

Lengths in the spec's units, angles in degrees, forces in N, torques in N m.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field
from typing import Any

import networkx as nx

from .._angles import FULL_TURN
from .._errors import InputError, NoPathError
from .._text import number_text
from .._units import json_units
from .._validate import check_range
from ..contact import SCREW_IN
from ..network import least_resistance_path
from ._searches import search_events
from ._sensor import SnapDetection, snap_detection

__all__ = ["ControllerProgram", "controller_program", "format_controller_program"]

#: Default margin on the torque limit, a share of the largest torque (stated, not derived:
#: the model's torque is quasi-static; a driver's own ripple and the parts' spread come on
#: top of it).
TORQUE_MARGIN = 0.25
#: The top of the VDI 2230 range of thread friction, at which the torque is also given.
HIGH_FRICTION = 0.20


@dataclass
class ControllerProgram:
    """What to program on the controller (module docstring); every entry says how it was
    derived in its ``rule``.

    Attributes
    ----------
    units : str
        The spec's length unit.
    compliance : dict
        The library's compliance.
    turn_limit, torque_limit, retry, snap_signal : dict
        The four settings, each with its figures and its ``rule``.
    steps : list of str
        The program in plain robot moves.
    notes : list of str
        What the figures do not say by themselves.
    """

    units: str
    compliance: dict[str, Any]
    turn_limit: dict[str, Any]
    torque_limit: dict[str, Any]
    retry: dict[str, Any]
    snap_signal: dict[str, Any]
    steps: list[str]
    notes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """The JSON document (``threadmate program --json``)."""
        return {
            "units": json_units(self.units, "angle", "torque", "moment", "force", "share"),
            "compliance": self.compliance,
            "turn_limit": self.turn_limit,
            "torque_limit": self.torque_limit,
            "retry": self.retry,
            "snap_signal": self.snap_signal,
            "steps": list(self.steps),
            "notes": list(self.notes),
        }


def _robot_moves(graph: nx.DiGraph, path: list[str], kinds: list[str]) -> list[str]:
    """A plan's path as plain robot moves: turns, and lift / tilt / lower for each tilt
    step."""
    nodes = graph.nodes
    moves: list[str] = []
    turned = 0.0
    lifted_from: dict[str, Any] | None = None  # the held tilt before a run of tilt steps
    for (u, v), kind in zip(zip(path, path[1:], strict=False), kinds, strict=True):
        if kind == "tilt-step":
            if turned > 0 or lifted_from is None:
                if turned > 0:
                    moves.append(f"turn counter-clockwise {turned:.0f} deg")
                turned = 0.0
                lifted_from = nodes[u]
            else:
                moves.pop()  # steps with no turn between them are one lift
            a, b = lifted_from, nodes[v]
            moves.append(
                f"lift clear, tilt by {b['held_roll'] - a['held_roll']:+g} deg roll and "
                f"{b['held_pitch'] - a['held_pitch']:+g} deg pitch (to held roll "
                f"{b['held_roll']:+g}, pitch {b['held_pitch']:+g} deg), lower onto the nut"
            )
        else:
            turned += float(graph.edges[u, v].get("turn", 0.0))
            if turned > 0:
                lifted_from = None
    moves.append(f"turn counter-clockwise {turned:.0f} deg to the snap")
    return moves


def controller_program(
    graph: nx.DiGraph,
    detection: SnapDetection | None = None,
    *,
    turn_margin: float | None = None,
    torque_margin: float = TORQUE_MARGIN,
    high_friction: float = HIGH_FRICTION,
) -> ControllerProgram:
    """What to program on the controller, from a library's network (module docstring).

    Parameters
    ----------
    graph : networkx.DiGraph
        The library's network; built with ``active=True`` for the retry plans (without,
        the retry is at the best held tilt).
    detection : SnapDetection, optional
        :func:`snap_detection` of the same network (computed when not given).
    turn_margin : float, optional
        Degrees added to the largest turn to the snap (default: the grid's largest
        start-phase step).
    torque_margin : float
        Share added to the largest torque (default 0.25).
    high_friction : float
        Friction coefficient of the torque's upper case (default 0.20).

    Returns
    -------
    ControllerProgram
    """
    torque_margin = check_range("torque_margin", torque_margin, 0.0, 10.0)
    high_friction = check_range("high_friction", high_friction, 0.0, 2.0)
    found = search_events(graph, high_friction=high_friction)
    det = detection if detection is not None else snap_detection(found)
    table = found.searches
    if table.empty:
        raise InputError("the library holds no start at rest: nothing to program")
    u = found.units
    notes: list[str] = []

    # -- the turn limit
    margin = found.phase_step if turn_margin is None else turn_margin
    margin = check_range("turn_margin", margin, 0.0, 2 * FULL_TURN, units="deg")
    snapping = table[table["snaps"]]
    largest_turn = float(snapping["snap_turn"].max()) if len(snapping) else math.nan
    limit = largest_turn + margin if len(snapping) else math.nan
    caught = table["snaps"] & (table["snap_turn"] <= limit + 1e-9)
    turn_limit = {
        "value": None if math.isnan(limit) else limit,
        "largest_turn_to_snap": None if math.isnan(largest_turn) else largest_turn,
        "margin": margin,
        "caught": int(caught.sum()),
        "starts": len(table),
        "share_caught": float(caught.mean()),
        "share_within_one_turn": float(
            (table["snaps"] & (table["snap_turn"] <= FULL_TURN + 1e-9)).mean()
        ),
        "rule": "the largest turn to the snap among the starts whose search snaps, plus "
        + (
            f"one start-phase step of the grid ({margin:g} deg: a start between two grid "
            "phases reaches the next grid phase within that gap, and from there the "
            "library's continuations mostly join that grid start's search)"
            if turn_margin is None
            else f"the margin asked for ({margin:g} deg)"
        )
        + "; the share is of the starts at rest whose search snaps within it",
    }
    if math.isnan(limit):
        notes.append("no search snaps: there is no turn limit to derive")

    # -- the torque limit
    peak = float(snapping["torque_peak"].max()) if len(snapping) else math.nan
    peak_high = float(snapping["torque_peak_high_friction"].max()) if len(snapping) else math.nan
    top = max((x for x in (peak, peak_high) if math.isfinite(x)), default=math.nan)
    torque_limit = {
        "value": None if math.isnan(top) else top * (1.0 + torque_margin),
        "largest_torque_to_snap": None if math.isnan(peak) else peak,
        "largest_torque_to_snap_high_friction": None if math.isnan(peak_high) else peak_high,
        "friction": float(found.compliance["friction"]),
        "high_friction": high_friction,
        "margin": torque_margin,
        "rule": "the larger of the largest driver torque up to the snap (searches that snap) "
        f"and the same at friction {high_friction:g} (the rest states' friction torque "
        "scaled by the ratio of the coefficients: the model's equilibrium is frictionless), "
        f"plus {torque_margin:.0%}",
    }

    # -- starts that never snap: lift and retry
    lost = table[~caught]
    tilts = table.assign(caught=caught).groupby(["held_roll", "held_pitch"], sort=True)
    ranked = sorted(
        (
            (
                float(rows["caught"].mean()),
                -float(rows.loc[rows["caught"], "snap_turn"].mean())
                if rows["caught"].any()
                else -math.inf,
                -math.hypot(float(r), float(p)),  # type: ignore[arg-type]
                float(r),  # type: ignore[arg-type]
                float(p),  # type: ignore[arg-type]
            )
            for (r, p), rows in tilts
        ),
        reverse=True,
    )
    best = ranked[0]
    best_tilt = {
        "held_roll": best[3],
        "held_pitch": best[4],
        "share_caught": best[0],
        "turn_mean": None if math.isinf(best[1]) else -best[1],
    }
    plans: list[dict[str, Any]] = []
    ends: Counter[tuple[float, float]] = Counter()
    active = bool(graph.graph.get("active"))
    no_plan = 0
    if active:
        for r, p, ph in zip(lost["held_roll"], lost["held_pitch"], lost["phase"], strict=True):
            try:
                plan = least_resistance_path(graph, r, p, ph, active=True)
            except NoPathError:
                no_plan += 1
                continue
            end = graph.nodes[plan.path[-1]]
            ends[(float(end["held_roll"]), float(end["held_pitch"]))] += 1
            plans.append(
                {
                    "start": {"held_roll": r, "held_pitch": p, "phase": ph},
                    "retry_tilt": {
                        "held_roll": float(end["held_roll"]),
                        "held_pitch": float(end["held_pitch"]),
                    },
                    "moves": _robot_moves(graph, plan.path, plan.kinds),
                    "tilt_steps": plan.moves,
                    "turn": plan.turn,
                    "cost": plan.cost,
                }
            )
    if ends:
        (rr, rp), count = max(ends.items(), key=lambda kv: (kv[1], -math.hypot(*kv[0])))
        retry_tilt = {"held_roll": rr, "held_pitch": rp, "plans": count, "source": "active plans"}
    else:
        retry_tilt = {
            "held_roll": best_tilt["held_roll"],
            "held_pitch": best_tilt["held_pitch"],
            "plans": 0,
            "source": "best held tilt",
        }
    retry = {
        "starts_not_caught": len(lost),
        "plans": len(plans),
        "no_plan": no_plan,
        "active": active,
        "retry_tilt": retry_tilt,
        "best_held_tilt": best_tilt,
        "plans_by_retry_tilt": [
            {"held_roll": k[0], "held_pitch": k[1], "plans": v} for k, v in ends.most_common()
        ],
        "rule": (
            "per start not caught within the turn limit, the network's least-resistance plan "
            "with active moves (change the held tilt by one grid step: lift, tilt, lower), "
            "written as robot moves; the retry tilt is the held tilt most plans end at. A "
            "plan's tilt change assumes the robot knows the held tilt it starts from (its "
            "misalignment); one that does not retries at the retry tilt itself"
            if active
            else "the network was built without active moves: retry at the held tilt that "
            "catches the most starts within the turn limit (then the least mean turn)"
        ),
        "plans_list": plans,
    }

    # -- the snap as a sensor threshold
    click = det.click
    first_click = None if click.smallest_snap is None else click.smallest_snap / 2.0
    table_j = table["jump_click"].astype(float)
    snap_first = table["snaps"] & (table["snap_event"] != "")
    # Every non-snap jump of a search comes before its snap (the walk ends there).
    jump_first = int((table_j >= (first_click or math.inf)).sum())
    jump_before_snap = int((snap_first & (table["jumps"] > 0)).sum())
    snap_signal = {
        "axial_force_change": 0.0,
        "axial_force": "the model presses the bolt with a constant axial force "
        f"({found.compliance['force']:g} N) through the compliance centre and has no axial "
        "spring: at rest before and after the snap the tool carries the same axial load, "
        "so the model predicts no change of axial force; a dip during the fall comes from "
        "the tool's axial dynamics, which the model does not hold",
        "click": click.to_dict(),
        "moment_change": det.signals["moment_change"].to_dict(),
        "torque_change": det.signals["torque_change"].to_dict(),
        "lateral_force_change": (
            det.signals["lateral_force_change"].to_dict()
            if "lateral_force_change" in det.signals
            else None
        ),
        "separating_signals": [k for k, s in det.signals.items() if s.separates],
        "first_click_threshold": first_click,
        "searches_with_a_jump_before_their_snap": jump_before_snap,
        "searches_whose_first_click_is_not_a_snap": jump_first,
        "confirm": f"turn clockwise {SCREW_IN:g} deg (the search's default screw-in, its "
        "proof of a snap): a snap descends at the lead (P/360 per degree); a landing that "
        "does not is not in the thread",
        "rule": "the click's threshold when it separates the snap from every other jump; "
        "otherwise stop at the first click of at least half the smallest snap click and "
        "confirm by screwing in (the model's own proof of a snap)",
    }
    stop = (
        f"a fall of the tool of at least {click.threshold:.4g} {u}"
        if click.separates and click.threshold is not None
        else (
            f"the first fall of the tool of at least {first_click:.4g} {u}, then confirm"
            if first_click is not None
            else "no snap to detect"
        )
    )
    stiffness = found.compliance["stiffness"]
    steps = [
        f"Press down with {found.compliance['force']:g} N through the compliance "
        f"({stiffness['roll']:g}/{stiffness['pitch']:g} N m/rad), at the pre-tilt the "
        "recommendation gives.",
        "Turn counter-clockwise (the unscrewing sense) and watch the tool's axial position: "
        f"stop at {stop}.",
        f"Confirm: {snap_signal['confirm']}; then screw in.",
        "Give up when the turn reaches "
        + (f"{limit:.0f} deg" if not math.isnan(limit) else "one turn")
        + (
            f" or the driver's torque reaches {torque_limit['value']:.3g} N m"
            if torque_limit["value"] is not None
            else ""
        )
        + ", or when the confirmation fails.",
        "Then lift clear and retry at held roll "
        f"{retry_tilt['held_roll']:+g}, pitch {retry_tilt['held_pitch']:+g} deg "
        f"({retry_tilt['source']}).",
    ]
    if jump_first:
        notes.append(
            f"in {jump_first} of {len(table)} searches the first click of at least "
            f"{first_click:.4g} {u} is not a snap (a landing in phase that jams, or a fall "
            "off an edge): the confirmation by screwing in catches them"
        )
    return ControllerProgram(
        u, found.compliance, turn_limit, torque_limit, retry, snap_signal, steps, notes
    )


def format_controller_program(prog: ControllerProgram) -> str:
    """The program as Markdown: the steps, then each setting with its rule."""
    u = prog.units
    t, q, r, s = prog.turn_limit, prog.torque_limit, prog.retry, prog.snap_signal
    lines = [f"- Step {i}. {step}" for i, step in enumerate(prog.steps, 1)]
    lines += [
        "",
        f"- **Turn limit: {number_text(t['value'], '.0f')} deg.** It catches {t['caught']} of "
        f"{t['starts']} starts ({t['share_caught']:.0%}; within one turn "
        f"{t['share_within_one_turn']:.0%}). Rule: {t['rule']}.",
        f"- **Torque limit: {number_text(q['value'], '.3g')} N m.** Largest torque up to the "
        f"snap {number_text(q['largest_torque_to_snap'], '.3g')} N m at friction "
        f"{q['friction']:g}, {number_text(q['largest_torque_to_snap_high_friction'], '.3g')} "
        f"N m at {q['high_friction']:g}. Rule: {q['rule']}.",
        f"- **Starts that never snap** ({r['starts_not_caught']} not caught within the turn "
        f"limit): lift and retry at held roll {r['retry_tilt']['held_roll']:+g}, pitch "
        f"{r['retry_tilt']['held_pitch']:+g} deg ({r['retry_tilt']['source']}"
        + (f", {r['retry_tilt']['plans']} of {r['plans']} plans" if r["plans"] else "")
        + f"). Rule: {r['rule']}.",
    ]
    for plan in r["plans_list"][:3]:
        st = plan["start"]
        lines.append(
            f"- A plan, from held roll {st['held_roll']:+g}, pitch {st['held_pitch']:+g}, phase "
            f"{st['phase']:g} deg: " + "; ".join(plan["moves"]) + "."
        )
    click = s["click"]
    lines += [
        f"- **The snap as a sensor threshold.** Axial force: {s['axial_force']}. Fall of the "
        "tool (the click): "
        + (
            f"threshold {click['threshold']:.4g} {u} separates the snap from every other jump"
            if click["separates"]
            else f"no threshold separates the snap from the other jumps; stop at the first "
            f"click of at least {number_text(s['first_click_threshold'], '.4g')} {u} and "
            "confirm"
        )
        + f". Signals that separate: {', '.join(s['separating_signals']) or 'none'}. "
        f"Searches with another jump before their snap: "
        f"{s['searches_with_a_jump_before_their_snap']}; whose first click is not a snap: "
        f"{s['searches_whose_first_click_is_not_a_snap']}. Rule: {s['rule']}.",
    ]
    lines += [f"\nNote: {n}." for n in prog.notes]
    return "\n".join(lines) + "\n"
