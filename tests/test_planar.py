"""The planar analysis (the thesis's chapter 2) against an independent brute force.

Everything the tests compare with is computed here from conventions.md directly: the
profile formula (sharp, clamped, with fillet arcs tangent to flank and flat derived
below), the outlines of the flush bolt and nut in F, a dense crossing search refined by
bisection, and closed forms for the in-phase window and the line contact at its edge.
"""

from __future__ import annotations

import dataclasses
import math
import xml.etree.ElementTree as ET
from functools import lru_cache

import numpy as np
import pytest

from threadmate import InputError
from threadmate.geometry import BOLT_REGIONS, NUT_REGIONS, BoltSpec, NutSpec, ThreadSpec
from threadmate.planar import (
    critical_phases,
    in_phase_window,
    phase_sweep,
    planar_state,
    plot_pivot_axes,
    plot_region_disk,
)

SQ3 = math.sqrt(3.0)
TWO_PI = 2.0 * math.pi


# -- independent geometry ----------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class Body:
    """One body's profile written out from conventions.md (no threadmate code)."""

    kind: str
    p: float
    pd: float
    major: float
    minor: float
    rho_hi: float  # fillet at the major-diameter corner (bolt crest, nut root)
    rho_lo: float  # fillet at the minor-diameter corner (bolt root, nut crest)

    @property
    def corners(self):
        """Flat radii and the fillet circles: a circle of radius rho tangent to the flat
        r = r_hi (centre rho below it) and to the flank sqrt3 u + R = K (centre at distance
        rho on the material side) has its centre at u_c = (K - 2 rho - r_c) / sqrt3; it
        touches the flat at u_c and the flank at u_c + rho sqrt3 / 2. Mirrored for the low
        corner."""
        k = self.pd / 2 + SQ3 * self.p / 4
        r_hi = min(self.major / 2, k)
        r_lo = max(self.minor / 2, self.pd / 2 - SQ3 * self.p / 4)
        rc_hi = r_hi - self.rho_hi
        uc_hi = (k - 2 * self.rho_hi - rc_hi) / SQ3
        rc_lo = r_lo + self.rho_lo
        uc_lo = (k + 2 * self.rho_lo - rc_lo) / SQ3
        b = (uc_hi, uc_hi + self.rho_hi * SQ3 / 2, uc_lo - self.rho_lo * SQ3 / 2, uc_lo)
        return r_hi, r_lo, (uc_hi, rc_hi), (uc_lo, rc_lo), b

    def radius(self, t):
        t = (np.asarray(t, float) + self.p / 2) % self.p - self.p / 2
        u = np.abs(t)
        r_hi, r_lo, (uh, rh), (ul, rl), (b1, b2, b3, b4) = self.corners
        r = np.clip(self.pd / 2 + SQ3 * (self.p / 4 - u), r_lo, r_hi)
        hi = (u > b1) & (u < b2)
        lo = (u > b3) & (u < b4)
        r = np.where(hi, rh + np.sqrt(np.clip(self.rho_hi**2 - (u - uh) ** 2, 0, None)), r)
        r = np.where(lo, rl - np.sqrt(np.clip(self.rho_lo**2 - (u - ul) ** 2, 0, None)), r)
        return r

    def region(self, t: float) -> str:
        t = (t + self.p / 2) % self.p - self.p / 2
        u = abs(t)
        *_, (b1, b2, b3, b4) = self.corners
        names = (
            ("crest", "CF", "F", "RF", "root")
            if self.kind == "bolt"
            else ("root", "RF", "F", "CF", "crest")
        )
        kind = names[int(np.searchsorted([b1, b2, b3, b4], u, side="left"))]
        return kind if kind in ("crest", "root") else ("+" if t < 0 else "-") + kind


