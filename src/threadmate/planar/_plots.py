"""Figures of one turn of phase: the thesis's Figures 2.6 and 2.9.

Both follow conventions.md: phase and angles are drawn from +X toward +Y (counter-clockwise
seen from +Z of F), lengths are in the spec's units. Figures are built on
:class:`matplotlib.figure.Figure` with the Agg canvas (no pyplot state), and written
atomically as PNG or SVG by the file's suffix.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Wedge

from .._angles import TWO_PI, wrap_phase
from .._errors import InputError
from .._figures import freeze_layout, new_figure, place_text, save_figure
from .._validate import FIGURE_FORMATS
from ..geometry import BOLT_REGIONS, NUT_REGIONS, nut_body
from ._analysis import critical_phases, in_phase_window, phase_sweep

if TYPE_CHECKING:
    from ..geometry import ThreadSpec

__all__ = ["FIGURE_SUFFIXES", "figure_format", "plot_pivot_axes", "plot_region_disk"]

#: File suffixes the planar figures may be written to (of :data:`FIGURE_FORMATS`), and their
#: matplotlib formats.
FIGURE_SUFFIXES = {s: FIGURE_FORMATS[s] for s in (".png", ".svg")}

#: One colour per region name; the positive side in blues, the negative side in oranges.
REGION_COLOURS = {
    "crest": "#f2c80f",
    "+CF": "#9ecae1",
    "+F": "#3182bd",
    "+RF": "#08306b",
    "root": "#74c476",
    "-RF": "#7f2704",
    "-F": "#e6550d",
    "-CF": "#fdae6b",
    "base": "#bcbddc",
    "surface": "#bcbddc",
}
IN_PHASE_COLOUR = "#1a1a1a"


def figure_format(path: str | os.PathLike[str]) -> str:
    """The matplotlib format for a figure path (``png`` or ``svg``), or :class:`InputError`."""
    suffix = Path(path).suffix.lower()
    if suffix not in FIGURE_SUFFIXES:
        raise InputError(
            f"figure file {os.fspath(path)!r} must end in "
            f"{' or '.join(FIGURE_SUFFIXES)} (got {suffix or 'no suffix'!r})"
        )
    return FIGURE_SUFFIXES[suffix]


def _spec_name(spec: ThreadSpec) -> str:
    if spec.designation:
        return spec.designation
    hand = "" if spec.hand == "right" else ", left hand"
    starts = "" if spec.starts == 1 else f", {spec.starts} starts"
    return (
        f"pitch {spec.pitch:g} {spec.units}, bolt PD {spec.bolt.pitch_diameter:g}, "
        f"nut PD {spec.nut.pitch_diameter:g} {spec.units}{hand}{starts}"
    )


def _runs(spec: ThreadSpec, step: float) -> list[tuple[float, float, tuple]]:
    """``(start, end, labels)`` over one turn of phase, where ``labels`` holds the
    ``(bolt, nut)`` regions of contacts 1 and 2 (None in phase). Boundaries are the exact
    critical phases and window edges; ``step`` adds a grid so nothing is skipped."""
    marks = {0.0, 360.0}
    marks |= {float(c.phase) for c in critical_phases(spec)}
    for a, b in in_phase_window(spec):
        marks |= {wrap_phase(a), wrap_phase(b)}
    marks |= set(np.arange(0.0, 360.0, step).tolist())
    edges = sorted(m for m in marks if 0.0 <= m <= 360.0)
    edges = [e for i, e in enumerate(edges) if i == 0 or e - edges[i - 1] > 1e-9]
    mids = [0.5 * (a + b) for a, b in zip(edges[:-1], edges[1:], strict=True)]
    runs: list[tuple[float, float, tuple]] = []
    for a, b, state in zip(edges[:-1], edges[1:], phase_sweep(spec, mids), strict=True):
        if state.in_phase or not state.contacts:
            labels: tuple = (None, None)
        else:
            c1, c2 = state.contacts[0], state.contacts[1]
            labels = ((c1.bolt_region, c1.nut_region), (c2.bolt_region, c2.nut_region))
        if runs and runs[-1][2] == labels:
            runs[-1] = (runs[-1][0], b, labels)
        else:
            runs.append((a, b, labels))
    return runs


def plot_region_disk(spec: ThreadSpec, path: str | os.PathLike[str], step: float = 1.0) -> Path:
    """Draw the contact-region combination disk (the thesis's Figure 2.6).

    For one turn of phase, drawn as the angle from +X counter-clockwise, the outer annulus
    shows the nut's region in contact and the inner disk the bolt's, each as two rings:
    contact 1 outside, contact 2 inside. The in-phase window is dark. Region boundaries
    are the exact critical phases; ``step`` (degrees) sets a grid of extra checks.

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair.
    path : path-like
        Output file, ``.png`` or ``.svg``.
    step : float
        Phase step in degrees for the grid of checks (default 1).

    Returns
    -------
    pathlib.Path
        The file written.
    """
    fmt = figure_format(path)
    if not (math.isfinite(step) and 0.0 < step <= 90.0):
        raise InputError(f"region-disk step must be within (0, 90] degrees, got {step!r}")
    runs = _runs(spec, step)
    fig = new_figure((10.0, 7.0))
    ax = fig.add_subplot()
    # ring (outer radius, width) per (body, contact): nut outside, bolt inside.
    rings = {
        ("nut", 0): (1.00, 0.15),
        ("nut", 1): (0.85, 0.15),
        ("bolt", 0): (0.64, 0.15),
        ("bolt", 1): (0.49, 0.15),
    }
    for a, b, labels in runs:
        for (body, k), (r, w) in rings.items():
            if labels[k] is None:
                colour = IN_PHASE_COLOUR
            else:
                colour = REGION_COLOURS[labels[k][0 if body == "bolt" else 1]]
            ax.add_patch(
                Wedge(
                    (0.0, 0.0), r, a, b, width=w, facecolor=colour, edgecolor=colour, linewidth=0.3
                )
            )
    for crit in critical_phases(spec):
        th = math.radians(crit.phase)
        ax.plot(
            [0.34 * math.cos(th), 1.0 * math.cos(th)],
            [0.34 * math.sin(th), 1.0 * math.sin(th)],
            color="white",
            lw=0.6,
        )
    for deg in range(0, 360, 30):
        th = math.radians(deg)
        ax.plot(
            [1.0 * math.cos(th), 1.04 * math.cos(th)],
            [1.0 * math.sin(th), 1.04 * math.sin(th)],
            color="black",
            lw=0.8,
        )
        ax.text(
            1.11 * math.cos(th),
            1.11 * math.sin(th),
            f"{deg}°",
            ha="center",
            va="center",
            fontsize=9,
        )
    ax.annotate(
        "",
        xy=(1.2 * math.cos(0.35), 1.2 * math.sin(0.35)),
        xytext=(1.2 * math.cos(0.08), 1.2 * math.sin(0.08)),
        arrowprops={"arrowstyle": "->", "connectionstyle": "arc3,rad=0.17"},
    )
    ax.text(
        1.22 * math.cos(0.2),
        1.22 * math.sin(0.2),
        " phase",
        fontsize=8,
        ha="left",
        va="center",
        rotation=78,
    )
    ax.text(
        0.0,
        0.0,
        "outer: nut\ninner: bolt\n(contact 1 outside,\ncontact 2 inside)",
        ha="center",
        va="center",
        fontsize=7.5,
    )
    ax.set_xlim(-1.3, 1.3)
    ax.set_ylim(-1.3, 1.3)
    ax.set_aspect("equal")
    ax.axis("off")
    names = list(dict.fromkeys(BOLT_REGIONS[:-1] + NUT_REGIONS[:-1]))
    handles = [Patch(facecolor=REGION_COLOURS[n], label=n) for n in names]
    handles.append(
        Patch(
            facecolor=REGION_COLOURS["base"],
            label=f"{BOLT_REGIONS[-1]} (bolt) / {NUT_REGIONS[-1]} (nut)",
        )
    )
    handles.append(Patch(facecolor=IN_PHASE_COLOUR, label="in phase (no contact)"))
    fig.legend(
        handles=handles,
        title="region in contact",
        loc="outside right center",
        frameon=False,
        fontsize=9,
    )
    fig.suptitle(f"Contact-region combination disk: {_spec_name(spec)}", fontsize=11)
    ax.set_title(
        f"bolt flush on nut; phase in degrees from +X, counter-clockwise seen from "
        f"+Z (lengths in {spec.units})",
        fontsize=8.5,
    )
    return save_figure(fig, path, fmt)


def plot_pivot_axes(
    spec: ThreadSpec, path: str | os.PathLike[str], phases: Iterable[float] = range(0, 360, 15)
) -> Path:
    """Draw the pivot axis against phase (the thesis's Figure 2.9).

    The nut's top outline in F and, for each phase that is not in phase, the pivot-axis
    segment between its two contact points, with the phase (degrees) written at both
    ends (a thread of ``n`` starts shows its ``n`` symmetric segments). Axes are equal and
    in the spec's units.

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair.
    path : path-like
        Output file, ``.png`` or ``.svg``.
    phases : iterable of float
        Phases in degrees (default every 15 degrees).

    Returns
    -------
    pathlib.Path
        The file written.
    """
    fmt = figure_format(path)
    return save_figure(pivot_axes_figure(spec, phases), path, fmt)


def pivot_axes_figure(spec: ThreadSpec, phases: Iterable[float] = range(0, 360, 15)) -> Figure:
    """The figure :func:`plot_pivot_axes` writes, laid out (its labels placed)."""
    phases = [float(p) for p in phases]
    states = phase_sweep(spec, phases)
    fig = new_figure((8.0, 8.0))
    ax = fig.add_subplot()
    theta = np.linspace(0.0, TWO_PI, 3601)
    r = nut_body(spec).section_radius(theta, 0.0)
    ax.plot(r * np.cos(theta), r * np.sin(theta), color="0.35", lw=1.0)
    ax.plot([0.0], [0.0], marker="+", color="0.35")
    cmap = colormaps["viridis"]
    r_out = float(np.max(r))
    skipped = []
    # Label ends: one label per point, naming every phase whose axis ends there.
    ends_at: dict[tuple[float, float], list[tuple[str, tuple[float, float, float, float]]]] = {}
    for phase, state in zip(phases, states, strict=True):
        if state.pivot_axis is None or state.pivot_axis_length == 0.0:
            skipped.append(state.phase)
            continue
        colour = cmap(0.9 * state.phase / 360.0)
        # A thread of n starts rests on n arcs: draw each arc's axis (images of the first).
        ends = [(c.x, c.y) for c in state.contacts]
        for (x1, y1), (x2, y2) in zip(ends[0::2], ends[1::2], strict=True):
            ax.plot([x1, x2], [y1, y2], color=colour, lw=1.2, marker="o", ms=2.5)
        for x, y in ends:
            key = (round(x / r_out, 6), round(y / r_out, 6))  # ends of many phases coincide
            ends_at.setdefault(key, []).append((f"{wrap_phase(phase):g}°", colour))
    lim = r_out * 1.5
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.grid(True, lw=0.3)
    ax.set_xlabel(f"x ({spec.units})")
    ax.set_ylabel(f"y ({spec.units})")
    handles = [
        Line2D([], [], color="0.35", label="nut top outline (z = 0)"),
        Line2D(
            [],
            [],
            color=cmap(0.3),
            marker="o",
            ms=3,
            label="pivot axis (contact 1 to contact 2), ends labelled with phase",
        ),
    ]
    if skipped:
        shown = ", ".join(f"{p:g}°" for p in skipped[:8]) + (" ..." if len(skipped) > 8 else "")
        handles.append(Line2D([], [], color="none", label=f"in phase, no axis: {shown}"))
    legend = ax.legend(handles=handles, loc="upper right", fontsize=8)
    fig.suptitle(f"Pivot axis vs phase: {_spec_name(spec)}", fontsize=11)
    ax.set_title(
        "bolt flush on nut, frame F; angles from +X counter-clockwise seen from +Z", fontsize=8.5
    )
    # Labels last, on the final layout: each on the first spot outward from its point
    # where it overlaps no label placed before it (nor the legend).
    freeze_layout(fig)
    taken = [legend.get_window_extent()]
    for (kx, ky), named in sorted(ends_at.items(), key=lambda kv: math.atan2(kv[0][1], kv[0][0])):
        x, y = kx * r_out, ky * r_out
        rr = math.hypot(x, y) or 1.0
        ux, uy = x / rr, y / rr
        spots = [
            (x + d * ux - t * uy, y + d * uy + t * ux)
            for d in (r_out * (0.03 + 0.035 * k) for k in range(12))
            for t in (0.0, 0.04 * r_out, -0.04 * r_out)
        ]
        text = "/".join(name for name, _ in named)
        ink: Any = named[0][1] if len(named) == 1 else "0.2"  # several phases: neutral
        place_text(ax, spots, text, taken, outward=(ux, uy), color=ink, fontsize=7)
    return fig
