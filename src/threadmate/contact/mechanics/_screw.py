"""Clockwise starts: the bolt turned the tightening way directly, with no search first.

The thesis asks which phases permit clockwise insertion without cross-threading (its
section 5.3). From the rest state of a start, the driver turns the bolt clockwise (for a
right-hand thread) and the bolt follows its rest state (:class:`Continuation` in the
``tighten`` sense). What it does is one of (docs/mechanics.md, "Clockwise starts"):

- ``engaged``: it descends at the lead (within :data:`LEAD_TOLERANCE` of it) over
  :data:`ENGAGED_TURN` of turning in phase: its thread is in the nut's;
- ``jammed``: no rest state continues the turn (the branch ends, and the bolt could go on
  only by rising against the load: wedged between the threads), or the driver's torque
  passes its limit;
- ``riding``: neither within the turns asked: it turns on the nut without descending.

The turn is walked in pieces of :data:`ENGAGED_TURN`, so that it stops once decided.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ...geometry import ThreadSpec
from ..scene import IN_PHASE, QUASI_STABLE, STABLE
from ._compliance import Compliance
from ._rest_state import (
    LEAD_TOLERANCE,
    MechanicalState,
    SearchEvent,
    tightening_torque,
    turn_units,
)
from ._search import Leg, Turn, Walked, begin_turn, joined_walk, wedged
from ._settings import CONTINUATION_STEP, PHASE_TOLERANCE
from ._settle import Mechanics

__all__ = ["SCREW_OUTCOMES", "ENGAGED_TURN", "ClockwiseStarts", "ScrewResult", "screw"]

#: What a clockwise start does.
SCREW_OUTCOMES = ("engaged", "riding", "jammed")
#: Classes of rest states whose load-carrying contacts are not all on the helices.
OFF_HELIX = (STABLE, QUASI_STABLE)
#: Turn in phase over which a descent at the lead decides ``engaged`` (degrees).
ENGAGED_TURN = 90.0


@dataclass(frozen=True)
class ScrewResult:
    """A clockwise (tightening) start simulated.

    Attributes
    ----------
    units : str
    held_roll, held_pitch, start_phase : float
        The start (degrees).
    parameters : dict
        The compliance used.
    outcome : str
        One of :data:`SCREW_OUTCOMES`.
    decided_phase : float or None
        Where it is decided (degrees, as turned: decreasing for a right-hand thread):
        where the bolt entered the turn in phase it then screwed in along (``engaged``),
        where it jammed (``jammed``); None when ``riding``.
    reason : str
        What decided it, in words.
    states : tuple of MechanicalState
        The rest states along the turn, in phase order (up to the jam).
    events : tuple of SearchEvent
    turns : float
        Turns asked for.
    work_friction, work_potential : float
        Driver's work against friction and against the potential (mJ) up to the decision
        (or over the turns).
    torque_limit : float
        Tightening torque past which the bolt counts as jammed (N m).
    descent : float
        Descent of the compliance centre per turn over the last :data:`ENGAGED_TURN`
        turned (spec units per turn; NaN if less was turned).
    lead : float
        The thread's lead (spec units per turn).
    queries : int
    """

    units: str
    held_roll: float
    held_pitch: float
    start_phase: float
    parameters: dict[str, Any]
    outcome: str
    decided_phase: float | None
    reason: str
    states: tuple[MechanicalState, ...]
    events: tuple[SearchEvent, ...]
    turns: float
    work_friction: float
    work_potential: float
    torque_limit: float
    descent: float
    lead: float
    queries: int = 0

    @property
    def work(self) -> float:
        """Driver's total work (mJ)."""
        return self.work_friction + self.work_potential

    @property
    def torques(self) -> list[float]:
        """The tightening torque at each state (N m; NaN away from rest)."""
        return [tightening_torque(s)[0] for s in self.states]

    @property
    def torque_peak(self) -> float:
        """Largest tightening torque along the turn (N m; NaN without a rest state)."""
        return max((t for t in self.torques if math.isfinite(t)), default=math.nan)

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``threadmate screw --json``."""
        return {
            "units": turn_units(self.units),
            "parameters": self.parameters,
            "start": {"roll": self.held_roll, "pitch": self.held_pitch, "phase": self.start_phase},
            "turns": self.turns,
            "outcome": self.outcome,
            "decided_phase": self.decided_phase,
            "reason": self.reason,
            "descent_per_turn": self.descent,
            "lead": self.lead,
            "torque_limit": self.torque_limit,
            "torque_peak": self.torque_peak,
            "work": {
                "total": self.work,
                "friction": self.work_friction,
                "potential": self.work_potential,
            },
            "events": [e.to_dict() for e in self.events],
            "states": [s.to_dict() for s in self.states],
            "queries": self.queries,
        }


def _descent(states: list[MechanicalState]) -> float:
    """Descent of the compliance centre per turn over the last :data:`ENGAGED_TURN`
    degrees of ``states`` (spec units per turn; NaN if they span less)."""
    end = states[-1]
    tail = [s for s in states if abs(s.phase - end.phase) <= ENGAGED_TURN + 1e-9]
    turned = abs(end.phase - tail[0].phase)
    if turned < ENGAGED_TURN - 1e-9:
        return math.nan
    return (tail[0].centre[2] - end.centre[2]) * 360.0 / turned


def screw(
    target: Mechanics | ThreadSpec,
    roll: float,
    pitch: float,
    phase: float,
    *,
    compliance: Compliance | None = None,
    turns: float = 1.0,
    step: float = CONTINUATION_STEP,
    phase_tolerance: float = PHASE_TOLERANCE,
    torque_limit: float | None = None,
    chord: float | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> ScrewResult:
    """Turn the bolt clockwise (tightening) from a start and say what it does (module
    docstring).

    Parameters
    ----------
    target : ThreadSpec or Mechanics
        The thread pair (a :class:`Mechanics` is built and cached for it) or a ready one.
    roll, pitch : float
        Held tilt (degrees).
    phase : float
        Start phase (degrees).
    compliance : Compliance, optional
        Load, stiffness, friction (with a spec; default :class:`Compliance()`).
    turns : float
        How far to turn (turns of 360 degrees, > 0, at most 10).
    step, phase_tolerance : float
        Continuation step and event tolerance (degrees).
    torque_limit : float, optional
        Tightening torque past which the bolt counts as jammed (N m, > 0; default
        :func:`threadmate.contact.default_torque_limit`).
    progress : callable, optional
        Called as ``progress(done, total)`` with the whole degrees turned and to turn.
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
        sense="tighten",
    )
    return _turned(turn, phase, turns, progress=progress)