class Pair:
    """The flush outlines in F: bolt at F-angle theta has bolt-frame angle theta - phase."""

    def __init__(self, spec: ThreadSpec):
        b, n = spec.bolt, spec.nut
        self.bolt = Body(
            "bolt", spec.pitch, b.pitch_diameter, b.major, b.minor, b.crest_fillet, b.root_fillet
        )
        self.nut = Body(
            "nut", spec.pitch, n.pitch_diameter, n.major, n.minor, n.root_fillet, n.crest_fillet
        )
        self.k = (1 if spec.hand == "right" else -1) * spec.pitch * spec.starts

    def t_bolt(self, theta, phase):
        return -self.k * (np.asarray(theta) - math.radians(phase)) / TWO_PI

    def t_nut(self, theta):
        return -self.k * np.asarray(theta) / TWO_PI

    def d(self, theta, phase):
        return self.bolt.radius(self.t_bolt(theta, phase)) - self.nut.radius(self.t_nut(theta))


@lru_cache(maxsize=8192)
def brute(spec: ThreadSpec, phase: float, n: int = 1 << 15):
    """Crossings by dense sampling and bisection: [(theta_rad, kind)], kind +1 where going
    counter-clockwise the bolt's outline passes from inside to outside the nut's."""
    pair = Pair(spec)
    th = np.linspace(0.0, TWO_PI, n, endpoint=False)
    d = pair.d(th, phase)
    i = np.flatnonzero((d <= 0) != (np.roll(d, -1) <= 0))
    lo, hi = th[i], th[i] + TWO_PI / n
    d_lo = d[i]
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        dm = pair.d(mid, phase)
        same = (dm <= 0) == (d_lo <= 0)
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    roots = 0.5 * (lo + hi) % TWO_PI
    kinds = np.where(d_lo <= 0, 1, -1)
    order = np.argsort(roots)
    return [(float(roots[j]), int(kinds[j])) for j in order]


def brute_arcs(spec, phase):
    """[(theta1, theta2)] in radians: each arc of overlap from its start to its end."""
    xs = brute(spec, phase)
    starts = [t for t, k in xs if k > 0]
    ends = [t for t, k in xs if k < 0]
    arcs = []
    for s in starts:
        e = min(ends, key=lambda e: (e - s) % TWO_PI)
        arcs.append((s, e))
    return arcs


def brute_labels(spec, phase):
    """(bolt, nut) regions at contact 1 and contact 2 of the arc whose start has the least
    angle; (None, None) without contacts."""
    arcs = brute_arcs(spec, phase)
    if not arcs:
        return (None, None)
    pair = Pair(spec)
    s, e = min(arcs)
    return tuple(
        (pair.bolt.region(float(pair.t_bolt(t, phase))), pair.nut.region(float(pair.t_nut(t))))
        for t in (s, e)
    )


def ang_diff(a_deg, b_deg):
    return abs((a_deg - b_deg + 180.0) % 360.0 - 180.0)


# -- specs -------------------------------------------------------------------------------


def _fillet_mm(**kw) -> ThreadSpec:
    return ThreadSpec(
        units="mm",
        pitch=1.0,
        bolt=BoltSpec(
            major=5.884, pitch_diameter=5.268, minor=4.77, crest_fillet=0.06, root_fillet=0.144
        ),
        nut=NutSpec(
            major=6.1, pitch_diameter=5.425, minor=5.035, crest_fillet=0.07, root_fillet=0.05
        ),
        **kw,
    )


FILLETED = _fillet_mm()
FILLETED_LEFT = _fillet_mm(hand="left")
FILLETED_TWO_START = _fillet_mm(starts=2)
SHARP_THREE_START_LEFT = ThreadSpec(
    units="mm",
    pitch=1.5,
    bolt=BoltSpec(major=9.85, pitch_diameter=8.95, minor=8.2),
    nut=NutSpec(major=10.1, pitch_diameter=9.1, minor=8.5),
    hand="left",
    starts=3,
)
# Big fillets on all four corners: fillet arcs meet fillet arcs.
ROUND = ThreadSpec(
    units="in",
    pitch=0.05,
    bolt=BoltSpec(
        major=0.2440, pitch_diameter=0.2140, minor=0.1880, crest_fillet=0.006, root_fillet=0.0075
    ),
    nut=NutSpec(
        major=0.2520, pitch_diameter=0.2200, minor=0.2000, crest_fillet=0.006, root_fillet=0.004
    ),
)

