"""The contact set of a lowered pose: the distinct contacts within ``near`` of it.

A lowering knows the triangle pairs that touch, or nearly, with their vertical gaps and
points. The contact set groups them by single linkage of their points a quarter pitch
apart (:meth:`_ContactSet.contacts`); each group is a contact at its least gap, with its
normal and regions from the exact bodies (:func:`threadmate.contact.scene.refined_contact`).
Where one group stands for more than a point, so does the set: a face flat on a face or a
rim along a face by the corners of its area, a flank along a flank by its least gap in
each :data:`HELIX_ARC` round the axis, the nut's material above the bolt by its least rise
in each of :data:`UPPER_BINS` pieces of its arc, the tip rim at the bore's edge by both
its supports. A contact lies on the helices (:func:`on_helix`) or not: what decides
whether the bolt is in phase (:mod:`._seat`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull, QhullError

from ..._angles import TWO_PI, phase_difference
from ..scene import (
    EDGE_FEATURE_KINDS,
    contact_normal,
    edge_crossing,
    lowest_on_rim,
    on_thread,
    refined_contact,
    region_at,
    single_linkage,
)
from ._lowering import _Drop, _Lowering

__all__ = ["HELICAL_FEATURES", "HELIX_ARC", "UPPER_BINS", "on_helix"]

#: Arc (degrees about the axis) of a contact along the helices, or round a ring, that one
#: point of it stands for (:meth:`Mechanics._round_the_axis`).
HELIX_ARC = 30.0
#: (bolt, nut) regions of a ring of contact round the axis: a point in the countersink, a
#: cone in a cone; known, as a contact along the helices is, by its least gap in each
#: :data:`HELIX_ARC` of it (:meth:`Mechanics.contacts`).
RING_REGIONS = frozenset({("chamfer", "countersink"), ("round", "countersink")})
#: Pieces of its arc by which a contact with material above stands for a line of contact
#: (:meth:`Mechanics.contacts`).
UPPER_BINS = 5
#: Features that lie on a body's helix: its thread's faces and the sharp corners between
#: them (:class:`threadmate.contact._exact.Feature`).
HELICAL_FEATURES = frozenset({"thread", "corner"})


def on_helix(bolt_feature: str, nut_feature: str, nut_thread: bool) -> bool:
    """Whether a contact lies on the helices (mechanics.md, "in-phase"): a bolt flank (its
    thread's face or corner) on the nut's flank or on the edge where the nut's thread
    meets its top face or countersink, or the bolt's end on the nut's flank.
    ``nut_thread``: the nut's feature belongs to its thread (:func:`on_thread`).

    Such a contact moves along the helix as the bolt turns. Where the bolt's thread
    touches, its surface there is carried into itself by the screw motion, so the contact
    neither opens nor closes as the bolt turns and moves along its axis by the lead; where
    the bolt's end touches a nut flank, the end's point slides along the nut's helix. A
    contact of the bolt's end on the nut's entry (tip face on top face, point on
    countersink, rim on the bore's edge), or of a bolt flank on the nut's top face or
    countersink away from its thread, does not: turning slides it round or lifts the bolt
    off it.
    """
    if not nut_thread:
        return False
    return nut_feature in HELICAL_FEATURES or bolt_feature in HELICAL_FEATURES


@dataclass
class _Near:
    """A contact near the current pose, as the descent sees it."""

    point: NDArray[np.float64]
    normal: NDArray[np.float64]
    gap: float  # vertical gap, spec units
    bolt_region: str
    nut_region: str
    bolt_feature: str
    nut_feature: str
    helical: bool = False  # on the helices (:func:`on_helix`)
    upper: bool = False  # nut material above the bolt: opens as the bolt moves down


class _ContactSet(_Lowering):
    """The contact set of a lowered pose (module docstring): a layer of :class:`Mechanics`."""

    def _contact(
        self,
        d: _Drop,
        point: NDArray[np.float64],
        gap: float,
        refine: bool = True,
        upper: bool = False,
    ) -> _Near:
        an = self.scene
        pose = self._pose(d.rotation, d.xy, d.zc + gap if upper else d.zc - gap)
        refined = (
            refined_contact(
                an.nut, an.bolt, pose, point, an.feature_tolerance, self.separation / 4, self._off
            )
            if refine
            else None
        )
        # A contact a lowering found opens as the bolt rises: its normal points up. One
        # pointing down means the refinement slid along an edge onto another feature close
        # by (where two thread starts meet edge to edge, the nut's tooth over the bolt's
        # flank): the contact then stays where the meshes touch. (Material above: the
        # other way round.)
        if refined is not None and (refined[0][2] <= 0.0 if upper else refined[0][2] >= 0.0):
            n, point, fn, fb = refined
        else:
            n, fn, fb = contact_normal(
                an.nut, an.bolt, pose, point, an.feature_tolerance, self._off
            )
        return _Near(
            point,
            n,
            gap,
            str(region_at(an.bolt, pose.to_bolt(point), fb, an.off_spec_tolerance)),
            str(region_at(an.nut, point, fn, an.off_spec_tolerance)),
            fb.kind,
            fn.kind,
            on_helix(fb.kind, fn.kind, on_thread(an.nut, point, fn, an.feature_tolerance)),
            upper,
        )

    def _rim_modes(self, d: _Drop, c: _Near) -> list[_Near]:
        """The tip rim touching the nut's top face at its bore edge: both supports.

        Where the rim's lowest point reaches the bore edge, the rim rests either on the
        face (normal +Z) or on the edge (the edges' common normal), and a rest state can
        sit on that kink with the force anywhere between the two normals. Both are given
        to the descent, each with its own gap, so that it can meet the kink.
        """
        if c.bolt_feature != "rim" or c.nut_feature not in ("cap", "rim"):
            return [c]
        an = self.scene
        theta = math.atan2(c.point[1], c.point[0])
        edge = float(an.nut.lateral_radius(theta, 0.0))
        if abs(math.hypot(c.point[0], c.point[1]) - edge) > self.separation / 8:
            return [c]
        pose = self._pose(d.rotation, d.xy, d.zc)
        tol = an.feature_tolerance
        window = self.separation / 4
        if c.nut_feature == "cap":
            anchor = np.array([edge * math.cos(theta), edge * math.sin(theta), 0.0])
            point, above = edge_crossing(an.nut, an.bolt, pose, anchor, c.point, tol, window)
            if above is None:
                return [c]
            other = self._contact(d, point, max(float(above[2] - point[2]), 0.0), refine=False)
        else:
            point = lowest_on_rim(an.bolt, pose, c.point, window)
            r = math.hypot(point[0], point[1])
            if r < float(an.nut.lateral_radius(math.atan2(point[1], point[0]), 0.0)):
                return [c]  # the lowest point is over the bore: the edge alone holds
            other = _Near(
                np.array([point[0], point[1], 0.0]),
                np.array([0.0, 0.0, 1.0]),
                max(float(point[2]), 0.0),
                c.bolt_region,
                "surface",
                "rim",
                "cap",
            )
        return [c, other]

    def contacts(self, d: _Drop) -> list[_Near]:
        """The distinct contacts within :attr:`near` of the pose, touching ones first.

        Pairs are grouped by single linkage of their touching points a quarter pitch
        apart; a group touches where its least gap is. A group that touches over an area
        or a line (a face flat on a face, a rim along a face) is represented by the
        corners of the convex hull of the area (at most six), each a contact of its own.
        """
        if len(d.gaps) == 0:
            return []
        out: list[_Near] = []
        labels = self._groups(d.points)
        for k in range(int(labels.max()) + 1):
            idx = np.flatnonzero(labels == k)
            gaps, pts = d.gaps[idx], d.points[idx]
            j = int(np.argmin(gaps))
            first = self._contact(d, pts[j], float(gaps[j]))
            flat = gaps <= gaps[j] + self.tolerance
            corners = _area_corners(pts[flat], first.normal, self.separation / 2)
            if corners is None:
                out.extend(self._rim_modes(d, first))
            else:
                # The corners of a flat contact are where the mesh puts them.
                at_corners = [
                    self._contact(d, pts[flat][c], float(gaps[flat][c]), refine=False)
                    for c in corners
                ]
                out.extend(at_corners)
                if (
                    first.bolt_feature in EDGE_FEATURE_KINDS
                    or first.nut_feature in EDGE_FEATURE_KINDS
                ) and all(float(first.normal @ c.normal) < 1.0 - 1e-9 for c in at_corners):
                    # The group's least gap, refined onto an exact edge, supports the bolt
                    # in a direction no corner does (a countersink's kink lying along the
                    # point's cone touches where the kinks cross, while the mesh's flat
                    # pairs run along the cone): it is a contact too, so that the set does
                    # not jump between the corners and that edge as the area's span
                    # crosses ``extent`` from pose to pose.
                    out.append(first)
            if first.helical or (first.bolt_region, first.nut_region) in RING_REGIONS:
                out.extend(self._round_the_axis(d, pts, gaps, j))
        if d.over_pairs is None:
            # (Kept with the pose: its nudges re-evaluate the same pairs.)
            over = self._overhead(d)
            d.over_pairs, d.rises, d.over_points = over.over_pairs, over.rises, over.over_points
        if len(d.rises):
            labels = self._groups(d.over_points)
            for k in range(int(labels.max()) + 1):
                idx = np.flatnonzero(labels == k)
                gaps, pts = d.rises[idx], d.over_points[idx]
                # A line of contact (a crest under the edge where the nut's thread meets
                # its top face, a flank under a flank): its least rise in each of
                # UPPER_BINS pieces of its arc round the axis, so that the descent knows
                # the line it may tip against, as a rim's corners stand for a rim below.
                theta = np.arctan2(pts[:, 1], pts[:, 0])
                j = int(np.argmin(gaps))
                rel = phase_difference(theta, theta[j], TWO_PI)
                width = float(rel.max() - rel.min())
                bins = np.minimum(
                    ((rel - rel.min()) / max(width, 1e-300) * UPPER_BINS).astype(np.int64),
                    UPPER_BINS - 1,
                )
                for b in np.unique(bins):
                    inside = np.flatnonzero(bins == b)
                    i = int(inside[np.argmin(gaps[inside])])
                    out.append(self._contact(d, pts[i], float(gaps[i]), upper=True))
        out.sort(key=lambda c: c.gap)
        return out

    def _groups(self, points: NDArray[np.float64]) -> NDArray[np.intp]:
        """Labels of ``points`` grouped by single linkage :attr:`separation` apart."""
        # Pairs a sixteenth of the linkage apart touch at nearly one place: one point of
        # each such cell stands for it in the clustering.
        cell = np.floor(points / (self.separation / 16)).astype(np.int64)
        # One integer per cell, ordered as the cells are lexicographically (the order
        # ``np.unique(cell, axis=0)`` gives, at a fraction of its cost).
        cell -= cell.min(axis=0)
        size = cell.max(axis=0) + 1
        key = (cell[:, 0] * size[1] + cell[:, 1]) * size[2] + cell[:, 2]
        _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
        return single_linkage(points[first], self.separation)[inverse.reshape(-1)]

    def _round_the_axis(
        self, d: _Drop, pts: NDArray[np.float64], gaps: NDArray[np.float64], j: int
    ) -> list[_Near]:
        """The rest of a contact along the helices: where one flank lies along the other
        (the bolt in the thread), or round a ring (:data:`RING_REGIONS`), the pairs within
        ``near`` run round the axis as one group; its least gap in each :data:`HELIX_ARC`
        of it (beyond the one holding ``j``, the group's least) is a contact of its own,
        so that the descent knows the whole line it may tip onto, not its lowest point
        alone."""
        theta = np.arctan2(pts[:, 1], pts[:, 0])
        rel = phase_difference(theta, theta[j], TWO_PI)
        arc = math.radians(HELIX_ARC)
        if float(rel.max() - rel.min()) <= arc:
            return []
        # Arcs counted from the least gap's, each way.
        bins = np.floor(rel / arc + 0.5).astype(np.int64)
        out = []
        for b in np.unique(bins):
            if b == 0:
                continue
            inside = np.flatnonzero(bins == b)
            i = int(inside[np.argmin(gaps[inside])])
            out.append(self._contact(d, pts[i], float(gaps[i])))
        return out


def _touching_pairs(near: list[_Near], touching: float) -> tuple[str, ...]:
    """The region pairs (``bolt/nut``) of the contacts within ``touching`` of touch, sorted."""
    return tuple(sorted(f"{c.bolt_region}/{c.nut_region}" for c in near if c.gap <= touching))


def _area_corners(
    points: NDArray[np.float64], normal: NDArray[np.float64], extent: float
) -> list[int] | None:
    """Indices of up to six corners of the convex hull of ``points`` seen along
    ``normal`` (None when the points span less than ``extent``: a point contact)."""
    if len(points) < 2 or float(np.ptp(points, axis=0).max()) < extent:
        return None
    n = normal / np.linalg.norm(normal)
    a = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(n, a)
    flat = np.column_stack([points @ a, points @ b])
    try:
        vertices = list(ConvexHull(flat).vertices)
    except (QhullError, ValueError):
        # Collinear: a line contact; its two ends.
        axis = flat - flat.mean(0)
        u, s, vt = np.linalg.svd(axis, full_matrices=False)
        t = axis @ vt[0]
        return [int(np.argmin(t)), int(np.argmax(t))]
    if len(vertices) <= 6:
        return [int(v) for v in vertices]
    chosen = [vertices[0]]
    while len(chosen) < 6:
        dist = np.min(np.linalg.norm(flat[vertices][:, None] - flat[chosen][None], axis=-1), axis=1)
        chosen.append(vertices[int(np.argmax(dist))])
    return [int(v) for v in chosen]
