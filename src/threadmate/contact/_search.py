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
it. A jump that lands in-phase is the snap; its drop (the fall of the compliance centre)
is the click.

The driver's torque at each rest state (:meth:`Mechanics.driver_torque`) is integrated
over phase by the trapezoidal rule along continuous branches; during a jump the phase
stands still and the driver does no work. The work splits into friction and the part
that raises the potential; without friction and away from jumps the latter equals the
change of the potential (a check the tests make, not an assumption).

:class:`Continuation` does the walking, in *legs* (a continuous branch, a jump, the snap);
:func:`search` and the library's sweep (:mod:`threadmate.library`) both walk with it, so a
library's passive paths and a search from the same start are the same computation.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._validate import check_open_range
from ..geometry import ThreadSpec
from ._compliance import Compliance
from ._rest_state import MechanicalState, SearchEvent, SearchResult
from ._settle import Mechanics, axis_turn, mechanics

__all__ = ["CONTINUATION_STEP", "Continuation", "Leg", "check_continuation", "search"]

#: Tilt of the bolt axis within one step above which the step is a jump (degrees).
JUMP_TILT = 0.5
#: The continuation's default step (degrees): the thesis's phase step. Folds and contact
#: changes inside a step are located by bisection; a step this size is what the library's
#: sweep and ``threadmate search`` both take by default, so that they agree.
CONTINUATION_STEP = 5.0
#: A probe's descent stops once it has gone this many times the jump's thresholds (the
#: fall ``pitch / 40``, the tilt ``JUMP_TILT``) from the state it leaves: far enough that
#: the rest state it would reach is not near that state either.
DEPARTURE = 2.0


def _tilt_between(a: MechanicalState, b: MechanicalState) -> float:
    return axis_turn(np.array(a.rotation)[:, 2], np.array(b.rotation)[:, 2])


