"""Rest states of the compliance-held bolt: an active-set descent of the potential.

docs/mechanics.md fixes the model. The bolt's free coordinates are the height ``z_C`` of
the compliance centre C and the tilt ``(roll, pitch)`` (and ``x_C, y_C`` when the
compliance has a lateral stiffness); the driver holds the phase. The potential is

    U = F z_C + k_roll/2 (roll - roll0)^2 + k_pitch/2 (pitch - pitch0)^2 (+ k_t/2 |xy|^2)

and a rest state is a local minimiser of U over the poses where bolt and nut do not
interpenetrate.

The descent. At the current pose the bolt touches the nut (it was lowered onto it); the
contacts within a small depth ``near`` below it are known with their vertical gaps, exact
for the meshes (:mod:`._vertical`), their points, and their normals and regions from the
exact bodies (:mod:`._exact`). A contact ``i`` at ``p_i`` with normal ``n_i`` (nut into
bolt) opens at the rate ``G_i . dq`` for a small motion ``dq`` of the coordinates, with
``G_i = (n_z, X . (r_i x n_i), Y' . (r_i x n_i)[, n_x, n_y])``, ``r_i = p_i - C``, ``X``
the roll axis and ``Y' = Rx(roll) Y`` the pitch axis. One step minimises the quadratic
model of U plus a proximal term under the linearised contacts (:mod:`._lcp`); its
multipliers are the contact forces. The bolt is then tilted by the step and lowered onto
the nut again with python-fcl (so every accepted pose touches and nothing
interpenetrates; a step that moves no bolt point by more than the length tolerance, onto
the pairs already known: :meth:`Mechanics._nudged`), and the step is kept when U fell
by a fair part of what the model promised (else the proximal weight grows: a trust
region). A contact released by the step is the thesis's rolling pivot; a contact that
appears is its next contact. The descent stops when the contact forces balance the load
and the spring (see :data:`BALANCE`).

Lowering (:meth:`Mechanics.drop`): the bolt at a tilt is placed a little above where it
is expected to touch, checked free with one yes/no query, and every triangle pair that
intersects a little lower is enumerated with one more; the exact drop at which each pair
first touches (:func:`vertical_touch`) gives the contact height without bisection, and
the gaps of the other contacts within the depth ``near``. A lowering that is kept is
verified (:meth:`Mechanics.verified`): the pairs crossing just above its touch, and
yes/no queries above it, find what the pairs at the bracket's foot missed.

Classes (mechanics.md), from the forces and the minimum, never from the way there:

- ``in-phase`` (engaged): every contact that carries the load lies on the helices
  (:func:`on_helix`: a bolt flank on the nut's thread or on the edge where it meets the
  nut's entry, or the bolt's end on a nut flank), so that turning moves the bolt along
  the helix (the snap lands here);
- ``stable``: the touching contacts alone hold the load: the load's generalised force
  ``(F, 0, 0)`` (and ``(0, 0)`` laterally when x, y are free) lies inside the cone of the
  contact rows with a margin: each of it pushed by ``F/100`` in height or by ``F`` times
  ``support_margin`` (pitch / 100) in moment is still balanced by non-negative forces.
  The state is then a strict minimum of U with ``k_r = 0``;
- ``quasi-stable``: a rest state that needs the compliance;
- ``unstable``: a contact state that is not a rest state (the states on the way).

Friction does not enter the equilibrium (mechanics.md): with C at the tip the sliding
friction of the spin acts nearly through C; it enters the driver's torque.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint, lsq_linear, minimize, nnls
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import ConvexHull, QhullError, cKDTree

from ..._angles import TWO_PI, axis_angle, phase_difference
from ..._errors import InputError
from ..._units import METRES_PER_UNIT, MJ_PER_J
from ..._validate import check_configuration, check_open_range
from ...geometry import Pose, ThreadSpec, bolt_rotation, rot_x
from ..scene import (
    ContactScene,
    as_vec,
    contact_normal,
    contact_scene,
    edge_crossing,
    lowest_on_rim,
    on_thread,
    pair_keys,
    refined_contact,
    region_at,
    vertical_rise,
    vertical_touch,
)
from ._compliance import Compliance
from ._lcp import contact_step
from ._rest_state import LoadedContact, MechanicalState, RestState

__all__ = ["Mechanics", "BALANCE", "MAX_STEPS", "mechanics", "settle"]

#: Largest residual of the equilibrium at a rest state, relative to the load (force: F;
#: moment: F times the bolt's major radius).
BALANCE = 1e-6
#: Largest contact force the model reports, in units of what the load and the spring can
#: press a contact with (:meth:`Mechanics.force_bound`): beyond it the rigid balance is
#: near-singular and the forces are bounded (:meth:`Mechanics.bounded`).
NEAR_SINGULAR = 3.0
#: Descent steps before a rest state is given up as not converged.
MAX_STEPS = 60
#: Descent steps over which a continued descent (one leaving a rest state at a nearby
#: phase) that neither lowered the potential by more than the mesh's noise nor its least
#: equilibrium residual by 1 % has stalled. It stops there: at the thread starts, where
#: both bodies' run-outs meet edge to edge, such descents would run on to ``MAX_STEPS``
#: without moving. (Not while tipping into a seat, nor from first contact: an upright
#: point settling on the countersink's ring of edges can wander that long before it finds
#: its support.)
STALL_STEPS = 20
#: Tilt (degrees) within which a bolt touching the nut's entry with its end only is tried
#: seated upright (:meth:`Mechanics._seat`), and the regions of such contacts.
SEAT_TILT = 3.0
# (``point``: a CAD bolt's end where it does not follow the spec, _exact.off_spec_region.)
SEAT_BOLT_REGIONS = frozenset({"base", "chamfer", "round", "point"})
SEAT_NUT_REGIONS = frozenset({"surface", "countersink"})
#: Force above which a contact carries the load (relative to the axial load): one below it
#: touches without load, or hovers at the touching threshold, and changes nothing a driver
#: or a sensor sees.
LOAD_CARRYING = 1e-4
#: Arc (degrees about the axis) of a contact along the helices that one point of it stands
#: for (:meth:`Mechanics._along_helix`).
HELIX_ARC = 30.0
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
    # The nut's material above the bolt (Mechanics._overhead; None: not looked for yet):
    # face pairs, each one's rise to its touch and where.
    over_pairs: NDArray[np.int64] | None = None
    rises: NDArray[np.float64] = field(default_factory=lambda: np.empty(0))
    over_points: NDArray[np.float64] = field(default_factory=lambda: np.empty((0, 3)))


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


class Mechanics:
    """Rest states and the counter-clockwise search of one thread pair and compliance.

    Its world (exact bodies, meshes, the python-fcl pair, the tolerances) is a
    :class:`ContactScene`, built once per process and shared with the thesis's procedure;
    one instance per process (python-fcl objects neither pickle nor release the GIL).

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair (lengths in ``spec.units``).
    compliance : Compliance, optional
        Load, stiffness and friction (default :class:`Compliance()`).
    chord : float, optional
        Chord tolerance of the generated meshes (spec units).
    bolt_mesh, nut_mesh : path or trimesh.Trimesh, optional
        Meshes from CAD, each in its own frame (see :class:`ContactScene`).
    mesh_units : {"in", "mm"}, optional
        Units of the mesh files (see :class:`ContactScene`).
    max_faces : int, optional
        Most triangles a mesh file may have (see :class:`ContactScene`).
    scene : ContactScene, optional
        A scene already built (default :func:`contact_scene` of the spec, chord and
        meshes, built once per process); its spec must be ``spec``.
    tolerance : float, optional
        Length tolerance of the descent (spec units, default the contact stages' travel
        tolerance, 1e-7 in): a rest state's tilt is converged when no bolt point would
        move by more than it.
    """

    def __init__(
        self,
        spec: ThreadSpec,
        compliance: Compliance | None = None,
        *,
        chord: float | None = None,
        bolt_mesh: object = None,
        nut_mesh: object = None,
        mesh_units: str | None = None,
        tolerance: float | None = None,
        scene: ContactScene | None = None,
        max_faces: int | None = None,
    ) -> None:
        if compliance is None:
            compliance = Compliance()
        if not isinstance(compliance, Compliance):
            raise InputError(f"compliance must be a Compliance, got {type(compliance).__name__}")
        if not isinstance(spec, ThreadSpec):
            raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
        compliance.check_for(spec.pitch)
        if scene is None:
            scene = contact_scene(
                spec,
                chord=chord,
                bolt_mesh=bolt_mesh,
                nut_mesh=nut_mesh,
                mesh_units=mesh_units,
                max_faces=max_faces,
            )
        elif scene.spec != spec:
            raise InputError("the scene's spec differs from the spec given")
        self.spec = spec
        self.units = spec.units
        self.compliance = compliance
        #: The exact bodies, meshes, collision pair and tolerances (:class:`ContactScene`).
        self.scene = scene
        self.engine = scene.engine
        self.metres = METRES_PER_UNIT[spec.units]
        travel = scene.travel
        if tolerance is not None:
            travel = check_open_range(
                "tolerance", tolerance, 0.0, spec.pitch / 100, units=spec.units
            )
        self.tolerance = travel
        #: Depth below the touching pose within which contacts are known to the descent.
        self.near = spec.pitch / 5000
        #: Spacing of the yes/no queries with which a lowering looks for material it passed
        #: whole above its touch (:meth:`verified`).
        self.probe = spec.pitch / 256
        #: Gap below which a contact counts as touching (carries force at rest).
        self.touching = 20 * travel
        #: Margin of a stable state's support (see the module docstring).
        self.support_margin = spec.pitch / 100
        #: Descent steps without progress after which a descent has stalled (STALL_STEPS).
        self.stall_steps = STALL_STEPS
        self.separation = spec.pitch / 4
        self.radius = 0.5 * spec.bolt.major  # moment scale (spec units)
        self._floor = scene.nut.z_min - 2 * scene.bolt.z_max - spec.pitch
        # Vertices that can pass whole into the other body: the nut's in its top pitch,
        # the bolt's in its first (the thread's run-outs on the end faces are wedges),
        # counted from where the full thread begins.
        nv, bv = self.engine.nut_vertices, self.engine.bolt_vertices
        self._nut_top = nv[nv[:, 2] >= -spec.pitch - spec.countersink_depth]
        self._bolt_tip = bv[bv[:, 2] <= spec.pitch + spec.point_height]
        #: Where meshes from CAD do not follow the spec (None: generated meshes).
        self._off = scene.off_spec

    @property
    def tolerances(self) -> dict[str, float]:
        """Tolerances in force (spec units): the descent's travel, the feature tolerance
        of the exact contact geometry, the touching gap, the contacts' grouping distance
        and the meshes' deviation."""
        return {
            "travel": self.tolerance,
            "feature": self.scene.feature_tolerance,
            "touching": self.touching,
            "separation": self.separation,
            "mesh_deviation": self.scene.deviation,
        }

    @property
    def load_carrying(self) -> float:
        """Force (N) above which a contact carries the load: :data:`LOAD_CARRYING` times
        the axial load. The one threshold of the descent, the search and the sweep."""
        return LOAD_CARRYING * self.compliance.force

    # -- poses ----------------------------------------------------------------------------
    def _pose(self, rotation: NDArray[np.float64], xy: NDArray[np.float64], zc: float) -> Pose:
        centre = np.array([xy[0], xy[1], zc])
        return Pose(rotation, centre - rotation[:, 2] * self.compliance.compliance_z)

    def _rotation(self, tilt: NDArray[np.float64], phase: float) -> NDArray[np.float64]:
        return bolt_rotation(math.degrees(tilt[0]), math.degrees(tilt[1]), phase)

    def _clear_of_top(self, rotation: NDArray[np.float64]) -> float:
        """Height of the compliance centre at which the bolt's lowest point lies on the
        nut's top face."""
        return -self.engine.lowest_bolt_z(rotation) + self.compliance.compliance_z * rotation[2, 2]

    # -- lowering -------------------------------------------------------------------------
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
            rotation, xy, top, span, known_free, self.spec.pitch / 16, None if climb else reach
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
    ) -> _Drop | None:
        """The touch the pairs crossing at a bracket's foot give, lowering from ``top`` in
        steps of ``span`` doubling up to ``cap`` (see :meth:`drop`; ``reach``: no climb)."""
        eng = self.engine
        start, hit = top, -math.inf  # hit: the highest height known to collide
        for _ in range(200):
            # ``top`` must be free: a pose deep in the nut can cross it with pairs that no
            # longer cross a little lower, so one enumeration below cannot tell.
            if not known_free:
                if eng.collides(self._pose(rotation, xy, top)):
                    if reach is not None:
                        under = self._under(rotation, xy, top, reach)
                        if under is None:
                            return None
                        top, known_free = under, True
                        continue
                    hit = top
                    top += span
                    span = min(2 * span, cap)
                    continue
                known_free = True
            low = top - span - self.near
            pairs = eng.pairs(self._pose(rotation, xy, low))
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
                known_free = False
                continue
            touch = top - first
            # Pairs asked for below are added to those known, never put in their place: a
            # pair crossing higher up can lie wholly inside the other body lower down.
            if touch < hit:
                # Below a height known to collide: the bracket, long after a climb, passed
                # material whole (a thin tooth where a thread runs out on an end face).
                low = hit
                pairs, drop, points, more = self._with_pairs_at(
                    rotation, xy, top, pairs, drop, points, low
                )
                touch = max(touch, top - float(more[np.isfinite(more)].min(initial=math.inf)))
            if touch - low < self.near * (1 - 1e-9):
                pairs, drop, points, _ = self._with_pairs_at(
                    rotation, xy, top, pairs, drop, points, touch - self.near
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
                )
            )
        raise RuntimeError("lowering the bolt did not settle on a bracket")

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
        if not np.all(_facing(bolt) > 0):
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
    ) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """``pairs`` (with their ``drops`` from ``top`` and ``touches``) and the pairs that
        cross at the height ``at`` (of the nut's ``sectors``, default all) added; and the
        drops of the pairs added."""
        eng = self.engine
        found = eng.pairs(self._pose(rotation, xy, at), sectors)
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
        python-fcl sees crossing triangles, never containment:

        - a bolt triangle meeting a nut flank nearly parallel to it sinks whole into the
          nut within the bracket and then crosses no nut triangle. The pairs crossing just
          above the touch are the ones missed: there are none, or they raise the touch;
        - a long bracket passes a thin tooth whole (where a thread runs out on an end
          face, a few 1e-4 in thick). Yes/no queries every :attr:`probe` above the touch
          find it, and the pairs crossing there raise the touch.
        """
        if d.verified:
            return d
        eng = self.engine
        while True:
            above, probed = d.zc + self.tolerance, d.zc
            while above < d.top:
                # Just above the touch, the pairs missed lie within the crossing pairs'
                # ring: a region of one body sunk into the other is bounded by crossings.
                # At a probe that collides, anywhere.
                around = eng.sectors_around(d.pairs) if above == d.zc + self.tolerance else None
                pairs, drops, touches, more = self._with_pairs_at(
                    d.rotation, d.xy, d.top, d.pairs, d.drops, d.touches, above, around
                )
                raised = more[np.isfinite(more)]
                # (Touching just above within rounding is free there.)
                if len(raised) and d.top - float(raised.min()) > d.zc + self.tolerance:
                    d = self._touching(replace(d, pairs=pairs, drops=drops, touches=touches))
                    above, probed = d.zc + self.tolerance, d.zc
                    continue
                above = probed + self.probe
                while above < d.top and not eng.collides(self._pose(d.rotation, d.xy, above)):
                    above += self.probe
                probed = above
            if not (d.start - d.zc > 2 * self.near and self._embedded(d.rotation, d.xy, d.zc)):
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

    def _deepened(self, d: _Drop, depth: float) -> _Drop:
        """``d`` knowing every contact within ``depth`` (more than ``near``) below its
        touch."""
        if depth <= self.near:
            return d
        pairs, drops, touches, _ = self._with_pairs_at(
            d.rotation, d.xy, d.top, d.pairs, d.drops, d.touches, d.zc - depth
        )
        return self._touching(replace(d, pairs=pairs, drops=drops, touches=touches), depth)

    def _nudged(self, d: _Drop, rotation: NDArray[np.float64], xy: NDArray[np.float64]) -> _Drop:
        """``d`` turned to ``rotation`` over ``xy`` by a motion that moves no bolt point
        by more than :attr:`tolerance` (with the nudges before it, since python-fcl last
        lowered the bolt), lowered onto its own pairs.

        The balance asks for tilts far finer than the length tolerance (the last steps
        of a descent move the bolt by nanometres), and any pair the motion brings to touch
        was within ``near`` below the touch before it, so among the pairs ``d`` knows: the
        exact drops of those pairs from ``d``'s free top, with no python-fcl query, give
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
                found = eng.pairs(self._pose(d.rotation, d.xy, d.zc + self.near))
                bolt, nut = eng.triangles(pose, found)
                # A nut face turned down over a bolt face turned up (outward normals): the
                # pairs of the contacts below, which a lift only separates, are not these.
                pairs = found[(_facing(bolt) > 0) & (_facing(nut) < 0)]
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
        # Only points within the other body's slab can be inside it: their height there
        # first (one product per point), the whole transform for those alone.
        rot, origin = pose.rotation, pose.origin
        bolt_z = (self._nut_top - origin) @ rot[:, 2]
        nut_z = self._bolt_tip @ rot[2] + origin[2]
        bolt, nut = an.bolt, an.nut
        m = self.tolerance  # a margin: rounding differs from the full transform's
        candidates = (
            (
                bolt,
                pose.to_bolt(
                    self._nut_top[(bolt_z >= bolt.z_min - m) & (bolt_z <= bolt.z_max + m)]
                ),
            ),
            (
                nut,
                pose.to_fixed(self._bolt_tip[(nut_z >= nut.z_min - m) & (nut_z <= nut.z_max + m)]),
            ),
        )
        for body, points in candidates:
            # Only points on the material's side of the profile's extreme radius can be
            # inside (the bolt's material lies within r_hi, the nut's beyond r_lo): most
            # are not, and the exact test is dearer.
            z, r2 = points[:, 2], points[:, 0] ** 2 + points[:, 1] ** 2
            prof = body.profile
            if body.kind == "bolt":
                maybe = r2 <= prof.r_hi**2 * (1 + 1e-9)
            else:
                maybe = r2 >= prof.r_lo**2 * (1 - 1e-9)
            points = points[maybe & (z >= body.z_min) & (z <= body.z_max)]
            inside = points[body.contains(points)]  # cheap; the distance only for these
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

    def engaged(self, near: list[_Near], forces: NDArray[np.float64] | None = None) -> bool:
        """Whether the bolt's thread is in the nut's (in phase, mechanics.md): every
        contact that carries the load lies on a helix (:func:`on_helix`), so that turning
        moves the bolt along the helix.

        With ``forces`` (a rest state's), the contacts carrying more than
        :data:`LOAD_CARRYING` times the load; without (a pose on the way), the touching
        ones. Nothing here depends on the tilt or on where the bolt is: only on what
        carries it.
        """
        if forces is None:
            carrying = [c for c in near if c.gap <= self.touching]
        else:
            floor = self.load_carrying
            carrying = [c for c, f in zip(near, forces, strict=True) if f > floor]
        return bool(carrying) and all(c.helical for c in carrying)

    # -- the seated tip -------------------------------------------------------------------
    def _seating(self, near: list[_Near], tilt: NDArray[np.float64]) -> bool:
        """Whether the bolt is tipping into a seat: within ``SEAT_TILT`` of upright, it
        touches the nut's entry (top face, countersink) with its end only (tip face,
        point), and no thread touches."""
        touching = [c for c in near if c.gap <= self.touching]
        return (
            bool(touching)
            and all(
                c.bolt_region in SEAT_BOLT_REGIONS and c.nut_region in SEAT_NUT_REGIONS
                for c in touching
            )
            and float(np.hypot(*tilt)) <= math.radians(SEAT_TILT)
        )

    def _seat(
        self,
        d: _Drop,
        tilt: NDArray[np.float64],
        phase: float,
        held: NDArray[np.float64],
        u_most: float,
    ) -> tuple[_Drop, list[_Near], NDArray[np.float64], float] | None:
        """The bolt seated upright in the nut's entry (the tip face flat on the top face,
        the point in the countersink), if it lies below the potential ``u_most``, lowered
        onto the nut there and touching end on entry only.

        A face landing on a face, or a point centring in a countersink, is where the
        descent's linearised contacts serve worst (the support jumps from a rim point to a
        patch, or runs round a ring); the seated pose is known but for its height, so it
        is tried once, as a step. The descent goes on from it: it is a rest state when its
        contacts balance the load and the spring (the KKT conditions), and the descent
        leaves it (a touch off upright, where coplanar meshes miss pairs) when not.
        """
        upright = np.zeros(2)
        rotation = self._rotation(upright, phase)
        # Turning upright moves no bolt point farther than this: the seat's height is
        # within it of the present one.
        reach = float(np.hypot(*tilt)) * (self.radius + self.scene.bolt.z_max)
        # The seat lies below ``u_most`` only if it lies below this height. Where the bolt
        # collides there, the seat (the first touch from above, so no lower) does not:
        # one yes/no query, cheap where it collides, spares the lowering (a face landing
        # on a face meets a thousand triangle pairs). Most seats tried fail so.
        highest = (u_most - self.potential(0.0, upright, d.xy, held)) / (
            self.compliance.force * self.metres
        )
        if highest <= d.zc + reach - self.near and self.engine.collides(
            self._pose(rotation, d.xy, highest)
        ):
            return None
        seat = self.drop(rotation, d.xy, d.zc, span=reach + 4 * self.tolerance)
        if seat is None:
            return None
        u = self.potential(seat.zc, upright, seat.xy, held)
        if u >= u_most:
            return None
        near = self.contacts(seat)
        if not self._seating(near, upright):
            return None
        return seat, near, upright, u

    # -- contacts -------------------------------------------------------------------------
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
                out.extend(
                    self._contact(d, pts[flat][c], float(gaps[flat][c]), refine=False)
                    for c in corners
                )
            if first.helical:
                out.extend(self._along_helix(d, pts, gaps, j))
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
        return _single_linkage(points[first], self.separation)[inverse.reshape(-1)]

    def _along_helix(
        self, d: _Drop, pts: NDArray[np.float64], gaps: NDArray[np.float64], j: int
    ) -> list[_Near]:
        """The rest of a contact along the helices: where one flank lies along the other
        (the bolt in the thread), the pairs within ``near`` run round the axis as one
        group; its least gap in each :data:`HELIX_ARC` of it (beyond the one holding
        ``j``, the group's least) is a contact of its own, so that the descent knows
        the whole line it may tip onto, not its lowest point alone."""
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

    # -- mechanics ------------------------------------------------------------------------
    def _rows(
        self, near: list[_Near], centre: NDArray[np.float64], tilt: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Contact rows ``G`` (SI: per m and per rad) and normal gaps (m)."""
        m = self.metres
        width = 3 if self.compliance.held_laterally else 5
        if not near:
            return np.zeros((0, width)), np.zeros(0)
        pitch_axis = rot_x(math.degrees(tilt[0]))[:, 1]
        # All contacts at once: a descent step builds these rows a few times.
        normal = np.array([c.normal for c in near], dtype=float)
        r = (np.array([c.point for c in near], dtype=float) - centre) * m
        # ``np.cross``'s formula, written out: its axis handling costs more than the
        # products on a few rows.
        moment = np.column_stack(
            [
                r[:, 1] * normal[:, 2] - r[:, 2] * normal[:, 1],
                r[:, 2] * normal[:, 0] - r[:, 0] * normal[:, 2],
                r[:, 0] * normal[:, 1] - r[:, 1] * normal[:, 0],
            ]
        )
        cols = [normal[:, 2], moment[:, 0], moment @ pitch_axis]
        if not self.compliance.held_laterally:
            cols += [normal[:, 0], normal[:, 1]]
        gaps = np.array([c.gap for c in near], dtype=float) * m
        return np.column_stack(cols), gaps * self._rate(near, range(len(near)))

    @staticmethod
    def _rate(near: list[_Near], rows: Iterable[int]) -> NDArray[np.float64]:
        """Normal gap per vertical gap of contacts ``rows``: the normal's upward part
        below the bolt, its downward part above (at least 0.05: a level normal)."""
        return np.array(
            [max(-near[i].normal[2] if near[i].upper else near[i].normal[2], 0.05) for i in rows]
        )

    def _gradient(
        self, tilt: NDArray[np.float64], xy: NDArray[np.float64], held: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Gradient of U in (z_C, roll, pitch[, x, y]) (SI)."""
        comp = self.compliance
        g = [
            comp.force,
            comp.roll_stiffness * (tilt[0] - held[0]),
            comp.pitch_stiffness * (tilt[1] - held[1]),
        ]
        if comp.lateral_stiffness is not None:  # not held laterally
            g += list(comp.lateral_stiffness * xy * self.metres)
        return np.array(g)

    def _stiffness(self) -> NDArray[np.float64]:
        comp = self.compliance
        k = [0.0, comp.roll_stiffness, comp.pitch_stiffness]
        if comp.lateral_stiffness is not None:  # not held laterally
            k += [comp.lateral_stiffness] * 2
        return np.array(k)

    def potential(
        self,
        zc: float,
        tilt: NDArray[np.float64],
        xy: NDArray[np.float64],
        held: NDArray[np.float64],
    ) -> float:
        """U in J (``z_C`` in spec units from the nut's top, tilts in radians)."""
        comp = self.compliance
        u = comp.force * zc * self.metres
        u += 0.5 * comp.roll_stiffness * (tilt[0] - held[0]) ** 2
        u += 0.5 * comp.pitch_stiffness * (tilt[1] - held[1]) ** 2
        if comp.lateral_stiffness is not None:  # not held laterally
            u += 0.5 * comp.lateral_stiffness * float(xy @ xy) * self.metres**2
        return float(u)

    def _balance_scale(self, n: int) -> NDArray[np.float64]:
        """Weights of the balance's ``n`` rows that make moments forces (over the bolt's
        major radius), so that force and moment residuals compare."""
        scale = np.ones(n)
        scale[1:3] = 1.0 / (self.radius * self.metres)
        return scale

    def forces(
        self,
        near: list[_Near],
        centre: NDArray[np.float64],
        tilt: NDArray[np.float64],
        xy: NDArray[np.float64],
        held: NDArray[np.float64],
    ) -> tuple[NDArray[np.float64], float, float]:
        """Non-negative normal forces (N) of the touching contacts that best balance the
        load and the spring, and the force and moment residuals relative to the load."""
        touching = [c for c in near if c.gap <= self.touching]
        grad = self._gradient(tilt, xy, held)
        f = self.compliance.force
        scale = self._balance_scale(len(grad))
        if not touching:
            return np.zeros(len(near)), 1.0, float(np.abs(grad[1:3]).max() * scale[1] / f)
        G, _ = self._rows(touching, centre, tilt)
        lam, _ = nnls((G * scale).T, grad * scale)
        resid = (G.T @ lam - grad) * scale / f
        forces = np.zeros(len(near))
        forces[[i for i, c in enumerate(near) if c.gap <= self.touching]] = lam
        moment = float(np.abs(resid[1:]).max()) if len(resid) > 1 else 0.0
        return forces, float(abs(resid[0])), moment

    def force_bound(self, tilt: NDArray[np.float64], held: NDArray[np.float64]) -> float:
        """The largest contact force the model reports (N): :data:`NEAR_SINGULAR` times
        what the load and the spring can press a contact with (the axial force, and the
        spring's moment over the bolt's major radius)."""
        k = self._stiffness()[1:3]
        moment = float(np.abs(k * (tilt - held)).max())
        return NEAR_SINGULAR * (self.compliance.force + moment / (self.radius * self.metres))

    def bounded(
        self,
        near: list[_Near],
        forces: NDArray[np.float64],
        centre: NDArray[np.float64],
        tilt: NDArray[np.float64],
        xy: NDArray[np.float64],
        held: NDArray[np.float64],
    ) -> tuple[NDArray[np.float64], bool]:
        """``forces`` of a rest state, and whether its rigid balance is near-singular.

        Where two contacts' line passes (nearly) through the compliance centre, or a
        contact's normal lies (nearly) level, the rigid balance asks for forces hundreds of
        times the load: the rigid model cannot tell them (a hair of contact compliance or
        friction would carry the load instead). The model bounds them: each contact force
        at most :meth:`force_bound`, the balance met as closely as the bound lets it
        (bounded least squares), and the state marked near-singular. Reported forces,
        the driver's torque and its work then come from the bounded forces.
        """
        bound = self.force_bound(tilt, held)
        if not len(forces) or float(np.max(forces)) <= bound:
            return forces, False
        on = [i for i, c in enumerate(near) if c.gap <= self.touching]
        G, _ = self._rows([near[i] for i in on], centre, tilt)
        grad = self._gradient(tilt, xy, held)
        scale = self._balance_scale(len(grad))
        fit = lsq_linear((G * scale).T, grad * scale, bounds=(0.0, bound))
        out = np.zeros(len(near))
        out[on] = np.clip(fit.x, 0.0, bound)
        return out, True

    def holds_without_compliance(
        self, near: list[_Near], centre: NDArray[np.float64], tilt: NDArray[np.float64]
    ) -> bool:
        """Whether the touching contacts alone hold the load with a margin (``stable``)."""
        touching = [c for c in near if c.gap <= self.touching]
        if len(touching) == 0:
            return False
        G, _ = self._rows(touching, centre, tilt)
        f = self.compliance.force
        scale = self._balance_scale(G.shape[1])
        A = (G * scale).T
        target = np.zeros(G.shape[1])
        target[0] = f
        push = np.zeros(G.shape[1])
        push[0] = f / 100
        push[1:3] = f * self.support_margin / self.radius
        push[3:] = f / 100
        for j in range(G.shape[1]):
            for sign in (1.0, -1.0):
                t = target.copy()
                t[j] += sign * push[j]
                _, resid = nnls(A, t)
                if resid > 1e-9 * f:
                    return False
        return True

    def driver_torque(
        self,
        near: list[_Near],
        forces: NDArray[np.float64],
        rotation: NDArray[np.float64],
        centre: NDArray[np.float64],
    ) -> tuple[float, float]:
        """Torque the driver applies about the bolt axis in the unscrewing sense (N m),
        and its friction part.

        Minus the axial moment about C of the contact forces: normal ``lambda_i n_i`` and
        friction ``mu lambda_i`` against each contact's sliding under the spin.
        """
        # The search turns the way that unscrews: counter-clockwise for a right-hand
        # thread, clockwise for a left-hand one.
        axis = rotation[:, 2] * self.spec.handedness
        mu = self.compliance.friction
        normal = friction = 0.0
        for c, lam in zip(near, forces, strict=True):
            if lam <= 0:
                continue
            r = (c.point - centre) * self.metres
            v = np.cross(axis, r)
            v = v - (v @ c.normal) * c.normal
            speed = float(np.linalg.norm(v))
            normal -= float(axis @ np.cross(r, lam * c.normal))
            if speed > 0:
                friction -= float(axis @ np.cross(r, -mu * lam * v / speed))
        return normal + friction, friction

    def predicted(self, state: MechanicalState, phase: float) -> MechanicalState:
        """``state`` moved to where the rest state at ``phase`` (degrees) is looked for
        when the nut's material lies over the bolt (:meth:`_overhead`).

        Between material below and above (the bolt's flank between the nut's, or under the
        edge where the nut's thread starts), the bolt turned at its own tilt can meet the
        nut at every height: the rest state continuing ``state`` lies at another tilt. The
        predictor is the least motion of the bolt (its points' displacement: the height,
        and the tilts times the major radius) that keeps each contact of ``state`` open to
        first order once turned to ``phase``, those above by half the touching gap (so
        that the lowering starts free and below them): the tangent of the branch where it
        is pinched, and the lead's share along the helices.
        """
        near = [
            _Near(
                np.array(c.point),
                np.array(c.normal),
                c.gap,
                c.bolt_region,
                c.nut_region,
                c.bolt_feature,
                c.nut_feature,
                upper=c.above,
            )
            for c in state.touching
        ]
        if not any(c.upper for c in near):
            return state
        m = self.metres
        centre = np.array(state.centre)
        tilt = np.radians([state.roll, state.pitch])
        G, gap = self._rows(near, centre, tilt)
        axis = np.array(state.rotation)[:, 2]
        r = (np.array([c.point for c in near]) - centre) * m
        normal = np.array([c.normal for c in near])
        # A bolt point's velocity per radian of phase is axis x r: each gap's rate.
        turned = np.einsum("ij,ij->i", normal, np.cross(axis, r))
        margin = np.array([0.5 * self.touching * m if c.upper else 0.0 for c in near])
        bound = (
            gap
            + turned * math.radians(phase - state.phase)
            - margin * self._rate(near, range(len(near)))
        )
        arm = self.radius * m
        scale = np.array([1.0, arm, arm, 1.0, 1.0][: G.shape[1]])
        A = G / scale  # in the points' displacement (m)
        # The contacts that carry the load stay closed (the branch's tangent); the others
        # stay open. Where that asks too much (more carrying contacts than coordinates,
        # not independent), open is all that is asked.
        carrying = np.array([c.force > self.load_carrying for c in state.touching])
        for tangent in (True, False):
            closed = carrying if tangent else np.zeros_like(carrying)
            # A y + bound = 0 on the closed rows, >= 0 on the others.
            constraints = [
                LinearConstraint(A[sel], -bound[sel], upper)
                for sel, upper in ((closed, -bound[closed]), (~closed, np.inf))
                if sel.any()
            ]
            # (scipy-stubs has no overload for a list of linear constraints with SLSQP.)
            res = minimize(  # type: ignore[call-overload]
                lambda y: 0.5 * float(y @ y),
                np.zeros(A.shape[1]),
                jac=lambda y: y,
                constraints=constraints,
                method="SLSQP",
                options={"ftol": 1e-20, "maxiter": 200},
            )
            if res.success and np.all(np.isfinite(res.x)):
                break
        else:
            return state
        dq = res.x / scale
        x, y, z = state.centre
        if len(dq) > 3:
            x, y = x + dq[3] / m, y + dq[4] / m
        return replace(
            state,
            roll=state.roll + math.degrees(dq[1]),
            pitch=state.pitch + math.degrees(dq[2]),
            centre=(x, y, z + dq[0] / m),
        )

    # -- the descent ----------------------------------------------------------------------
    def state(
        self,
        kind: str,
        cls: str,
        d: _Drop,
        near: list[_Near],
        phase: float,
        held: NDArray[np.float64],
        tilt: NDArray[np.float64],
        forces: NDArray[np.float64] | None = None,
        turn: float = 0.0,
    ) -> MechanicalState:
        """A :class:`MechanicalState` of the pose ``d`` (forces None: not at rest)."""
        pose = self._pose(d.rotation, d.xy, d.zc)
        centre = np.array([d.xy[0], d.xy[1], d.zc])
        torque = friction = math.nan
        singular = False
        if forces is None:
            forces = np.full(len(near), math.nan)
        else:
            forces, singular = self.bounded(near, forces, centre, tilt, d.xy, held)
            torque, friction = self.driver_torque(near, forces, d.rotation, centre)
        # A support given twice (the tip rim at the bore edge, as face and as edge) is
        # reported once: the one that carries the force.
        idle = forces <= BALANCE / 10 * self.compliance.force
        twin = [
            bool(idle[i])
            and any(
                j != i and not idle[j] and np.linalg.norm(o.point - c.point) < self.separation / 4
                for j, o in enumerate(near)
            )
            for i, c in enumerate(near)
        ]
        contacts = tuple(
            LoadedContact(
                as_vec(c.point),
                as_vec(c.normal),
                float(f),
                0.0 if c.gap <= self.touching else float(c.gap),
                c.bolt_region,
                c.nut_region,
                c.bolt_feature,
                c.nut_feature,
                c.upper,
            )
            for c, f, t in zip(near, forces, twin, strict=True)
            if not t
        )
        rot = (as_vec(d.rotation[0]), as_vec(d.rotation[1]), as_vec(d.rotation[2]))
        return MechanicalState(
            kind,
            cls,
            float(phase),
            math.degrees(tilt[0]),
            math.degrees(tilt[1]),
            as_vec(pose.origin),
            rot,
            as_vec(centre),
            contacts,
            MJ_PER_J * self.potential(d.zc, tilt, d.xy, held),
            torque,
            friction,
            turn,
            singular,
        )

    def settle(
        self,
        roll: float,
        pitch: float,
        phase: float,
        *,
        start: MechanicalState | None = None,
        leave: tuple[float, float] | None = None,
        arrive: Callable[[MechanicalState], MechanicalState | None] | None = None,
    ) -> RestState:
        """The rest state of the bolt held at tilt ``(roll, pitch)`` and turned to
        ``phase`` (degrees), reached from first contact (or from ``start``, a state at a
        nearby phase: the continuation of the search).

        With ``leave = (fall, turn)`` the descent from ``start`` stops, unbalanced (kind
        ``departed``), once the compliance centre has fallen more than ``fall`` (spec
        units) below ``start``'s or the bolt axis has turned more than ``turn`` degrees
        from ``start``'s: the bisection asks only whether the rest state
        is near the state it leaves, and a descent that has gone this far on its way down
        the potential does not come back; it settles in full the jump it keeps.
        ``arrive`` (the library's sweep) is asked at each pose of the descent, as a state
        not yet at rest, for a rest state already known at this phase that the pose has
        reached (same load-carrying contacts, within the sweep's tolerances of its pose);
        the descent stops there and returns that state (``balance["arrived"]``): the sweep
        would take the one it ends at for that state anyway, and the descent is in its
        basin.

        Returns
        -------
        RestState
            The rest (or in-phase) state, the unstable states passed on the way, the
            equilibrium residuals.
        """
        roll, pitch, phase = check_configuration(roll, pitch, phase)
        q0 = self.engine.queries
        held = np.radians([roll, pitch])
        if start is None:
            tilt, xy, zc = held.copy(), np.zeros(2), None
        else:
            tilt = np.radians([start.roll, start.pitch])
            xy = np.array(start.centre[:2])
            zc = start.centre[2]
        d = self.drop(self._rotation(tilt, phase), xy, zc)
        if d is None:
            raise InputError(
                f"the bolt passes the nut without touching at roll {roll:g}, "
                f"pitch {pitch:g}, phase {phase:g}"
            )

        start_axis = None if start is None else np.array(start.rotation)[:, 2]
        if start is not None:
            # The turn may lift the bolt off some of the contacts it rested on (a flank
            # riding onto an edge lifts it off the face beside): those contacts still bound
            # the motion, and a descent that does not know them can tip past them into
            # another basin. It knows every contact within the lift, and ``near`` beyond.
            d = self._deepened(d, self.near + max(0.0, d.zc - start.centre[2]))

        def gone(d: _Drop) -> bool:
            # (See ``leave``.)
            return (
                leave is not None
                and start is not None
                and start_axis is not None
                and (
                    start.centre[2] - d.zc > leave[0]
                    or axis_angle(d.rotation[:, 2], start_axis) > leave[1]
                )
            )

        departed = gone(d)
        near = [] if departed else self.contacts(d)
        path: list[MechanicalState] = []
        if start is None:
            path.append(self.state("first-contact", "unstable", d, near, phase, held, tilt))
        last_axis = d.rotation[:, 2].copy()
        comp = self.compliance
        f = comp.force
        k = self._stiffness()
        thread_pitch_m = self.spec.pitch * self.metres
        arm_m = self.radius * self.metres
        prox0 = np.array(
            [
                f / (thread_pitch_m / 20),
                f * arm_m / math.radians(8.0),
                f * arm_m / math.radians(8.0),
            ]
            + [f / (thread_pitch_m / 20)] * 2
        )
        prox = prox0[: len(k)].copy()
        curvature = np.zeros((2, 2))
        if start is not None and start.contact_curvature is not None:
            # Continuation: the model at the state left is a good start for the next.
            curvature, prox = np.array(start.contact_curvature, dtype=float), prox * 1e-2
        u = self.potential(d.zc, tilt, xy, held)
        noise = 2.0 * f * max(self.scene.deviation, self.tolerance) * self.metres
        engaged = self.engaged(near)  # the pose in phase (the descent's path records it)
        last_step = np.zeros(2)
        nudged = 0.0  # bolt motion since python-fcl last lowered the bolt (see _nudged)
        ahead: list[_Near] = []  # contacts met by rejected steps (see below)
        progress: list[tuple[float, float]] = []  # potential and residual (stall_steps)
        support: tuple[int, ...] = ()
        steps = 0
        converged = False
        # Upright, the spring's moment is k x held; the end's contacts can hold at most the
        # load times the bolt's radius against it: beyond that no seat can be a rest state.
        seat_tried = float(np.hypot(*(k[1:3] * held))) > f * arm_m
        touching = _touching_pairs(near, self.touching)

        def result(state: MechanicalState, balance: dict[str, float]) -> RestState:
            return RestState(
                self.units,
                float(roll),
                float(pitch),
                float(phase),
                comp.to_dict(),
                state,
                tuple(path),
                balance,
                steps,
                self.engine.queries - q0,
            )

        while not departed and steps < MAX_STEPS:
            centre = np.array([d.xy[0], d.xy[1], d.zc])
            G, gap = self._rows(near + ahead, centre, tilt)
            grad = self._gradient(tilt, d.xy, held)
            forces, f_res, m_res = self.forces(near, centre, tilt, d.xy, held)
            if arrive is not None and not engaged:
                known = arrive(self.state("rest", "unstable", d, near, phase, held, tilt, forces))
                if known is not None:
                    # At this phase as turned (a continuation's phases run past 360).
                    balance = {"force": f_res, "moment": m_res, "converged": 0.0, "arrived": 1.0}
                    return result(replace(known, phase=float(phase)), balance)
            if f_res <= BALANCE / 10 and m_res <= BALANCE / 10:
                converged = True
                break
            seating = self._seating(near, tilt)
            progress.append((u, max(f_res, m_res)))
            window = self.stall_steps
            # (Pinched under material above, a descent slides along the flank in short
            # steps whose gain is below the noise: it is not stalled, and the step limit
            # bounds it.)
            pinched = any(c.upper and c.gap <= self.touching for c in near)
            if start is not None and len(progress) > window and not seating and not pinched:
                u_then = progress[-window - 1][0]
                best_then = min(r for _, r in progress[:-window])
                if u_then - u <= noise and min(r for _, r in progress[-window:]) > (
                    0.99 * best_then
                ):
                    # Stalled: a rest state if it balances (as when nothing is left to gain).
                    converged = f_res <= BALANCE and m_res <= BALANCE
                    break
            if not seat_tried and tilt.any() and seating:
                seat_tried = True
                seat = self._seat(d, tilt, phase, held, u)
                if seat is not None:
                    steps += 1
                    d, near, tilt, u = seat
                    nudged = 0.0
                    ahead, support, prox = [], (), prox0[: len(k)].copy()
                    touching = _touching_pairs(near, self.touching)
                    continue
            metric = np.diag(k + prox)
            metric[1:3, 1:3] += curvature
            over = [i for i, c in enumerate(near) if c.upper]
            held_off = gap
            if over:
                # Material above is kept half the touching gap away where it is farther,
                # so that the lowering after the step starts free under it.
                held_off = gap.copy()
                margin = 0.5 * self.touching * self.metres * self._rate(near, over)
                held_off[over] = np.maximum(gap[over] - margin, 0.0)
            dq, lam = contact_step(metric, grad, G, held_off, support)
            if not np.all(np.isfinite(dq)):
                break  # a degenerate contact problem: give up here, unconverged
            support = tuple(int(i) for i in np.flatnonzero(lam > 0))
            promised = -float(grad @ dq + 0.5 * dq @ (k * dq))
            dtilt = dq[1:3]
            dxy = dq[3:5] / self.metres if len(dq) > 3 else np.zeros(2)
            moved = (
                float(np.abs(dtilt).max()) * (self.radius + self.scene.bolt.z_max)
                + float(np.abs(dxy).max(initial=0.0))
                + abs(dq[0]) / self.metres
            )
            # (The balance asks for tilts far finer than the travel tolerance: 1e-6 F times
            # the radius against a 1 N m/rad spring is 3e-8 rad, against 1e4 N m/rad
            # 3e-12 rad. Steps that small are still Newton steps of the same model.)
            if moved <= 1e-6 * self.tolerance and promised <= 1e-12 * f * thread_pitch_m:
                # Nothing left to gain at this tolerance: a rest state if it balances.
                converged = f_res <= BALANCE and m_res <= BALANCE
                break
            steps += 1
            if (
                float(np.abs(dtilt).max()) > math.radians(5.0)
                or abs(dq[0]) / self.metres > self.spec.pitch
            ):
                # Far beyond what the linearised contacts can tell: a shorter step.
                prox *= 4
                continue
            new_tilt = tilt + dtilt
            if not comp.held_laterally:
                new_xy = d.xy + dxy
            else:
                new_xy = d.xy
            # Nudges add up: all of them since python-fcl last lowered the bolt stay within
            # the tolerance, so that no run of them walks into a contact it does not know.
            nudge = nudged + moved <= self.tolerance
            span = max(4 * self.tolerance, 0.25 * moved)
            if over:
                # Under material, the lowering starts below it (where the linearised
                # contacts put it) and does not climb: the bolt is between two flanks.
                ahead_gap = (gap[over] + G[over] @ dq) / (self.metres * self._rate(near, over))
                span = min(span, max(1e-3 * self.tolerance, 0.5 * float(ahead_gap.min())))
            lowered = (
                self._nudged(d, self._rotation(new_tilt, phase), new_xy)
                if nudge
                else self.drop(
                    self._rotation(new_tilt, phase),
                    new_xy,
                    d.zc + dq[0] / self.metres,
                    span=span,
                    verify=False,
                    climb=not over,
                    reach=moved,
                )
            )
            if lowered is None:
                prox *= 4
                continue
            trial = lowered

            def kept(u_new: float, u: float = u, promised: float = promised) -> bool:
                # Mesh heights carry the chord error: below it, the exact contact geometry
                # of the model decides (the step stays feasible: it was lowered onto the nut).
                return (u - u_new >= 0.1 * promised and u_new < u) or (
                    promised <= noise and u_new <= u + noise
                )

            u_new = self.potential(trial.zc, new_tilt, new_xy, held)
            if kept(u_new):
                # Only a step kept at its bracket's touch can be kept at the first touch,
                # which is no lower.
                trial = self.verified(trial)
                u_new = self.potential(trial.zc, new_tilt, new_xy, held)
            step_q = np.concatenate([[(trial.zc - d.zc) * self.metres], dq[1:]])
            if kept(u_new):
                old_rows, old_sig = G[: len(near), 1:3], _touching_pairs(near, self.touching)
                near = self.contacts(trial)
                # In phase as long as the pose's contacts lie on the helices: a contact
                # that leaves them (the bolt rolls back onto its end) ends the snap.
                if self.engaged(near) != engaged:
                    engaged = not engaged
                    if engaged and not any(p.kind == "in-phase" for p in path):
                        path.append(
                            self.state("in-phase", "unstable", trial, near, phase, held, new_tilt)
                        )
                d, tilt, u = trial, new_tilt, u_new
                if gone(d):
                    departed = True
                    break
                nudged = nudged + moved if nudge else 0.0
                ahead = []
                if _touching_pairs(near, self.touching) == old_sig and len(near) == len(old_rows):
                    # The contacts' moment changes with the tilt as their points slide (a
                    # rim's lowest point turns with the tilt's direction): its rate, the
                    # contacts' geometric stiffness, is learnt by damped BFGS.
                    new_rows = self._rows(near, np.array([*d.xy, d.zc]), tilt)[0][:, 1:3]
                    _bfgs(
                        curvature,
                        dtilt,
                        -(new_rows - old_rows).T @ lam[: len(old_rows)],
                        1e3 * f * arm_m,
                    )
                now = _touching_pairs(near, self.touching)
                if float(dq[1:3] @ last_step) < 0:
                    # Turned back on the last step: the contact model flickers between two
                    # poses (a contact at the touching threshold); damp to meet between.
                    prox *= 4
                else:
                    # Same contacts: the model is good, trust it more.
                    prox = np.maximum(prox / (10 if now == touching else 3), prox0[: len(k)] * 1e-8)
                last_step = dq[1:3].copy()
                if now != touching and not engaged:
                    kind = "new-contact" if len(now) >= len(touching) else "rolling"
                    axis = d.rotation[:, 2]
                    turn = axis_angle(axis, last_axis)
                    path.append(self.state(kind, "unstable", d, near, phase, held, tilt, turn=turn))
                    last_axis = axis.copy()
                    touching = now
            else:
                prox *= 4
                if prox[1] > prox0[1] * 1e12:
                    break
                # What stopped the step: the contacts touching at the trial pose, carried
                # back to this pose by their linearisation (a cutting plane), so that the
                # next step knows them.
                ahead = []
                for c in self.contacts(trial):
                    if c.gap > self.touching:
                        continue
                    row, _ = self._rows([c], centre, tilt)
                    opening = -float(row[0] @ step_q)
                    if opening > 0:
                        ahead.append(
                            replace(c, gap=opening / (self.metres * self._rate([c], [0])[0]))
                        )
        centre = np.array([d.xy[0], d.xy[1], d.zc])
        if departed:
            return result(
                self.state("departed", "unstable", d, [], phase, held, tilt),
                {"force": math.nan, "moment": math.nan, "converged": 0.0},
            )
        forces, f_res, m_res = self.forces(near, centre, tilt, d.xy, held)
        axis = d.rotation[:, 2]
        turn = axis_angle(axis, last_axis)
        if self.engaged(near, forces):
            cls, kind = "in-phase", "in-phase"
        elif self.holds_without_compliance(near, centre, tilt):
            cls, kind = "stable", "rest"
        else:
            cls, kind = "quasi-stable", "rest"
        if not converged:
            cls = "unstable"
        final = replace(
            self.state(kind, cls, d, near, phase, held, tilt, forces, turn),
            contact_curvature=(
                (float(curvature[0, 0]), float(curvature[0, 1])),
                (float(curvature[1, 0]), float(curvature[1, 1])),
            ),
        )
        # The first state is a rest state already when the descent did not move.
        if path and path[0].kind == "first-contact" and steps == 0:
            path.clear()
        return result(final, {"force": f_res, "moment": m_res, "converged": float(converged)})


def _facing(triangles: NDArray[np.float64]) -> NDArray[np.float64]:
    """The Z part of each triangle's outward normal (unnormalised; the meshes wind their
    triangles outward): positive for a face turned up."""
    t = np.asarray(triangles, dtype=float)
    return np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])[:, 2]


