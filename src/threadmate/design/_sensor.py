"""The snap a sensor can detect: snap clicks against the other jumps of the same searches.

A snap is only useful if a sensor can tell it from the other jumps of a search
(docs/mechanics.md, "Recommendations"). For every start of a library
(:func:`~threadmate.design.search_events`), the snap's signal is set against the
**largest** signal of any non-snap jump in the same search: a controller that stops at
the first event above a threshold decides a search right only if its snap is above the
threshold and every jump before it is below (or, for a search that never snaps, every
jump is below). So the threshold is judged per search:

- if the largest non-snap signal of every search lies below the smallest snap signal,
  the threshold is the midpoint of that gap, with half the gap as margin on each side;
- otherwise no threshold separates them: the one given is the one that decides the most
  searches right (ties: fewest false alarms, then fewest missed snaps), placed midway
  between neighbouring values, with its counts of missed snaps, false alarms and
  searches decided wrongly.

This is done for each signal of :data:`~threadmate.design.EVENT_SIGNALS` (the click, the
tilt spring's moment, the driver's torque), per library (one compliance) and per held
pitch. Lengths in the spec's units, torques and moments in N m.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np
import pandas as pd

from .._figures import new_figure, save_figure
from .._text import number_text
from ._searches import EVENT_SIGNALS, SearchEvents, search_events

__all__ = [
    "Separation",
    "SnapDetection",
    "format_snap_detection",
    "plot_snap_detection",
    "separation",
    "snap_detection",
]


@dataclass(frozen=True)
class Separation:
    """How well one signal tells the snap from the other jumps, over a set of searches.

    Attributes
    ----------
    signal, unit : str
        The signal (:data:`EVENT_SIGNALS`) and its unit.
    searches : int
        Searches judged.
    snaps : int
        Searches that snap (with an event: a start already in the thread has none).
    with_jumps : int
        Searches with at least one non-snap jump.
    smallest_snap, largest_jump : float or None
        The smallest snap signal and the largest non-snap one (None: none).
    separates : bool
        Every snap's signal lies above every search's largest non-snap one.
    threshold : float or None
        Detect the snap when the signal reaches it (None: no snap to detect).
    margin_snap, margin_jump : float or None
        ``smallest_snap - threshold`` and ``threshold - largest_jump`` (negative where the
        threshold misses snaps or admits jumps; None where there is no value).
    missed_snaps : int
        Snaps whose signal is below the threshold.
    false_alarms : int
        Searches with a non-snap jump at or above the threshold (before their snap, or
        in a search that never snaps).
    false_alarms_before_snap : int
        Those of the false alarms that come before the search's snap.
    wrong : int
        Searches decided wrongly at the threshold (a missed snap or a false alarm).
    """

    signal: str
    unit: str
    searches: int
    snaps: int
    with_jumps: int
    smallest_snap: float | None
    largest_jump: float | None
    separates: bool
    threshold: float | None
    margin_snap: float | None
    margin_jump: float | None
    missed_snaps: int
    false_alarms: int
    false_alarms_before_snap: int
    wrong: int

    def statement(self, units: str) -> str:
        """One sentence: the threshold and its margins, or that none separates."""
        u = units if self.unit == "length" else self.unit
        name = self.signal.replace("_", " ")
        if self.threshold is None:
            return f"{name}: no search snaps with an event, so there is no snap to detect"
        t = f"{self.threshold:.4g} {u}"
        if self.separates and self.largest_jump is None:
            return (
                f"{name}: no search has a non-snap jump; every snap is at least "
                f"{self.smallest_snap:.4g} {u}, and a threshold of {t} (half that) detects "
                "each"
            )
        if self.separates:
            return (
                f"{name}: a threshold of {t} separates the snap from every other jump: the "
                f"smallest snap is {self.smallest_snap:.4g} {u} (margin "
                f"{self.margin_snap:.3g} {u}), the largest other jump "
                f"{self.largest_jump:.4g} {u} (margin {self.margin_jump:.3g} {u})"
            )
        head = (
            f"{name}: no threshold separates the snap from the other jumps (the largest "
            f"other jump, {self.largest_jump:.4g} {u}, is not below the smallest snap, "
            f"{self.smallest_snap:.4g} {u}); "
        )
        alarms = (
            f"{self.false_alarms} false alarms, {self.false_alarms_before_snap} of them "
            "before a snap and the rest in searches that never snap"
        )
        if self.missed_snaps == self.snaps:
            return head + (
                f"the fewest wrong decisions ({self.wrong} of {self.searches} searches) come "
                f"from detecting no snap at all (a threshold above every value, {t}): any "
                "lower threshold admits more jumps than it catches snaps"
            )
        return head + (
            f"the best threshold, {t}, decides {self.wrong} of {self.searches} searches "
            f"wrongly ({self.missed_snaps} snaps missed; {alarms})"
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping for JSON."""
        return {
            "signal": self.signal,
            "unit": self.unit,
            "searches": self.searches,
            "snaps": self.snaps,
            "with_jumps": self.with_jumps,
            "smallest_snap": self.smallest_snap,
            "largest_jump": self.largest_jump,
            "separates": self.separates,
            "threshold": self.threshold,
            "margin_snap": self.margin_snap,
            "margin_jump": self.margin_jump,
            "missed_snaps": self.missed_snaps,
            "false_alarms": self.false_alarms,
            "false_alarms_before_snap": self.false_alarms_before_snap,
            "wrong": self.wrong,
        }