# Shallow engagement with big crest fillets: the bolt's crest fillet meets the nut's crest
# fillet (arc against arc), and the window's edge is a tangency of two arcs, not a line.
SHALLOW = ThreadSpec(
    units="in",
    pitch=0.05,
    bolt=BoltSpec(
        major=0.236, pitch_diameter=0.214, minor=0.188, crest_fillet=0.01, root_fillet=0.004
    ),
    nut=NutSpec(
        major=0.252, pitch_diameter=0.220, minor=0.214, crest_fillet=0.014, root_fillet=0.004
    ),
)


@pytest.fixture(
    scope="module",
    params=[
        "sharp",
        "quarter",
        "filleted",
        "left",
        "two-start",
        "three-start-left",
        "round",
        "shallow",
    ],
)
def spec(request, sharp_quarter_20, quarter_20):
    return {
        "sharp": sharp_quarter_20,
        "quarter": quarter_20,
        "filleted": FILLETED,
        "left": FILLETED_LEFT,
        "two-start": FILLETED_TWO_START,
        "three-start-left": SHARP_THREE_START_LEFT,
        "round": ROUND,
        "shallow": SHALLOW,
    }[request.param]


PHASES = [float(p) for p in np.arange(3.7, 360.0, 11.3)]


# -- contact points ------------------------------------------------------------------------


def test_contacts_match_brute_force_crossings(spec):
    pair = Pair(spec)
    for phase in PHASES:
        state = planar_state(spec, phase)
        arcs = brute_arcs(spec, phase)
        assert state.in_phase == (not arcs), phase
        assert len(state.contacts) == 2 * len(arcs), phase
        got = sorted((c.theta, i % 2) for i, c in enumerate(state.contacts))
        want = sorted(
            [(math.degrees(s), 0) for s, _ in arcs] + [(math.degrees(e), 1) for _, e in arcs]
        )
        for (g, gk), (w, wk) in zip(got, want, strict=True):
            assert ang_diff(g, w) < 1e-8 and gk == wk, (phase, got, want)
        for c in state.contacts:
            th = math.radians(c.theta)
            r = float(pair.nut.radius(pair.t_nut(th)))
            assert c.radius == pytest.approx(r, abs=1e-12)
            assert c.x == pytest.approx(r * math.cos(th), abs=1e-9 * r)
            assert c.y == pytest.approx(r * math.sin(th), abs=1e-9 * r)
            # Regions read independently at the crossing (no phase here sits on a boundary).
            assert c.bolt_region == pair.bolt.region(float(pair.t_bolt(th, phase)))
            assert c.nut_region == pair.nut.region(float(pair.t_nut(th)))
            assert c.bolt_region in BOLT_REGIONS and c.nut_region in NUT_REGIONS


def test_contact_angle_and_pivot_axis_match_brute_force(spec):
    for phase in PHASES[::2]:
        state = planar_state(spec, phase)
        arcs = brute_arcs(spec, phase)
        span = sum(math.degrees((e - s) % TWO_PI) for s, e in arcs)
        assert state.contact_angle == pytest.approx(span, abs=1e-7)
        # The fraction of dense samples where the bolt's outline is outside agrees too.
        th = np.linspace(0.0, TWO_PI, 1 << 15, endpoint=False)
        frac = 360.0 * np.mean(Pair(spec).d(th, phase) > 0)
        assert state.contact_angle == pytest.approx(frac, abs=0.05)
        if not arcs:
            assert state.pivot_axis is None and state.pivot_axis_length == 0.0
            continue
        s, e = min(arcs)
        pair = Pair(spec)
        pts = [
            float(pair.nut.radius(pair.t_nut(t))) * np.array([math.cos(t), math.sin(t)])
            for t in (s, e)
        ]
        assert state.pivot_axis_length == pytest.approx(np.linalg.norm(pts[1] - pts[0]), abs=1e-9)
        np.testing.assert_allclose(state.pivot_axis, pts, atol=1e-9)


