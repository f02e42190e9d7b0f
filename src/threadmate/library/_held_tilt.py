"""The states of one held tilt: every start, its settling, and the continuations.

For one held tilt and the grid's phases, in this order:

1. every grid phase is a *start*: the bolt dropped there settles (``Mechanics.settle``);
   the first contact and the unstable states passed become states too, joined by
   *settling* transitions;
2. from every start the counter-clockwise search continues (:class:`Continuation`, the
   computation of :func:`threadmate.contact.search`) one grid phase at a time: *turning*
   transitions along continuous branches, *jump* and *snap* transitions at folds, located
   between grid phases by bisection;
3. a continuation that reaches, at a grid phase, a state already there (same load-carrying
   contacts, compliance centre within ``pitch / 1000``, axis within 0.05 degree) joins it:
   the quasi-static dynamics are deterministic, so from there on the paths are one. Its
   descent to the grid phase stops as soon as a pose of it reaches such a rest state
   (:meth:`_Tilt.arrival`): it is then in that state's basin. So does one that reaches,
   either side of a jump between grid phases, a state another continuation passed (the
   same, and within the continuation's phase tolerance). A continuation that neither
   snaps nor joins stops after ``MAX_FOLLOW_TURNS`` turns.

The rows follow the state record of :mod:`threadmate.contact` (``STATE_COLUMNS``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from .._angles import FULL_TURN, axis_angle, phase_difference, wrap_phase
from ..contact import (
    ERROR_CLASS,
    QUASI_STABLE,
    STABLE,
    UNSTABLE,
    ClockwiseStarts,
    Continuation,
    Leg,
    MechanicalState,
    Mechanics,
    blank_row,
    same_pose,
    state_id,
    state_row,
    state_schema,
)

__all__ = ["ALIKE_MARGIN", "MAX_FOLLOW_TURNS", "states_of_held_tilt", "states_over_frictions"]

#: Turns after which a continuation that neither snapped nor joined another stops.
MAX_FOLLOW_TURNS = 2.0


def engaged(s: MechanicalState) -> bool:
    """Whether ``s`` is a snap's end: in phase and proved by screwing in."""
    return s.engagement is not None and s.engagement.engaged


def _axis(s: MechanicalState) -> np.ndarray:
    return np.asarray(s.rotation, dtype=float)[:, 2]


