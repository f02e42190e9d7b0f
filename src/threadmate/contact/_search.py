"""The counter-clockwise search simulated: quasi-static continuation in phase.

From the rest state of a start (held tilt, start phase), the driver turns the bolt
counter-clockwise in steps of ``step`` degrees; at each step the bolt follows the nearest
rest state, found by the descent of :mod:`._settle` warm-started from the last one. A
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
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from .._errors import InputError
from ..geometry import ThreadSpec
from ._compliance import Compliance
from ._rest_state import MechanicalState, SearchEvent, SearchResult
from ._settle import Mechanics, axis_turn, mechanics

__all__ = ["search"]

#: Tilt of the bolt axis within one step above which the step is a jump (degrees).
JUMP_TILT = 0.5


def _tilt_between(a: MechanicalState, b: MechanicalState) -> float:
    return axis_turn(np.array(a.rotation)[:, 2], np.array(b.rotation)[:, 2])


def _signature(s: MechanicalState, floor: float) -> tuple[str, ...]:
    """The contacts that carry the load (more than ``floor``, N): a contact touching
    without force, or hovering at the touching threshold, changes nothing a driver or a
    sensor sees."""
    return tuple(sorted(c.regions for c in s.touching if c.force > floor))


def search(target: Mechanics | ThreadSpec, roll: float, pitch: float, phase: float, *,
           compliance: Compliance | None = None, turns: float = 1.0, step: float = 2.0,
           phase_tolerance: float = 0.01, chord: float | None = None,
           progress: Callable[[int, int], None] | None = None) -> SearchResult:
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
    for name, value, lo, hi in (("turns", turns, 0.0, 10.0), ("step", step, 0.0, 10.0),
                                ("phase_tolerance", phase_tolerance, 0.0, step)):
        if isinstance(value, bool) or not isinstance(value, int | float) \
                or not math.isfinite(value) or not lo < value <= hi:
            raise InputError(f"{name} must be within ({lo:g}, {hi:g}], got {value!r}")
    mech = mechanics(target, compliance, chord)
    q0 = mech.engine.queries
    drop_limit = mech.spec.pitch / 40
    rest = mech.settle(roll, pitch, phase)
    start = rest.state
    states = [start]
    events: list[SearchEvent] = []
    work_f = work_p = 0.0
    snap: SearchEvent | None = None
    if start.classification == "in-phase":
        snap = SearchEvent(float(phase), "snap", "", start.region_combination, 0.0, 0.0)
        events.append(snap)
    sign = mech.spec.handedness  # +1: counter-clockwise (increasing phase)
    end = 360.0 * turns  # turn from the start, degrees

    def settle(turn: float, before: MechanicalState) -> MechanicalState:
        return mech.settle(roll, pitch, phase + sign * turn, start=before).state

    def continuous(a: MechanicalState, b: MechanicalState) -> bool:
        if b.classification == "in-phase" and a.classification != "in-phase":
            return False
        return (a.centre[2] - b.centre[2] <= drop_limit
                and _tilt_between(a, b) <= JUMP_TILT)

    def integrate(a: MechanicalState, b: MechanicalState) -> None:
        nonlocal work_f, work_p
        turn = math.radians(abs(b.phase - a.phase))
        if not (math.isfinite(a.driver_torque) and math.isfinite(b.driver_torque)):
            return
        total = 0.5 * (a.driver_torque + b.driver_torque) * turn
        fric = 0.5 * (a.friction_torque + b.friction_torque) * turn
        work_f += 1e3 * fric
        work_p += 1e3 * (total - fric)

    def bisect(lo: float, hi: float, s_lo: MechanicalState, s_hi: MechanicalState,
               same: Callable[[MechanicalState, MechanicalState], bool]
               ) -> tuple[float, float, MechanicalState, MechanicalState]:
        """Close in on where ``same(s_lo, state)`` stops holding, from the side before."""
        while hi - lo > phase_tolerance:
            mid = 0.5 * (lo + hi)
            s_mid = settle(mid, s_lo)
            if same(s_lo, s_mid):
                lo, s_lo = mid, s_mid
            else:
                hi, s_hi = mid, s_mid
        return lo, hi, s_lo, s_hi

    def signature(s: MechanicalState) -> tuple[str, ...]:
        return _signature(s, 1e-4 * mech.compliance.force)

    def at_phase(turn: float) -> float:
        return float(phase + sign * turn)

    prev = start
    at = 0.0
    while snap is None and at < end - 1e-12:
        if progress is not None:
            progress(int(at), int(math.ceil(end)))
        nxt = min(at + step, end)
        cur = settle(nxt, prev)
        if continuous(prev, cur):
            if signature(cur) != signature(prev):
                before = signature(prev)
                lo, hi, s_lo, s_hi = bisect(
                    at, nxt, prev, cur,
                    lambda a, b, before=before: signature(b) == before and continuous(a, b))
                events.append(SearchEvent(at_phase(0.5 * (lo + hi)), "contact-change",
                                          prev.region_combination, s_hi.region_combination,
                                          s_lo.centre[2] - s_hi.centre[2],
                                          _tilt_between(s_lo, s_hi)))
                for a, b in ((prev, s_lo), (s_lo, s_hi), (s_hi, cur)):
                    integrate(a, b)
                states += [s_lo, s_hi]
            else:
                integrate(prev, cur)
            states.append(cur)
            prev, at = cur, nxt
            continue
        # A fold within (at, nxt]: close in on it from the side before.
        lo, hi, s_lo, s_hi = bisect(at, nxt, prev, cur, continuous)
        integrate(prev, s_lo)
        kind = "snap" if s_hi.classification == "in-phase" else "jump"
        event = SearchEvent(at_phase(hi), kind, s_lo.region_combination,
                            s_hi.region_combination, s_lo.centre[2] - s_hi.centre[2],
                            _tilt_between(s_lo, s_hi))
        events.append(event)
        states += [s_lo, s_hi]
        if kind == "snap":
            snap = event
            break
        prev, at = s_hi, hi
    if progress is not None:
        progress(int(math.ceil(end)), int(math.ceil(end)))
    return SearchResult(mech.units, float(roll), float(pitch), float(phase),
                        mech.compliance.to_dict(), tuple(states), tuple(events), snap,
                        float(turns), work_f, work_p, mech.engine.queries - q0)
