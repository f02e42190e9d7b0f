"""Figure output shared by the stages: an Agg canvas (no display needed), an atomic save
that refuses an unwritable path with one clear message, label placement that keeps labels
from being drawn over one another, and the signature of a turn (height, tilt and torque
against phase) that a search, a screw-in and a network path share."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.text import Annotation, Text
from matplotlib.transforms import Bbox

from ._angles import Z_AXIS, axis_angle
from ._errors import InputError
from ._io import atomic_path

__all__ = [
    "DPI",
    "EventLabel",
    "Mark",
    "freeze_layout",
    "label_events",
    "new_figure",
    "place_text",
    "save_figure",
    "signature_figure",
    "spread",
]

#: Resolution of raster figures.
DPI = 150
#: Space kept between two labels (pixels at :data:`DPI`).
LABEL_GAP = 2.0


def new_figure(size: tuple[float, float]) -> Figure:
    """A figure of ``size`` inches on its own Agg canvas (pyplot's state is not touched)."""
    fig = Figure(figsize=size, layout="constrained", dpi=DPI)
    FigureCanvasAgg(fig)
    return fig


def save_figure(fig: Figure, path: str | os.PathLike[str], fmt: str | None = None) -> Path:
    """Write ``fig`` to ``path`` in format ``fmt`` (default: the path's suffix, PNG without
    one) atomically (temp file + rename)."""
    if fmt is None:
        fmt = Path(path).suffix.lstrip(".").lower() or "png"
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=fmt, dpi=DPI)
    except OSError as exc:
        raise InputError(
            f"cannot write figure {os.fspath(path)!r}: {exc.strerror or exc}"
        ) from None
    return Path(path)


def freeze_layout(fig: Figure) -> None:
    """Lay ``fig`` out once and keep the axes where they are, so that labels placed in
    display coordinates afterwards stay where they were placed when the figure is saved."""
    fig.draw_without_rendering()
    fig.set_layout_engine("none")


# -- labels --------------------------------------------------------------------------------
def spread(
    centres: Sequence[float],
    widths: Sequence[float],
    gap: float = 0.0,
    lo: float = -math.inf,
    hi: float = math.inf,
) -> list[float]:
    """Centres of intervals of ``widths`` as close to ``centres`` as they can be without
    overlapping (``gap`` apart) and, where they fit, within ``[lo, hi]``.

    The intervals keep the order of their centres; each run of intervals pushed together
    sits where it moves its members least (the mean of their wanted shifts), the least
    squares placement under the order constraint.
    """
    n = len(centres)
    order = sorted(range(n), key=lambda i: centres[i])
    # Blocks of intervals pushed together: (indices, offsets from the block's first centre).
    blocks: list[tuple[list[int], list[float]]] = []
    starts: list[float] = []

    def place(members: list[int], offsets: list[float]) -> float:
        s = sum(centres[i] - o for i, o in zip(members, offsets, strict=True)) / len(members)
        first, last = members[0], members[-1]
        span = offsets[-1] + widths[last] / 2 + widths[first] / 2
        if span <= hi - lo:  # keep the block inside the bounds when it fits
            s = min(max(s, lo + widths[first] / 2), hi - span + widths[first] / 2)
        return s

    for i in order:
        members, offsets = [i], [0.0]
        s = place(members, offsets)
        while blocks:
            prev_members, prev_offsets = blocks[-1]
            last = prev_members[-1]
            end = starts[-1] + prev_offsets[-1] + widths[last] / 2
            if end + gap <= s - widths[members[0]] / 2 + 1e-12:
                break
            shift = prev_offsets[-1] + widths[last] / 2 + gap + widths[members[0]] / 2
            members = prev_members + members
            offsets = prev_offsets + [shift + o for o in offsets]
            blocks.pop()
            starts.pop()
            s = place(members, offsets)
        blocks.append((members, offsets))
        starts.append(s)
    out = [0.0] * n
    for (members, offsets), s in zip(blocks, starts, strict=True):
        for i, o in zip(members, offsets, strict=True):
            out[i] = s + o
    return out


