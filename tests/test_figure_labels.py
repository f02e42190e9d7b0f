"""Labels drawn over one another: the label placement of the search's figure (events along
the top of the axes) and of the pivot-axis chart (phases at the axes' ends), checked by
rendering and measuring every label's box (matplotlib ``get_window_extent``)."""

from __future__ import annotations

import itertools
import random

import numpy as np
import pytest
from scipy.optimize import minimize

# The shared label placement and the pivot-axes figure: internals with no public form.
from threadmate._figures import EventLabel, label_events, new_figure, spread
from threadmate.geometry import spec_from_designation
from threadmate.planar import phase_sweep
from threadmate.planar._plots import pivot_axes_figure  # an internal with no public form


def overlapping(texts, fig):
    """Pairs of texts whose drawn boxes intersect."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for t in texts]
    return [
        (texts[i].get_text(), texts[j].get_text())
        for i, j in itertools.combinations(range(len(texts)), 2)
        if boxes[i].overlaps(boxes[j])
    ]


# -- spread ---------------------------------------------------------------------------------
def test_spread_two_equal_intervals_move_apart_symmetrically():
    # Two intervals of width 2 wanted 0.5 apart: each moves 0.75 away from the other.
    assert spread([0.0, 0.5], [2.0, 2.0]) == pytest.approx([-0.75, 1.25])
    assert spread([5.0, 0.0], [1.0, 1.0], gap=1.0) == [5.0, 0.0]  # apart already: untouched


def test_spread_keeps_inside_the_bounds_when_it_fits():
    out = spread([0.0, 0.1], [1.0, 1.0], 0.5, lo=0.0, hi=10.0)
    assert out == pytest.approx([0.5, 2.0])  # pushed right of lo, 1.5 apart
    out = spread([10.0, 10.0], [3.0, 3.0], 0.0, lo=0.0, hi=10.0)
    assert out == pytest.approx([5.5, 8.5])


@pytest.mark.parametrize("seed", range(8))
def test_spread_is_the_least_squares_placement(seed):
    """No two intervals overlap, their order is kept, and the total squared shift is the
    constrained optimum that a general solver (SLSQP) finds."""
    rng = random.Random(seed)
    n = rng.randint(2, 7)
    centres = [rng.uniform(0, 10) for _ in range(n)]
    widths = [rng.uniform(0.5, 3) for _ in range(n)]
    gap = 0.2
    out = spread(centres, widths, gap)
    order = np.argsort(centres, kind="stable")
    for a, b in zip(order[:-1], order[1:], strict=True):
        assert out[b] - out[a] >= (widths[a] + widths[b]) / 2 + gap - 1e-9
    c = np.array(centres)
    cons = [
        {
            "type": "ineq",
            "fun": lambda x, a=a, b=b: x[b] - x[a] - (widths[a] + widths[b]) / 2 - gap,
        }
        for a, b in zip(order[:-1], order[1:], strict=True)
    ]
    best = minimize(lambda x: np.sum((x - c) ** 2), c, constraints=cons, method="SLSQP")
    assert np.sum((np.array(out) - c) ** 2) == pytest.approx(best.fun, rel=1e-5, abs=1e-8)


# -- events along the top of an axes ----------------------------------------------------------
def _axes(xmax=360.0, invert=False):
    fig = new_figure((8.0, 3.0))
    ax = fig.subplots()
    ax.plot([0.0, xmax], [0.0, 1.0])
    if invert:
        ax.invert_xaxis()
    return fig, ax


@pytest.mark.parametrize("invert", [False, True])
def test_event_labels_do_not_overlap(invert):
    """Events 3 degrees apart (the M10 search's 277 and 280 deg), a jump among them and a
    snap at the very end of the axis: drawn, no two labels' boxes meet and every label
    stays within the axes."""
    fig, ax = _axes(invert=invert)
    bold = {"fontweight": "bold", "color": "#d62728", "fontsize": "small"}
    events = [
        EventLabel(277.0, "contact-change"),
        EventLabel(280.0, "jump"),
        EventLabel(281.0, "contact-change"),
        EventLabel(283.0, "contact-change"),
        EventLabel(359.9, "snap: click 0.0112 in", bold),
        EventLabel(10.0, "contact-change"),
    ]
    texts = label_events(ax, events)
    assert overlapping(texts, fig) == []
    frame = ax.get_window_extent()
    for t in texts:
        box = t.get_window_extent()
        assert frame.x0 - 0.5 <= box.x0 and box.x1 <= frame.x1 + 0.5, t.get_text()


def test_crowded_flicker_becomes_one_label():
    """Twenty contact changes within one degree (a flicker) are one label that counts
    them; a lone event keeps its own label."""
    fig, ax = _axes()
    events = [EventLabel(100.0 + 0.05 * k, "contact-change") for k in range(20)]
    texts = label_events(ax, [*events, EventLabel(200.0, "jump")])
    assert sorted(t.get_text() for t in texts) == ["contact-change x 20", "jump"]
    assert overlapping(texts, fig) == []


def test_event_labels_hang_beside_their_events():
    """A label with room stays at its event: its box starts just right of the event's x."""
    fig, ax = _axes()
    (text,) = label_events(ax, [EventLabel(90.0, "snap")])
    fig.canvas.draw()
    x = ax.transData.transform((90.0, 0.0))[0]
    box = text.get_window_extent()
    assert 0.0 <= box.x0 - x <= 6.0


# -- the pivot-axis chart ---------------------------------------------------------------------
@pytest.mark.parametrize(
    "designation",
    [
        "1/4-20 UNC-2A/2B",
        "#10-32 UNF-2A/2B",
        "#10-24 UNC",
        "M10x1.5-6g/6H",
        "3/8-16 UNC-2A/2B",
        "1/2-13 UNC-2A/2B",
        "M6x1-6g/6H",
        "M8",
    ],
)
def test_pivot_axis_labels_do_not_overlap(designation):
    """Every phase with a pivot axis is named at both of its ends (ends that coincide share
    one label naming each of their phases), and no two labels' boxes meet."""
    spec = spec_from_designation(designation)
    phases = [float(p) for p in range(0, 360, 15)]
    fig = pivot_axes_figure(spec, phases)
    ax = fig.axes[0]
    texts = list(ax.texts)
    assert overlapping(texts, fig) == []
    named: dict[str, int] = {}
    for t in texts:
        for name in t.get_text().split("/"):
            named[name] = named.get(name, 0) + 1
    with_axis = [
        f"{p:g}°"
        for p, s in zip(phases, phase_sweep(spec, phases), strict=True)
        if s.pivot_axis is not None and s.pivot_axis_length > 0
    ]
    assert with_axis and named == {name: 2 for name in with_axis}


# -- the search's figure and text, on a search of known events ---------------------------------
def _search_run():
    """A search from phase 120 deg that turns on past 360: events 3 deg apart at 277 and
    280 deg (a contact change, then a jump), a flicker of contact changes at 397 deg, and
    the snap at 462.5 deg (102.5 deg, after a turn of 342.5 deg)."""
    from threadmate.contact import Compliance, MechanicalState, SearchEvent, SearchResult

    eye = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    states = tuple(
        MechanicalState(
            "rest",
            "quasi-stable",
            float(ph),
            1.0,
            -1.0,
            (0.0, 0.0, -0.03 - 1e-5 * k),
            eye,
            (0.0, 0.0, -0.03 - 1e-5 * k),
            (),
            -3.0,
            driver_torque=0.005,
        )
        for k, ph in enumerate(np.arange(120.0, 465.0, 5.0))
    )
    events = (
        SearchEvent(277.0, "contact-change", "a/b", "a/c"),
        SearchEvent(280.0, "jump", "a/c", "a/d", drop=0.001, tilt_change=0.5),
        *(SearchEvent(397.0 + 0.1 * k, "contact-change", "a/d", "a/e") for k in range(4)),
    )
    snap = SearchEvent(462.5, "snap", "a/e", "b/f", drop=0.0113, tilt_change=3.0, click=0.0113)
    return SearchResult(
        "in",
        1.0,
        -1.0,
        120.0,
        Compliance().to_dict(),
        states,
        (*events, snap),
        snap,
        1.0,
        1.0,
        0.5,
    )


def test_search_figure_labels_do_not_overlap(monkeypatch, tmp_path):
    # The module whose figure saving is patched: an internal, the place the figure is saved.
    import threadmate.contact.mechanics._figures
    from threadmate.contact import plot_search

    figures = []
    # The figure as it would be saved.
    monkeypatch.setattr(
        threadmate.contact.mechanics._figures,
        "save_figure",
        lambda fig, path, fmt=None: figures.append(fig),
    )
    spec = spec_from_designation("M10x1.5-6g/6H")
    plot_search(_search_run(), tmp_path / "s.png", spec=spec)
    (fig,) = figures
    texts = [t for t in fig.axes[0].texts if t.get_text()]  # (leader lines are empty texts)
    assert {t.get_text() for t in texts} == {
        "contact-change",
        "jump",
        "contact-change x 4",
        "snap: click 0.0113 in",
    }
    assert overlapping(texts, fig) == []
    # The title gives the snap's phase wrapped into [0, 360).
    assert "snap at 102.50 deg after 342.50 deg" in fig.get_suptitle()


def test_search_text_wraps_the_phase_and_says_the_turn():
    # The search's text as the command prints it: a CLI internal with no public form.
    from threadmate.cli._mechanics import _search_text

    text = _search_text(spec_from_designation("M10x1.5-6g/6H"), _search_run(), 5.0)
    assert "Snap: at phase 102.5000 deg after a turn of 342.5000 deg (0.95 turns)" in text
    rows = [line.split() for line in text.splitlines() if "contact-change" in line]
    # Events past 360 are printed wrapped, with the turn from the start beside them.
    assert ["277.0000", "157.0000", "contact-change"] == rows[0][:3]
    assert ["37.0000", "277.0000", "contact-change"] == rows[1][:3]
