"""The three contact stages: bisection on yes/no collision queries.

First contact. The bolt, at ``x = y = 0`` with ``R = Rx(roll) Ry(pitch) Rz(phase)``,
starts where its lowest vertex is ``travel`` above the nut's top plane (it cannot touch),
and comes down along -Z. One query a ``travel`` lower settles the common case of a tip
rim landing on the top face; otherwise the drop doubles from a sixteenth of the pitch until
the bolt collides, and bisection closes the bracket to ``travel`` (1e-7 in). The stage's
pose is the collision-free end of the bracket; its contacts are read at the other end.

Every search closes its bracket the same way (:func:`_close_in`): one query names the nut
sectors the bolt intersects at the colliding end, the bisection asks only those (an
interference that starts inside the bracket persists to its colliding end, as the bolt
only goes deeper), and a last query of the other sectors confirms the free end. Should it
collide (a contact that came and went inside the bracket), the bisection is redone on the
whole nut.

Second and third contact. The bolt turns about a line (second: through the first
contact along the nut's tangent there; third: the pivot axis through the two contacts) in
the sense that lowers the compliance centre. The predicate of the search is "a NEW
distinct contact exists". Each existing contact owns the nut's angular sectors (36 about
the axis, see :mod:`._collision`) that come within ``separation`` (a quarter pitch, as
arc length at the contact's radius) of its triangle pairs; the predicate is one yes/no
query of the bolt against the other sectors. Interference beside an existing contact (the
bolt dips locally about a contact it turns about) is thereby ignored, interference that
spreads beyond its sectors (the thesis's "rolling" contact) counts as new. At the end the
pairs are enumerated once: those in owned sectors relocate the existing contacts (each to
the contact whose pairs come nearest), the rest are clustered into the new ones
(:mod:`._triangles`).

The turn doubles from a sixteenth of ``max_turn`` (30 degrees) up to ``max_turn``, then
bisects until the farthest bolt point moves less than ``travel``. (The turns seen over the
thesis's grid range from thousandths of a degree to about 8 degrees; a first trial near
their median spends the costly queries of the whole nut on few trials, and the bisection
that follows asks only the sectors that collide.) The stage's pose is the end of the
bracket without the new contact; contacts are read at the other end. A stage that finds
nothing within the range is reported as not found.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from ...geometry import Pose
from ..scene import (
    CollisionPair,
    IntersectionSegments,
    cluster_location,
    cluster_segments,
    intersection_segments,
)

__all__ = [
    "Cluster",
    "Search",
    "StageOutcome",
    "TurnOutcome",
    "first_contact",
    "turn_to_new_contact",
    "clusters_at",
    "lowering_direction",
]


@dataclass(frozen=True)
class Cluster:
    """A distinct contact as the meshes see it: location (F) and its triangle pairs."""

    point: NDArray[np.float64]
    pairs: int
    ends: NDArray[np.float64]  # segment end points, (2 * pairs, 3)


@dataclass(frozen=True)
class Search:
    """Tolerances of the stage searches (spec units, degrees)."""

    travel: float
    separation: float
    thread_pitch: float
    min_radius: float
    max_turn: float = 30.0


@dataclass(frozen=True)
class StageOutcome:
    """What a stage search found: free pose, contact pose, clusters, angle (degrees)."""

    free: Pose
    contact: Pose
    clusters: list[Cluster]
    angle: float
    queries: int


def _segments(
    engine: CollisionPair, pose: Pose, sectors: frozenset[int] | None = None
) -> IntersectionSegments:
    pairs = engine.pairs(pose, sectors)
    return intersection_segments(*engine.triangles(pose, pairs))


def _subset(segs: IntersectionSegments, sel: NDArray[np.bool_]) -> IntersectionSegments:
    return IntersectionSegments(segs.start[sel], segs.end[sel], segs.valid[sel])


def _cluster(segs: IntersectionSegments) -> Cluster:
    return Cluster(cluster_location(segs), len(segs), np.concatenate([segs.start, segs.end]))


def _clusters(segs: IntersectionSegments, separation: float) -> list[Cluster]:
    if len(segs) == 0:
        return []
    labels = cluster_segments(segs, separation)
    return [_cluster(_subset(segs, labels == k)) for k in range(labels.max() + 1)]


def clusters_at(engine: CollisionPair, pose: Pose, separation: float) -> list[Cluster]:
    """Distinct contacts of the meshes at ``pose`` (one pair-enumeration query)."""
    return _clusters(_segments(engine, pose), separation)


def first_contact(
    engine: CollisionPair, rotation: NDArray[np.float64], search: Search, floor: float
) -> StageOutcome | None:
    """Lower the bolt along -Z until it first touches the nut (None: it never does).

    ``floor`` is an origin height below which the bolt has passed the nut entirely.
    """
    q0 = engine.queries
    tol = search.travel
    h0 = -engine.lowest_bolt_z(rotation)

    def pose(h: float) -> Pose:
        return Pose(rotation, np.array([0.0, 0.0, h]))

    hi = h0 + tol  # lowest vertex above z = 0 >= every nut point: free without a query
    lo = h0 - tol
    hit = engine.colliding_sectors(pose(lo))
    if not hit:
        hi = lo
        step = search.thread_pitch / 16
        while True:
            lo = h0 - step
            hit = engine.colliding_sectors(pose(lo))
            if hit:
                break
            hi = lo
            if lo < floor:
                return None
            step *= 2
    hi, lo, sectors = _close_in(engine, pose, hi, lo, hit, tol, frozenset())
    contact = pose(lo)
    clusters = _clusters(_segments(engine, contact, sectors), search.separation)
    return StageOutcome(pose(hi), contact, clusters, 0.0, engine.queries - q0)


def _close_in(
    engine: CollisionPair,
    pose: Callable[[float], Pose],
    free: float,
    stuck: float,
    hit: frozenset[int],
    tol: float,
    excluded: frozenset[int],
) -> tuple[float, float, frozenset[int] | None]:
    """Bisect from a collision-free parameter ``free`` to a colliding one ``stuck``, where
    the bolt meets the nut sectors ``hit``, asking only those sectors (see the module
    docstring); ``excluded`` sectors never count.

    Returns the closed bracket and the sectors holding every intersecting pair at its ends
    (None: any, the search fell back to the whole nut).
    """
    start = free
    while abs(stuck - free) > tol:
        mid = 0.5 * (free + stuck)
        now = engine.colliding_sectors(pose(mid), among=hit)
        if now:
            stuck, hit = mid, now
        else:
            free = mid
    # The bisection cleared ``hit`` at ``free``; the other sectors are asked once.
    if not engine.collides_outside(pose(free), excluded | hit):
        return free, stuck, hit | excluded
    free = start
    while abs(stuck - free) > tol:
        mid = 0.5 * (free + stuck)
        if engine.collides_outside(pose(mid), excluded):
            stuck = mid
        else:
            free = mid
    return free, stuck, None


def lowering_direction(
    axis_point: NDArray[np.float64], axis: NDArray[np.float64], centre: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``axis`` or its opposite: the one whose right-hand turn lowers ``centre``."""
    a = axis / np.linalg.norm(axis)
    velocity = np.cross(a, centre - axis_point)
    return -a if velocity[2] > 0 else a


