"""The SRCC recommendation: which pre-tilt (and compliance) makes the passive search snap
reliably, quickly and cheaply.

A *setting* is a held pitch of the grid (the pre-tilt the robot sets about the nut's Y
axis) for one compliance (one library). Its starts are the library's starts at that held
pitch whose held roll lies within the expected roll error (``|roll| <= roll_spread``), at
every start phase. Starts whose drop failed or whose descent did not reach a rest state
are counted apart (``failed``, ``not_at_rest``) and left out of every figure. Over the
others, from :func:`start_outcomes` (the passive search):

- ``share_snap``: share that snap within one turn;
- ``turn_mean``, ``turn_worst``: degrees turned to the snap (over those that snap);
- ``work_mean``, ``work_worst``: the driver's work to the snap (mJ, same starts);
- ``click_mean``: the click, the fall of the compliance centre a sensor sees at the snap,
  from the highest the bolt stands within the last degree of turn to the landing (spec
  units; starts that drop straight in phase, or pass into it without a jump, have no
  click and are left out);
- ``torque_peak``: the largest driver torque met (N m);
- ``share_unstable``: share whose path passes a jump or an unstable transition before
  the snap.

Settings are ranked by what a designer needs first: ``share_snap`` (higher), then
``turn_mean`` (lower), then ``work_mean`` (lower). The margin is the pick's lead over the
next setting in each. A pick at the smallest or largest held pitch of the grid is flagged:
the best may lie beyond the range searched.

**The nut's azimuth.** The robot rarely knows where the nut's thread starts. Turning the
nut about its axis by a quarter turn turns a pre-tilt about Y into one about X; every
figure above depends on the tilt's direction relative to the thread start, and the start
phases (all of them are averaged) absorb the rest. The azimuth-proof recommendation takes,
for each pre-tilt size ``s`` that the grid holds in all four quarter-turn directions
(held pitch ``+s`` and ``-s`` with the roll spread, held roll ``+s`` and ``-s`` with the
same spread in pitch), the *worst* of the four directions, and ranks the sizes the same
way. Directions between the quarter turns are not computed. A library of a polar grid
(docs/design.md) gives, for each tilt size, the worst of every direction it holds.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np
import pandas as pd

from .._errors import InputError
from .._figures import new_figure, save_figure
from .._io import atomic_write_text
from .._json import json_text
from .._text import number_text
from .._units import json_units
from .._validate import check_roll_spread
from ..contact import UNSTABLE
from ._paths import start_outcomes

__all__ = [
    "METRICS",
    "Recommendation",
    "format_recommendation",
    "plot_recommendation",
    "recommend",
    "write_recommendation",
]

#: The figures of a setting, with units.
METRICS = {
    "share_snap": "1",
    "turn_mean": "deg",
    "turn_worst": "deg",
    "work_mean": "mJ",
    "work_worst": "mJ",
    "click_mean": "length",
    "torque_peak": "N m",
    "share_unstable": "1",
}


#: The class of a start whose descent did not reach a rest state (it did not converge).
NOT_AT_REST = UNSTABLE


def _figures(rows: pd.DataFrame) -> dict[str, Any]:
    # A start whose descent did not reach a rest state has no search to speak of: it is
    # counted apart (not_at_rest) and left out of every figure, as a failed one is.
    unsettled = ~rows["failed"] & (rows["classification"] == NOT_AT_REST)
    ok = rows[~rows["failed"] & ~unsettled]
    snapped = ok[ok["snapped"]]
    clicks = snapped.loc[snapped["turn"] > 0, "click"]

    def stat(series: pd.Series, how: str) -> float | None:
        series = series.dropna()
        if series.empty:
            return None
        return float(series.mean() if how == "mean" else series.max())

    return {
        "starts": len(ok),
        "failed": int(rows["failed"].sum()),
        "not_at_rest": int(unsettled.sum()),
        "share_snap": float(len(snapped) / len(ok)) if len(ok) else 0.0,
        "turn_mean": stat(snapped["turn"], "mean"),
        "turn_worst": stat(snapped["turn"], "max"),
        "work_mean": stat(snapped["work"], "mean"),
        "work_worst": stat(snapped["work"], "max"),
        "click_mean": stat(clicks, "mean"),
        "torque_peak": stat(ok["torque_peak"], "max"),
        "share_unstable": float(ok["passes_unstable"].mean()) if len(ok) else 0.0,
    }


#: Settings whose mean turn and mean work differ by less than this share (with the same snap
#: share) are reported as equivalent to the pick.
EQUIVALENT = 0.05


def _equivalent(a: dict[str, Any], b: dict[str, Any]) -> bool:
    if a["share_snap"] != b["share_snap"]:
        return False
    for key in ("turn_mean", "work_mean"):
        x, y = a[key], b[key]
        if x is None or y is None or abs(x - y) > EQUIVALENT * max(abs(x), abs(y), 1e-12):
            return False
    return True


def _rank_key(s: dict[str, Any]) -> tuple[float, float, float]:
    inf = math.inf
    return (
        -s["share_snap"],
        s["turn_mean"] if s["turn_mean"] is not None else inf,
        s["work_mean"] if s["work_mean"] is not None else inf,
    )


@dataclass
class Recommendation:
    """Settings ranked, the pick and its margin, the azimuth-proof pick.

    Attributes
    ----------
    settings : list of dict
        One per (compliance, held pitch), ranked best first: ``force`` (N),
        ``stiffness`` (N m/rad, roll and pitch), ``held_pitch`` (deg) and the
        :data:`METRICS`.
    margin : dict
        The pick's lead over the next setting (``share_snap``, ``turn_mean``,
        ``work_mean``), None with one setting.
    at_edge : bool
        The pick's held pitch is the grid's smallest or largest.
    azimuth_proof : list of dict
        Per pre-tilt size and compliance, the worst of the four quarter-turn directions,
        ranked best first (empty when the grid holds no size in all four directions).
    roll_spread : float
        The roll error over which starts were taken (degrees).
    units : str
        Length units.
    pitch_range : tuple of float
        Smallest and largest held pitch searched.
    notes : list of str
        What the figures do not say by themselves (the pick at the edge, equivalent
        settings, an incomplete library).
    progress : list of dict
        Per network: ``done`` (starts), ``configurations`` (the grid's) and ``complete``.
    """

    settings: list[dict[str, Any]]
    margin: dict[str, float | None] | None
    at_edge: bool
    azimuth_proof: list[dict[str, Any]]
    roll_spread: float
    units: str
    pitch_range: tuple[float, float]
    notes: list[str] = field(default_factory=list)
    progress: list[dict[str, Any]] = field(default_factory=list)

    @property
    def best(self) -> dict[str, Any]:
        """The recommended setting."""
        return self.settings[0]

    def to_dict(self) -> dict[str, Any]:
        """The JSON document (``threadmate recommend --json``)."""
        return {
            "units": json_units(
                self.units, "angle", "work", "torque", "force", "stiffness", "share"
            ),
            "metrics": METRICS,
            "roll_spread": self.roll_spread,
            "pitch_range": list(self.pitch_range),
            "recommended": self.best,
            "margin": self.margin,
            "at_edge": self.at_edge,
            "settings": self.settings,
            "azimuth_proof": self.azimuth_proof,
            "azimuth_proof_pick": self.azimuth_proof[0] if self.azimuth_proof else None,
            "notes": list(self.notes),
            "complete": all(p["complete"] for p in self.progress),
            "progress": [dict(p) for p in self.progress],
        }


def _compliance(graph: nx.DiGraph) -> dict[str, Any]:
    c = json.loads(graph.graph["compliance"])
    return {"force": c["force"], "stiffness": [c["stiffness"]["roll"], c["stiffness"]["pitch"]]}


def recommend(
    networks: nx.DiGraph | list[nx.DiGraph],
    roll_spread: float | None = None,
    *,
    partial: bool = False,
) -> Recommendation:
    """Rank the SRCC settings of one or more networks (see the module docstring).

    Parameters
    ----------
    networks : networkx.DiGraph or list of them
        Networks of libraries on the same grid and thread, differing in compliance.
    roll_spread : float, optional
        Largest roll error expected (degrees, from 0 to the largest held roll a grid
        holds, ``threadmate._validate.MAX_TILT``); default every roll of the grid.
    partial : bool
        Rank the starts of an incomplete library (a sweep unfinished or still running)
        too, with a note saying how many are done; without it such a library is refused,
        as a ranking of the held tilts swept so far may pick one the rest would beat.

    Returns
    -------
    Recommendation
    """
    graphs = [networks] if isinstance(networks, nx.DiGraph) else list(networks)
    if not graphs:
        raise InputError("no network to recommend from")
    roll_spread = check_roll_spread(roll_spread)
    spread = math.inf if roll_spread is None else float(roll_spread)
    grids = {g.graph["grid"] for g in graphs}
    if len(grids) > 1 or len({g.graph["spec"] for g in graphs}) > 1:
        raise InputError("the libraries to compare must share one thread and one grid")
    _check_distinct(graphs)
    many = len(graphs) > 1
    settings, proof, notes = [], [], []
    swept = [_progress(g) for g in graphs]
    for p in swept:
        if not p["complete"]:
            words = f"{p['done']} of {p['configurations']} starts done"
            if not partial:
                raise InputError(
                    f"the library is incomplete ({words}): a ranking of the held tilts swept "
                    "so far may pick one the rest would beat; finish its sweep (run the same "
                    "sweep again), or pass partial=True to rank the starts done"
                )
            notes.append(f"from an incomplete library: {words}; the ranking may change")
    rolls: set[float] = set()
    for graph in graphs:
        comp = _compliance(graph)
        out = start_outcomes(graph)
        if out.empty:
            raise InputError("the library holds no finished start")
        rolls.update(out["held_roll"].abs())
        inside = out[out["held_roll"].abs() <= spread + 1e-9]
        if inside.empty:
            raise InputError(f"no start within the roll spread {roll_spread:g} deg")
        for pitch, rows in inside.groupby("held_pitch", sort=True):
            # pandas-stubs type a group key as any scalar; held pitches are floats.
            settings.append(
                {
                    **comp,
                    "held_pitch": float(pitch),  # type: ignore[arg-type]
                    **_figures(rows),
                }
            )
        polar = json.loads(graph.graph["grid"]).get("kind") == "polar"
        proof += _polar_proof(out, comp) if polar else _azimuth_proof(out, spread, comp)
    settings.sort(key=_rank_key)
    proof.sort(key=_rank_key)
    pitches = sorted({s["held_pitch"] for s in settings})
    best = settings[0]
    margin = None
    if len(settings) > 1:
        nxt = settings[1]
        margin = {
            k: (
                None
                if best[k] is None or nxt[k] is None
                else (best[k] - nxt[k] if k == "share_snap" else nxt[k] - best[k])
            )
            for k in ("share_snap", "turn_mean", "work_mean")
        }
    at_edge = len(pitches) > 1 and best["held_pitch"] in (pitches[0], pitches[-1])
    if at_edge:
        notes.append(
            f"the pick, {_setting_words(best, many)}, is at the edge of "
            f"the range searched ({pitches[0]:g}..{pitches[-1]:g} deg): a larger "
            "pre-tilt that way may do better; sweep a wider pitch range"
        )
    equivalent = [x for x in settings[1:] if _equivalent(best, x)]
    if equivalent:
        # With several compliances each setting says which (a held pitch alone names a
        # setting of every compliance).
        pick = f"the pick ({_setting_words(best, True)})" if many else "the pick"
        notes.append(
            f"within this grid's resolution {pick} is no better than "
            + "; ".join(_setting_words(x, many) for x in equivalent)
            + " (same snap share, "
            f"mean turn and work within {EQUIVALENT:.0%}): prefer the one nearest "
            "upright, or refine the grid"
        )
    if best["share_snap"] < 1.0:
        notes.append(
            f"even the pick leaves {1 - best['share_snap']:.0%} of starts without "
            "a snap within one turn"
        )
    if not proof:
        notes.append(
            "no pre-tilt size lies in all four quarter-turn directions of this "
            "grid: no azimuth-proof pick (sweep a square roll x pitch grid)"
        )
    units = graphs[0].graph["units"]
    # Without a spread every held roll of the grid counts: say how far they reach.
    spread_out = spread if math.isfinite(spread) else float(max(rolls))
    return Recommendation(
        settings, margin, at_edge, proof, spread_out, units, (pitches[0], pitches[-1]), notes, swept
    )


def _check_distinct(graphs: list[nx.DiGraph]) -> None:
    """Refuse two networks of one compliance: the settings are told apart by force and
    stiffness, so every row would be there twice."""
    seen: dict[tuple[float, tuple[float, ...]], int] = {}
    for i, graph in enumerate(graphs, 1):
        comp = _compliance(graph)
        key = (comp["force"], tuple(comp["stiffness"]))
        if key in seen:
            raise InputError(
                f"libraries {seen[key]} and {i} hold the same compliance "
                f"({_compliance_words(comp)}): give each compliance's library once "
                "(recommend compares compliances)"
            )
        seen[key] = i


def _compliance_words(s: dict[str, Any]) -> str:
    return f"{s['force']:g} N, {s['stiffness'][0]:g}/{s['stiffness'][1]:g} N m/rad"


def _setting_words(s: dict[str, Any], many: bool) -> str:
    """A setting in words: its held pitch, and its compliance when several are compared."""
    words = f"held pitch {s['held_pitch']:+g} deg"
    return f"{words} at {_compliance_words(s)}" if many else words


def _progress(graph: nx.DiGraph) -> dict[str, Any]:
    """How far the library of a network was swept (a graph built without it: complete)."""
    g = graph.graph
    n = int(g.get("done", 0))
    return {
        "done": n,
        "configurations": int(g.get("configurations", n)),
        "complete": bool(g.get("complete", True)),
    }


def _azimuth_proof(out: pd.DataFrame, spread: float, comp: dict[str, Any]) -> list[dict[str, Any]]:
    """Per pre-tilt size held in all four quarter-turn directions, its worst direction."""
    rolls = set(out["held_roll"])
    pitches = set(out["held_pitch"])
    sizes = sorted(
        {abs(p) for p in pitches if p in pitches and -p in pitches and p in rolls and -p in rolls}
    )
    found = []
    for s in sizes:
        directions = {
            "+pitch": out[(out["held_pitch"] == s) & (out["held_roll"].abs() <= spread)],
            "-pitch": out[(out["held_pitch"] == -s) & (out["held_roll"].abs() <= spread)],
            "+roll": out[(out["held_roll"] == s) & (out["held_pitch"].abs() <= spread)],
            "-roll": out[(out["held_roll"] == -s) & (out["held_pitch"].abs() <= spread)],
        }
        if s == 0:
            directions = {
                "upright": out[(out["held_pitch"] == 0) & (out["held_roll"].abs() <= spread)]
            }
        figures = {k: _figures(v) for k, v in directions.items() if len(v)}
        if not figures:
            continue
        worst = max(figures.items(), key=lambda kv: _rank_key(kv[1]))
        found.append({**comp, "tilt_size": float(s), "worst_direction": worst[0], **worst[1]})
    return found


def _polar_proof(out: pd.DataFrame, comp: dict[str, Any]) -> list[dict[str, Any]]:
    """A polar grid's tilt sizes, each with the worst of all its directions (every
    direction the grid holds, not only the quarter turns; the roll spread does not apply:
    the directions are the spread)."""
    found = []
    for size, rows in out.groupby("held_tilt", sort=True):
        by_direction = (
            {"upright": rows}
            if float(size) == 0  # type: ignore[arg-type]
            else {f"{d:g} deg": g for d, g in rows.groupby("held_direction", sort=True)}
        )
        figures = {k: _figures(v) for k, v in by_direction.items()}
        worst = max(figures.items(), key=lambda kv: _rank_key(kv[1]))
        found.append(
            {**comp, "tilt_size": float(size), "worst_direction": worst[0], **worst[1]}  # type: ignore[arg-type]
        )
    return found


def format_recommendation(rec: Recommendation) -> str:
    """The ranking as a Markdown table, then the pick in words (the notes are
    ``rec.notes``)."""
    many = len({(s["force"], tuple(s["stiffness"])) for s in rec.settings}) > 1
    head = (
        "| "
        + ("force N | stiffness N m/rad | " if many else "")
        + "held pitch deg | share snap | turn mean deg | turn worst deg | work mean mJ | "
        f"work worst mJ | click mean {rec.units} | torque peak N m | share unstable |"
    )
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for s in rec.settings:
        comp = f"{s['force']:g} | {s['stiffness'][0]:g}/{s['stiffness'][1]:g} | " if many else ""
        lines.append(
            f"| {comp}{s['held_pitch']:+g} | {s['share_snap']:.0%} | "
            f"{number_text(s['turn_mean'], '.0f')} | {number_text(s['turn_worst'], '.0f')} | "
            f"{number_text(s['work_mean'], '.3g')} | {number_text(s['work_worst'], '.3g')} | "
            f"{number_text(s['click_mean'], '.2e')} | {number_text(s['torque_peak'], '.3g')} | "
            f"{s['share_unstable']:.0%} |"
        )
    return "\n".join([*lines, "", *_pick_lines(rec)]) + "\n"


def _pick_lines(rec: Recommendation) -> list[str]:
    """The pick in words: the setting, what it achieves, and the azimuth-proof pick."""
    many = len({(s["force"], tuple(s["stiffness"])) for s in rec.settings}) > 1
    best = rec.best
    lines = [
        f"Recommended: {_setting_words(best, many)}: {best['share_snap']:.0%} of "
        f"{best['starts']} starts snap within one turn, after "
        f"{number_text(best['turn_mean'], '.0f')} "
        f"deg and {number_text(best['work_mean'], '.3g')} mJ on average."
    ]
    if rec.azimuth_proof:
        p = rec.azimuth_proof[0]
        comp = f" at {_compliance_words(p)}" if many else ""
        lines.append(
            f"Whatever the nut's thread-start azimuth: a pre-tilt of {p['tilt_size']:g} "
            f"deg{comp} (worst direction {p['worst_direction']}: {p['share_snap']:.0%} "
            "snap within one turn)."
        )
    return lines


def write_recommendation(rec: Recommendation, path: str | os.PathLike[str]) -> Path:
    """Write the JSON document atomically."""
    return atomic_write_text(path, json_text(rec.to_dict()))


def plot_recommendation(rec: Recommendation, path: str | os.PathLike[str]) -> Path:
    """Share of starts that snap within a turn, and the mean turn to the snap, against the
    held pitch (one line per compliance); the pick marked."""
    fig = new_figure((7.0, 5.5))
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    groups: dict[tuple[Any, ...], list[dict[str, Any]]] = {}
    for s in rec.settings:
        groups.setdefault((s["force"], tuple(s["stiffness"])), []).append(s)
    for (force, stiff), rows in groups.items():
        rows = sorted(rows, key=lambda s: s["held_pitch"])
        x = [s["held_pitch"] for s in rows]
        label = f"F {force:g} N, k {stiff[0]:g}/{stiff[1]:g} N m/rad"
        ax1.plot(x, [100 * s["share_snap"] for s in rows], "o-", label=label)
        ax2.plot(
            x,
            [np.nan if s["turn_mean"] is None else s["turn_mean"] for s in rows],
            "o-",
            label=label,
        )
    best = rec.best
    ax1.axvline(best["held_pitch"], color="0.5", ls=":", lw=1)
    ax2.axvline(best["held_pitch"], color="0.5", ls=":", lw=1)
    ax1.set_ylabel("snap within one turn (%)")
    ax2.set_ylabel("mean turn to the snap (deg)")
    ax2.set_xlabel("held pitch: the SRCC pre-tilt about the nut's Y axis (deg)")
    ax1.set_title(
        f"starts with |roll| <= {rec.roll_spread:g} deg, every start phase; "
        f"pick {best['held_pitch']:+g} deg" + (" (at the edge)" if rec.at_edge else "")
    )
    ax1.legend(fontsize=7)
    return save_figure(fig, path)