def _signature(s: MechanicalState, floor: float) -> tuple[str, ...]:
    """The contacts that carry the load (more than ``floor``, N): a contact touching
    without force, or hovering at the touching threshold, changes nothing a driver or a
    sensor sees."""
    return tuple(sorted(c.regions for c in s.touching if c.force > floor))


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
    """

    kind: str
    before: MechanicalState
    after: MechanicalState
    turn: float
    work_friction: float
    work_potential: float
    torque_peak: float
    label: str

    @property
    def drop(self) -> float:
        """Fall of the compliance centre along the leg (spec units)."""
        return float(self.before.centre[2] - self.after.centre[2])

    @property
    def tilt_change(self) -> float:
        """Angle between the bolt axes at its ends (degrees)."""
        return _tilt_between(self.before, self.after)


def _label(states: list[MechanicalState]) -> str:
    classes = {s.classification for s in states}
    if "unstable" in classes:
        return "unstable"
    return "quasi-stable" if "quasi-stable" in classes else "stable"


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
        between jumps and not the contact changes within them). The branch followed is the
        same either way: a located contact change only adds the states either side of it
        to the work's trapezoid rule.
    """

    def __init__(
        self,
        mech: Mechanics,
        roll: float,
        pitch: float,
        *,
        step: float = CONTINUATION_STEP,
        phase_tolerance: float = 0.01,
        contact_changes: bool = True,
    ) -> None:
        self.mech = mech
        self.held_roll, self.held_pitch = float(roll), float(pitch)
        self.step, self.phase_tolerance = float(step), float(phase_tolerance)
        self.contact_changes = contact_changes
        self.sign = mech.spec.handedness  # +1: counter-clockwise (increasing phase)
        self.drop_limit = mech.spec.pitch / 40
        self.floor = 1e-4 * mech.compliance.force

    def _settle(
        self,
        phase: float,
        before: MechanicalState,
        *,
        probe: bool = True,
        arrive: Callable[[MechanicalState], MechanicalState | None] | None = None,
    ) -> MechanicalState:
        """The rest state at ``phase`` continued from ``before``; a ``probe`` stops at
        the first pose in phase, or once departed from ``before`` (:data:`DEPARTURE`,
        :meth:`Mechanics.settle`): the continuation asks only whether it snapped or left
        the branch, and :meth:`_bisect` settles in full the jump it keeps."""
        return self.mech.settle(
            self.held_roll,
            self.held_pitch,
            phase,
            start=before,
            stop_in_phase=probe,
            leave=(DEPARTURE * self.drop_limit, DEPARTURE * JUMP_TILT) if probe else None,
            arrive=arrive,
        ).state

    def _continuous(self, a: MechanicalState, b: MechanicalState) -> bool:
        if b.classification == "in-phase" and a.classification != "in-phase":
            return False
        return a.centre[2] - b.centre[2] <= self.drop_limit and _tilt_between(a, b) <= JUMP_TILT

    def _bisect(
        self,
        phase: float,
        lo: float,
        hi: float,
        s_lo: MechanicalState,
        s_hi: MechanicalState,
        same: Callable[[MechanicalState, MechanicalState], bool],
        hi_from: MechanicalState,
    ) -> tuple[float, float, MechanicalState, MechanicalState]:
        """Close in on where ``same(s_lo, state)`` stops holding, from the side before
        (``lo``, ``hi``: turns from ``phase``; ``s_hi`` was settled from ``hi_from``). An
        in-phase or departed ``s_hi`` (a probe) is settled in full: settles depend only on
        the state they leave, so this is the same computation carried to its end."""
        while hi - lo > self.phase_tolerance:
            mid = 0.5 * (lo + hi)
            s_mid = self._settle(phase + self.sign * mid, s_lo)
            if same(s_lo, s_mid):
                lo, s_lo = mid, s_mid
            else:
                hi, s_hi, hi_from = mid, s_mid, s_lo
        if s_hi.classification == "in-phase" or s_hi.kind == "departed":
            s_hi = self._settle(phase + self.sign * hi, hi_from, probe=False)
        return lo, hi, s_lo, s_hi

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
        the unscrewing sense, stopping early at a snap. ``arrive``: rest states already
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
        branch_start = 0.0
        work = [0.0, 0.0]  # friction, potential (mJ) along the current turning leg

        def integrate(a: MechanicalState, b: MechanicalState) -> None:
            dphi = math.radians(abs(b.phase - a.phase))
            if not (math.isfinite(a.driver_torque) and math.isfinite(b.driver_torque)):
                return
            total = 0.5 * (a.driver_torque + b.driver_torque) * dphi
            fric = 0.5 * (a.friction_torque + b.friction_torque) * dphi
            work[0] += 1e3 * fric
            work[1] += 1e3 * (total - fric)

        def close_branch(at: float) -> None:
            if at > branch_start or len(branch) > 1:
                torques = [s.driver_torque for s in branch if math.isfinite(s.driver_torque)]
                legs.append(
                    Leg(
                        "turning",
                        branch[0],
                        branch[-1],
                        at - branch_start,
                        work[0],
                        work[1],
                        max(torques, default=math.nan),
                        _label(branch),
                    )
                )

        def signature(s: MechanicalState) -> tuple[str, ...]:
            return _signature(s, self.floor)

        def follow(a: MechanicalState, at_a: float, b: MechanicalState, at_b: float) -> None:
            """Extend the branch from ``a`` (at turn ``at_a``) to ``b``, continuous with it,
            locating a change of the load-carrying contacts between them."""
            before = signature(a)
            if self.contact_changes and signature(b) != before:

                def same(
                    x: MechanicalState, y: MechanicalState, before: tuple[str, ...] = before
                ) -> bool:
                    return signature(y) == before and self._continuous(x, y)

                lo, hi, s_lo, s_hi = self._bisect(phase, at_a, at_b, a, b, same, a)
                events.append(
                    SearchEvent(
                        phase + sign * 0.5 * (lo + hi),
                        "contact-change",
                        a.region_combination,
                        s_hi.region_combination,
                        s_lo.centre[2] - s_hi.centre[2],
                        _tilt_between(s_lo, s_hi),
                    )
                )
                for x, y in ((a, s_lo), (s_lo, s_hi), (s_hi, b)):
                    integrate(x, y)
                states.extend([s_lo, s_hi])
                branch.extend([s_lo, s_hi])
            else:
                integrate(a, b)
            states.append(b)
            branch.append(b)

        prev, at = state, 0.0
        while at < turn - 1e-12:
            if progress is not None:
                progress(at)
            nxt = min(at + self.step, turn)
            cur = self._settle(phase + sign * nxt, prev, arrive=arrive if nxt == turn else None)
            if self._continuous(prev, cur):
                follow(prev, at, cur, nxt)
                prev, at = cur, nxt
                continue
            # A fold within (at, nxt]: close in on it from the side before.
            lo, hi, s_lo, s_hi = self._bisect(phase, at, nxt, prev, cur, self._continuous, prev)
            # The branch up to the last state on it (``prev`` itself when the fold lies
            # within the tolerance of it), its contact changes located.
            if s_lo is not prev:
                follow(prev, at, s_lo, lo)
            if self._continuous(s_lo, s_hi):
                # The probe left the branch, but its descent carried to its end came back
                # to it (where the thread starts meet, a descent can wander that far along
                # a nearly flat valley): no fold here. Carry on from the state at ``hi``.
                follow(s_lo, lo, s_hi, hi)
                prev, at = s_hi, hi
                continue
            close_branch(lo)
            kind = "snap" if s_hi.classification == "in-phase" else "jump"
            legs.append(Leg(kind, s_lo, s_hi, hi - lo, 0.0, 0.0, math.nan, "unstable"))
            events.append(
                SearchEvent(
                    phase + sign * hi,
                    kind,
                    s_lo.region_combination,
                    s_hi.region_combination,
                    s_lo.centre[2] - s_hi.centre[2],
                    _tilt_between(s_lo, s_hi),
                )
            )
            states.append(s_hi)
            if kind == "snap":
                return legs, events, states
            prev, at = s_hi, hi
            branch, branch_start, work = [s_hi], hi, [0.0, 0.0]
        close_branch(at)
        return legs, events, states