@dataclass(frozen=True)
class EventLabel:
    """A label for an event at ``x`` (data coordinates) along the top of an axes."""

    x: float
    text: str
    style: dict[str, Any] = field(default_factory=dict)


def label_events(ax: Axes, labels: Sequence[EventLabel], gap: float = LABEL_GAP) -> list[Text]:
    """Write ``labels`` upright (rotated 90 degrees) along the top of ``ax``, each hanging
    just right of its event's ``x``, none over another.

    Neighbouring labels of the same text whose events lie closer than a label's width
    become one label (``"text x n"``); the rest are spread sideways as little as needed
    (:func:`spread`, within the axes) and those moved are joined to their events by
    leader lines. Call it when everything else is drawn: it lays the figure out
    (:func:`freeze_layout`) to measure the labels. Returns the labels' text artists.
    """
    fig = ax.get_figure()
    assert isinstance(fig, Figure)
    freeze_layout(fig)
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    to_px = ax.transData.transform

    def px(x: float) -> float:
        return float(to_px((x, 0.0))[0])

    points = 72.0 / fig.dpi
    beside = 2.0  # pixels between an event's line and its label

    def make(x: float, text: str, style: dict[str, Any]) -> Annotation:
        return ax.annotate(
            text,
            (x, 1.0),
            xycoords=("data", "axes fraction"),
            xytext=(0.0, -4.0),
            textcoords="offset points",
            rotation=90,
            va="top",
            ha="center",
            annotation_clip=False,
            # Other events' lines may pass under a label: keep it legible over them.
            bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.85},
            zorder=5,
            **style,
        )

    # Merge runs of one text whose events crowd each other (left to right as drawn: an
    # axis may be inverted).
    items = sorted(labels, key=lambda e: px(e.x))
    merged: list[tuple[float, str, dict[str, Any], int]] = []
    for e in items:
        if merged and merged[-1][1] == e.text and merged[-1][2] == e.style:
            x0, text, style, count = merged[-1]
            probe = make(e.x, e.text, e.style)
            width = probe.get_window_extent(renderer).width
            probe.remove()
            if abs(px(e.x) - px(x0)) < width + gap:
                merged[-1] = (x0, text, style, count + 1)
                continue
        merged.append((e.x, e.text, e.style, 1))
    texts = [
        make(x, text if count == 1 else f"{text} x {count}", style)
        for x, text, style, count in merged
    ]
    if not texts:
        return []
    widths = [t.get_window_extent(renderer).width for t in texts]
    frame = ax.get_window_extent(renderer)
    anchors = [px(x) for x, *_ in merged]
    wanted = [a + beside + w / 2 for a, w in zip(anchors, widths, strict=True)]
    placed = spread(wanted, widths, gap, frame.x0, frame.x1)
    for t, anchor, want, at in zip(texts, anchors, wanted, placed, strict=True):
        if abs(at - want) < 0.5:
            t.xyann = ((at - anchor) * points, -4.0)
            continue
        t.xyann = ((at - anchor) * points, -14.0)
        colour = t.get_color()
        ax.annotate(
            "",
            t.xy,
            xycoords=("data", "axes fraction"),
            xytext=((at - anchor) * points, -14.0),
            textcoords="offset points",
            arrowprops={"arrowstyle": "-", "color": colour, "lw": 0.5, "shrinkA": 0, "shrinkB": 0},
            annotation_clip=False,
        )
    return list(texts)