def _turned(
    turn: Turn,
    phase: float,
    turns: float,
    *,
    progress: Callable[[int, int], None] | None = None,
    walks: list[Walked] | None = None,
) -> ScrewResult:
    """The clockwise start ``turn`` (:func:`begin_turn`'s set-up) turned and judged; with
    ``walks``, its pieces taken from the earlier walks where it reaches one of their
    states (:func:`joined_walk`), and its own walk added to them."""
    mech, walk, end = turn.mech, turn.walk, turn.end
    lead = mech.spec.lead
    states = [turn.start]
    events: list[SearchEvent] = []
    legs: list[Leg] = []
    outcome, decided, reason = "riding", None, ""
    at, ph = 0.0, float(phase)
    walked = states  # every state walked, those past a torque jam included (``walks``)
    while at < end - 1e-9:
        if progress is not None:
            progress(int(at), int(math.ceil(end)))
        piece = min(ENGAGED_TURN, end - at)
        if walks is None:
            more_legs, more_events, more = walk.advance(states[-1], ph, piece)
        else:
            more_legs, more_events, more = joined_walk(walks, walk, states[-1], ph, piece)
        legs += more_legs
        events += more_events
        states += more
        at += piece
        ph += walk.sign * piece
        wedge = wedged(more_legs, more_events)
        if wedge is not None:
            jam = wedge[0]
            outcome, decided = "jammed", jam.phase
            reason = (
                f"no rest state continues the turn at phase {jam.phase:.2f} deg: the bolt "
                "would have to rise against the load (wedged)"
            )
            states = [s for s in states if walk.sign * (s.phase - jam.phase) <= 0]
            break
        over = [s for s in states if walk.jams(s)]
        if over:
            outcome, decided = "jammed", over[0].phase
            reason = (
                f"the tightening torque passes the limit {walk.torque_limit:.3g} N m at "
                f"phase {over[0].phase:.2f} deg"
            )
            break
        # Descending at the lead over the last piece, in phase at its end: engaged.
        descent = _descent(states)
        if states[-1].classification == IN_PHASE and abs(descent - lead) <= LEAD_TOLERANCE * lead:
            # Where it entered the thread: the last rest state off the helices before.
            entered = len(states) - 1
            while entered > 0 and states[entered - 1].classification not in OFF_HELIX:
                entered -= 1
            outcome, decided = "engaged", states[entered].phase
            reason = (
                f"in phase from phase {decided:.2f} deg, it descends "
                f"{descent:.4g} {mech.units} per turn (the lead {lead:.4g} {mech.units})"
            )
            break
    if walks is not None:
        walks.append(Walked(turn.start, legs, events, walked[1:]))
    if progress is not None:
        progress(int(math.ceil(end)), int(math.ceil(end)))
    if outcome == "riding":
        reason = f"turned {at:g} deg clockwise it neither descends at the lead nor jams"
    descent = _descent(states)
    kept = [leg for leg in legs if walk.sign * (leg.after.phase - states[-1].phase) <= 0]
    return ScrewResult(
        mech.units,
        walk.held_roll,
        walk.held_pitch,
        float(phase),
        mech.compliance.to_dict(),
        outcome,
        decided,
        reason,
        tuple(states),
        tuple(e for e in events if decided is None or walk.sign * (e.phase - decided) <= 0),
        float(turns),
        sum(leg.work_friction for leg in kept),
        sum(leg.work_potential for leg in kept),
        walk.torque_limit,
        descent,
        lead,
        mech.engine.queries - turn.queries,
    )