class _Tilt:
    """The growing set of states of one held tilt, and the rows that describe them."""

    def __init__(self, mech: Mechanics, roll: float, pitch: float) -> None:
        self.mech, self.held_roll, self.held_pitch = mech, roll, pitch
        self.rows: dict[str, dict[str, Any]] = {}
        self.states: dict[str, MechanicalState] = {}
        self.serial = 0
        self.floor = mech.load_carrying
        self.events: list[str] = []  # states either side of a jump between grid phases
        self.legs: dict[str, Leg] = {}  # the leg each transition row stands for

    def add(self, state: MechanicalState, role: str, config_id: int) -> str:
        sid = state_id(self.held_roll, self.held_pitch, state.phase, self.serial)
        self.serial += 1
        self.rows[sid] = state_row(
            state,
            config_id=config_id,
            state_id=sid,
            held_roll=self.held_roll,
            held_pitch=self.held_pitch,
            role=role,
        )
        self.states[sid] = state
        return sid

    def link(
        self,
        src: str,
        dst: str,
        kind: str,
        label: str,
        *,
        turn: float = 0.0,
        work_friction: float = 0.0,
        work_potential: float = 0.0,
        torque_peak: float = math.nan,
    ) -> None:
        a, b = self.states[src], self.states[dst]
        self.rows[src].update(
            next_id=dst,
            transition=kind,
            transition_label=label,
            transition_turn=turn,
            work_friction=work_friction,
            work_potential=work_potential,
            torque_peak=torque_peak,
            drop=float(a.centre[2] - b.centre[2]),
            tilt_change=axis_angle(_axis(a), _axis(b)),
        )

    def link_leg(self, src: str, dst: str, leg: Leg, snap_window: float = math.nan) -> None:
        """The transition ``leg`` from ``src`` to ``dst`` (with its window, at a snap)."""
        self.rows[src]["snap_window"] = snap_window if leg.kind == "snap" else math.nan
        self.rows[src]["click"] = leg.click
        self.legs[src] = leg
        self.link(
            src,
            dst,
            leg.kind,
            leg.label,
            turn=leg.turn,
            work_friction=leg.work_friction,
            work_potential=leg.work_potential,
            torque_peak=leg.torque_peak,
        )

    def rows_scaled(self, scale: float) -> list[dict[str, Any]]:
        """The rows with every friction part scaled by ``scale``: the driver's torque and
        its friction part at each state, the work against friction and the peak torque
        along each transition, and the screw-in notes that name a torque. They are the
        rows of the friction coefficient so scaled wherever every proof judges alike
        there (:attr:`threadmate.contact.Engagement.frictions`)."""
        out = []
        for sid, row in self.rows.items():
            row = dict(row)
            torque, friction = row["driver_torque"], row["friction_torque"]
            row["driver_torque"] = torque + (scale - 1.0) * friction
            row["friction_torque"] = scale * friction
            row["work_friction"] = scale * row["work_friction"]
            leg = self.legs.get(sid)
            if leg is not None:
                row["torque_peak"] = leg.torque_peak_scaled(scale)
            state = self.states.get(sid)  # none for a configuration that failed
            proof = None if state is None else state.engagement
            if proof is not None:
                row["screw_note"] = proof.scaled(scale).reason
            out.append(row)
        return out

    def carrying(self, s: MechanicalState) -> list[str]:
        """Regions of the contacts that carry load (as the continuation tells events)."""
        return sorted(c.regions for c in s.touching if c.force > self.floor)

    def same(self, a: MechanicalState, b: MechanicalState) -> bool:
        """One state reached twice: same class (below), load-carrying contacts and pose
        within the join tolerances."""
        return a.classification == b.classification and self._joins(a, b)

    def _joins(self, a: MechanicalState, b: MechanicalState) -> bool:
        """Same load-carrying contacts, pose within the join tolerances
        (:data:`threadmate.contact.JOIN_DISTANCE`, :data:`threadmate.contact.JOIN_TILT`)."""
        return self.carrying(a) == self.carrying(b) and same_pose(a, b, self.mech.spec.pitch)

    def arrival(self, known: list[str]) -> Callable[[MechanicalState], MechanicalState | None]:
        """For a continuation's last descent to a grid phase: the rest state among
        ``known`` (ids of the states at that phase, read when asked) that a pose of the
        descent has reached (:meth:`_joins`). The descent is then in its basin, and the
        state it would end at would be joined to it."""

        def arrive(s: MechanicalState) -> MechanicalState | None:
            for o in known:
                t = self.states[o]
                if t.classification in (STABLE, QUASI_STABLE) and self._joins(t, s):
                    return t
            return None

        return arrive

    def known_event(self, s: MechanicalState, phase_tolerance: float) -> str | None:
        """A state already known either side of a jump, within ``phase_tolerance`` of
        ``s``'s phase and the same as ``s`` (:meth:`same`)."""
        for o in self.events:
            t = self.states[o]
            gap = abs(phase_difference(t.phase, s.phase))
            if gap <= phase_tolerance and self.same(t, s):
                return o
        return None

    def fail(self, config_id: int, phase: float, role: str, exc: BaseException) -> None:
        sid = state_id(self.held_roll, self.held_pitch, phase, self.serial)
        self.serial += 1
        row = blank_row(state_schema())
        row.update(
            config_id=config_id,
            state_id=sid,
            held_roll=self.held_roll,
            held_pitch=self.held_pitch,
            phase=float(wrap_phase(phase)),
            role=role,
            classification=ERROR_CLASS,
            error=f"{type(exc).__name__}: {exc}",
        )
        self.rows[sid] = row


def _turns_between(phases: Sequence[float], sign: int) -> list[float]:
    """Degrees turned from each grid phase to the next in the turning sense."""
    n = len(phases)
    if n == 1:
        return [360.0]
    return [wrap_phase(sign * (phases[(j + 1) % n] - phases[j])) for j in range(n)]