@dataclass(frozen=True)
class TurnOutcome:
    """What a turn found: free and contact poses, the existing contacts as they are at the
    contact pose (None where one has no pairs left), the new ones, the angle (degrees),
    the queries spent and the nut sectors where the bolt meets the nut."""

    free: Pose
    contact: Pose
    existing: list[Cluster | None]
    new: list[Cluster]
    angle: float
    queries: int
    #: Nut sectors that hold every intersecting pair at either pose (None: any).
    sectors: frozenset[int] | None = None


def turn_to_new_contact(
    engine: CollisionPair,
    start: Pose,
    axis_point: NDArray[np.float64],
    axis: NDArray[np.float64],
    existing: list[Cluster],
    search: Search,
) -> TurnOutcome | None:
    """Turn ``start`` about the line (``axis_point``, unit ``axis``, right hand) until a new
    distinct contact appears (None: not within ``search.max_turn`` degrees).

    The existing contacts own the nut's sectors within ``search.separation`` of their
    pairs (see the module docstring); a collision anywhere else is a new contact.
    """
    q0 = engine.queries
    sep = search.separation
    zone_pts = np.concatenate([c.ends for c in existing])
    excluded = engine.sectors_near(zone_pts, sep, search.min_radius)
    # Farthest bolt point from the axis bounds the motion of any point per radian.
    rel = start.origin - axis_point
    arm = float(np.linalg.norm(rel - (rel @ axis) * axis)) + engine.bolt_radius
    tol_deg = math.degrees(search.travel / arm)

    def pose(deg: float) -> Pose:
        return start.rotated_about(axis_point, axis, deg)

    lo = 0.0
    step = max(search.max_turn / 16, 4 * tol_deg)
    while True:
        hi = min(step, search.max_turn)
        hit = engine.colliding_sectors(pose(hi), excluded)
        if hit:
            break
        lo = hi
        if hi >= search.max_turn:
            return None
        step *= 2
    lo, hi, sectors = _close_in(engine, pose, lo, hi, hit, tol_deg, excluded)
    contact = start.rotated_about(axis_point, axis, hi)
    pairs = engine.pairs(contact, sectors)
    segs = intersection_segments(*engine.triangles(contact, pairs))
    new_pair = ~np.isin(engine.nut_sector[pairs[:, 1]], list(excluded))
    # Old pairs go to the existing contact whose pairs come nearest.
    owner = np.full(len(pairs), -1)
    if (~new_pair).any():
        zone_of = np.concatenate([np.full(len(c.ends), k) for k, c in enumerate(existing)])
        _, nearest = cKDTree(zone_pts).query(segs.midpoint[~new_pair])
        owner[~new_pair] = zone_of[nearest]
    old = [
        _cluster(_subset(segs, owner == k)) if (owner == k).any() else None
        for k in range(len(existing))
    ]
    new = _clusters(_subset(segs, new_pair), sep)
    free = start.rotated_about(axis_point, axis, lo)
    return TurnOutcome(free, contact, old, new, lo, engine.queries - q0, sectors)