def test_normals(quarter_20):
    pair = Pair(quarter_20)
    for phase in (30.0, 75.0, 200.0, 300.0):
        for i, c in enumerate(planar_state(quarter_20, phase).contacts):
            assert c.normal == (0.0, 0.0, 1.0)
            th = math.radians(c.theta)
            h = 1e-7
            for n, f in (
                (c.bolt_outline_normal, lambda t, ph=phase: pair.bolt.radius(pair.t_bolt(t, ph))),
                (c.nut_outline_normal, lambda t: pair.nut.radius(pair.t_nut(t))),
            ):
                # The outline's tangent, by central differences of the polar curve.
                side = 1.0 if i % 2 == 0 else -1.0
                t0, t1 = th + side * h, th + side * 2 * h
                p0 = float(f(t0)) * np.array([math.cos(t0), math.sin(t0)])
                p1 = float(f(t1)) * np.array([math.cos(t1), math.sin(t1)])
                tangent = (p1 - p0) / np.linalg.norm(p1 - p0)
                assert math.hypot(*n) == pytest.approx(1.0, abs=1e-12)
                assert abs(np.dot(n, tangent)) < 1e-5
                assert np.dot(n, [math.cos(th), math.sin(th)]) > 0  # away from the axis
            # The thesis's common normal: cross product of the two rims' tangents.
            tb = np.array([-c.bolt_outline_normal[1], c.bolt_outline_normal[0], 0.0])
            tn = np.array([-c.nut_outline_normal[1], c.nut_outline_normal[0], 0.0])
            cross = np.cross(tb, tn)
            assert np.allclose(cross[:2], 0.0) and abs(cross[2]) > 1e-6


def test_in_phase_state(sharp_quarter_20):
    state = planar_state(sharp_quarter_20, 0.0)
    assert state.in_phase and state.contacts == () and state.contact_angle == 0.0
    assert state.pivot_axis_length == 0.0 and state.pivot_axis is None
    assert not state.line_contact


def test_phase_is_taken_modulo_360(quarter_20):
    a, b, c = (planar_state(quarter_20, p) for p in (30.0, 390.0, -330.0))
    assert a.phase == b.phase == pytest.approx(30.0) and c.phase == pytest.approx(30.0)
    for x, y in zip(a.contacts, c.contacts, strict=True):
        assert ang_diff(x.theta, y.theta) < 1e-9
    for bad in (math.nan, math.inf, -math.inf, "thirty"):
        with pytest.raises(InputError):
            planar_state(quarter_20, bad)


def test_default_example_phase_shows_two_contacts(quarter_20):
    state = planar_state(quarter_20, 30.0)
    assert not state.in_phase and len(state.contacts) == 2
    assert 0.0 < state.contact_angle < 360.0 and state.pivot_axis_length > 0.0


def test_phase_sweep_is_planar_state_at_each_phase():
    phases = [0.0, 45.0, 123.4]
    for s, p in zip(phase_sweep(FILLETED, phases), phases, strict=True):
        assert s == planar_state(FILLETED, p)


# -- in-phase window -----------------------------------------------------------------------


def _closed_form_half_width(spec):
    clearance = (spec.nut.pitch_diameter - spec.bolt.pitch_diameter) / SQ3
    return 360.0 * clearance / (2.0 * spec.pitch * spec.starts)


@pytest.mark.parametrize("which", ["sharp", "two-start-left", "three-start"])
def test_window_closed_form_for_sharp_flanks(which, sharp_quarter_20):
    spec = {
        "sharp": sharp_quarter_20,
        "two-start-left": dataclasses.replace(sharp_quarter_20, starts=2, hand="left"),
        "three-start": SHARP_THREE_START_LEFT,
    }[which]
    half = _closed_form_half_width(spec)
    window = in_phase_window(spec)
    assert len(window) == spec.starts
    assert [a for a, _ in window] == sorted(a for a, _ in window)
    hit = set()
    for a, b in window:
        assert a < b and -180.0 <= a < 180.0
        assert (b - a) / 2 == pytest.approx(half, abs=1e-9)
        # Centred on 0 and repeated every 360 / starts degrees.
        k = [k for k in range(spec.starts) if ang_diff((a + b) / 2, k * 360.0 / spec.starts) < 1e-9]
        assert len(k) == 1
        hit.add(k[0])
    assert hit == set(range(spec.starts))


