"""Results of the mechanics: rest states, the states passed on the way, the search.

Plain frozen objects with a JSON form. Lengths in the spec's units, angles in degrees,
forces in N, torques in N m, potentials and work in mJ (docs/mechanics.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ...geometry import Pose
from ..scene import RegionPair, Vec

__all__ = [
    "tightening_torque",
    "turn_units",
    "Engagement",
    "LEAD_TOLERANCE",
    "LoadedContact",
    "MechanicalState",
    "RestState",
    "SearchEvent",
    "SearchResult",
]

#: Largest departure of a screwed-in bolt's descent per turn from the lead, relative to the
#: lead, for the bolt to count as engaged (:class:`Engagement`).
LEAD_TOLERANCE = 0.1


def turn_units(length: str) -> dict[str, str]:
    """The ``units`` of a turn's JSON document (a search's or a clockwise start's)."""
    return {
        "length": length,
        "angle": "deg",
        "force": "N",
        "torque": "N m",
        "work": "mJ",
        "potential": "mJ",
    }


def tightening_torque(s: MechanicalState) -> tuple[float, float]:
    """The driver's torque at ``s`` turned the tightening way, and its friction part (N m).
    A state stores them in the unscrewing sense: turned the other way the normal forces'
    moment changes sign, friction still resists."""
    return 2.0 * s.friction_torque - s.driver_torque, s.friction_torque


def scaled_peak(torques: tuple[tuple[float, float], ...], scale: float) -> float:
    """The largest of ``torques`` (each a torque and its friction part, N m) with every
    friction part scaled by ``scale``; NaN for none."""
    return max((t + (scale - 1.0) * f for t, f in torques), default=math.nan)


def torque_jam_reason(torque: float, phase: float, limit: float) -> str:
    """Why a proof whose tightening torque passed its limit is no snap (N m, degrees)."""
    return (
        f"the tightening torque reaches {torque:.3g} N m at phase {phase:.2f} deg, past the "
        f"limit {limit:.3g} N m (jammed)"
    )