def search(
    target: Mechanics | ThreadSpec,
    roll: float,
    pitch: float,
    phase: float,
    *,
    compliance: Compliance | None = None,
    turns: float = 1.0,
    step: float = CONTINUATION_STEP,
    phase_tolerance: float = 0.01,
    chord: float | None = None,
    progress: Callable[[int, int], None] | None = None,
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

    Returns
    -------
    SearchResult
        ``snap`` is None when no snap came within ``turns``.
    """
    check_continuation(turns=turns, step=step, phase_tolerance=phase_tolerance)
    mech = mechanics(target, compliance, chord)
    q0 = mech.engine.queries
    start = mech.settle(roll, pitch, phase).state
    end = 360.0 * turns  # turn from the start, degrees
    legs: list[Leg] = []
    events: list[SearchEvent] = []
    states = [start]
    if start.classification == "in-phase":
        events.append(SearchEvent(float(phase), "snap", "", start.region_combination, 0.0, 0.0))
    else:
        walk = Continuation(mech, roll, pitch, step=step, phase_tolerance=phase_tolerance)
        tick = None if progress is None else (lambda at: progress(int(at), int(math.ceil(end))))
        legs, events, more = walk.advance(start, float(phase), end, progress=tick)
        states += more
    if progress is not None:
        progress(int(math.ceil(end)), int(math.ceil(end)))
    snap = next((e for e in events if e.kind == "snap"), None)
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
        mech.engine.queries - q0,
    )


def check_continuation(
    *, turns: float = 1.0, step: float = CONTINUATION_STEP, phase_tolerance: float = 0.01
) -> None:
    """Refuse continuation settings out of range (InputError naming the setting)."""
    for name, value, lo, hi in (
        ("turns", turns, 0.0, 10.0),
        ("step", step, 0.0, 10.0),
        ("phase_tolerance", phase_tolerance, 0.0, step),
    ):
        check_open_range(name, value, lo, hi)