def _bfgs(
    b: NDArray[np.float64], s: NDArray[np.float64], y: NDArray[np.float64], bound: float
) -> None:
    """Powell-damped BFGS update of the 2 x 2 curvature ``b`` in place, kept symmetric
    with eigenvalues in ``[0, bound]`` (a step too short to measure leaves it alone)."""
    ss = float(s @ s)
    if ss <= 1e-18:  # below a nanoradian the secant is rounding noise
        return
    bs = b @ s
    sbs = float(s @ bs)
    sy = float(s @ y)
    if sbs <= 1e-12 * ss * max(float(np.abs(b).max()), 1e-300):
        if sy > 1e-12 * ss:  # first update: the secant alone
            b += np.outer(y, y) / sy
    else:
        theta = 1.0 if sy >= 0.2 * sbs else 0.8 * sbs / (sbs - sy)
        r = theta * y + (1 - theta) * bs
        b += np.outer(r, r) / float(s @ r) - np.outer(bs, bs) / sbs
    w, v = np.linalg.eigh(0.5 * (b + b.T))
    b[:] = (v * np.clip(w, 0.0, bound)) @ v.T


def _single_linkage(points: NDArray[np.float64], separation: float) -> NDArray[np.intp]:
    """Label points (0, 1, ... by first appearance) linked in chains of steps no longer
    than ``separation``: the distinct contacts of :meth:`Mechanics.contacts`.

    The points are one per cell of a sixteenth of the linkage, so there are few (tens to a
    few hundred): a dense link matrix and label propagation (each point takes the least
    label among its links, then its label's label) cost less than a k-d tree and a
    union-find in Python, or a sparse graph's validation.
    """
    n = len(points)
    if n == 1:
        return np.zeros(1, dtype=np.intp)
    labels: NDArray[np.integer]
    if n > 400:  # a broad patch: the links from a k-d tree, as a sparse graph
        pairs = cKDTree(points).query_pairs(separation, output_type="ndarray").reshape(-1, 2)
        graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        labels = connected_components(graph, directed=False)[1]
    else:
        diff = points[:, None, :] - points[None, :, :]
        linked = np.einsum("ijk,ijk->ij", diff, diff) <= separation * separation
        labels = np.arange(n)
        while True:
            new = np.where(linked, labels[None, :], n).min(axis=1)
            new = new[new]  # pointer jumping: long chains in few rounds
            if np.array_equal(new, labels):
                break
            labels = new
    # Renumber by first appearance (with propagation, a component's label is its first
    # point already).
    _, first, inverse = np.unique(labels, return_index=True, return_inverse=True)
    return np.argsort(np.argsort(first))[inverse].astype(np.intp)


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