class ClockwiseStarts:
    """The clockwise starts of one held tilt, each turned as :func:`screw` turns it, the
    walks shared where they meet.

    Turned clockwise, the starts of one held tilt often come onto one branch: a start's
    walk that reaches a state of an earlier start's walk (the same class and pose at the
    same phase) joins it, for the quasi-static dynamics are deterministic: from there on
    the two are one (:func:`joined_walk`, as the snaps' proofs share theirs). A walk turns
    toward lower phases (a right-hand thread), so starts asked in ascending phase (a
    left-hand thread: descending) meet the walks of those before them.

    Parameters
    ----------
    mech : Mechanics
        The thread pair and compliance.
    roll, pitch : float
        Held tilt (degrees).
    turns, step, phase_tolerance, torque_limit
        As :func:`screw`.
    """

    def __init__(
        self,
        mech: Mechanics,
        roll: float,
        pitch: float,
        *,
        turns: float = 1.0,
        step: float = CONTINUATION_STEP,
        phase_tolerance: float = PHASE_TOLERANCE,
        torque_limit: float | None = None,
    ) -> None:
        self.mech, self.roll, self.pitch = mech, float(roll), float(pitch)
        # What :func:`screw` passes :func:`begin_turn` for a ready ``Mechanics``.
        self._turn: dict[str, Any] = {
            "compliance": None,
            "turns": turns,
            "step": step,
            "phase_tolerance": phase_tolerance,
            "chord": None,
            "torque_limit": torque_limit,
            "sense": "tighten",
        }
        self.walks: list[Walked] = []

    def screw(self, phase: float) -> ScrewResult:
        """The start at ``phase`` (degrees) turned clockwise (:func:`screw`)."""
        turn = begin_turn(self.mech, self.roll, self.pitch, phase, **self._turn)
        return _turned(turn, phase, self._turn["turns"], walks=self.walks)
