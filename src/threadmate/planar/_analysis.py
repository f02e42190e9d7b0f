"""The thesis's chapter 2: the bolt flush on the nut at any phase.

The bolt stands on the nut with roll = pitch = 0 and its tip face in the nut's top plane
``z = 0`` of F, turned to ``phase`` degrees (counter-clockwise seen from +Z,
conventions.md). Its tip outline at the F-angle ``theta`` is the bolt's cross-section
radius at bolt-frame angle ``theta - phase`` (``R = Rz(phase)``), the nut's top outline the
nut's cross-section radius at ``theta``. Where the bolt's outline lies outside the nut's,
the bolt's tip rests on the nut's top face; the two points where the outlines cross are
the contact points, the arc between them the contact angle and the segment joining them
the pivot axis (the thesis's section 2.4-2.5). See :mod:`._crossings` for how the
crossings are found (closed form on flats and flanks, a bracketed root finder on fillets).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.optimize import brentq

from .._angles import TWO_PI, phase_difference, wrap_phase
from .._validate import check_phase
from ._crossings import SIDE_STEP, OutlinePair, Stretch, outline_pair, profile_inverse

if TYPE_CHECKING:
    from ..geometry import ThreadSpec

__all__ = [
    "CriticalPhase",
    "PlanarContact",
    "PlanarState",
    "critical_phases",
    "in_phase_window",
    "phase_sweep",
    "planar_state",
]

#: Phase step (degrees) either side of a critical phase at which its regions are read.
_CRITICAL_STEP = 1e-6

#: The common normal of two rims crossing in ``z = 0``: +Z of F, from the nut into the bolt.
_UP = (0.0, 0.0, 1.0)


@dataclass(frozen=True)
class PlanarContact:
    """One point where the bolt's tip outline crosses the nut's top outline.

    Attributes
    ----------
    theta : float
        Angle of the point in F, degrees from +X toward +Y, in ``[0, 360)``.
    x, y : float
        The point in F (its ``z`` is 0), in the spec's units.
    radius : float
        Its distance from the axis (both outlines' radius there).
    bolt_region, nut_region : str
        The regions in contact (conventions.md names). At a crossing that sits exactly on
        a region boundary (a critical phase, or the ends of a line contact) the region on
        the side of the overlap arc is reported.
    normal : tuple of 3 float
        The common normal of the two crossing rims (the thesis's section 3.11: the cross
        product of the rims' tangents). Both rims lie in the plane ``z = 0``, so it is
        ``(0, 0, 1)``: +Z of F, pointing from the nut into the bolt.
    bolt_outline_normal, nut_outline_normal : tuple of 2 float
        In-plane unit normals of each outline at the point, pointing away from the axis
        (out of the bolt's section; into the nut's material).
    """

    theta: float
    x: float
    y: float
    radius: float
    bolt_region: str
    nut_region: str
    normal: tuple[float, float, float]
    bolt_outline_normal: tuple[float, float]
    nut_outline_normal: tuple[float, float]

    def to_dict(self) -> dict[str, Any]:
        """The contact as plain JSON types."""
        return {
            "theta": self.theta,
            "x": self.x,
            "y": self.y,
            "radius": self.radius,
            "bolt_region": self.bolt_region,
            "nut_region": self.nut_region,
            "normal": list(self.normal),
            "bolt_outline_normal": list(self.bolt_outline_normal),
            "nut_outline_normal": list(self.nut_outline_normal),
        }


@dataclass(frozen=True)
class PlanarState:
    """The flush bolt on the nut at one phase.

    Attributes
    ----------
    phase : float
        Degrees, in ``[0, 360)``.
    in_phase : bool
        True when the outlines do not overlap: the bolt can drop into the nut. Then
        ``contacts`` is empty, ``contact_angle`` and ``pivot_axis_length`` are 0 — except
        exactly at an edge of the in-phase window, where the outlines touch (see
        ``line_contact``).
    contacts : tuple of PlanarContact
        For each arc where the bolt's outline lies outside the nut's, contact 1 (where,
        going counter-clockwise, the bolt's outline passes from inside to outside the
        nut's: the arc's start) then contact 2 (where it comes back). A single-start
        pair has one arc; a thread of ``n`` starts has ``n`` arcs, images of each other
        under turns of ``360 / n`` degrees, listed by the angle of their contact 1.
    contact_angle : float
        Degrees of outline over which the bolt's outline lies outside the nut's (summed
        over the arcs). At a window edge: the span over which the outlines coincide.
    pivot_axis_length : float
        Distance between contacts 1 and 2 of the first arc (spec's units).
    pivot_axis : tuple of two (x, y) points, or None
        The segment from contact 1 to contact 2 of the first arc; None without contacts.
    line_contact : bool
        True exactly at an edge of the in-phase window where equal flanks coincide over a
        stretch: ``contacts`` are then the ends of that line contact and ``in_phase`` is
        True (the outlines touch but do not overlap). A fillet that touches at a single
        point there gives both contacts at that point, with ``line_contact`` False.
    """

    phase: float
    in_phase: bool
    contacts: tuple[PlanarContact, ...]
    contact_angle: float
    pivot_axis_length: float
    pivot_axis: tuple[tuple[float, float], tuple[float, float]] | None
    line_contact: bool = False

    def to_dict(self) -> dict[str, Any]:
        """The state as plain JSON types (contacts numbered from 1 in list order)."""
        contacts = []
        for i, c in enumerate(self.contacts):
            doc = c.to_dict()
            doc["contact"] = i % 2 + 1
            contacts.append(doc)
        return {
            "phase": self.phase,
            "in_phase": self.in_phase,
            "line_contact": self.line_contact,
            "contact_angle": self.contact_angle,
            "pivot_axis_length": self.pivot_axis_length,
            "pivot_axis": None if self.pivot_axis is None else [list(p) for p in self.pivot_axis],
            "contacts": contacts,
        }


@dataclass(frozen=True)
class CriticalPhase:
    """A phase at which a contact passes from one pair of regions to another.

    Attributes
    ----------
    phase : float
        Degrees, in ``[0, 360)``.
    contact : int
        1 or 2 (numbering of :class:`PlanarState`).
    before, after : (bolt_region, nut_region) or None
        The regions in contact just below and just above the phase; None where there is
        no contact on that side (an edge of the in-phase window).
    """

    phase: float
    contact: int
    before: tuple[str, str] | None
    after: tuple[str, str] | None

    def to_dict(self) -> dict[str, Any]:
        """The critical phase as plain JSON types."""

        def pair(p: tuple[str, str] | None) -> dict[str, str] | None:
            return None if p is None else {"bolt_region": p[0], "nut_region": p[1]}

        return {
            "phase": self.phase,
            "contact": self.contact,
            "before": pair(self.before),
            "after": pair(self.after),
        }


# -- public functions --------------------------------------------------------------------


def planar_state(spec: ThreadSpec, phase: float) -> PlanarState:
    """The contact points, contact angle and pivot axis of the flush bolt at ``phase``.

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair.
    phase : float
        The bolt's phase in degrees (counter-clockwise seen from +Z); any finite value,
        taken modulo 360.

    Returns
    -------
    PlanarState

    Raises
    ------
    InputError
        If ``phase`` is not a finite number.
    """
    return _state(outline_pair(spec), _normalise(phase))


def phase_sweep(spec: ThreadSpec, phases: Iterable[float]) -> list[PlanarState]:
    """:func:`planar_state` at each of ``phases`` (degrees), for figures and tables."""
    pair = outline_pair(spec)
    return [_state(pair, _normalise(p)) for p in phases]


def in_phase_window(spec: ThreadSpec) -> list[tuple[float, float]]:
    """The phases (degrees) at which the flush outlines do not overlap.

    For a sharp single-start pair the window is centred on 0 with half-width
    ``360 * clearance / (2 * lead)``, ``clearance = spec.axial_clearance``. It is computed
    here for any profile: the phase at which the largest excess of the bolt's radius over
    the nut's, found exactly over the breakpoints and stationary points of the two
    outlines, crosses zero (:func:`scipy.optimize.brentq`). A thread of ``n`` starts
    repeats it every ``360 / n`` degrees.

    Returns
    -------
    list of (start, end)
        ``start < end``, ``start`` normalised into ``[-180, 180)``, sorted by ``start``.
        Empty when no open window exists (no clearance); ``[(-180, 180)]`` when the bolt
        clears the nut at every phase.
    """
    return list(_window(spec))


def critical_phases(spec: ThreadSpec) -> list[CriticalPhase]:
    """The phases in ``[0, 360)`` at which a contact changes regions (the thesis's
    section 2.5, eq. 2.23, for every pair of regions and fillets).

    A contact changes region when the crossing reaches a breakpoint of either outline:
    where the nut's outline changes region at ``tau = b`` with radius ``R_n(b)``, the
    crossing sits there when ``R_b(b + sigma) = R_n(b)``, and the bolt's profile is
    inverted in closed form on each of its monotone pieces (line or circle); likewise for
    the bolt's breakpoints. Each candidate is kept where the regions read just below and
    just above it differ. The edges of the in-phase window, where the contacts appear and
    vanish, are included with ``before`` or ``after`` None.
    """
    return list(_critical(spec))


# -- implementation ----------------------------------------------------------------------


def _normalise(phase: float) -> float:
    value = wrap_phase(check_phase("phase", phase))
    return 0.0 if value >= 360.0 else value


def _outline_normal(theta: float, r: float, dr: float) -> tuple[float, float]:
    """Unit normal, away from the axis, of the polar curve ``r(theta)`` with slope ``dr``."""
    c, s = math.cos(theta), math.sin(theta)
    # P' = dr e_r + r e_theta, so (r e_r - dr e_theta) is normal to it and points outward.
    nx, ny = r * c + dr * s, r * s - dr * c
    n = math.hypot(nx, ny)
    return (nx / n, ny / n)


def _contact(pair: OutlinePair, sigma: float, tau: float, side: int, theta: float) -> PlanarContact:
    """The contact at ``tau`` (seen at F-angle ``theta``), its regions and slopes read on
    ``side`` (+1 / -1: toward larger / smaller ``tau``; 0: at the point)."""
    step = side * SIDE_STEP * pair.thread_pitch
    r = float(pair.nut.radius(tau))
    dt_dtheta = -pair.hand * pair.lead / TWO_PI
    dr_bolt = float(pair.bolt.slope(tau + sigma + step)) * dt_dtheta
    dr_nut = float(pair.nut.slope(tau + step)) * dt_dtheta
    return PlanarContact(
        theta=math.degrees(theta),
        x=r * math.cos(theta),
        y=r * math.sin(theta),
        radius=r,
        bolt_region=str(pair.bolt.region(tau + sigma + step)),
        nut_region=str(pair.nut.region(tau + step)),
        normal=_UP,
        bolt_outline_normal=_outline_normal(theta, r, dr_bolt),
        nut_outline_normal=_outline_normal(theta, r, dr_nut),
    )


def _arcs(
    pair: OutlinePair, sigma: float, stretches: list[Stretch]
) -> list[tuple[PlanarContact, PlanarContact]]:
    """Contacts 1 and 2 of each arc, sorted by the angle of contact 1."""
    arcs = []
    for st in stretches:
        # theta runs against tau for a right hand (tau = -lead theta / 2 pi), with it for
        # a left hand: the arc's counter-clockwise start is tau's end, or its start.
        if pair.hand > 0:
            first, second = (st.end, -1), (st.start, +1)
        else:
            first, second = (st.start, +1), (st.end, -1)
        for th1, th2 in zip(pair.thetas(first[0]), pair.thetas(second[0]), strict=True):
            arcs.append(
                (
                    _contact(pair, sigma, first[0], first[1], th1),
                    _contact(pair, sigma, second[0], second[1], th2),
                )
            )
    arcs.sort(key=lambda a: a[0].theta)
    return arcs


def _build(
    phase: float,
    in_phase: bool,
    arcs: list[tuple[PlanarContact, PlanarContact]],
    angle: float,
    line: bool,
) -> PlanarState:
    if not arcs:
        return PlanarState(phase, in_phase, (), angle, 0.0, None, line)
    c1, c2 = arcs[0]
    axis = ((c1.x, c1.y), (c2.x, c2.y))
    length = math.hypot(c2.x - c1.x, c2.y - c1.y)
    contacts = tuple(c for arc in arcs for c in arc)
    return PlanarState(phase, in_phase, contacts, angle, length, axis, line)


def _state(pair: OutlinePair, phase: float) -> PlanarState:
    sigma = pair.shift(phase)
    top, where = pair.maximum(sigma)
    deg_per_tau = 360.0 / pair.thread_pitch  # summed over the starts
    if top < -pair.tol:
        return PlanarState(phase, True, (), 0.0, 0.0, None, False)
    if top <= pair.tol:
        # The window's edge: the outlines touch without overlapping.
        stretches = pair.coincident(sigma)
        if stretches:
            angle = sum(s.end - s.start for s in stretches) * deg_per_tau
            return _build(phase, True, _arcs(pair, sigma, stretches), angle, True)
        arcs = [
            (_contact(pair, sigma, where, 0, th), _contact(pair, sigma, where, 0, th))
            for th in pair.thetas(where)
        ]
        arcs.sort(key=lambda a: a[0].theta)
        return _build(phase, True, arcs, 0.0, False)
    stretches = pair.overlap(sigma)
    if not stretches:
        # The bolt's outline lies outside the nut's all round: no crossing at all.
        return PlanarState(phase, False, (), 360.0, 0.0, None, False)
    angle = sum(s.end - s.start for s in stretches) * deg_per_tau
    return _build(phase, False, _arcs(pair, sigma, stretches), angle, False)


@lru_cache(maxsize=64)
def _window(spec: ThreadSpec) -> tuple[tuple[float, float], ...]:
    pair = outline_pair(spec)
    p = pair.thread_pitch

    def top(sigma: float) -> float:
        return pair.maximum(sigma)[0]

    if top(0.0) > -pair.tol:
        return ()

    def edge(direction: float) -> float | None:
        # March out from the in-phase centre to the first overlap, then root-find.
        prev = 0.0
        for s in direction * np.linspace(0.0, p / 2, 129)[1:]:
            if top(float(s)) > 0.0:
                return brentq(top, prev, float(s), xtol=1e-15 * p, rtol=4 * np.finfo(float).eps)
            prev = float(s)
        return None

    lo, hi = edge(-1.0), edge(1.0)
    if lo is None or hi is None:
        return ((-180.0, 180.0),)
    start, end = sorted((pair.phase(lo), pair.phase(hi)))
    period = 360.0 / pair.starts
    out = []
    for k in range(pair.starts):
        s = phase_difference(start + k * period)
        out.append((s, s + (end - start)))
    return tuple(sorted(out))


def _labels(pair: OutlinePair, phase: float) -> tuple[tuple[str, str] | None, ...]:
    state = _state(pair, _normalise(phase))
    if state.in_phase or not state.contacts:
        return (None, None)
    c1, c2 = state.contacts[0], state.contacts[1]
    return ((c1.bolt_region, c1.nut_region), (c2.bolt_region, c2.nut_region))


@lru_cache(maxsize=64)
def _critical(spec: ThreadSpec) -> tuple[CriticalPhase, ...]:
    pair = outline_pair(spec)
    shifts: list[float] = []
    for b in pair.nut_edges:
        shifts += [t - b for t in profile_inverse(pair.bolt, float(pair.nut.radius(b)))]
    for b in pair.bolt_edges:
        shifts += [b - t for t in profile_inverse(pair.nut, float(pair.bolt.radius(b)))]
    period = 360.0 / pair.starts
    cands = {wrap_phase(pair.phase(s) + k * period) for s in shifts for k in range(pair.starts)}
    for start, end in _window(spec):
        if end - start < 360.0:
            cands |= {wrap_phase(start), wrap_phase(end)}
    ordered: list[float] = []
    for c in sorted(cands):
        c = 0.0 if c >= 360.0 else c
        if not ordered or c - ordered[-1] > 10 * _CRITICAL_STEP:
            ordered.append(c)
    if len(ordered) > 1 and ordered[0] + 360.0 - ordered[-1] <= 10 * _CRITICAL_STEP:
        ordered.pop()
    out = []
    for c in ordered:
        before = _labels(pair, c - _CRITICAL_STEP)
        after = _labels(pair, c + _CRITICAL_STEP)
        for i in (0, 1):
            if before[i] != after[i]:
                out.append(CriticalPhase(float(c), i + 1, before[i], after[i]))
    return tuple(out)