def place_text(
    ax: Axes,
    candidates: Sequence[tuple[float, float]],
    text: str,
    taken: list[Bbox],
    gap: float = LABEL_GAP,
    outward: tuple[float, float] = (0.0, 0.0),
    **style: Any,
) -> Text:
    """Write ``text`` at the first of ``candidates`` (data coordinates) where its box keeps
    ``gap`` pixels clear of every box in ``taken`` (the last candidate when none does), and
    add its box to ``taken``.

    The box is centred on the candidate, or, with ``outward`` (a unit direction in data
    coordinates), moved along it until its edge touches the candidate (a label beside its
    point, not over it). The axes' limits and layout must be final (:func:`freeze_layout`):
    boxes are measured in display coordinates.
    """
    fig = ax.get_figure()
    assert isinstance(fig, Figure)
    renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    label = ax.text(0.0, 0.0, text, ha="center", va="center", **style)
    box = label.get_window_extent(renderer)
    w, h = box.width + 2 * gap, box.height + 2 * gap
    ux, uy = outward
    shift = abs(ux) * box.width / 2 + abs(uy) * box.height / 2
    to_data = ax.transData.inverted()
    centre = (0.0, 0.0)
    for x, y in candidates:
        cx, cy = ax.transData.transform((x, y))
        cx, cy = cx + shift * ux, cy + shift * uy
        centre = (float(cx), float(cy))
        trial = Bbox.from_bounds(cx - w / 2, cy - h / 2, w, h)
        if not any(trial.overlaps(b) for b in taken):
            break
    label.set_position(tuple(to_data.transform(centre)))
    taken.append(label.get_window_extent(renderer))
    return label


# -- the signature of a turn -----------------------------------------------------------------
@dataclass(frozen=True)
class Mark:
    """A vertical line across every panel of a signature figure at ``x``: an event (a
    jump, a contact change); ``bold`` for the one the figure is about (the snap)."""

    x: float
    bold: bool = False


def signature_figure(
    x: Sequence[float],
    height: Sequence[float],
    roll: Sequence[float],
    pitch: Sequence[float],
    torque: Sequence[float],
    *,
    units: str,
    xlabel: str,
    title: str,
    marks: Sequence[Mark] = (),
    labels: Sequence[EventLabel] = (),
    size: tuple[float, float] = (8.0, 8.0),
) -> Figure:
    """What a robot's sensors see along a turn of the bolt, one panel each: the height of
    the compliance centre (``units``), the tilt of the bolt axis from the nut's (degrees,
    from the states' ``roll`` and ``pitch``) and the driver's torque (N m) against ``x``
    (a phase, or the turn from a start), the events marked and labelled
    (:func:`label_events`). The one drawing of a search's, a screw-in's and a network
    path's signature. A turn that runs to smaller ``x`` (a clockwise turn) is drawn right
    to left, as time runs."""
    from .geometry import Pose

    xs = np.asarray(x, dtype=float)
    tilt = [
        axis_angle(Pose.from_angles(r, p, 0.0).axis, Z_AXIS)
        for r, p in zip(roll, pitch, strict=True)
    ]
    fig = new_figure(size)
    axes = fig.subplots(3, 1, sharex=True)
    series = (
        (height, f"compliance centre height ({units})"),
        (tilt, "tilt of the bolt axis (deg)"),
        (torque, "driver torque (N m)"),
    )
    for ax, (values, label) in zip(axes, series, strict=True):
        ax.plot(xs, np.asarray(values, dtype=float), ".-", color="#3182bd", lw=1.2, ms=3)
        ax.set_ylabel(label)
        ax.grid(True, color="0.9")
        for m in marks:
            ax.axvline(
                m.x,
                color="#d62728" if m.bold else "0.55",
                lw=2.0 if m.bold else 0.8,
                ls="-" if m.bold else "--",
                zorder=0,
            )
    axes[-1].set_xlabel(xlabel)
    if xs.size > 1 and xs[-1] < xs[0]:
        axes[-1].invert_xaxis()
    fig.suptitle(title, fontsize="medium")
    # Labels last: they are placed on the final layout, none over another.
    label_events(axes[0], labels)
    return fig