def test_window_half_width_of_quarter_20(sharp_quarter_20):
    # 1/4-20 UNC-2A/2B mean PDs: 360 x (0.21995 - 0.21455)/sqrt3 / (2 x 0.05) = 11.2237 deg
    ((a, b),) = in_phase_window(sharp_quarter_20)
    assert b == pytest.approx(360 * (0.21995 - 0.21455) / SQ3 / 0.1, abs=1e-9)
    assert a == pytest.approx(-b, abs=1e-9)


def _brute_window_edge(spec):
    """Bisect the phase at which the sampled max of bolt-minus-nut radius reaches 0."""
    th = np.linspace(0.0, TWO_PI, 1 << 16, endpoint=False)
    pair = Pair(spec)
    lo, hi = 0.0, 90.0 / spec.starts
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        if np.max(pair.d(th, mid)) > 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("which", ["filleted", "round", "two-start", "shallow"])
def test_window_with_fillets_matches_brute_force(which):
    spec = {
        "filleted": FILLETED,
        "round": ROUND,
        "two-start": FILLETED_TWO_START,
        "shallow": SHALLOW,
    }[which]
    edge = _brute_window_edge(spec)
    window = in_phase_window(spec)
    a, b = window[0]
    assert b == pytest.approx(edge, abs=2e-4) and a == pytest.approx(-edge, abs=2e-4)
    # Inside the window: no contact; just outside: two contacts per start.
    assert planar_state(spec, b - 1e-4).in_phase
    outside = planar_state(spec, b + 1e-4)
    assert not outside.in_phase and len(outside.contacts) == 2 * spec.starts


def test_line_contact_at_the_window_edge(sharp_quarter_20):
    spec = sharp_quarter_20
    p = spec.pitch
    edge = _closed_form_half_width(spec)
    state = planar_state(spec, edge)
    assert state.in_phase and state.line_contact and len(state.contacts) == 2
    # Closed form: at sigma = clearance / 2 the two "+" flanks coincide where both bodies
    # are on their flanks: nut t in [-u_lo_n, -u_hi_n], bolt t = tau + sigma likewise.
    sigma = p * edge / 360.0

    def flank_u(pd, r):
        return p / 4 + (pd / 2 - r) / SQ3

    b, n = spec.bolt, spec.nut
    u_hi_b, u_lo_b = flank_u(b.pitch_diameter, b.major / 2), flank_u(b.pitch_diameter, b.minor / 2)
    u_hi_n, u_lo_n = flank_u(n.pitch_diameter, n.major / 2), flank_u(n.pitch_diameter, n.minor / 2)
    tau_lo = max(-u_lo_n, -u_lo_b - sigma)
    tau_hi = min(-u_hi_n, -u_hi_b - sigma)
    # theta = -tau 360 / p: contact 1 (counter-clockwise start) is the larger tau.
    th1, th2 = -tau_hi * 360.0 / p, -tau_lo * 360.0 / p
    assert ang_diff(state.contacts[0].theta, th1) < 1e-8
    assert ang_diff(state.contacts[1].theta, th2) < 1e-8
    assert state.contact_angle == pytest.approx(th2 - th1, abs=1e-8)
    for c in state.contacts:
        assert (c.bolt_region, c.nut_region) == ("+F", "+F")
    # Just outside the edge the contacts have barely moved: the limit is this line contact.
    near = planar_state(spec, edge + 1e-7)
    assert not near.in_phase and not near.line_contact
    for x, y in zip(near.contacts, state.contacts, strict=True):
        assert ang_diff(x.theta, y.theta) < 1e-4


# -- critical phases -----------------------------------------------------------------------


def _brute_critical(spec, step=0.5):
    """Scan one turn for changes of each contact's regions, then split every step whose
    ends differ until each change is pinned to 1e-10 degrees (several changes within one
    step are all found, as long as their labels differ)."""
    grid = np.arange(0.0, 360.0 + step / 2, step)
    found = []

    def split(lo, hi, a, b, k):
        if hi - lo < 1e-10:
            found.append((0.5 * (lo + hi) % 360.0, k + 1, a, b))
            return
        mid = 0.5 * (lo + hi)
        m = brute_labels(spec, mid)[k]
        if m != a:
            split(lo, mid, a, m, k)
        if m != b:
            split(mid, hi, m, b, k)

    labels = [brute_labels(spec, float(p)) for p in grid]
    for i in range(len(grid) - 1):
        for k in (0, 1):
            if labels[i][k] != labels[i + 1][k]:
                split(float(grid[i]), float(grid[i + 1]), labels[i][k], labels[i + 1][k], k)
    return found


