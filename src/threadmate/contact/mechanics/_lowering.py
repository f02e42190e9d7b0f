"""Lowering the bolt onto the nut at a tilt: the touching pose, exact for the meshes.

The bolt at a tilt is placed a little above where it is expected to touch, checked free
with one yes/no query, and every triangle pair that intersects a little lower is
enumerated with one more, both in one walk of the trees swept between the two heights
(:meth:`_Lowering.drop`); the exact drop at which each pair first touches
(:func:`threadmate.contact.scene.vertical_touch`) gives the contact height without
bisection, and the gaps of the other contacts within the depth ``near``. Where nothing
intersects at the foot, the pairs the swept walk kept tell whether a tooth of the nut lay
between, passed whole, before the bolt is lowered on. A
lowering that is kept is verified (:meth:`_Lowering.verified`): what the pairs at the
bracket's foot missed touches between its top and its touch, where the bracket's walk of
the trees (swept between the two) has kept every pair that can meet; one compiled pass
over those, each tested as the bolt moves down between the two heights, asks whether
any meets above the touch (:meth:`threadmate.contact.scene.Sweep.touching_within`), with
no walk of its own. Where one does, the pairs crossing just above the touch and yes/no
queries above it raise it, and the pass's pairs the rest of the way, all asked of the
walk's leaf pairs narrowed to those the bolt meets on the way (every pair they can find
lies in one: :meth:`threadmate.contact.scene.Sweep.narrowed`). A motion finer than
the length tolerance is lowered onto the pairs already known, with no query
(:meth:`_Lowering._nudged`), and the nut's material above the bolt, where the bolt lies
in the thread, is known as the pairs below are (:meth:`_Lowering._overhead`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from ...geometry import Pose
from ..scene import Sweep, deep_candidates, pair_keys, upward, vertical_rise, vertical_touch
from ._held_bolt import _HeldBolt

__all__: list[str] = []

#: The share of the bolt's free fall into the nut's bore, as guessed from its hull's
#: vertices, that a lowering from above asks in one walk (:meth:`_Lowering._free_steps`):
#: the guess can overshoot where the bolt's faces, between its vertices, meet the nut's
#: thread at the foot of its countersink.
FREE_FALL_SHARE = 0.75


@dataclass
class _Drop:
    """The bolt lowered onto the nut at one tilt."""

    rotation: NDArray[np.float64]
    xy: NDArray[np.float64]
    zc: float  # height of the compliance centre when touching
    top: float  # the free height the touch is measured from
    start: float  # where the lowering started (see Mechanics.verified)
    span: float  # its last step
    cap: float  # the longest step it may take
    pairs: NDArray[np.int64]  # (bolt, nut) face pairs whose touch from ``top`` is known
    drops: NDArray[np.float64]  # each pair's drop from ``top`` to its touch (or inf)
    touches: NDArray[np.float64]  # where each pair touches (F; NaN with an inf drop)
    gaps: NDArray[np.float64] = field(default_factory=lambda: np.empty(0))  # vertical (>= 0)
    points: NDArray[np.float64] = field(default_factory=lambda: np.empty((0, 3)))  # (F)
    verified: bool = False  # at the first touch from ``top`` (Mechanics.verified)
    # The bolt collides above the lowering's ceiling (Mechanics.drop): ``zc`` is that
    # height, not a touch, and nothing else is known.
    above_ceiling: bool = False
    # The nut's material above the bolt (Mechanics._overhead; None: not looked for yet):
    # face pairs, each one's rise to its touch and where.
    over_pairs: NDArray[np.int64] | None = None
    rises: NDArray[np.float64] = field(default_factory=lambda: np.empty(0))
    over_points: NDArray[np.float64] = field(default_factory=lambda: np.empty((0, 3)))
    # The bracket's last walk, swept from ``top`` down (None: it was not swept), which
    # answers the verification's queries between (Sweep.covers).
    sweep: Sweep | None = None
    # Every height from ``start`` down to ``top`` was passed by the bracket's walks, each
    # free at its top and its pairs tested exactly (Mechanics._tooth): no body passed
    # whole into the other above ``top``.
    passed: bool = False


class _Lowering(_HeldBolt):
    """Lowering the bolt onto the nut (module docstring): a layer of :class:`Mechanics`."""

    def drop(
        self,
        rotation: NDArray[np.float64],
        xy: NDArray[np.float64],
        zc: float | None,
        span: float | None = None,
        *,
        verify: bool = True,
        climb: bool = True,
        reach: float = 0.0,
        ceiling: float | None = None,
    ) -> _Drop | None:
        """Lower the bolt at ``rotation`` (compliance centre over ``xy``) onto the nut.

        ``zc`` is where the compliance centre is expected to touch (None: unknown, the
        bolt comes from above the nut). Returns None when the bolt passes the nut.
        Without ``verify`` the touch is the one the bracket's pairs give, which can lie
        below the first touch (see :meth:`verified`): a descent step asks for it only once
        the step would be kept there, since the first touch lies higher still.
        Without ``climb``, a pose that meets material above where it is expected to touch
        is lowered off it by as much as ``reach`` (the step's motion: what its linearised
        contacts can miss by), else gives None: in the thread, with material above, a
        climb can only leave the thread.
        """
        known_free = False
        # Where the lowest bolt point is just above the nut's top face: free for sure.
        above = self._clear_of_top(rotation) + self.tolerance
        if zc is None or zc + (span or 0.0) >= above:
            # Short first steps, doubling: a thin wedge of material where a thread runs out
            # on the nut's face (a few 1e-5 in at the edge of the in-phase window) is met
            # by a step no longer than it before one can pass it unseen.
            zc, span, known_free = above, self.spec.pitch / 4096, True
        # (Under material a bracket may be shorter than the tolerance: it starts between
        # the flanks, where the gap may be that narrow.)
        span = max(span or 0.0, self.tolerance if climb else 0.0)
        # The bracket [top - span - near, top] reaches a little below the expected height
        # (a quarter of ``near`` at most): the linearised contacts predict the touch within
        # a few thousandths of a span, and half the touches fall just below the
        # prediction, each of which would otherwise need a second enumeration of the pairs
        # within ``near`` of it. (No further: a deeper bracket can pass a thin wedge of
        # material whole, where a thread runs out on an end face.)
        top = zc if known_free else zc + span - min(0.25 * span, 0.25 * self.near)
        found = self._bracket(
            rotation,
            xy,
            top,
            span,
            known_free,
            self.spec.pitch / 16,
            None if climb else reach,
            ceiling,
        )
        return self.verified(found) if verify and found is not None else found

    def _bracket(
        self,
        rotation: NDArray[np.float64],
        xy: NDArray[np.float64],
        top: float,
        span: float,
        known_free: bool,
        cap: float,
        reach: float | None = None,
        ceiling: float | None = None,
    ) -> _Drop | None:
        """The touch the pairs crossing at a bracket's foot give, lowering from ``top`` in
        steps of ``span`` doubling up to ``cap`` (see :meth:`drop`; ``reach``: no climb;
        ``ceiling``: the height above which a climb ends)."""
        eng = self.engine
        start, hit = top, -math.inf  # hit: the highest height known to collide
        passed = True  # (see _Drop.passed)
        if known_free:
            top, span = self._free_steps(rotation, xy, top, span, cap)
            if top < self._floor:
                return None
        for _ in range(200):
            # ``top`` must be free: a pose deep in the nut can cross it with pairs that no
            # longer cross a little lower, so one enumeration below cannot tell. One walk,
            # swept from ``top`` down, asks whether it is (where not known), the pairs at
            # ``low``, and keeps the leaf pairs between, where a tooth of the nut passed
            # whole (none of its pairs crossing at ``low``) is found (:meth:`_tooth`).
            low = top - span - self.near
            sweep = eng.pairs_below(
                self._pose(rotation, xy, low), self._pose(rotation, xy, top), known_free
            )
            found = None if sweep is None else sweep.pairs
            if found is None:  # ``top`` collides
                if reach is not None:
                    under = self._under(rotation, xy, top, reach)
                    if under is None:
                        return None
                    top, known_free, passed = under, True, False
                    continue
                hit, passed = top, False
                if ceiling is not None and hit > ceiling:
                    return _Drop(
                        rotation,
                        np.array(xy, dtype=float),
                        hit,
                        hit,
                        start,
                        span,
                        cap,
                        np.empty((0, 2), dtype=np.int64),
                        np.empty(0),
                        np.empty((0, 3)),
                        verified=True,
                        above_ceiling=True,
                    )
                top += span
                span = min(2 * span, cap)
                continue
            known_free, pairs = True, found
            if len(pairs) == 0:
                pairs = self._tooth(rotation, xy, top, top - low, sweep)
            if len(pairs) == 0:
                top = low
                span = min(2 * span, cap)
                if top < self._floor:
                    return None
                continue
            drop, points = vertical_touch(*eng.triangles(self._pose(rotation, xy, top), pairs))
            ok = np.isfinite(drop)
            if not ok.any():  # only pairs seen edge-on from above: a shallower bracket
                span /= 2
                continue
            first = float(drop[ok].min())
            if first < 0.0:  # a pair crosses at ``top`` after all: start higher
                top += span - first
                known_free, passed = False, False
                continue
            touch = top - first
            # Pairs asked for below are added to those known, never put in their place: a
            # pair crossing higher up can lie wholly inside the other body lower down.
            if touch < hit:
                # Below a height known to collide: the bracket, long after a climb, passed
                # material whole (a thin tooth where a thread runs out on an end face).
                low = hit
                pairs, drop, points, more = self._with_pairs_at(
                    rotation, xy, top, pairs, drop, points, low, sweep=sweep
                )
                touch = max(touch, top - float(more[np.isfinite(more)].min(initial=math.inf)))
            if touch - low < self.near * (1 - 1e-9):
                pairs, drop, points, _ = self._with_pairs_at(
                    rotation, xy, top, pairs, drop, points, touch - self.near, sweep=sweep
                )
            return self._touching(
                _Drop(
                    rotation,
                    np.array(xy, dtype=float),
                    touch,
                    top,
                    start,
                    span,
                    cap,
                    pairs,
                    drop,
                    points,
                    sweep=sweep,
                    passed=passed,
                )
            )
        raise RuntimeError("lowering the bolt did not settle on a bracket")

    def _free_steps(
        self,
        rotation: NDArray[np.float64],
        xy: NDArray[np.float64],
        top: float,
        span: float,
        cap: float,
    ) -> tuple[float, float]:
        """The top and span from which :meth:`_bracket`, lowering from the free height
        ``top`` in steps of ``span`` doubling up to ``cap``, goes on past its first steps,
        those that meet nothing, asked in one walk (``top`` and ``span`` themselves where
        that walk meets something, or the steps are too few to gain by it).

        From above the nut, a bracket's first steps meet nothing: the bolt's end falls
        into the bore. How far it can fall is guessed from the bore
        (:meth:`threadmate.contact.scene.CollisionPair.free_fall`, a share of it); the
        steps within that are taken as the bracket takes them, and one walk swept over
        them all asks whether any meets the nut: none does where no pair crosses at the
        last one's foot and no pair the walk kept touches above it (nor within ``near``
        below, where rounding could decide), and the bracket goes on from there as it
        would have. Else it starts from ``top``: the same steps, in the same order, give
        the same touch."""
        fall = FREE_FALL_SHARE * self.engine.free_fall(self._pose(rotation, xy, top))
        steps, at, step = 0, top, span
        while at - step - self.near >= top - fall:
            at = at - step - self.near
            step = min(2 * step, cap)
            steps += 1
        if steps < 2:
            return top, span
        sweep = self.engine.pairs_below(
            self._pose(rotation, xy, at), self._pose(rotation, xy, top), True
        )
        if sweep is None or len(sweep.pairs):
            return top, span
        if len(self._tooth(rotation, xy, top, top - at + self.near, sweep)):
            return top, span
        return at, step

    def _tooth(
        self,
        rotation: NDArray[np.float64],
        xy: NDArray[np.float64],
        top: float,
        depth: float,
        sweep: Sweep | None,
    ) -> NDArray[np.int64]:
        """The pairs of a tooth of the nut the bolt, lowered from the free height ``top``
        by ``depth``, passes whole (none of them crosses at the foot): those among the
        sweep's that touch within the drop (:func:`vertical_touch`, exact). Empty where the
        drop is free. The model's height is the first touch from above (docs/mechanics.md,
        "Lowering"), and a bracket step (up to a sixteenth of a pitch) can be longer than
        a tooth is thick where a thread runs out into the countersink or the nut's face."""
        if sweep is None:
            return np.empty((0, 2), dtype=np.int64)
        candidates = sweep.candidates()
        if len(candidates) == 0:
            return candidates
        drop, _ = vertical_touch(*self.engine.triangles(self._pose(rotation, xy, top), candidates))
        # (A negative drop: the nut's triangle lies above the bolt's, met going up.)
        return candidates[np.isfinite(drop) & (drop >= 0.0) & (drop <= depth)]

    def _under(
        self, rotation: NDArray[np.float64], xy: NDArray[np.float64], top: float, reach: float
    ) -> float | None:
        """A free height just below ``top``, where the bolt there meets material above it
        by no more than ``reach`` (or the length tolerance); None otherwise."""
        eng = self.engine
        pose = self._pose(rotation, xy, top)
        pairs = eng.pairs(pose)
        if len(pairs) == 0:
            return None
        bolt, nut = eng.triangles(pose, pairs)
        # Bolt faces turned up, under the nut's material (its flank or the edge where its
        # thread meets the top face, whose faces either side both cross).
        if not np.all(upward(bolt) > 0):
            return None  # material below crosses too: no height here is free
        rise, _ = vertical_rise(bolt, nut)
        depth = -float(rise[np.isfinite(rise)].min(initial=math.inf))
        if not 0.0 <= depth <= max(reach, self.tolerance):
            return None
        lower = top - depth - 1e-3 * self.tolerance
        return None if eng.collides(self._pose(rotation, xy, lower)) else lower

    def _with_pairs_at(
        self,
        rotation: NDArray[np.float64],
        xy: NDArray[np.float64],
        top: float,
        pairs: NDArray[np.int64],
        drops: NDArray[np.float64],
        touches: NDArray[np.float64],
        at: float,
        sectors: frozenset[int] | None = None,
        sweep: Sweep | None = None,
    ) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """``pairs`` (with their ``drops`` from ``top`` and ``touches``) and the pairs that
        cross at the height ``at`` (of the nut's ``sectors``, default all) added; and the
        drops of the pairs added. Asked of ``sweep`` where it covers that pose."""
        eng = self.engine
        pose = self._pose(rotation, xy, at)
        found = (
            sweep.pairs_at(pose, sectors)
            if sweep is not None and sweep.covers(pose)
            else eng.pairs(pose, sectors)
        )
        if len(found) == 0:  # (most verifications: nothing to add)
            return pairs, drops, touches, np.empty(0)
        new = found[~np.isin(pair_keys(found), pair_keys(pairs))]
        drop, points = vertical_touch(*eng.triangles(self._pose(rotation, xy, top), new))
        return (
            np.concatenate([pairs, new]),
            np.concatenate([drops, drop]),
            np.concatenate([touches, points]),
            drop,
        )

    def _touching(self, d: _Drop, depth: float | None = None) -> _Drop:
        """``d`` with its touch raised to the first of its pairs' (when higher), and the
        gaps and points of its pairs within ``depth`` (default ``near``) below it."""
        ok = np.isfinite(d.drops)
        first = min(d.top - d.zc, float(d.drops[ok].min(initial=math.inf)))
        gaps = d.drops - first
        keep = ok & (gaps <= (self.near if depth is None else depth))
        return replace(
            d,
            zc=d.top - first,
            gaps=np.maximum(gaps[keep], 0.0),
            points=d.touches[keep],
        )

    def verified(self, d: _Drop) -> _Drop:
        """``d`` at the first touch below its free top.

        The pairs crossing at the bracket's foot can miss what the bolt meets first, as
        the collision query sees crossing triangles, never containment:

        - a bolt triangle meeting a nut flank nearly parallel to it sinks whole into the
          nut within the bracket and then crosses no nut triangle. The pairs crossing just
          above the touch are the ones missed: there are none, or they raise the touch;
        - a long bracket passes a thin tooth whole (where a thread runs out on an end
          face, a few 1e-4 in thick). Yes/no queries every :attr:`probe` above the touch
          find it, and the pairs crossing there raise the touch.

        Both touch the bolt first between the bracket's top and its touch, and whether any
        pair does is asked first, exactly (:meth:`_met_above`): mostly none does, and the
        touch stands. Where one does, the pairs crossing just above and the probes raise
        the touch (:meth:`_probed`), and what they still miss is raised to exactly
        (:meth:`_raised`). A lowering whose walks did not pass every height from its start
        so (:attr:`_Drop.passed`) is then checked for a vertex of one body deep in the
        other (:meth:`_embedded`).
        """
        if d.verified:
            return d
        while True:
            sweep = self._covering(d)
            if len(self._met_above(d, sweep)):
                # What the probes and the raise ask meets the bolt within the drop to the
                # touch and ``near`` below: their walk's leaf pairs narrowed to those.
                top = self._pose(d.rotation, d.xy, d.top)
                narrow = sweep.narrowed(top, d.top - d.zc + self.near)
                raised = self._raised(self._probed(replace(d, sweep=narrow)), narrow)
                d = replace(raised, sweep=d.sweep)
            if d.passed or not (
                d.start - d.zc > 2 * self.near and self._embedded(d.rotation, d.xy, d.zc)
            ):
                return replace(d, verified=True)
            # A thin wedge of one body (where a thread runs out on an end face) passed whole
            # into the other within a step. Again from the start, in steps a quarter as long.
            cap = d.cap / 4
            if cap < self.tolerance:
                raise RuntimeError("lowering the bolt keeps passing into the nut")
            found = self._bracket(d.rotation, d.xy, d.start, min(d.span, cap), False, cap)
            if found is None:  # pragma: no cover - the bolt touched from this start before
                raise RuntimeError("lowering the bolt passed the nut on a second try")
            d = found

    def _covering(self, d: _Drop) -> Sweep:
        """A walk swept between ``d``'s free top and its touch: its bracket's last, or,
        where that one does not cover the heights between, one of its own."""
        top, at = self._pose(d.rotation, d.xy, d.top), self._pose(d.rotation, d.xy, d.zc)
        if d.sweep is not None and d.sweep.covers(top) and d.sweep.covers(at):
            return d.sweep
        sweep = self.engine.pairs_below(at, top, free=True)
        assert sweep is not None  # (None only where the top, not asked, collides)
        return sweep

    def _met_above(self, d: _Drop, sweep: Sweep, depth: float = 0.0) -> NDArray[np.int64]:
        """The pairs the bolt meets lowered from ``d``'s free top to more than the
        tolerance above its touch (and ``depth`` below that), exactly: every pair that
        touches between the top and the touch is among the leaf pairs of ``sweep``, a walk
        swept between the two, and one compiled pass tests each as the bolt moves down
        (:meth:`Sweep.touching_within`). (Touching just above within rounding is free
        there.)"""
        drop = d.top - d.zc - self.tolerance
        if drop <= 0.0:
            return np.empty((0, 2), dtype=np.int64)
        return sweep.touching_within(self._pose(d.rotation, d.xy, d.top), drop + depth)

    def _raised(self, d: _Drop, sweep: Sweep) -> _Drop:
        """``d`` raised to the first pair it meets lowered from its free top (:meth:`_met_above`),
        with the pairs within :attr:`near` below that one; ``d`` where it meets none."""
        found = self._met_above(d, sweep, self.near)
        new = found[~np.isin(pair_keys(found), pair_keys(d.pairs))]
        if not len(new):
            return d
        drop, points = vertical_touch(
            *self.engine.triangles(self._pose(d.rotation, d.xy, d.top), new)
        )
        ok = np.isfinite(drop) & (drop >= 0.0)
        if not ok.any() or d.top - float(drop[ok].min()) <= d.zc + self.tolerance:
            return d
        keep = ok & (drop <= float(drop[ok].min()) + self.near)
        return self._touching(
            replace(
                d,
                pairs=np.concatenate([d.pairs, new[keep]]),
                drops=np.concatenate([d.drops, drop[keep]]),
                touches=np.concatenate([d.touches, points[keep]]),
            )
        )

    def _probed(self, d: _Drop) -> _Drop:
        """``d`` raised by the pairs crossing just above its touch and by those at the
        first of the yes/no queries every :attr:`probe` above it that collides (see
        :meth:`verified`), until neither raises it."""
        eng = self.engine
        above, probed = d.zc + self.tolerance, d.zc
        while above < d.top:
            # Just above the touch, the pairs missed lie within the crossing pairs' ring:
            # a region of one body sunk into the other is bounded by crossings. At a probe
            # that collides, anywhere.
            around = eng.sectors_around(d.pairs) if above == d.zc + self.tolerance else None
            pairs, drops, touches, more = self._with_pairs_at(
                d.rotation, d.xy, d.top, d.pairs, d.drops, d.touches, above, around, d.sweep
            )
            raised = more[np.isfinite(more)]
            # (Touching just above within rounding is free there.)
            if len(raised) and d.top - float(raised.min()) > d.zc + self.tolerance:
                d = self._touching(replace(d, pairs=pairs, drops=drops, touches=touches))
                above, probed = d.zc + self.tolerance, d.zc
                continue
            above = probed + self.probe
            while above < d.top and not self._collides(
                self._pose(d.rotation, d.xy, above), d.sweep
            ):
                above += self.probe
            probed = above
        return d

    def _collides(self, pose: Pose, sweep: Sweep | None) -> bool:
        """Whether the bolt at ``pose`` meets the nut, asked of ``sweep`` where it covers
        the pose."""
        if sweep is not None and sweep.covers(pose):
            return sweep.collides_at(pose)
        return self.engine.collides(pose)

    def _deepened(self, d: _Drop, depth: float) -> _Drop:
        """``d`` knowing every contact within ``depth`` (more than ``near``) below its
        touch."""
        if depth <= self.near:
            return d
        pairs, drops, touches, _ = self._with_pairs_at(
            d.rotation, d.xy, d.top, d.pairs, d.drops, d.touches, d.zc - depth, sweep=d.sweep
        )
        return self._touching(replace(d, pairs=pairs, drops=drops, touches=touches), depth)

    def _nudged(self, d: _Drop, rotation: NDArray[np.float64], xy: NDArray[np.float64]) -> _Drop:
        """``d`` turned to ``rotation`` over ``xy`` by a motion that moves no bolt point
        by more than :attr:`tolerance` (with the nudges before it, since the collision
        queries last lowered the bolt), lowered onto its own pairs.

        The balance asks for tilts far finer than the length tolerance (the last steps
        of a descent move the bolt by nanometres), and any pair the motion brings to touch
        was within ``near`` below the touch before it, so among the pairs ``d`` knows: the
        exact drops of those pairs from ``d``'s free top, with no collision query, give
        the touch (what a query could add lies within the tolerance).
        """
        eng = self.engine
        drops, touches = vertical_touch(*eng.triangles(self._pose(rotation, xy, d.top), d.pairs))
        ok = np.isfinite(drops)
        first = float(drops[ok].min()) if ok.any() else d.top - d.zc
        nudged = self._touching(
            replace(
                d,
                rotation=rotation,
                xy=np.array(xy, dtype=float),
                zc=d.top - first,
                drops=drops,
                touches=touches,
                verified=True,
                sweep=None,  # another pose
            )
        )
        # The material above as well: its pairs are those known (the motion is as small).
        return nudged if d.over_pairs is None else self._overhead(nudged)

    def _overhead(self, d: _Drop) -> _Drop:
        """``d`` knowing the nut's material within :attr:`near` above the bolt.

        In the thread the bolt lies between two nut flanks. Tilted as it goes in, or
        turned where the thread starts pinch it, its flank meets the nut's flank above:
        that bounds its motion from above as the pairs below bound it from below (a
        contact whose normal points down, opening as the bolt moves down). Only where the
        bolt's end lies below the nut's top face can nut material lie over it. The pairs
        are looked for once per lowering (one enumeration, lifted by ``near``) and their
        rises re-evaluated exactly at each pose.
        """
        eng = self.engine
        pairs = d.over_pairs
        pose = self._pose(d.rotation, d.xy, d.zc)
        if pairs is None:
            if d.zc >= self._clear_of_top(d.rotation):
                pairs = np.empty((0, 2), dtype=np.int64)
            else:
                found = eng.pairs_under_material(self._pose(d.rotation, d.xy, d.zc + self.near))
                bolt, _ = eng.triangles(pose, found)
                # A nut face turned down over a bolt face turned up (outward normals): the
                # pairs of the contacts below, which a lift only separates, are not these.
                pairs = found[(upward(bolt) > 0) & (eng.nut_upward[found[:, 1]] < 0)]
        if len(pairs) == 0:
            return replace(d, over_pairs=pairs, rises=np.empty(0), over_points=np.empty((0, 3)))
        rise, points = vertical_rise(*eng.triangles(pose, pairs))
        keep = np.isfinite(rise) & (rise <= self.near)
        return replace(
            d, over_pairs=pairs, rises=np.maximum(rise[keep], 0.0), over_points=points[keep]
        )

    def _embedded(self, rotation: NDArray[np.float64], xy: NDArray[np.float64], zc: float) -> bool:
        """Whether a vertex of one mesh lies inside the other exact body, deeper than the
        meshes' deviation, at the pose where the bolt's centre is at ``zc``."""
        pose = self._pose(rotation, xy, zc)
        an = self.scene
        depth = 2 * an.deviation + self.tolerance
        # Only the points a compiled pass keeps can be that deep (the nut's near its top
        # against the bolt, the bolt's near its end against the nut); the exact tests for
        # those alone.
        for body, points, inverse in (
            (an.bolt, self._nut_top, True),
            (an.nut, self._bolt_tip, False),
        ):
            near = deep_candidates(
                body,
                points,
                pose.rotation,
                pose.origin,
                inverse=inverse,
                depth=depth,
                margin=self.tolerance,
            )
            if not len(near):
                continue
            points = pose.to_bolt(points[near]) if inverse else pose.to_fixed(points[near])
            inside = points[body.contains(points)]
            deep = inside[body.surface_distance(inside) > depth]
            # A mesh from CAD is taken as given: deep in the spec's body is not inside the
            # mesh where it does not follow the spec (an unstated point or countersink).
            if len(deep) and (
                self._off is None
                or body.kind not in self._off.bodies
                or float(self.engine.signed_distance(body.kind, deep).min()) < -depth
            ):
                return True
        return False