@dataclass(frozen=True)
class Engagement:
    """The proof of a snap: the bolt turned clockwise (tightening) from a state.

    Attributes
    ----------
    engaged : bool
        It descends at the lead (within :data:`LEAD_TOLERANCE` of it) without the
        driver's torque passing its limit: the bolt's thread is in the nut's.
    turn : float
        How far it was turned (degrees).
    descent : float
        Descent of the compliance centre per turn over the turn's last half screw-in
        (by default its last 90 degrees; spec units per 360 degrees).
    lead : float
        The thread's lead (spec units per turn).
    tilt : float
        Angle between the bolt and nut axes at the end (degrees).
    torque_peak : float
        Largest tightening torque the driver applied (N m).
    reason : str
        Why it is not engaged ('' when it is).
    jammed : bool
        It is not engaged because it wedged or its torque passed the limit (not because
        it descends at another rate).
    frictions : (float, float)
        The friction coefficients ``(low, high)`` strictly between which the proof
        judges every state it passed as it did, each past the torque limit or not: the
        same walk and the same verdict (the rest states are frictionless, and the
        friction part of every torque is proportional to the coefficient). The
        coefficient it was made with lies inside, or on an end when that is 0.
    torques : tuple of (float, float)
        The tightening torque and its friction part at each state passed (N m), for
        :meth:`scaled`.
    torque_jam : (float, float, float, float) or None
        Where the torque passed its limit first: the torque, its friction part (N m),
        the phase (degrees) and the limit (N m); None when it did not.
    """

    engaged: bool
    turn: float
    descent: float
    lead: float
    tilt: float
    torque_peak: float
    reason: str = ""
    jammed: bool = False
    frictions: tuple[float, float] = (0.0, math.inf)
    torques: tuple[tuple[float, float], ...] = ()
    torque_jam: tuple[float, float, float, float] | None = None

    def scaled(self, scale: float) -> Engagement:
        """The proof as made with the friction coefficient scaled by ``scale``, for a
        coefficient within :attr:`frictions`: the same walk and verdict, its torques'
        friction parts scaled."""
        if scale == 1.0:
            return self
        reason = self.reason
        if self.torque_jam is not None:
            t, f, phase, limit = self.torque_jam
            reason = torque_jam_reason(t + (scale - 1.0) * f, phase, limit)
        return replace(self, torque_peak=scaled_peak(self.torques, scale), reason=reason)

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping for JSON."""
        return {
            "engaged": self.engaged,
            "turn": self.turn,
            "descent_per_turn": self.descent,
            "lead": self.lead,
            "tilt_at_end": self.tilt,
            "torque_peak": self.torque_peak,
            "jammed": self.jammed,
            "reason": self.reason,
        }


@dataclass(frozen=True)
class LoadedContact(RegionPair):
    """One contact of a mechanical state.

    Attributes
    ----------
    point : (x, y, z)
        Location in F (spec units).
    normal : (nx, ny, nz)
        Unit common normal in F, from the nut into the bolt.
    force : float
        Normal force the nut exerts on the bolt there (N; 0 for a contact that touches
        without load, NaN in a state that is not at rest).
    gap : float
        Vertical gap (spec units) at the state's pose; 0 when touching. A contact of a
        rest state found within the meshes' accuracy (mechanics.md, "Stop") may carry
        force open by up to the meshes' deviation: it keeps its gap.
    bolt_region, nut_region : str
        Regions of the exact profiles (conventions.md names).
    bolt_feature, nut_feature : str
        ``rim``, ``cap``, ``corner`` or ``thread``.
    above : bool
        The nut's material lies above the bolt there (a nut flank over a bolt flank in
        the thread): the contact opens as the bolt moves down, and ``gap`` is its rise.
    """

    point: Vec
    normal: Vec
    force: float
    gap: float
    bolt_region: str
    nut_region: str
    bolt_feature: str = ""
    nut_feature: str = ""
    above: bool = False


@dataclass(frozen=True)
class MechanicalState:
    """The bolt at one pose: where it is, what it touches, what it costs.

    Attributes
    ----------
    kind : str
        What the state is on the way: ``first-contact``, ``new-contact``, ``rolling``
        (a contact released: the pivot rolls), ``rest``, ``in-phase``; ``departed``: a
        probe of the continuation stopped once off the branch (never a library state).
    classification : str
        One of :data:`REST_CLASSES`.
    phase : float
        Spin of the bolt (degrees).
    roll, pitch : float
        Actual tilt of the bolt (degrees).
    origin : (x, y, z)
        Bolt origin (tip centre) in F.
    rotation : 3 x 3 nested tuple
        Bolt rotation matrix in F.
    centre : (x, y, z)
        Compliance centre in F.
    contacts : tuple of LoadedContact
        The contacts within the descent's depth ``near`` of the pose: touching (gap 0)
        and near ones.
    potential : float
        ``F z_C + k/2 |tilt - held|^2 (+ k_t/2 |xy|^2)`` in mJ (``z_C`` from the nut's top).
    driver_torque : float
        Torque the driver applies about the bolt axis to keep turning counter-clockwise,
        normal and friction forces together (N m; NaN away from rest).
    friction_torque : float
        The part of :attr:`driver_torque` that overcomes friction (N m).
    turn : float
        Tilt of the bolt axis since the previous state on the way (degrees).
    near_singular : bool
        The rigid balance asks for contact forces far beyond what the load and the
        spring can explain (two contacts' line through the compliance centre, a level
        normal): the forces reported are bounded (mechanics.md, "Near-singular contacts").
    engagement : Engagement or None
        For an in-phase state a continuation or a sweep proved: its screw-in (None: not
        proved). Not part of the state's identity.
    contact_curvature : 2 x 2 nested tuple or None
        The descent's model of the contacts' curvature about roll and pitch at a rest
        state (N m/rad, quasi-Newton): a continuation from this state starts its descent
        with it, so that each step depends on the state it leaves and on nothing settled
        before. Not part of the state's identity or its JSON.
    """

    kind: str
    classification: str
    phase: float
    roll: float
    pitch: float
    origin: Vec
    rotation: tuple[Vec, Vec, Vec]
    centre: Vec
    contacts: tuple[LoadedContact, ...]
    potential: float
    driver_torque: float = float("nan")
    friction_torque: float = float("nan")
    turn: float = 0.0
    near_singular: bool = False
    contact_curvature: tuple[tuple[float, float], tuple[float, float]] | None = field(
        default=None, repr=False, compare=False
    )
    engagement: Engagement | None = field(default=None, repr=False, compare=False)

    @property
    def pose(self) -> Pose:
        """The bolt pose."""
        return Pose(np.array(self.rotation, dtype=float), np.array(self.origin, dtype=float))

    @property
    def touching(self) -> tuple[LoadedContact, ...]:
        """The contacts with no gap, and those open by less than the meshes' accuracy
        that carry force in a rest state found within it (mechanics.md, "Stop")."""
        return tuple(c for c in self.contacts if c.gap == 0.0 or c.force > 0.0)

    @property
    def region_combination(self) -> str:
        """``bolt/nut`` regions of the touching contacts joined by `` + ``."""
        return " + ".join(c.regions for c in self.touching)

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping for JSON."""
        return {
            "kind": self.kind,
            "classification": self.classification,
            "phase": self.phase,
            "roll": self.roll,
            "pitch": self.pitch,
            "origin": list(self.origin),
            "rotation": [list(r) for r in self.rotation],
            "centre": list(self.centre),
            "potential": self.potential,
            "driver_torque": self.driver_torque,
            "friction_torque": self.friction_torque,
            "turn": self.turn,
            "near_singular": self.near_singular,
            "region_combination": self.region_combination,
            "contacts": [c.to_dict() for c in self.contacts],
        }


@dataclass(frozen=True)
class RestState:
    """A rest state of the compliance-held bolt and the states passed on the way to it.

    Attributes
    ----------
    units : str
        Length units.
    held_roll, held_pitch : float
        The tilt the tool holds (degrees).
    phase : float
        The phase the driver holds (degrees).
    parameters : dict
        The :class:`Compliance` used (``Compliance.to_dict``).
    state : MechanicalState
        The rest state (or the in-phase state the bolt dropped into).
    path : tuple of MechanicalState
        The unstable states passed through from first contact, in order.
    balance : dict
        ``force`` and ``moment`` residuals of the equilibrium, relative to the load
        (``F`` and ``F`` times the bolt's major radius); ``converged``; ``touching_gap``
        (spec units) for a rest state found within the meshes' accuracy: the gap below
        which its balance counts a contact (mechanics.md, "Stop").
    iterations, queries : int
        Descent steps and collision queries spent.
    """

    units: str
    held_roll: float
    held_pitch: float
    phase: float
    parameters: dict[str, Any]
    state: MechanicalState
    path: tuple[MechanicalState, ...] = ()
    balance: dict[str, float] = field(default_factory=dict)
    iterations: int = 0
    queries: int = 0

    @property
    def classification(self) -> str:
        """The rest state's class."""
        return self.state.classification

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``threadmate settle --json``."""
        s = self.state
        return {
            "units": {
                "length": self.units,
                "angle": "deg",
                "force": "N",
                "torque": "N m",
                "potential": "mJ",
            },
            "held": {"roll": self.held_roll, "pitch": self.held_pitch},
            "phase": self.phase,
            "parameters": self.parameters,
            "classification": s.classification,
            "rest": {
                "origin": list(s.origin),
                "rotation": [list(r) for r in s.rotation],
                "roll": s.roll,
                "pitch": s.pitch,
                "centre": list(s.centre),
            },
            "contacts": [c.to_dict() for c in s.touching],
            "region_combination": s.region_combination,
            "potential": s.potential,
            "driver_torque": s.driver_torque,
            "balance": dict(self.balance),
            "path": [p.to_dict() for p in self.path],
            "iterations": self.iterations,
            "queries": self.queries,
        }


@dataclass(frozen=True)
class SearchEvent:
    """Something that happens during the search, located in phase.

    Attributes
    ----------
    phase : float
        Where (degrees), to the search's phase tolerance.
    kind : str
        ``contact-change`` (the touching contacts change smoothly), ``jump`` (the rest
        state ceases to exist: the bolt tips, rolls or drops to another) or ``snap``
        (the jump into the in-phase state).
    before, after : str
        Region combinations before and after.
    drop : float
        Fall of the compliance centre across the event (spec units).
    tilt_change : float
        Angle between the bolt axes before and after (degrees).
    note : str
        Why a jump into a state whose contacts lie on the helices is not a snap, or that a
        snap came without a jump ('' else).
    engagement : Engagement or None
        The screw-in proof of a landing in phase (None for other events).
    click : float
        At a jump or the snap, the fall a sensor sees: from the highest the branch stands
        within the last degree of turn (``CLICK_SPAN``) before the jump to the landing, a
        steep last stretch of the branch and earlier jumps within that turn included
        (``sensor_click`` in :mod:`threadmate.contact`; spec units); 0 for a contact
        change; NaN where no rest state precedes the jump.
    """

    phase: float
    kind: str
    before: str
    after: str
    drop: float = 0.0
    tilt_change: float = 0.0
    note: str = ""
    engagement: Engagement | None = None
    click: float = 0.0

    def to_dict(self) -> dict[str, Any]:
        """Plain mapping for JSON."""
        return {
            "phase": self.phase,
            "kind": self.kind,
            "before": self.before,
            "after": self.after,
            "drop": self.drop,
            "click": self.click,
            "tilt_change": self.tilt_change,
            "note": self.note,
            "engagement": None if self.engagement is None else self.engagement.to_dict(),
        }


@dataclass(frozen=True)
class SearchResult:
    """The counter-clockwise search simulated from one start.

    Attributes
    ----------
    units : str
    held_roll, held_pitch, start_phase : float
        The start (degrees).
    parameters : dict
        The compliance used.
    states : tuple of MechanicalState
        The rest states along the turn (every continuation step, and both sides of each
        event), in phase order; the last is in-phase after a snap.
    events : tuple of SearchEvent
    snap : SearchEvent or None
        The snap, or None when none came within the turns asked.
    turns : float
        Turns searched (1 = 360 degrees).
    work_friction, work_potential : float
        Driver's work to the snap (or over the turns searched) against friction and
        against the potential (mJ); their sum is :attr:`work`.
    queries : int
    snap_window : (float, float) or None
        The phases within which the bolt may drop into the thread (degrees, as turned;
        both the snap's phase where the branch before it is no shallow basin): see
        :meth:`Continuation.snap_window`. None without a snap.
    """

    units: str
    held_roll: float
    held_pitch: float
    start_phase: float
    parameters: dict[str, Any]
    states: tuple[MechanicalState, ...]
    events: tuple[SearchEvent, ...]
    snap: SearchEvent | None
    turns: float
    work_friction: float
    work_potential: float
    queries: int = 0
    snap_window: tuple[float, float] | None = None

    @property
    def work(self) -> float:
        """Driver's total work (mJ)."""
        return self.work_friction + self.work_potential

    @property
    def snap_turn(self) -> float | None:
        """Turn from the start to the snap (degrees, in the unscrewing sense), None
        without a snap."""
        return None if self.snap is None else abs(self.snap.phase - self.start_phase)

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``threadmate search --json``."""
        return {
            "units": turn_units(self.units),
            "parameters": self.parameters,
            "start": {"roll": self.held_roll, "pitch": self.held_pitch, "phase": self.start_phase},
            "turns": self.turns,
            "snap": None
            if self.snap is None
            else {
                "phase": self.snap.phase,
                "turn": self.snap_turn,
                "drop": self.snap.drop,
                "click": self.snap.click,
                "window": None if self.snap_window is None else list(self.snap_window),
                "engagement": None
                if self.snap.engagement is None
                else self.snap.engagement.to_dict(),
            },
            "work": {
                "total": self.work,
                "friction": self.work_friction,
                "potential": self.work_potential,
            },
            "events": [e.to_dict() for e in self.events],
            "states": [s.to_dict() for s in self.states],
            "queries": self.queries,
        }