def _opt(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def separation(
    snap: Any, largest_jump: Any, *, signal: str = "click", unit: str = "length"
) -> Separation:
    """The threshold that tells the snap from the other jumps (module docstring).

    Parameters
    ----------
    snap : array_like
        Per search, its snap's signal (NaN: the search does not snap with an event).
    largest_jump : array_like
        Per search (the same order), the largest signal of its non-snap jumps (NaN:
        none).
    signal, unit : str
        What the values are, for the result.

    Returns
    -------
    Separation
    """
    s = np.asarray(snap, dtype=float)
    j = np.asarray(largest_jump, dtype=float)
    if s.shape != j.shape:
        raise ValueError("snap and largest_jump must hold one value per search each")
    has_s, has_j = np.isfinite(s), np.isfinite(j)
    snaps, others = s[has_s], j[has_j]
    n = len(s)
    smallest = float(snaps.min()) if snaps.size else math.nan
    largest = float(others.max()) if others.size else math.nan

    def counts(t: float) -> tuple[int, int, int, int]:
        missed = has_s & (s < t)
        alarm = has_j & (j >= t)
        early = int((alarm & has_s).sum())
        return int(missed.sum()), int(alarm.sum()), int((missed | alarm).sum()), early

    if not snaps.size:
        return Separation(
            signal, unit, n, 0, int(has_j.sum()), None, _opt(largest), False, None, None,
            None, 0, int(has_j.sum()), 0, int(has_j.sum()),
        )  # fmt: skip
    if not others.size:
        t = smallest / 2.0
    elif largest < smallest:
        t = (largest + smallest) / 2.0
    else:
        # Overlap: every threshold between two neighbouring values decides the same
        # searches; try the midpoints, and one below and one above every value.
        values = np.unique(np.concatenate([snaps, others]))
        span = max(float(values[-1] - values[0]), abs(float(values[-1])), 1e-300)
        candidates = np.concatenate(
            [
                [values[0] - 0.05 * span],
                (values[:-1] + values[1:]) / 2.0,
                [values[-1] + 0.05 * span],
            ]
        )
        best = min(candidates, key=lambda t: (counts(t)[2], counts(t)[1], counts(t)[0]))
        # (fewest wrong, then fewest false alarms: an alarm tightens a bolt that is not in
        # the thread, a missed snap only turns on to the turn limit)
        t = float(best)
    missed, alarms, wrong, early = counts(t)
    return Separation(
        signal,
        unit,
        n,
        int(snaps.size),
        int(has_j.sum()),
        smallest,
        _opt(largest),
        wrong == 0 and (not others.size or largest < smallest),
        float(t),
        smallest - t,
        _opt(t - largest),
        missed,
        alarms,
        early,
        wrong,
    )


def _stats(values: pd.Series) -> dict[str, float | int | None]:
    v = values[np.isfinite(values.astype(float))].astype(float)
    if v.empty:
        return {"count": 0, "min": None, "median": None, "max": None}
    return {
        "count": int(len(v)),
        "min": float(v.min()),
        "median": float(v.median()),
        "max": float(v.max()),
    }


@dataclass
class SnapDetection:
    """The snap a sensor can detect, for one library (one compliance).

    Attributes
    ----------
    units : str
        The spec's length unit.
    compliance : dict
        The library's compliance.
    starts, searches, snaps, with_jumps : int
        Starts of the library; searches judged (the starts at rest); those that snap
        with an event; those with a non-snap jump.
    signals : dict of str to Separation
        Per signal (click, moment_change, torque_change, and lateral_force_change when
        the library's rows were given), over every search: the threshold or the overlap.
    by_held_pitch : list of dict
        Per held pitch (the pre-tilt a setting fixes): ``held_pitch`` (deg) and the
        click's :class:`Separation` over its searches.
    torque : dict
        The driver-torque signature: ``before_snap``, ``after_snap``, ``change_at_snap``,
        ``before_jump``, ``after_jump``, ``change_at_jump`` (count, min, median, max over
        the distinct transitions; N m) and ``peak_to_snap`` (over the searches that snap).
    events : pandas.DataFrame
        The distinct jumps and snaps met (:class:`SearchEvents`).
    searches_table : pandas.DataFrame
        One row per search (:class:`SearchEvents`).
    branch_fall : float or None
        The steepest mean fall per degree of turn of a continuous branch the searches pass
        (length/deg): what a sensor watching for a click sees without a jump.
    notes : list of str
        What the figures do not say by themselves.
    """

    units: str
    compliance: dict[str, Any]
    starts: int
    searches: int
    snaps: int
    with_jumps: int
    signals: dict[str, Separation]
    by_held_pitch: list[dict[str, Any]]
    torque: dict[str, Any]
    events: pd.DataFrame
    searches_table: pd.DataFrame
    branch_fall: float | None = None
    notes: list[str] = field(default_factory=list)

    @property
    def click(self) -> Separation:
        """The click's separation (the sensor's first signal)."""
        return self.signals["click"]

    def to_dict(self) -> dict[str, Any]:
        """The JSON document (``threadmate sensor --json``)."""
        events = self.events
        return {
            "units": {
                "length": self.units,
                "click": self.units,
                "moment_change": "N m",
                "lateral_force_change": "N",
                "torque": "N m",
                "force": "N",
                "angle": "deg",
                "branch_fall_per_degree": f"{self.units}/deg",
            },
            "compliance": self.compliance,
            "starts": self.starts,
            "searches": self.searches,
            "snaps": self.snaps,
            "with_jumps": self.with_jumps,
            "signals": {k: v.to_dict() for k, v in self.signals.items()},
            "statements": {k: v.statement(self.units) for k, v in self.signals.items()},
            "by_held_pitch": [
                {"held_pitch": r["held_pitch"], **r["click"].to_dict()} for r in self.by_held_pitch
            ],
            "torque": self.torque,
            "branch_fall_per_degree": self.branch_fall,
            "snap_clicks": [float(x) for x in self.searches_table["snap_click"].dropna()],
            "largest_jump_clicks": [float(x) for x in self.searches_table["jump_click"].dropna()],
            "events": [
                {
                    k: (None if isinstance(v, float) and not math.isfinite(v) else v)
                    for k, v in row.items()
                }
                for row in events.to_dict("records")
            ],  # fmt: skip
            "notes": list(self.notes),
        }


def snap_detection(
    graph: nx.DiGraph | SearchEvents, rows: pd.DataFrame | None = None
) -> SnapDetection:
    """The snap a sensor can detect in a library's searches (module docstring).

    Parameters
    ----------
    graph : networkx.DiGraph or SearchEvents
        The library's network (:func:`threadmate.network.build_network`), or its
        searches already walked (:func:`search_events`).
    rows : pandas.DataFrame, optional
        The library's rows, for the lateral force (:func:`search_events`).

    Returns
    -------
    SnapDetection
    """
    found = graph if isinstance(graph, SearchEvents) else search_events(graph, rows)
    table = found.searches
    signals = {
        name: separation(
            table[f"snap_{name}"], table[f"jump_{name}"], signal=name, unit=EVENT_SIGNALS[name][0]
        )
        for name in EVENT_SIGNALS
        # a signal the library did not give (the lateral force without its rows) is left out
        if table[f"snap_{name}"].notna().any() or table[f"jump_{name}"].notna().any()
    }
    signals.setdefault("click", separation(table["snap_click"], table["jump_click"]))
    by_pitch = [
        {
            "held_pitch": float(pitch),  # type: ignore[arg-type]
            "click": separation(rows["snap_click"], rows["jump_click"]),
        }
        for pitch, rows in table.groupby("held_pitch", sort=True)
    ]
    ev = found.events
    snaps_ev, jumps_ev = ev[ev["kind"] == "snap"], ev[ev["kind"] == "jump"]
    snapping = table[table["snaps"] & table["snap_event"].ne("")]
    torque = {
        "before_snap": _stats(snaps_ev["torque_before"]),
        "after_snap": _stats(snaps_ev["torque_after"]),
        "change_at_snap": _stats(snaps_ev["torque_after"] - snaps_ev["torque_before"]),
        "before_jump": _stats(jumps_ev["torque_before"]),
        "after_jump": _stats(jumps_ev["torque_after"]),
        "change_at_jump": _stats(jumps_ev["torque_after"] - jumps_ev["torque_before"]),
        "peak_to_snap": _stats(snapping["torque_peak"]),
    }
    notes = []
    in_phase_jumps = jumps_ev[jumps_ev["landing"] == "in-phase"]
    if len(in_phase_jumps):
        notes.append(
            f"{len(in_phase_jumps)} of the {len(jumps_ev)} non-snap jumps land in phase but "
            "jam when screwed in (not a snap): a controller that takes them for the snap "
            "tightens a bolt that is not in the thread"
        )
    already = int((table["snaps"] & table["snap_event"].eq("")).sum())
    if already:
        notes.append(
            f"{already} start(s) reach the thread with no snap (in it from the start, or "
            "turned into it without a jump): no click; they count as caught but not as "
            "snaps to detect"
        )
    fall = found.branch_fall
    if math.isfinite(fall) and signals["click"].smallest_snap is not None:
        notes.append(
            f"along the continuous branches the compliance centre falls at most {fall:.3g} "
            f"{found.units} per degree of turn on average between the library's states "
            f"(the smallest snap click is {signals['click'].smallest_snap:.3g} "
            f"{found.units}); the library does not resolve a branch's steepest degree"
        )
    return SnapDetection(
        found.units,
        found.compliance,
        found.starts,
        len(table),
        int(np.isfinite(table["snap_click"].astype(float)).sum()),
        int((table["jumps"] > 0).sum()),
        signals,
        by_pitch,
        torque,
        ev,
        table,
        _opt(fall),
        notes,
    )


def _torque_line(name: str, s: dict[str, Any]) -> str:
    if not s["count"]:
        return f"| {name} | 0 | - | - | - |"
    return (
        f"| {name} | {s['count']} | {number_text(s['min'], '.4g')} | "
        f"{number_text(s['median'], '.4g')} | {number_text(s['max'], '.4g')} |"
    )


def format_snap_detection(det: SnapDetection) -> str:
    """The detection as Markdown: the statements, the table per held pitch, the torque."""
    u = det.units
    c = det.compliance
    lines = [
        f"Compliance: {c['force']:g} N, {c['stiffness']['roll']:g}/"
        f"{c['stiffness']['pitch']:g} N m/rad. Searches judged: {det.searches} (the starts "
        f"at rest, of {det.starts}); {det.snaps} snap with a click, {det.with_jumps} have "
        "at least one other jump.",
        "",
        *(f"- {s.statement(u)}." for s in det.signals.values()),
        "",
        f"| held pitch deg | searches | snaps | smallest snap click {u} | largest other "
        f"jump {u} | threshold {u} | separates | wrong |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in det.by_held_pitch:
        s = r["click"]
        lines.append(
            f"| {r['held_pitch']:+g} | {s.searches} | {s.snaps} | "
            f"{number_text(s.smallest_snap, '.4g')} | {number_text(s.largest_jump, '.4g')} | "
            f"{number_text(s.threshold, '.4g')} | {'yes' if s.separates else 'no'} | "
            f"{s.wrong} |"
        )
    lines += [
        "",
        "Driver torque (N m) across the snap and the other jumps (distinct transitions):",
        "",
        "| torque | count | min | median | max |",
        "|---|---|---|---|---|",
    ]
    names = {
        "before_snap": "before the snap",
        "after_snap": "after the snap",
        "change_at_snap": "change at the snap",
        "before_jump": "before another jump",
        "after_jump": "after another jump",
        "change_at_jump": "change at another jump",
        "peak_to_snap": "peak up to the snap (per search)",
    }
    lines += [_torque_line(names[k], v) for k, v in det.torque.items()]
    lines += [f"\nNote: {n}." for n in det.notes]
    return "\n".join(lines) + "\n"


def plot_snap_detection(
    detections: SnapDetection | list[SnapDetection],
    path: str | os.PathLike[str],
    labels: list[str] | None = None,
) -> Path:
    """Strips of the snap clicks and each search's largest other jump, one row of axes per
    compliance, with the threshold (solid where it separates, dashed where none does);
    ``labels`` (one per detection, e.g. the libraries' paths) head each row."""
    dets = [detections] if isinstance(detections, SnapDetection) else list(detections)
    if labels is not None and len(labels) != len(dets):
        raise ValueError("give one label per detection")
    fig = new_figure((7.5, 1.0 + 2.2 * len(dets)))
    axes = fig.subplots(len(dets), 1, squeeze=False)[:, 0]
    rng = np.random.default_rng(0)
    for i, (ax, det) in enumerate(zip(axes, dets, strict=True)):
        t = det.searches_table
        u = det.units
        for y, column, colour, label in (
            (1.0, "snap_click", "tab:red", "snap click"),
            (0.0, "jump_click", "tab:blue", "largest other jump"),
        ):
            v = t[column].astype(float).to_numpy()
            v = v[np.isfinite(v)]
            ax.scatter(
                v,
                y + rng.uniform(-0.25, 0.25, v.size),
                s=12,
                alpha=0.6,
                color=colour,
                label=f"{label} ({v.size} searches)",
            )
        s = det.click
        if s.threshold is not None:
            ax.axvline(
                s.threshold,
                color="k",
                ls="-" if s.separates else "--",
                lw=1.2,
                label=f"threshold {s.threshold:.4g} {u}"
                + ("" if s.separates else f" (best; {s.wrong} wrong)"),
            )
            lo, hi = ax.get_xlim()
            pad = 0.03 * (max(hi, s.threshold) - min(lo, s.threshold))
            ax.set_xlim(min(lo, 0.0, s.threshold - pad), max(hi, s.threshold + pad))
        c = det.compliance
        ax.set_title(
            (f"{labels[i]}: " if labels else "")
            + f"F {c['force']:g} N, k {c['stiffness']['roll']:g}/{c['stiffness']['pitch']:g} "
            "N m/rad: " + ("separated" if s.separates else "no threshold separates"),
            fontsize=9,
        )
        ax.set_yticks([0, 1], ["other jumps\n(largest per search)", "snaps"])
        ax.set_ylim(-0.6, 1.6)
        ax.set_xlabel(f"fall of the compliance centre a sensor sees ({u})")
        ax.legend(fontsize=7, loc="best")
    return save_figure(fig, path)