def states_of_held_tilt(
    mech: Mechanics,
    roll: float,
    pitch: float,
    phases: Sequence[float],
    config_ids: Sequence[int],
    *,
    step: float,
    phase_tolerance: float,
    clockwise: bool = False,
) -> list[dict[str, Any]]:
    """State records of one held tilt over the grid's phases (module docstring).

    Parameters
    ----------
    mech : Mechanics
        The thread pair and compliance (built once per worker).
    roll, pitch : float
        Held tilt (degrees).
    phases : sequence of float
        The grid's phases (degrees, distinct, within [0, 360)).
    config_ids : sequence of int
        The configuration of each phase.
    step, phase_tolerance : float
        The continuation's step and event tolerance (degrees).
    clockwise : bool
        Also turn every start clockwise directly and record its outcome on the start's
        row (:class:`threadmate.contact.ClockwiseStarts`: as ``screw``, the walks of the
        held tilt's starts shared where they meet).

    Returns
    -------
    list of dict
        Rows of the state record; a configuration that fails gives one ``error`` row.
    """
    tilt, _ = _walk_held_tilt(
        mech,
        roll,
        pitch,
        phases,
        config_ids,
        step=step,
        phase_tolerance=phase_tolerance,
        clockwise=clockwise,
    )
    return list(tilt.rows.values())


#: How far inside the coefficients at which every proof judges alike (a fraction of
#: each end) another coefficient must lie for the rows to be scaled, not walked again:
#: scaled and computed torques differ by rounding.
ALIKE_MARGIN = 1e-6


def states_over_frictions(
    mech: Mechanics,
    roll: float,
    pitch: float,
    phases: Sequence[float],
    config_ids: Sequence[int],
    frictions: Sequence[float],
    *,
    step: float,
    phase_tolerance: float,
) -> dict[float, list[dict[str, Any]]]:
    """:func:`states_of_held_tilt` at each friction coefficient of ``frictions``, the
    held tilt walked once where it can be.

    The rest states are frictionless, and so is the search but for its proofs: a proof
    whose tightening torque passes its limit is no snap. Where every proof of the held
    tilt judges alike at a coefficient (:attr:`threadmate.contact.Engagement.frictions`,
    strictly inside by :data:`ALIKE_MARGIN`), the rows there are those walked with
    ``mech``'s, their friction parts scaled (:meth:`_Tilt.rows_scaled`); elsewhere, and
    at every other coefficient when ``mech``'s is 0 (whose friction parts tell no
    proportion), the held tilt is walked again with that coefficient.

    Returns
    -------
    dict
        ``{friction: rows}``.
    """
    tilt, walk = _walk_held_tilt(
        mech, roll, pitch, phases, config_ids, step=step, phase_tolerance=phase_tolerance
    )
    mu = mech.compliance.friction
    low, high = walk.frictions
    out: dict[float, list[dict[str, Any]]] = {}
    for m in map(float, frictions):
        if m == mu:
            out[m] = list(tilt.rows.values())
        elif low * (1 + ALIKE_MARGIN) < m < high * (1 - ALIKE_MARGIN):
            out[m] = tilt.rows_scaled(m / mu)
        else:
            other = Mechanics(mech.spec, replace(mech.compliance, friction=m), scene=mech.scene)
            out[m] = states_of_held_tilt(
                other, roll, pitch, phases, config_ids, step=step, phase_tolerance=phase_tolerance
            )
    return out