@functools.lru_cache(maxsize=4)
def _cached(spec: ThreadSpec, compliance: Compliance, chord: float | None) -> Mechanics:
    return Mechanics(spec, compliance, chord=chord)


def mechanics(
    target: Mechanics | ThreadSpec, compliance: Compliance | None = None, chord: float | None = None
) -> Mechanics:
    """``target`` itself when it is a :class:`Mechanics`, else a cached one for the spec."""
    if isinstance(target, Mechanics):
        if compliance is not None and compliance != target.compliance:
            raise InputError("give the compliance to Mechanics, not again with it")
        return target
    if not isinstance(target, ThreadSpec):
        raise InputError(f"expected a ThreadSpec or Mechanics, got {type(target).__name__}")
    return _cached(target, compliance if compliance is not None else Compliance(), chord)


def settle(
    target: Mechanics | ThreadSpec,
    roll: float,
    pitch: float,
    phase: float,
    *,
    compliance: Compliance | None = None,
    chord: float | None = None,
) -> RestState:
    """The rest state of a bolt held at ``(roll, pitch)`` and turned to ``phase`` (degrees).

    Parameters
    ----------
    target : ThreadSpec or Mechanics
        The thread pair (a :class:`Mechanics` is built and cached for it) or a ready
        :class:`Mechanics`.
    roll, pitch : float
        Held tilt (degrees).
    phase : float
        Phase (degrees).
    compliance : Compliance, optional
        Load, stiffness, friction (default :class:`Compliance()`).

    Examples
    --------
    >>> from threadmate.geometry import spec_from_designation
    >>> from threadmate.contact import Compliance, settle
    >>> rest = settle(spec_from_designation("1/4-20 UNC-2A/2B"), 4, 0, 185,
    ...               compliance=Compliance(force=10, stiffness=1))     # doctest: +SKIP
    >>> rest.classification, [c.force for c in rest.state.touching]     # doctest: +SKIP
    """
    return mechanics(target, compliance, chord).settle(roll, pitch, phase)
