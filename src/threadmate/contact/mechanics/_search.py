"""The counter-clockwise search simulated: quasi-static continuation in phase.

From the rest state of a start (held tilt, start phase), the driver turns the bolt
counter-clockwise in steps of ``step`` degrees; at each step the bolt follows the nearest
rest state, found by the descent of :mod:`._settle` warm-started from the state it leaves
(and from nothing settled before it, so that a step is a function of that state). A
step is *continuous* when the new rest state is near the last: the compliance centre
falls less than ``pitch / 40`` and the bolt axis turns less than ``jump_tilt`` (0.5
degree). Otherwise the rest state ceased to exist within the step (a fold): the bolt
jumped (tipped, rolled or dropped) to another one. Jumps, and changes of the touching
contacts along a continuous branch, are located by bisection in phase to
``phase_tolerance`` (0.01 degree): each half is settled from the state on the side before
it. A jump that lands in-phase is the snap, and so is a continuous step whose end moves
along the helix and screws in (the bolt passed into phase without a jump, located by
bisection too: :meth:`Continuation._entered`). Its click is the fall of the compliance
centre a sensor sees: from the highest the branch stands within the last
:data:`CLICK_SPAN` degree of turn before the jump to the landing, a steep last stretch
of the branch and jumps down within that turn included (:func:`sensor_click`).

The driver's work along a continuous branch splits into friction and the part that raises
the potential; during a jump the phase stands still and the driver does no work. The
potential part is the change of U between the branch's ends (without friction and away
from jumps the integral of the driver's torque equals it: a check the tests make on the
torques); the friction part is the trapezoidal rule on the friction torque
(:meth:`Mechanics.driver_torque`) over the states the walk steps to, a state not at rest
taking its step's rest state's torque (:meth:`Continuation.friction_work`). A contact
change located within a step adds no node, so that the library's walk, which locates
none, integrates over the same states.

:class:`Continuation` does the walking, in *legs* (a continuous branch, a jump, the snap);
:func:`search` and the library's sweep (:mod:`threadmate.library`) both walk with it, so a
library's passive paths and a search from the same start are the same computation.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from ..._angles import Z_AXIS, axis_angle
from ..._errors import InputError
from ..._units import MJ_PER_J
from ...geometry import ThreadSpec
from ..scene import IN_PHASE, QUASI_STABLE, STABLE, UNSTABLE
from ._compliance import Compliance
from ._contact_set import HELICAL_FEATURES
from ._rest_state import (
    LEAD_TOLERANCE,
    Engagement,
    MechanicalState,
    SearchEvent,
    SearchResult,
    scaled_peak,
    tightening_torque,
    torque_jam_reason,
)
from ._settings import (
    CONTINUATION_STEP,
    JOIN_DISTANCE,
    JOIN_TILT,
    PHASE_TOLERANCE,
    PROOF_FOLD_TOLERANCE,
    PROOF_TURN_LIMIT,
    SCREW_IN,
    TIGHTEN_STEP,
    check_continuation,
    check_screw,
)
from ._settle import Mechanics, mechanics

__all__ = [
    "CLICK_SPAN",
    "Continuation",
    "Leg",
    "SENSES",
    "Turn",
    "begin_turn",
    "default_torque_limit",
    "engagement",
    "same_pose",
    "search",
    "sensor_click",
    "wedged",
]

#: Turn (degrees) by which a state is screwed in at its own tilt, to see whether it
#: follows the helix before it is proved (:meth:`Continuation.follows_helix`).
HELIX_PROBE = 1.0
#: The helix probe's turn grows with the meshes' deviation: the lead's share of it is at
#: least this many times the deviation, so that the facets of a coarse mesh cannot pass
#: for a descent along the helix (nor hide one).
HELIX_PROBE_MARGIN = 8.0
#: The helix probe's descent, as shares of the lead's share of its turn, that a state
#: moving along the helix may show: carried partly by the nut's thread (its point on a
#: nut flank, its thread on the countersink), more than half and less than one and a half
#: (the thread's contact moves along the helix, the other one holds the bolt back a
#: little as it turns); carried by the nut's entry alone (its thread's edge on the
#: countersink), within a quarter of one: an edge of the helix on a cone about the axis
#: moves at the lead exactly, and one that merely rides the cone, the tilt taking it,
#: moves at about half of it.
HELIX_SHARES = {"thread": (0.5, 1.5), "entry": (0.75, 1.25)}
#: Tilt of the bolt axis within one step above which the step is a jump (degrees).
JUMP_TILT = 0.5
#: Senses a continuation turns the bolt in: ``unscrew`` (the search: counter-clockwise for a
#: right-hand thread) or ``tighten`` (screwing in: clockwise).
SENSES = ("unscrew", "tighten")
#: Tilts (degrees) from the last state of a branch at which a rest state continuing it is
#: looked for where the turn wedges the bolt at its own tilt (:meth:`Continuation._tilted`).
TILT_PROBES = (0.02, 0.1)
#: How far before a snap its window is looked for, and the probe's turn (degrees;
#: :meth:`Continuation.snap_window`).
WINDOW = 15.0
WINDOW_PROBE = 1.0
#: Default limit of the tightening torque, in units of the axial force times the bolt's
#: major radius (a contact force equal to the load acting tangentially at the crest): a
#: driver that needs more is wedging the bolt, not screwing it in (the rigid form of
#: jamming and cross-threading).
TORQUE_LIMIT = 1.0
#: Contact changes that undo each other within this turn (degrees) are a contact point
#: flickering across the border of two regions (a chamfer on a nut flank's edge with its
#: crest): neither is told (:func:`_without_flicker`).
FLICKER = 1.0
#: The turn (degrees) before a jump over which a sensor sees the fall as one click. A
#: branch can fall steeply for its last hundredths of a degree before it ends (a tilted
#: bolt tipping off the bore's edge or a crest), and a driver turning at any practical
#: speed passes such a stretch, and the cascade of small jumps a real bolt makes down it,
#: within milliseconds: the sensor sees one fall, from the highest the bolt stood within
#: that turn. Measured over a fixed turn, the click does not depend on where a slope
#: threshold would split the branch from the fall, and an independent dynamic simulation
#: measures it the same way.
CLICK_SPAN = 1.0
#: A probe's descent stops once it has gone this many times the jump's thresholds (the
#: fall ``pitch / 40``, the tilt ``JUMP_TILT``) from the state it leaves: far enough that
#: the rest state it would reach is not near that state either.
DEPARTURE = 2.0


def _without_flicker(events: list[SearchEvent]) -> list[SearchEvent]:
    """``events`` without the contact changes that a later one within :data:`FLICKER`
    undoes (A to B, then B to A): what the load rests on did not change."""
    out: list[SearchEvent] = []
    for e in events:
        last = out[-1] if out else None
        if (
            last is not None
            and e.kind == last.kind == "contact-change"
            and e.after == last.before
            and abs(e.phase - last.phase) < FLICKER
        ):
            out.pop()
            continue
        out.append(e)
    return out


def sensor_click(ride: Sequence[MechanicalState], landing: MechanicalState, at: float) -> float:
    """The click a sensor sees at a jump: the fall of the compliance centre from the
    highest the branch stands within the turn from phase ``at`` (:data:`CLICK_SPAN`
    before the jump) to the jump, to ``landing``.

    Parameters
    ----------
    ride : sequence of MechanicalState
        The states the turn passed before the jump (states that are not rest states are
        passed over, and so are rest states whose rigid balance is near-singular: held up
        by forces many times the load, their height is not one the bolt keeps, a hair of
        contact compliance letting it down).
    landing : MechanicalState
        Where the jump lands, at the jump's phase.
    at : float
        Phase (degrees) where the span a sensor sees as one fall begins.

    The branch's height at ``at`` itself is interpolated linearly in phase between the
    rest states either side of it (the nearest one's where it lies outside them):
    :class:`Continuation` settles a state there, so that the interpolation is exact. A
    ride that climbs into the jump (a flank riding onto an edge) clicks the fall from
    its top, a branch that falls steeply before the jump the fall from where it began.
    NaN when ``ride`` holds no rest state: no height of the branch is known to fall from.
    """
    rest = sorted(
        (s.phase, s.centre[2]) for s in ride if s.classification != UNSTABLE and not s.near_singular
    )
    if not rest:
        return math.nan
    phases = [p for p, _ in rest]
    heights = [z for _, z in rest]
    lo, hi = sorted((at, landing.phase))
    inside = [z for p, z in rest if lo <= p <= hi]
    top = max([float(np.interp(at, phases, heights)), *inside])
    return top - float(landing.centre[2])


def _tilt_between(a: MechanicalState, b: MechanicalState) -> float:
    return axis_angle(np.array(a.rotation)[:, 2], np.array(b.rotation)[:, 2])


def _carrying_pairs(s: MechanicalState, floor: float) -> tuple[str, ...]:
    """The region pairs of the contacts that carry the load (more than ``floor``, N): a
    contact touching without force, or hovering at the touching threshold, changes
    nothing a driver or a sensor sees, and neither does one more or one fewer point of
    the same pair (the corners of a face flat on a face, the pieces of a line along the
    helix)."""
    return tuple(sorted({c.regions for c in s.touching if c.force > floor}))


@dataclass(frozen=True)
class Leg:
    """One transition of the continuation.

    Attributes
    ----------
    kind : str
        ``turning`` (a continuous branch of rest states, contact changes included),
        ``jump`` (the rest state ceased to exist: the bolt tipped, rolled or dropped) or
        ``snap`` (the jump into the in-phase state).
    before, after : MechanicalState
        The states it joins.
    turn : float
        Phase turned along it (degrees, >= 0; 0 for a jump).
    work_friction, work_potential : float
        Driver's work against friction and against the potential (mJ; 0 for a jump).
    torque_peak : float
        Largest driver torque along it (N m; NaN for a jump).
    label : str
        ``stable`` when every state passed is a stable rest state, ``quasi-stable`` when
        one is quasi-stable, ``unstable`` for a jump or a snap.
    engagement : Engagement or None
        The screw-in proof of a landing in phase (a snap's, or a jump's that failed it).
    click : float
        The fall a sensor sees at a jump or a snap (:func:`sensor_click`; spec units;
        NaN for a turning leg).
    torques : tuple of (float, float)
        The driver's torque and its friction part at each state of a turning leg that
        has one (N m), for :meth:`torque_peak_scaled`; empty for a jump.
    """

    kind: str
    before: MechanicalState
    after: MechanicalState
    turn: float
    work_friction: float
    work_potential: float
    torque_peak: float
    label: str
    engagement: Engagement | None = None
    click: float = math.nan
    torques: tuple[tuple[float, float], ...] = ()

    def torque_peak_scaled(self, scale: float) -> float:
        """:attr:`torque_peak` with every friction part scaled by ``scale`` (the ratio of
        another friction coefficient to the one walked with: the rest states are
        frictionless, so only the friction parts change)."""
        return self.torque_peak if scale == 1.0 else scaled_peak(self.torques, scale)

    @property
    def drop(self) -> float:
        """Fall of the compliance centre along the leg (spec units)."""
        return float(self.before.centre[2] - self.after.centre[2])

    @property
    def tilt_change(self) -> float:
        """Angle between the bolt axes at its ends (degrees)."""
        return _tilt_between(self.before, self.after)


def default_torque_limit(mech: Mechanics) -> float:
    """The tightening torque past which a bolt counts as jammed (N m,
    :data:`TORQUE_LIMIT`)."""
    return TORQUE_LIMIT * mech.compliance.force * mech.radius * mech.metres


def engagement(
    walk: Continuation,
    start: MechanicalState,
    legs: list[Leg],
    events: list[SearchEvent],
    states: list[MechanicalState],
    turn: float,
    window: float,
) -> Engagement:
    """Judge a tightening continuation from ``start`` over ``turn`` degrees: engaged when
    the compliance centre descends at the lead over the last ``window`` degrees (after any
    settling into the thread, where a jump is allowed) and the driver's torque stays
    within its limit."""
    lead = walk.mech.spec.lead
    path = [start, *states]
    end = path[-1]
    turned = abs(end.phase - start.phase)
    judged = min(window, turned)
    half = min(path, key=lambda s: abs(abs(s.phase - start.phase) - (turned - judged)))
    span = abs(end.phase - half.phase)
    descent = (half.centre[2] - end.centre[2]) * 360.0 / span if span > 0 else math.nan
    tilt = axis_angle(np.abs(np.asarray(end.rotation)[:, 2]), Z_AXIS)  # either way up
    torques = tuple((t, f) for t, f in map(walk.torque, path) if math.isfinite(t))
    peak = max((t for t, _ in torques), default=math.nan)
    units = walk.mech.units
    reason = ""
    torque_jam = None
    wedge = wedged(legs, events)
    if wedge is not None:
        e, leg = wedge
        reason = (
            f"no rest state continues the turn at phase {e.phase:.2f} deg: the bolt would "
            f"have to rise {-leg.drop:.4g} {units} against the load (jammed)"
        )
    elif any(map(walk.jams, path)):
        at = next(s for s in path if walk.jams(s))
        torque_jam = (*walk.torque(at), at.phase, walk.torque_limit)
        reason = torque_jam_reason(torque_jam[0], at.phase, walk.torque_limit)
    jammed = bool(reason)
    if not jammed and (not math.isfinite(descent) or abs(descent - lead) > LEAD_TOLERANCE * lead):
        jumps = [e for e in events if e.kind == "jump"]
        reason = (
            f"turned clockwise {turned:g} deg it descends {descent:.4g} {units} per turn, "
            f"not the lead {lead:.4g} {units}"
            + (f" (it jumps at phase {jumps[0].phase:.2f} deg)" if jumps else "")
        )
    return Engagement(
        not reason,
        turned,
        descent,
        lead,
        tilt,
        peak,
        reason,
        jammed,
        judged_alike(walk, path),
        torques,
        torque_jam,
    )


def judged_alike(walk: Continuation, path: Sequence[MechanicalState]) -> tuple[float, float]:
    """The friction coefficients ``(low, high)`` strictly between which ``walk`` judges
    every state of ``path`` as at its own (:meth:`Continuation.jams`).

    The rest states are frictionless, so only the torques change with the coefficient, and
    each linearly: the friction part in proportion, the normal forces' moment not at all.
    Each state's torque crosses the limit at one coefficient at most, which bounds the
    interval on the side it lies. With no friction the friction parts are 0 and tell no
    proportion: ``(0, 0)``, no other coefficient known alike.
    """
    mu = walk.mech.compliance.friction
    if mu <= 0.0:
        return (0.0, 0.0)
    low, high = 0.0, math.inf
    for s in path:
        torque, friction = walk.torque(s)
        if s.near_singular or not (math.isfinite(torque) and math.isfinite(friction)):
            continue  # never judged jammed, whatever the friction
        rate = friction / mu  # the torque's change per unit of the coefficient
        if rate == 0.0:
            continue
        crossing = mu + (walk.torque_limit - torque) / rate
        if (torque > walk.torque_limit) == (rate > 0.0):
            low = max(low, crossing)
        else:
            high = min(high, crossing)
    return (low, high)


def same_pose(a: MechanicalState, b: MechanicalState, pitch: float) -> bool:
    """Whether two states have one pose: compliance centres within :data:`JOIN_DISTANCE`
    pitches (``pitch`` in spec units) and axes within :data:`JOIN_TILT`."""
    return math.dist(a.centre, b.centre) <= JOIN_DISTANCE * pitch and (
        _tilt_between(a, b) <= JOIN_TILT
    )


@dataclass(frozen=True)
class Walked:
    """A clockwise walk (a proof's, a clockwise start's): its start, and the legs, events
    and states :meth:`Continuation.advance` gave (:func:`joined_walk`)."""

    start: MechanicalState
    legs: list[Leg]
    events: list[SearchEvent]
    states: list[MechanicalState]

    def beyond(
        self, s: MechanicalState, phase: float, reach: float, sign: int, pitch: float
    ) -> tuple[list[Leg], list[SearchEvent], list[MechanicalState]] | None:
        """Its legs, events and states after ``s`` (at ``phase``) up to ``reach``
        degrees further in the sense ``sign``, when ``s`` is one of its states (the
        same class and pose, :func:`same_pose`, at that phase); None otherwise."""
        path = [self.start, *self.states]
        at = next(
            (
                k
                for k, o in enumerate(path)
                if abs(o.phase - phase) <= 1e-9
                and o.classification == s.classification
                and same_pose(o, s, pitch)
            ),
            None,
        )
        if at is None:
            return None

        def within(x: float) -> bool:
            return 1e-9 < sign * (x - phase) <= reach + 1e-9

        states = [o for o in self.states[at:] if within(o.phase)]
        if not states:
            return None
        legs = [
            leg
            for leg in self.legs
            if within(leg.after.phase) and sign * (leg.before.phase - phase) >= -1e-9
        ]
        return legs, [e for e in self.events if within(e.phase)], states


def joined_walk(
    walks: list[Walked],
    walk: Continuation,
    state: MechanicalState,
    phase: float,
    turn: float,
) -> tuple[list[Leg], list[SearchEvent], list[MechanicalState]]:
    """``walk.advance(state, phase, turn)``, taken from the earlier ``walks`` (walked
    with the same settings and in the same sense) where it can.

    The landings and the starts of one held tilt often lie on one branch. A walk that
    reaches a state of an earlier one (the same class and pose at the same phase,
    :meth:`Walked.beyond`) joins it, for the quasi-static dynamics are deterministic:
    from there on the two are one. So the walk is turned on to where it may join: the
    start of an earlier walk further on, or (once, for a state between an earlier walk's
    phases) the next of that walk's states within a step; beyond what the earlier walks
    hold, it goes on by itself. It ends at a wedge, as :meth:`Continuation.advance`
    does."""
    sign, pitch = walk.sign, walk.mech.spec.pitch
    legs: list[Leg] = []
    events: list[SearchEvent] = []
    states: list[MechanicalState] = []
    at, s, ph, aligned = 0.0, state, phase, False
    while at < turn - 1e-9:
        reach = turn - at
        piece = next((p for w in walks if (p := w.beyond(s, ph, reach, sign, pitch))), None)
        if piece is None:
            ahead = [
                o.phase
                for w in walks
                for o, near in [(w.start, False), *((o, True) for o in w.states)]
                if 1e-9 < sign * (o.phase - ph) <= (min(walk.step, reach) if near else reach)
                and not (near and aligned)
            ]
            aligned = True
            to = min((sign * (x - ph) for x in ahead), default=reach)
            piece = walk.advance(s, ph, to)
        legs += piece[0]
        events += piece[1]
        states += piece[2]
        if wedged(piece[0], piece[1]) is not None:
            break  # the driver stalls at the wedge (:meth:`Continuation.advance`)
        s = piece[2][-1]
        at += sign * (s.phase - ph)
        ph = s.phase
    return legs, events, states


def wedged(legs: list[Leg], events: list[SearchEvent]) -> tuple[SearchEvent, Leg] | None:
    """The first fold of a continuation that the bolt can leave only upwards, against the
    load, with its event: no rest state continues the turn there (the bolt wedged between
    the threads), and the driver stalls. ``legs`` and ``events`` as
    :meth:`Continuation.advance` returns them (one jump or snap leg per such event)."""
    folds = [e for e in events if e.kind != "contact-change"]
    jumps = [leg for leg in legs if leg.kind != "turning"]
    for e, leg in zip(folds, jumps, strict=True):
        if leg.after.potential > leg.before.potential:
            return e, leg
    return None


def _label(states: list[MechanicalState]) -> str:
    classes = {s.classification for s in states}
    if UNSTABLE in classes:
        return UNSTABLE
    return QUASI_STABLE if QUASI_STABLE in classes else STABLE


class Continuation:
    """The quasi-static continuation of one held tilt, walked in legs.

    Parameters
    ----------
    mech : Mechanics
        The thread pair and compliance.
    roll, pitch : float
        Held tilt (degrees).
    step : float
        Continuation step (degrees).
    phase_tolerance : float
        How closely events are located in phase (degrees).
    contact_changes : bool
        Locate the contact changes along continuous branches too (True, the search's
        events), or only the folds (False: the library's sweep, which keeps the legs
        between jumps and not the contact changes within them). The branch followed, and
        the driver's work along it, are the same either way: a located contact change
        adds the states either side of it to :meth:`advance`'s states, not to the
        work's nodes.
    fold_tolerance : float, optional
        How closely a fold is located when the bolt leaves it downward, not continuous
        with the branch (degrees; default ``phase_tolerance``): the screw-in proof's
        :data:`PROOF_FOLD_TOLERANCE`. A fold whose landing is continuous with the branch
        or lies above it is then located on to ``phase_tolerance``, by the same bisection,
        so that it is told and judged where it was. Coarser than ``phase_tolerance``, the
        walk halves a step that leaves the branch before it looks for a fold in it
        (:meth:`_halves`).
    clicks : bool
        Measure each jump's click (:func:`sensor_click`, one settle more per jump).
        False: a proof's walk, judged by its descent and torque alone; its jumps' clicks
        are NaN.
    """

    def __init__(
        self,
        mech: Mechanics,
        roll: float,
        pitch: float,
        *,
        step: float = CONTINUATION_STEP,
        phase_tolerance: float = PHASE_TOLERANCE,
        contact_changes: bool = True,
        sense: str = "unscrew",
        screw_in: float = SCREW_IN,
        torque_limit: float | None = None,
        fold_tolerance: float | None = None,
        clicks: bool = True,
    ) -> None:
        if sense not in SENSES:
            raise InputError(f"sense must be one of {', '.join(SENSES)}, got {sense!r}")
        self.mech = mech
        self.held_roll, self.held_pitch = float(roll), float(pitch)
        self.sense = sense
        self.tightening = sense == "tighten"
        # Turned clockwise, steps of at most TIGHTEN_STEP whatever the search's.
        self.step = min(float(step), TIGHTEN_STEP) if self.tightening else float(step)
        self.phase_tolerance = float(phase_tolerance)
        self.fold_tolerance = max(self.phase_tolerance, fold_tolerance or 0.0)
        self.contact_changes = contact_changes
        self.clicks = clicks
        # +1: counter-clockwise (increasing phase), the unscrewing sense of a right-hand
        # thread; tightening turns the other way.
        self.sign = mech.spec.handedness * (-1 if self.tightening else 1)
        self.drop_limit = mech.spec.pitch / 40
        self.floor = mech.load_carrying
        #: Turn of the clockwise continuation that proves a snap (degrees; 0: none).
        self.screw_in = float(screw_in)
        self.torque_limit = default_torque_limit(mech) if torque_limit is None else torque_limit
        #: The proofs' clockwise walks so far (:meth:`_tighten` joins them).
        self._screwed: list[Walked] = []
        #: The friction coefficients strictly between which every proof made so far
        #: judges alike (:attr:`Engagement.frictions`, intersected).
        self.frictions: tuple[float, float] = (0.0, math.inf)

    def _settle(
        self,
        phase: float,
        before: MechanicalState,
        *,
        probe: bool = True,
        arrive: Callable[[MechanicalState], MechanicalState | None] | None = None,
    ) -> MechanicalState:
        """The rest state at ``phase`` continued from ``before``; a ``probe`` stops once
        departed from ``before`` (:data:`DEPARTURE`, :meth:`Mechanics.settle`): the
        continuation asks only whether it left the branch, and :meth:`_bisect` settles in
        full the jump it keeps."""
        fall = self._helical_fall(before, abs(phase - before.phase))
        if any(c.above for c in before.touching):
            # Material over the bolt: the branch's tangent decides the tilt as well.
            before = self.mech.predicted(before, phase)
        elif fall:
            # Predicted along the helix: the descent starts where the thread takes the bolt,
            # and its departure is measured from there.
            x, y, z = before.centre
            before = replace(before, centre=(x, y, z - fall))
        return self.mech.settle(
            self.held_roll,
            self.held_pitch,
            phase,
            start=before,
            leave=(DEPARTURE * self.drop_limit, DEPARTURE * JUMP_TILT) if probe else None,
            arrive=arrive,
        ).state

    def _tilted(self, before: MechanicalState, phase: float) -> MechanicalState | None:
        """A rest state at ``phase`` continuous with ``before``, settled from ``before``
        tilted by :data:`TILT_PROBES` in each of eight directions; None when there is
        none (no rest state continues the branch: the bolt is wedged)."""
        for size in TILT_PROBES:
            for k in range(8):
                a = math.radians(45.0 * k)
                start = replace(
                    before,
                    roll=before.roll + size * math.cos(a),
                    pitch=before.pitch + size * math.sin(a),
                )
                found = self._settle(phase, start, probe=False)
                if found.classification != UNSTABLE and self._continuous(before, found):
                    return found
        return None

    def _helical_fall(self, a: MechanicalState, turn: float) -> float:
        """How far the compliance centre of ``a`` falls along the helix when turned by
        ``turn`` degrees in this continuation's sense: the lead's share when ``a`` is in
        phase (down tightening, up unscrewing), else nothing."""
        if a.classification != IN_PHASE:
            return 0.0
        fall = self.mech.spec.lead * turn / 360.0
        return fall if self.tightening else -fall

    def _halves(self, a: MechanicalState, b: MechanicalState, turn: float) -> bool:
        """Whether a walk that locates folds coarser than the phase tolerance (a proof's),
        whose step of ``turn`` degrees from ``a`` left the branch at ``b``, takes half the
        step again instead of looking for a fold in it.

        A proof asks only whether and how the bolt goes in, not where its walk's steps
        fall (a search's do: its legs' work and events are the library's). Where its
        steps leave the branch, most often the predictor fell short, not the branch: a
        bolt pinched between the flanks, turned that far at its tilt, meets the nut at
        every height and the lowering climbs out; a descent from a long turn wanders off
        along a nearly flat valley. A shorter step then stays on it, for one settle where
        closing in on the step's end takes ten. A step is halved down to what the fold's
        bisection would locate: a landing above the branch (no jump: a jump goes down) to
        a few times the phase tolerance, any other to twice the fold tolerance. A step
        whose landing left the branch by its class alone (into phase, as at a snap, where
        the bisection stops at the fold tolerance) is not halved.
        """
        fall = self._fall(a, b)
        if self.fold_tolerance <= self.phase_tolerance or (
            abs(fall) <= self.drop_limit and _tilt_between(a, b) <= JUMP_TILT
        ):
            return False
        return turn > (
            8 * self.phase_tolerance if fall < -self.drop_limit else 2 * self.fold_tolerance
        )

    def _fall(self, a: MechanicalState, b: MechanicalState) -> float:
        """How far ``b`` lies below the branch through ``a``: its compliance centre's drop
        beyond the helix's share (negative above)."""
        return a.centre[2] - b.centre[2] - self._helical_fall(a, abs(b.phase - a.phase))

    def _continuous(self, a: MechanicalState, b: MechanicalState) -> bool:
        # Into phase is a fold (the snap), but not screwing in from a pose in phase
        # already whose descent stopped short of the balance: the thread held the bolt.
        if (
            b.classification == IN_PHASE
            and a.classification != IN_PHASE
            and not (self.tightening and a.kind == IN_PHASE)
        ):
            return False
        # Either way: a rest state that climbs out of the thread within a step (turned at
        # a tilt where the thread pinches the bolt, the lowering leaves it) is no more
        # the branch than one that falls.
        return abs(self._fall(a, b)) <= self.drop_limit and _tilt_between(a, b) <= JUMP_TILT

    def _bisect(
        self,
        phase: float,
        lo: float,
        hi: float,
        s_lo: MechanicalState,
        s_hi: MechanicalState,
        same: Callable[[MechanicalState, MechanicalState], bool],
        hi_from: MechanicalState,
        ride: list[MechanicalState] | None = None,
        *,
        fold: bool = False,
    ) -> tuple[float, float, MechanicalState, MechanicalState]:
        """Close in on where ``same(s_lo, state)`` stops holding, from the side before
        (``lo``, ``hi``: turns from ``phase``; ``s_hi`` was settled from ``hi_from``).
        ``ride``, when given, collects the states found on the side before: they resolve
        the branch's last stretch, where the bisection closes in (:func:`sensor_click`).

        The state returned at ``hi`` is the one the bolt reaches from the last state on
        the side before, turned on to ``hi``: settled in full from ``s_lo``. A state at
        ``hi`` settled from an earlier one (or a probe stopped once departed) answers
        only whether a longer turn leaves the branch; from further back a descent can
        fall past a rest state that continues it.

        A ``fold`` stops at :attr:`fold_tolerance` when the state returned there leaves
        the branch downward; otherwise the bisection goes on to the phase tolerance from
        where it stopped, as if it had not (the same halvings, the same states)."""
        tolerance = self.fold_tolerance if fold else self.phase_tolerance
        while True:
            while hi - lo > tolerance:
                mid = 0.5 * (lo + hi)
                s_mid = self._settle(phase + self.sign * mid, s_lo)
                if same(s_lo, s_mid):
                    lo, s_lo = mid, s_mid
                    if ride is not None:
                        ride.append(s_mid)
                else:
                    hi, s_hi, hi_from = mid, s_mid, s_lo
            landing = s_hi
            if s_hi.kind == "departed" or hi_from is not s_lo:
                landing = self._settle(phase + self.sign * hi, s_lo, probe=False)
            if tolerance <= self.phase_tolerance or (
                not same(s_lo, landing) and landing.potential <= s_lo.potential
            ):
                return lo, hi, s_lo, landing
            tolerance = self.phase_tolerance

    def torque(self, s: MechanicalState) -> tuple[float, float]:
        """The driver's torque at ``s`` in this continuation's sense, and its friction
        part (N m)."""
        if not self.tightening:
            return s.driver_torque, s.friction_torque
        return tightening_torque(s)

    def friction_work(self, a: MechanicalState, b: MechanicalState) -> float:
        """The driver's work against friction over the step from ``a`` to ``b``, states
        the walk settled one after the other on a continuous branch (mJ): the trapezoid
        rule on their friction torques (:meth:`torque`).

        A state that is not a rest state (its descent stopped short of the balance: class
        ``unstable``) has contact forces that do not balance the load and the spring, so
        no driver's torque of its own: where the other end of the step is a rest state,
        that state's friction torque stands for the whole step; where neither is, their
        own torques (the forces that best balance the load) are the only estimate there
        is. The rule looks at the step alone, so that a walk split into legs anywhere
        (the library's, at its grid phases) gives the same sum.
        """
        fa, fb = self.torque(a)[1], self.torque(b)[1]
        rest_a, rest_b = a.classification != UNSTABLE, b.classification != UNSTABLE
        if rest_a != rest_b:
            fa = fb = fa if rest_a else fb
        if not (math.isfinite(fa) and math.isfinite(fb)):
            return 0.0
        return MJ_PER_J * 0.5 * (fa + fb) * math.radians(abs(b.phase - a.phase))

    def snap_window(self, states: list[MechanicalState], snap: SearchEvent) -> tuple[float, float]:
        """The phases within which the bolt may drop into the thread: from the first rest
        state of the branch before ``snap`` (within :data:`WINDOW` of it) whose settle
        :data:`WINDOW_PROBE` further on falls in phase, to the snap itself.

        Where that branch is a shallow basin (a point riding a crest, a countersink's
        edge), a descent started a little further along it can fall out of it well before
        the branch ends: where the drop comes then depends on how far the bolt is turned
        between settles (or, on a robot, on vibration). The snap is that window, not one
        phase; where no probe falls early the window is the snap's phase alone.
        """
        end = snap.phase
        branch = [
            s
            for s in states
            if s.classification in (STABLE, QUASI_STABLE)
            and 0.0 < self.sign * (end - s.phase) <= WINDOW
        ]
        for s in branch:
            at = s.phase + self.sign * WINDOW_PROBE
            if self.sign * (end - at) <= 0:
                break
            probe = self._settle(at, s, probe=False)
            if probe.classification == IN_PHASE and s.centre[2] - probe.centre[2] > self.drop_limit:
                return (min(at, end), max(at, end))
        return (end, end)

    def jams(self, s: MechanicalState) -> bool:
        """Whether the driver's torque at ``s`` passes the limit. Not at a near-singular
        state, whose forces (and so torque) are the model's bound, not the physics'."""
        return not s.near_singular and self.torque(s)[0] > self.torque_limit

    def proved(
        self, state: MechanicalState, phase: float
    ) -> tuple[MechanicalState, Engagement | None]:
        """``state`` (at ``phase``, degrees as turned) with its proof (:meth:`prove`), and
        the proof, when its load-carrying contacts lie in phase (kind ``in-phase``),
        whether or not its descent balanced, or when it follows the helix and screws in
        (below); else ``state`` itself and None.

        A descent in the thread can stop short of the balance (a flank on the nut's crest
        corner, the spring pulling the bolt's tilt back): such a state is no rest state,
        but one that screws in moves along the helix as it turns, and that makes it in
        phase whatever else it looks like (mechanics.md): it is classed so.

        So is any other state that moves along the helix as it turns
        (:meth:`follows_helix`) and screws in: a bolt carried partly by the nut's thread
        and partly by its entry (its point on a nut flank, its crest on the countersink),
        or by the countersink alone (its thread's edge on the cone: turned, the thread
        moves along its own helix, in the nut's groove or not, and the screw-in tells
        which). Classed in phase and returned with its proof when it screws in; else
        returned as it is, with None."""
        if state.kind == IN_PHASE:
            proof = self.prove(state, phase)
            cls = IN_PHASE if proof.engaged else state.classification
            return replace(state, classification=cls, engagement=proof), proof
        if self.follows_helix(state):
            proof = self.prove(state, phase)
            if proof.engaged:
                return replace(state, classification=IN_PHASE, engagement=proof), proof
        return state, None

    def follows_helix(self, state: MechanicalState) -> bool:
        """Whether ``state``, turned clockwise (tightening) at its own tilt and lowered onto
        the nut, descends by the lead's share of that turn, within :data:`HELIX_SHARES`
        of it (as it is carried partly by the nut's thread or by its entry alone,
        :meth:`_in_nut_thread`): the test of mechanics.md ("a state that moves along the
        helix as it turns is in phase"), asked before the dearer screw-in proves it.

        The turn is :data:`HELIX_PROBE`, or longer where the meshes are coarse
        (:data:`HELIX_PROBE_MARGIN`)."""
        mech = self.mech
        spec = mech.spec
        deviation = max(mech.scene.deviation, mech.tolerance)
        turn = max(HELIX_PROBE, HELIX_PROBE_MARGIN * deviation * 360.0 / spec.lead)
        tilt = np.radians([state.roll, state.pitch])
        zc = state.centre[2]
        d = mech.drop(
            mech._rotation(tilt, state.phase - spec.handedness * turn),
            np.array(state.centre[:2]),
            zc,
        )
        share = spec.lead * turn / 360.0
        low, high = HELIX_SHARES["thread" if self._in_nut_thread(state) else "entry"]
        return d is not None and low * share < zc - d.zc < high * share

    def _in_nut_thread(self, state: MechanicalState) -> bool:
        """Whether a contact that carries ``state`` lies on the nut's thread (a face or a
        corner of it): the contacts carrying more than the load-carrying share of the
        load, or where the forces are unknown (not at rest), the touching ones."""
        return any(
            c.nut_feature in HELICAL_FEATURES
            and (c.force > self.floor if math.isfinite(c.force) else c.gap == 0.0)
            for c in state.contacts
        )

    def _entered(
        self, phase: float, at: float, nxt: float, prev: MechanicalState, cur: MechanicalState
    ) -> tuple[float, float, MechanicalState, MechanicalState] | None:
        """Where the search's continuous step from ``prev`` (turn ``at`` from ``phase``) to
        ``cur`` (turn ``nxt``) passed into phase without a jump (the thread's edge riding
        the countersink into the nut's groove, say): the turns either side, the last
        state before and the proved state after; None where ``cur`` does not follow the
        helix or does not screw in (the walk goes on).

        Located by bisection to the phase tolerance: where the states start to follow the
        helix (:meth:`follows_helix`), or where ``prev`` follows it already, where the
        load-carrying contacts change; the state there, settled in full from the last
        one before, is proved in its turn. Where that one does not screw in, the passage
        is the step's end."""
        if self.tightening or not self.follows_helix(cur):
            return None
        entered, proof = self.proved(cur, phase + self.sign * nxt)
        if proof is None or not proof.engaged:
            return None
        before = _carrying_pairs(prev, self.floor)
        following = self.follows_helix(prev)

        def same(x: MechanicalState, y: MechanicalState) -> bool:
            moved = _carrying_pairs(y, self.floor) != before if following else self.follows_helix(y)
            return not moved and self._continuous(x, y)

        lo, hi, s_lo, s_hi = self._bisect(phase, at, nxt, prev, cur, same, prev)
        if self._continuous(s_lo, s_hi):
            s_hi, proof = self.proved(s_hi, phase + self.sign * hi)
            if proof is not None and proof.engaged:
                return lo, hi, s_lo, s_hi
        return at, nxt, prev, entered

    def prove(self, state: MechanicalState, phase: float) -> Engagement:
        """Whether ``state`` (at ``phase``, degrees as turned) is engaged: turned
        clockwise (tightening) by :attr:`screw_in` degrees from it, the bolt descends at
        the lead over the second half (:func:`engagement`).

        A bolt that lands in the thread tilted straightens as the thread draws it in, and
        meanwhile descends by less than the lead. While it still descends, neither at the
        lead nor jammed, the turn goes on by half the screw-in at a time, judged over the
        last half, up to :data:`PROOF_TURN_LIMIT` in all: it is engaged once it descends
        at the lead."""
        if self.screw_in <= 0.0:
            return Engagement(True, 0.0, math.nan, self.mech.spec.lead, math.nan, math.nan)
        walk = Continuation(
            self.mech,
            self.held_roll,
            self.held_pitch,
            step=self.step,
            phase_tolerance=self.phase_tolerance,
            contact_changes=False,
            sense="tighten",
            torque_limit=self.torque_limit,
            fold_tolerance=PROOF_FOLD_TOLERANCE,
            clicks=False,
        )
        legs, events, states = joined_walk(self._screwed, walk, state, phase, self.screw_in)
        turned, piece = self.screw_in, 0.5 * self.screw_in
        proof = engagement(walk, state, legs, events, states, turned, piece)
        while (
            not (proof.engaged or proof.jammed)
            and proof.descent > LEAD_TOLERANCE * proof.lead
            and turned + piece <= PROOF_TURN_LIMIT + 1e-9
        ):
            more_legs, more_events, more = joined_walk(
                self._screwed, walk, states[-1], states[-1].phase, piece
            )
            legs += more_legs
            events += more_events
            states += more
            turned += piece
            proof = engagement(walk, state, legs, events, states, turned, piece)
        self._screwed.append(Walked(state, legs, events, states))
        low, high = proof.frictions
        self.frictions = (max(self.frictions[0], low), min(self.frictions[1], high))
        return proof

    def _click(self, passed: list[MechanicalState], jump: float, landing: MechanicalState) -> float:
        """The click of the jump at phase ``jump`` onto ``landing`` (:func:`sensor_click`),
        from the rest state at :data:`CLICK_SPAN` before it: settled from the last rest
        state ``passed`` before that phase (or the first, where none lies before it),
        unless one lies within the phase tolerance of it already."""
        at = jump - self.sign * CLICK_SPAN
        rest = [s for s in passed if s.classification != UNSTABLE]
        if rest and all(abs(s.phase - at) > self.phase_tolerance for s in rest):
            before = [s for s in rest if self.sign * (at - s.phase) > 0]
            start = max(before, key=lambda s: self.sign * s.phase) if before else rest[0]
            there = self._settle(at, start, probe=False)
            if there.classification != UNSTABLE and self._continuous(start, there):
                rest.append(there)
        return sensor_click(rest, landing, at)

    def advance(
        self,
        state: MechanicalState,
        phase: float,
        turn: float,
        *,
        progress: Callable[[float], None] | None = None,
        arrive: Callable[[MechanicalState], MechanicalState | None] | None = None,
    ) -> tuple[list[Leg], list[SearchEvent], list[MechanicalState]]:
        """Turn from ``state`` (a rest state at ``phase``, degrees) by ``turn`` degrees in
        this continuation's sense, stopping early at a snap or, screwing in, at a wedge
        (:func:`wedged`: the driver stalls there). ``arrive``: rest states already
        known at the end of the turn, as :meth:`Mechanics.settle` asks for them on its
        last step (the library's sweep).

        Returns
        -------
        legs : list of Leg
            In order; a turning leg ends at each jump and at the end of the turn.
        events : list of SearchEvent
            Contact changes, jumps, the snap.
        states : list of MechanicalState
            Every rest state settled, both sides of each event, in phase order.
        """
        legs: list[Leg] = []
        events: list[SearchEvent] = []
        states: list[MechanicalState] = []
        sign = self.sign
        branch = [state]  # states of the current turning leg
        ride: list[MechanicalState] = []  # the folds' bisections' states before the fold
        branch_start = 0.0
        work = [0.0, 0.0]  # friction, potential (mJ) along the current turning leg

        def integrate(a: MechanicalState, b: MechanicalState) -> None:
            work[0] += self.friction_work(a, b)
            work[1] += b.potential - a.potential

        def close_branch(at: float) -> None:
            if at > branch_start or len(branch) > 1:
                torques = tuple((t, f) for t, f in map(self.torque, branch) if math.isfinite(t))
                legs.append(
                    Leg(
                        "turning",
                        branch[0],
                        branch[-1],
                        at - branch_start,
                        work[0],
                        work[1],
                        max((t for t, _ in torques), default=math.nan),
                        _label(branch),
                        torques=torques,
                    )
                )

        def carrying(s: MechanicalState) -> tuple[str, ...]:
            return _carrying_pairs(s, self.floor)

        def follow(a: MechanicalState, at_a: float, b: MechanicalState, at_b: float) -> None:
            """Extend the branch from ``a`` (at turn ``at_a``) to ``b``, continuous with it,
            locating a change of the load-carrying contacts between them."""
            before = carrying(a)
            if self.contact_changes and carrying(b) != before:

                def same(
                    x: MechanicalState, y: MechanicalState, before: tuple[str, ...] = before
                ) -> bool:
                    return carrying(y) == before and self._continuous(x, y)

                lo, hi, s_lo, s_hi = self._bisect(phase, at_a, at_b, a, b, same, a)
                if not self._continuous(s_lo, s_hi):
                    # A settle within the step left the branch that the step's own settle
                    # stayed on (pinched, a shorter turn's prediction can fall short): no
                    # contact change to tell, the branch runs on to ``b``.
                    integrate(a, b)
                    states.append(b)
                    branch.append(b)
                    return
                events.append(
                    SearchEvent(
                        phase + sign * 0.5 * (lo + hi),
                        "contact-change",
                        # What changed: the load-carrying pairs either side.
                        " + ".join(before),
                        " + ".join(carrying(s_hi)),
                        s_lo.centre[2] - s_hi.centre[2],
                        _tilt_between(s_lo, s_hi),
                    )
                )
                states.extend([s_lo, s_hi])
                branch.extend([s_lo, s_hi])
            # The work over the step the walk took, whatever was located within it: the
            # library's walk, which locates no contact changes, has the same nodes.
            integrate(a, b)
            states.append(b)
            branch.append(b)

        def snap(
            lo: float,
            hi: float,
            s_lo: MechanicalState,
            s_hi: MechanicalState,
            note: str,
            proof: Engagement | None,
            *,
            jumped: bool = True,
        ) -> bool:
            """Record the passage from ``s_lo`` (turn ``lo``) to ``s_hi`` (turn ``hi``):
            the snap where ``proof`` is engaged, else a jump; True for the snap. A passage
            into phase that is no jump (``jumped`` False) is a snap too: its work is the
            driver's over its turn, its click what a sensor sees of it (none, or a
            rise)."""
            kind = "snap" if proof is not None and proof.engaged else "jump"
            click = (
                self._click([state, *states, *ride], phase + sign * hi, s_hi)
                if self.clicks
                else math.nan
            )
            work = (
                (0.0, 0.0)
                if jumped
                else (self.friction_work(s_lo, s_hi), s_hi.potential - s_lo.potential)
            )
            label = UNSTABLE if jumped else _label([s_lo, s_hi])
            legs.append(Leg(kind, s_lo, s_hi, hi - lo, *work, math.nan, label, proof, click))
            events.append(
                SearchEvent(
                    phase + sign * hi,
                    kind,
                    s_lo.region_combination,
                    s_hi.region_combination,
                    s_lo.centre[2] - s_hi.centre[2],
                    _tilt_between(s_lo, s_hi),
                    note,
                    proof,
                    click,
                )
            )
            states.append(s_hi)
            return kind == "snap"

        prev, at = state, 0.0
        # The step taken: shorter where a step's predictor fell short of a branch that
        # goes on (see below, and :meth:`_halves` in a proof), growing back on each
        # continuous step.
        stride, grow = self.step, True
        while at < turn - 1e-12:
            if progress is not None:
                progress(at)
            nxt = min(at + stride, turn)
            cur = self._settle(phase + sign * nxt, prev, arrive=arrive if nxt == turn else None)
            if self._continuous(prev, cur):
                entered = self._entered(phase, at, nxt, prev, cur)
                if entered is not None:
                    lo, hi, s_lo, s_in = entered
                    if s_lo is not prev:
                        follow(prev, at, s_lo, lo)
                    close_branch(lo)
                    note = "passed into phase without a jump"
                    snap(lo, hi, s_lo, s_in, note, s_in.engagement, jumped=False)
                    return legs, _without_flicker(events), states
                follow(prev, at, cur, nxt)
                prev, at = cur, nxt
                # (Not at once after a halved step: the step's far end left the branch.)
                stride, grow = min(2 * stride, self.step) if grow else stride, True
                continue
            if self._halves(prev, cur, nxt - at):
                stride, grow = 0.5 * (nxt - at), False
                continue
            # A fold within (at, nxt]: close in on it from the side before.
            lo, hi, s_lo, s_hi = self._bisect(
                phase, at, nxt, prev, cur, self._continuous, prev, ride, fold=True
            )
            # The branch up to the last state on it (``prev`` itself when the fold lies
            # within the tolerance of it), its contact changes located.
            if s_lo is not prev:
                follow(prev, at, s_lo, lo)
            if not self._continuous(s_lo, s_hi) and s_hi.potential > s_lo.potential:
                # A fold is a fold only when no rest state continues the branch
                # (mechanics.md). ``s_hi`` is the settle from the last state on it, turned
                # on by less than the phase tolerance. A landing above the branch's
                # potential is no jump (a jump goes down U): turned at its tilt the bolt
                # meets the nut at every height in the thread (wedged between the flanks)
                # and the lowering climbed out; a rest state may continue the branch at a
                # tilt nearby.
                s_hi = self._tilted(s_lo, phase + sign * hi) or s_hi
            if self._continuous(s_lo, s_hi):
                # The probe left the branch, but its descent carried to its end came back
                # to it (where the thread starts meet, a descent can wander that far along
                # a nearly flat valley, or the step was longer than its predictor's
                # reach): no fold here. Carry on from the state at ``hi``, in steps as
                # long as the one that stayed on the branch.
                follow(s_lo, lo, s_hi, hi)
                stride = max(lo - at, hi - lo, 8 * self.phase_tolerance)
                prev, at = s_hi, hi
                continue
            close_branch(lo)
            proof, note = None, ""
            if not self.tightening:
                s_hi, proof = self.proved(s_hi, phase + sign * hi)
                if proof is not None and not proof.engaged:
                    note = f"not a snap: {proof.reason}"
            if snap(lo, hi, s_lo, s_hi, note, proof):
                return legs, _without_flicker(events), states
            if self.tightening and s_hi.potential > s_lo.potential:
                # Wedged (:func:`wedged`): screwing in, the driver stalls here; the turn
                # beyond, from a landing the bolt could reach only by rising, is no walk.
                return legs, _without_flicker(events), states
            prev, at = s_hi, hi
            branch, branch_start, work = [s_hi], hi, [0.0, 0.0]
        close_branch(at)
        return legs, _without_flicker(events), states


@dataclass(frozen=True)
class Turn:
    """A turn from a start, set up by :func:`begin_turn`.

    Attributes
    ----------
    mech : Mechanics
        The thread pair and compliance.
    walk : Continuation
        The continuation that turns the bolt.
    start : MechanicalState
        The start's rest state (settled from first contact).
    end : float
        The turn asked for (degrees).
    queries : int
        The mechanics' collision queries before the start was settled.
    """

    mech: Mechanics
    walk: Continuation
    start: MechanicalState
    end: float
    queries: int


def begin_turn(
    target: Mechanics | ThreadSpec,
    roll: float,
    pitch: float,
    phase: float,
    *,
    compliance: Compliance | None,
    turns: float,
    step: float,
    phase_tolerance: float,
    chord: float | None,
    torque_limit: float | None,
    sense: str = "unscrew",
    screw_in: float = SCREW_IN,
) -> Turn:
    """The set-up that :func:`search` and :func:`threadmate.contact.screw` share: their
    settings checked, the mechanics built (or taken), the continuation in ``sense`` and
    the start's rest state. The parameters are theirs."""
    check_continuation(turns=turns, step=step, phase_tolerance=phase_tolerance)
    check_screw(screw_in=screw_in, torque_limit=torque_limit)
    mech = mechanics(target, compliance, chord)
    queries = mech.engine.queries
    walk = Continuation(
        mech,
        roll,
        pitch,
        step=step,
        phase_tolerance=phase_tolerance,
        sense=sense,
        screw_in=screw_in,
        torque_limit=torque_limit,
    )
    start = mech.settle(roll, pitch, phase).state
    return Turn(mech, walk, start, 360.0 * turns, queries)


def search(
    target: Mechanics | ThreadSpec,
    roll: float,
    pitch: float,
    phase: float,
    *,
    compliance: Compliance | None = None,
    turns: float = 1.0,
    step: float = CONTINUATION_STEP,
    phase_tolerance: float = PHASE_TOLERANCE,
    chord: float | None = None,
    progress: Callable[[int, int], None] | None = None,
    screw_in: float = SCREW_IN,
    torque_limit: float | None = None,
) -> SearchResult:
    """Simulate the counter-clockwise search from a start (see the module docstring).

    The bolt turns the way that unscrews its thread: counter-clockwise (increasing phase)
    for a right-hand thread, clockwise for a left-hand one.

    Parameters
    ----------
    target : ThreadSpec or Mechanics
        The thread pair (a :class:`Mechanics` is built and cached for it) or a ready one.
    compliance : Compliance, optional
        Load, stiffness, friction (with a spec; default :class:`Compliance()`).
    roll, pitch : float
        Held tilt (degrees).
    phase : float
        Start phase (degrees).
    turns : float
        How far to search (turns of 360 degrees, > 0, at most 10).
    step : float
        Continuation step (degrees, within (0, 10]).
    phase_tolerance : float
        How closely events are located in phase (degrees, within (0, step]).
    progress : callable, optional
        Called as ``progress(done, total)`` with the whole degrees turned and to turn.
    screw_in : float
        Turn of the clockwise continuation that proves each snap (degrees, within
        [0, 720]; 0: no proof): a landing in phase that does not then descend at the
        lead is a jump, and its event says why.
    torque_limit : float, optional
        Tightening torque past which the proof counts the bolt jammed (N m, > 0; default
        :func:`default_torque_limit`).

    Returns
    -------
    SearchResult
        ``snap`` is None when no snap came within ``turns``.
    """
    turn = begin_turn(
        target,
        roll,
        pitch,
        phase,
        compliance=compliance,
        turns=turns,
        step=step,
        phase_tolerance=phase_tolerance,
        chord=chord,
        torque_limit=torque_limit,
        screw_in=screw_in,
    )
    mech, walk, start, end = turn.mech, turn.walk, turn.start, turn.end
    legs: list[Leg] = []
    events: list[SearchEvent] = []
    start, proof = walk.proved(start, float(phase))
    states = [start]
    if proof is not None and proof.engaged:
        events.append(
            SearchEvent(float(phase), "snap", "", start.region_combination, 0.0, 0.0, "", proof)
        )
    else:
        if proof is not None:
            events.append(
                SearchEvent(
                    float(phase),
                    "jump",
                    "",
                    start.region_combination,
                    0.0,
                    0.0,
                    f"not a snap: {proof.reason}",
                    proof,
                )
            )
        tick = None if progress is None else (lambda at: progress(int(at), int(math.ceil(end))))
        legs, more_events, more = walk.advance(start, float(phase), end, progress=tick)
        events += more_events
        states += more
    if progress is not None:
        progress(int(math.ceil(end)), int(math.ceil(end)))
    snap = next((e for e in events if e.kind == "snap"), None)
    window = None if snap is None else walk.snap_window(states, snap)
    return SearchResult(
        mech.units,
        float(roll),
        float(pitch),
        float(phase),
        mech.compliance.to_dict(),
        tuple(states),
        tuple(events),
        snap,
        float(turns),
        sum(leg.work_friction for leg in legs),
        sum(leg.work_potential for leg in legs),
        mech.engine.queries - turn.queries,
        window,
    )