def _walk_held_tilt(
    mech: Mechanics,
    roll: float,
    pitch: float,
    phases: Sequence[float],
    config_ids: Sequence[int],
    *,
    step: float,
    phase_tolerance: float,
    clockwise: bool = False,
) -> tuple[_Tilt, Continuation]:
    """The held tilt's states (:func:`states_of_held_tilt`) and the continuation that
    walked its searches and made its proofs."""
    sign = mech.spec.handedness
    order = sorted(range(len(phases)), key=lambda j: sign * phases[j])
    grid = [float(phases[j]) for j in order]
    ids = [int(config_ids[j]) for j in order]
    turns = _turns_between(grid, sign)
    tilt = _Tilt(mech, float(roll), float(pitch))
    at_phase: list[list[str]] = [[] for _ in grid]  # state ids at each grid phase
    starts: list[str | None] = []
    walk = Continuation(
        mech, roll, pitch, step=step, phase_tolerance=phase_tolerance, contact_changes=False
    )
    # The starts in the grid's order (ascending in the unscrewing sense): each clockwise
    # walk turns toward the starts before it and meets their walks.
    clockwise_starts = (
        ClockwiseStarts(mech, roll, pitch, step=step, phase_tolerance=phase_tolerance)
        if clockwise
        else None
    )
    for j, phase in enumerate(grid):
        try:
            rest = mech.settle(roll, pitch, phase)
            # A start in phase is a snap only if it screws in (as a landing is).
            rest = replace(rest, state=walk.proved(rest.state, phase)[0])
        except Exception as exc:  # noqa: BLE001 - one bad configuration must not stop a sweep
            tilt.fail(ids[j], phase, "start", exc)
            starts.append(None)
            continue
        prev = None
        for s in rest.path:
            sid = tilt.add(s, "first-contact" if s.kind == "first-contact" else "passed", ids[j])
            if prev is not None:
                tilt.link(prev, sid, "settling", UNSTABLE)
            prev = sid
        sid = tilt.add(rest.state, "start", ids[j])
        if prev is not None:
            tilt.link(prev, sid, "settling", UNSTABLE)
        if clockwise_starts is not None:
            try:
                turned = clockwise_starts.screw(phase)
                at = turned.decided_phase
                tilt.rows[sid].update(
                    clockwise=turned.outcome,
                    clockwise_phase=math.nan if at is None else wrap_phase(at),
                )
            except Exception as exc:  # noqa: BLE001 - keep the start and its search
                tilt.rows[sid]["error"] = f"clockwise: {type(exc).__name__}: {exc}"
        starts.append(sid)
        at_phase[j].append(sid)

    for j, start in enumerate(starts):
        if start is not None:
            _continue(tilt, walk, start, j, grid, turns, ids[j], at_phase)
    return tilt, walk


def _continue(
    tilt: _Tilt,
    walk: Continuation,
    sid: str,
    j: int,
    grid: list[float],
    turns: list[float],
    config_id: int,
    at_phase: list[list[str]],
) -> None:
    """Follow the continuation from state ``sid`` at grid phase ``j`` until it snaps,
    joins a state already known at a grid phase, or has turned ``MAX_FOLLOW_TURNS``."""
    n = len(grid)
    phase = grid[j]  # unwrapped: the continuation's phases keep growing
    turned = 0.0
    while not engaged(tilt.states[sid]) and turned < FULL_TURN * MAX_FOLLOW_TURNS:
        k = (j + 1) % n
        try:
            legs, events, states = walk.advance(
                tilt.states[sid], phase, turns[j], arrive=tilt.arrival(at_phase[k])
            )
        except Exception as exc:  # noqa: BLE001 - keep the states found so far
            tilt.rows[sid]["error"] = f"{type(exc).__name__}: {exc}"
            return
        legs = [leg for leg in legs if not (leg.kind == "turning" and leg.after is leg.before)]
        snapped = bool(legs) and legs[-1].kind == "snap"
        window = math.nan
        if snapped:
            # The window the drop may come in, looked for on the branch since this grid
            # phase (as ``search`` looks on its own).
            lo, hi = walk.snap_window([tilt.states[sid], *states], events[-1])
            window = abs(hi - lo)
        for i, leg in enumerate(legs):
            last = i == len(legs) - 1 and not snapped
            if last:
                # The state at the next grid phase: a known one, or a new continued one.
                known = next((o for o in at_phase[k] if tilt.same(tilt.states[o], leg.after)), None)
                if known is not None:
                    tilt.link_leg(sid, known, leg)
                    return
                role = "continued" if leg.kind == "turning" else "after-jump"
                dst = tilt.add(leg.after, role, config_id)
                at_phase[k].append(dst)
            else:
                # Either side of a jump between grid phases: another continuation may have
                # passed it already (starts between the same two grid phases share their
                # last branch); then the paths are one from here on.
                known = tilt.known_event(leg.after, walk.phase_tolerance)
                if known is not None:
                    tilt.link_leg(sid, known, leg, window)
                    return
                dst = tilt.add(
                    leg.after, "before-jump" if leg.kind == "turning" else "after-jump", config_id
                )
                tilt.events.append(dst)
            tilt.link_leg(sid, dst, leg, window)
            sid = dst
        if snapped or not legs:
            return
        phase += walk.sign * turns[j]
        turned += turns[j]
        j = k