@pytest.mark.parametrize("which", ["sharp", "filleted", "round", "shallow"])
def test_critical_phases_match_brute_force(which, sharp_quarter_20):
    spec = {"sharp": sharp_quarter_20, "filleted": FILLETED, "round": ROUND, "shallow": SHALLOW}[
        which
    ]
    want = _brute_critical(spec)
    got = critical_phases(spec)
    assert len(got) == len(want), (got, want)
    for phase, contact, before, after in want:
        match = [c for c in got if c.contact == contact and ang_diff(c.phase, phase) < 1e-6]
        assert len(match) == 1, (phase, contact, got)
        assert match[0].before == before and match[0].after == after
        assert 0.0 <= match[0].phase < 360.0


def test_critical_phases_include_window_edges(sharp_quarter_20):
    ((a, b),) = in_phase_window(sharp_quarter_20)
    crit = critical_phases(sharp_quarter_20)
    opening = [c for c in crit if c.before is None]
    closing = [c for c in crit if c.after is None]
    assert {c.contact for c in opening} == {1, 2} == {c.contact for c in closing}
    assert all(ang_diff(c.phase, b) < 1e-9 for c in opening)
    assert all(ang_diff(c.phase, a) < 1e-9 for c in closing)


# -- figures -------------------------------------------------------------------------------


def test_figures_are_written(tmp_path, quarter_20):
    png = plot_region_disk(quarter_20, tmp_path / "disk.png", step=5.0)
    svg = plot_pivot_axes(quarter_20, tmp_path / "pivot.svg", phases=range(0, 360, 30))
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    root = ET.parse(svg).getroot()
    assert root.tag.endswith("svg")
    svg2 = plot_region_disk(FILLETED_TWO_START, tmp_path / "disk2.svg", step=10.0)
    png2 = plot_pivot_axes(FILLETED_LEFT, tmp_path / "pivot2.png", phases=[0, 30, 200])
    assert ET.parse(svg2).getroot().tag.endswith("svg")
    assert png2.read_bytes()[:4] == b"\x89PNG"
    # Only the figures: no temporary files left beside them.
    assert sorted(f.name for f in tmp_path.iterdir()) == sorted(
        ["disk.png", "pivot.svg", "disk2.svg", "pivot2.png"]
    )


def test_figure_suffix_is_checked_before_work(tmp_path, quarter_20):
    for name in ("disk.pdf", "disk", "disk.jpg"):
        with pytest.raises(InputError, match="must end in"):
            plot_region_disk(quarter_20, tmp_path / name)
        with pytest.raises(InputError, match="must end in"):
            plot_pivot_axes(quarter_20, tmp_path / name)
    with pytest.raises(InputError):
        plot_region_disk(quarter_20, tmp_path / "d.png", step=0.0)
    assert list(tmp_path.iterdir()) == []


def test_tangent_arcs_at_the_window_edge():
    # SHALLOW's window ends where two crest fillets touch at one point: both contacts
    # sit at that point, where the sampled excess of the bolt's radius peaks.
    ((a, b),) = in_phase_window(SHALLOW)
    state = planar_state(SHALLOW, b)
    assert state.in_phase and not state.line_contact and len(state.contacts) == 2
    c1, c2 = state.contacts
    assert c1.theta == c2.theta and state.pivot_axis_length == 0.0
    th = np.linspace(0.0, TWO_PI, 1 << 18, endpoint=False)
    d = Pair(SHALLOW).d(th, b)
    assert abs(d.max()) < 1e-9
    assert ang_diff(c1.theta, math.degrees(th[np.argmax(d)])) < 0.01
    assert (c1.bolt_region, c1.nut_region) == ("+CF", "+CF")
    # The sharp closed form does not hold here: the flanks never face each other.
    assert b > _closed_form_half_width(SHALLOW) + 0.1
