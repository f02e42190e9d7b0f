"""The descent to a rest state: an active-set descent of the potential, in named steps.

At the current pose the bolt touches the nut (it was lowered onto it, :mod:`._lowering`)
and its contacts within a small depth ``near`` below it are known (:mod:`._contact_set`).
One step (:meth:`_Descent.step`) minimises the quadratic model of U plus a proximal term
under the linearised contacts (:meth:`_Descent.solve_contact_qp`, :mod:`._lcp`); its
multipliers are the contact forces. The bolt is then tilted by the step and lowered onto
the nut again (:meth:`_Descent.line_search`), so that every accepted pose touches and
nothing interpenetrates, and the step is kept when U fell by a fair part of what the model
promised (:meth:`_Descent.kept`); else the proximal weight grows, a trust region
(:meth:`_Descent.reject`). A contact released by the step is the thesis's rolling pivot;
a contact that appears is its next contact (:meth:`_Descent.record`). The descent stops
when the contact forces balance the load and the spring (:meth:`_Descent.balanced`, see
:data:`BALANCE`), when nothing is left to gain at the length tolerance
(:meth:`_Descent.exhausted`), when a continued descent has stalled
(:meth:`_Descent.stalled`), or after :data:`MAX_STEPS` steps; and its end is classed
from the forces and the minimum (:meth:`_Descent.classify`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import nnls

from ..._angles import axis_angle
from ..._errors import InputError
from ..._validate import check_configuration
from ..scene import IN_PHASE, QUASI_STABLE, STABLE, UNSTABLE
from ._contact_set import _Near, _touching_pairs
from ._lcp import contact_step
from ._lowering import _Drop
from ._rest_state import MechanicalState, RestState

if TYPE_CHECKING:  # the class whose descent this is (it imports this module)
    from ._settle import Mechanics

__all__ = ["BALANCE", "MAX_STEPS"]

#: Largest residual of the equilibrium at a rest state, relative to the load (force: F;
#: moment: F times the bolt's major radius).
BALANCE = 1e-6
#: Descent steps before a rest state is given up as not converged.
MAX_STEPS = 60
#: Tilts (degrees) by which a rest state found within the meshes' accuracy is perturbed,
#: each in :data:`PROBE_DIRECTIONS` directions, to check it is a minimum
#: (:meth:`_Descent.is_minimum`).
PROBE_TILTS = (0.01, 0.05, 0.2)
PROBE_DIRECTIONS = 8
#: Passed poses tried as a rest state within the meshes' accuracy
#: (:meth:`_Descent.within_mesh`).
WITHIN_MESH_TRIES = 3
#: Times a passed pose is tilted to where its contacts balance, at most, and the largest
#: such tilt (degrees) (:meth:`_Descent.polished`).
POLISH_STEPS = 3
POLISH_REACH = 1e-3


@dataclass
class _Step:
    """A step the contact QP proposes, in the coordinates ``(z_C, roll, pitch[, x, y])``
    (SI), with what the descent reads off it."""

    dq: NDArray[np.float64]  # the motion
    lam: NDArray[np.float64]  # its multipliers: the contact forces of the model
    over: list[int]  # the contacts (in ``near``) with the nut's material above the bolt
    promised: float  # the fall of U the quadratic model promises (J)
    dtilt: NDArray[np.float64]  # its tilt part (rad)
    dxy: NDArray[np.float64]  # its lateral part (spec units; zero when held laterally)
    moved: float  # the farthest any bolt point moves (spec units)


class _Descent:
    """One descent to a rest state (:meth:`Mechanics.settle`), as named steps.

    Its attributes are the descent's state: the pose ``d`` with its contacts ``near`` and
    tilt, the potential ``u``, the trust region (``prox``) and the contacts' learnt
    curvature, the contacts met by rejected steps (``ahead``), the unstable states passed
    (``path``) and the step count.

    Parameters
    ----------
    mech : Mechanics
        The mechanics whose layers the steps use.
    roll, pitch, phase, start, leave, arrive
        As :meth:`Mechanics.settle` takes them.
    """

    def __init__(
        self,
        mech: Mechanics,
        roll: float,
        pitch: float,
        phase: float,
        *,
        start: MechanicalState | None,
        leave: tuple[float, float] | None,
        arrive: Callable[[MechanicalState], MechanicalState | None] | None,
    ) -> None:
        self.mech = mech
        self.roll, self.pitch, self.phase = check_configuration(roll, pitch, phase)
        self.start, self.leave, self.arrive = start, leave, arrive
        self.q0 = mech.engine.queries
        self.held = np.radians([self.roll, self.pitch])
        self.path: list[MechanicalState] = []
        self.steps = 0
        self.converged = False
        #: The rest state already known that the descent reached (see ``arrive``).
        self.arrival: RestState | None = None
        #: The poses passed (U, pose, contacts, tilt), for a descent that ends unbalanced
        #: (:meth:`within_mesh`).
        self.passed: list[tuple[float, _Drop, list[_Near], NDArray[np.float64]]] = []
        #: The gap below which the end's balance counts a contact (None: the touching
        #: gap; the meshes' deviation for a rest state found within their accuracy).
        self.touching_gap: float | None = None
        self.first_touch()
        comp = mech.compliance
        self.f = f = comp.force
        self.k = mech._stiffness()
        self.thread_pitch_m = mech.spec.pitch * mech.metres
        self.arm_m = mech.radius * mech.metres
        # The first proximal weights: alone, they let the load move the bolt a twentieth of
        # a pitch (in height, and laterally), and a moment of the load times the bolt's
        # radius tilt it 8 degrees.
        self.prox0 = np.array(
            [
                f / (self.thread_pitch_m / 20),
                f * self.arm_m / math.radians(8.0),
                f * self.arm_m / math.radians(8.0),
            ]
            + [f / (self.thread_pitch_m / 20)] * 2
        )
        self.prox = self.prox0[: len(self.k)].copy()
        self.curvature = np.zeros((2, 2))
        if self.start is not None and self.start.contact_curvature is not None:
            # Continuation: the model at the state left is a good start for the next.
            self.curvature = np.array(self.start.contact_curvature, dtype=float)
            self.prox = self.prox * 1e-2
        self.u = mech.potential(self.d.zc, self.tilt, self.d.xy, self.held)
        self.noise = 2.0 * f * max(mech.scene.deviation, mech.tolerance) * mech.metres
        self.in_phase = mech.engaged(self.near)  # the pose in phase (the path records it)
        self.last_step = np.zeros(2)
        self.nudged = 0.0  # bolt motion since the collision queries last lowered the bolt (_nudged)
        self.ahead: list[_Near] = []  # contacts met by rejected steps (see reject)
        self.progress: list[tuple[float, float]] = []  # potential and residual (stalled)
        self.support: tuple[int, ...] = ()
        # Upright, the spring's moment is k x held; the end's contacts can hold at most the
        # load times the bolt's radius against it: beyond that no seat can be a rest state.
        self.seat_tried = float(np.hypot(*(self.k[1:3] * self.held))) > f * self.arm_m
        #: The region pairs touching when the path last recorded a state.
        self.signature = _touching_pairs(self.near, mech.touching)

    # -- the way in and out ---------------------------------------------------------------
    def first_touch(self) -> None:
        """Lower the bolt onto the nut and know its contacts: from above at the held tilt,
        or, continuing, at the tilt and over the height of ``start``.

        The first touch is the path's first state (kind ``first-contact``) when the
        descent starts fresh. A probe (``leave``) has departed as soon as the lowering
        from ``start`` meets the nut higher above it than ``leave`` lets the centre fall
        below: turned at its tilt, the bolt meets material at every height near the
        branch (pinched between the flanks), and the climb would leave the thread.
        """
        mech, start, leave = self.mech, self.start, self.leave
        ceiling = None
        if start is None:
            tilt, xy, zc = self.held.copy(), np.zeros(2), None
        else:
            tilt = np.radians([start.roll, start.pitch])
            xy = np.array(start.centre[:2])
            zc = start.centre[2]
            ceiling = None if leave is None else zc + leave[0]
        d = mech.drop(mech._rotation(tilt, self.phase), xy, zc, ceiling=ceiling)
        if d is None:
            raise InputError(
                f"the bolt passes the nut without touching at roll {self.roll:g}, "
                f"pitch {self.pitch:g}, phase {self.phase:g}"
            )
        self.start_axis = None if start is None else np.array(start.rotation)[:, 2]
        if start is not None and not d.above_ceiling:
            # The turn may lift the bolt off some of the contacts it rested on (a flank
            # riding onto an edge lifts it off the face beside): those contacts still bound
            # the motion, and a descent that does not know them can tip past them into
            # another basin. It knows every contact within the lift, and ``near`` beyond.
            d = mech._deepened(d, mech.near + max(0.0, d.zc - start.centre[2]))
        self.d, self.tilt = d, tilt
        self.departed = d.above_ceiling or self.gone(d)
        self.near = [] if self.departed else mech.contacts(d)
        if start is None:
            self.path.append(
                mech.state("first-contact", UNSTABLE, d, self.near, self.phase, self.held, tilt)
            )
        self.last_axis = d.rotation[:, 2].copy()

    def gone(self, d: _Drop) -> bool:
        """Whether the pose ``d`` has left ``start`` by more than ``leave`` allows (its
        compliance centre fallen, or its axis turned, too far): the bisection then knows
        enough (see :meth:`Mechanics.settle`)."""
        leave, start, start_axis = self.leave, self.start, self.start_axis
        return (
            leave is not None
            and start is not None
            and start_axis is not None
            and (
                start.centre[2] - d.zc > leave[0]
                or axis_angle(d.rotation[:, 2], start_axis) > leave[1]
            )
        )

    def result(self, state: MechanicalState, balance: dict[str, float]) -> RestState:
        """The :class:`RestState` of the descent ending at ``state``."""
        mech = self.mech
        return RestState(
            mech.units,
            float(self.roll),
            float(self.pitch),
            float(self.phase),
            mech.compliance.to_dict(),
            state,
            tuple(self.path),
            balance,
            self.steps,
            mech.engine.queries - self.q0,
        )

    def run(self) -> RestState:
        """Step until the descent ends; its rest state (or the state it ended at)."""
        while not self.departed and self.steps < MAX_STEPS:
            if not self.step():
                break
        return self.arrival if self.arrival is not None else self.finish()

    # -- one step -------------------------------------------------------------------------
    def step(self) -> bool:
        """One step of the descent from the current pose; False once the descent ends.

        The contacts' balance first (the descent may end here), a seat where the bolt
        tips into one, then the contact QP's step, lowered onto the nut and kept or not.
        """
        mech = self.mech
        if self.start is None:  # (only a descent from first contact looks back)
            self.passed.append((self.u, self.d, self.near, self.tilt))
        centre = np.array([self.d.xy[0], self.d.xy[1], self.d.zc])
        G, gap = mech._rows(self.near + self.ahead, centre, self.tilt)
        grad = mech._gradient(self.tilt, self.d.xy, self.held)
        forces, f_res, m_res = mech.forces(self.near, centre, self.tilt, self.d.xy, self.held)
        if not self.in_phase:
            self.arrival = self.arrived(forces, f_res, m_res)
            if self.arrival is not None:
                return False
        if self.balanced(f_res, m_res):
            return False
        seating = mech._seating(self.near, self.tilt)
        if self.stalled(f_res, m_res, seating):
            return False
        if self.seated(seating):
            return True
        step = self.solve_contact_qp(G, gap, grad)
        if step is None:
            return False  # a degenerate contact problem: give up here, unconverged
        if self.exhausted(step, f_res, m_res):
            return False
        self.steps += 1
        if self.too_long(step):
            # Far beyond what the linearised contacts can tell: a shorter step.
            self.prox *= 4
            return True
        return self.line_search(step, centre, G, gap)

    def arrived(self, forces: NDArray[np.float64], f_res: float, m_res: float) -> RestState | None:
        """The rest state already known that the pose has reached, as ``arrive`` (the
        library's sweep) tells, at this phase as turned (a continuation's phases run past
        360); None when it tells none, or none is asked."""
        mech = self.mech
        if self.arrive is None:
            return None
        known = self.arrive(
            mech.state(
                "rest", UNSTABLE, self.d, self.near, self.phase, self.held, self.tilt, forces
            )
        )
        if known is None:
            return None
        balance = {"force": f_res, "moment": m_res, "converged": 0.0, "arrived": 1.0}
        return self.result(replace(known, phase=float(self.phase)), balance)

    def balanced(self, f_res: float, m_res: float) -> bool:
        """Whether the contact forces balance the load and the spring to a tenth of
        :data:`BALANCE`: converged, the descent ends."""
        if f_res <= BALANCE / 10 and m_res <= BALANCE / 10:
            self.converged = True
            return True
        return False

    def stalled(self, f_res: float, m_res: float, seating: bool) -> bool:
        """Whether a continued descent has stalled: over ``stall_steps`` steps it lowered
        U by no more than the mesh's noise and its least residual by less than 1 %
        (:data:`._held_bolt.STALL_STEPS`). It ends there, a rest state if it balances.

        Not while tipping into a seat, nor pinched under material above (a descent then
        slides along the flank in short steps whose gain is below the noise: the step
        limit bounds it), nor from first contact.
        """
        mech = self.mech
        self.progress.append((self.u, max(f_res, m_res)))
        window = mech.stall_steps
        pinched = any(c.upper and c.gap <= mech.touching for c in self.near)
        if self.start is not None and len(self.progress) > window and not seating and not pinched:
            u_then = self.progress[-window - 1][0]
            best_then = min(r for _, r in self.progress[:-window])
            if u_then - self.u <= self.noise and min(r for _, r in self.progress[-window:]) > (
                0.99 * best_then
            ):
                # Stalled: a rest state if it balances (as when nothing is left to gain).
                self.converged = f_res <= BALANCE and m_res <= BALANCE
                return True
        return False

    def seated(self, seating: bool) -> bool:
        """Whether the bolt, tipping into a seat, was seated upright (once per descent,
        :meth:`Mechanics._seat`): a step, after which the descent goes on from the seat
        with a fresh trust region."""
        mech = self.mech
        if self.seat_tried or not self.tilt.any() or not seating:
            return False
        self.seat_tried = True
        seat = mech._seat(self.d, self.tilt, self.phase, self.held, self.u)
        if seat is None:
            return False
        self.steps += 1
        self.d, self.near, self.tilt, self.u = seat
        self.nudged = 0.0
        self.ahead, self.support, self.prox = [], (), self.prox0[: len(self.k)].copy()
        self.signature = _touching_pairs(self.near, mech.touching)
        return True

    def solve_contact_qp(
        self, G: NDArray[np.float64], gap: NDArray[np.float64], grad: NDArray[np.float64]
    ) -> _Step | None:
        """The step that minimises the quadratic model of U (the springs, the proximal
        weight and the contacts' learnt curvature) under the linearised contacts
        (:func:`._lcp.contact_step`, warm-started from the last support); None when the
        contact problem is degenerate."""
        mech = self.mech
        metric = np.diag(self.k + self.prox)
        metric[1:3, 1:3] += self.curvature
        over = [i for i, c in enumerate(self.near) if c.upper]
        held_off = gap
        if over:
            # Material above is kept half the touching gap away where it is farther,
            # so that the lowering after the step starts free under it.
            held_off = gap.copy()
            margin = 0.5 * mech.touching * mech.metres * mech._rate(self.near, over)
            held_off[over] = np.maximum(gap[over] - margin, 0.0)
        dq, lam = contact_step(metric, grad, G, held_off, self.support)
        if not np.all(np.isfinite(dq)):
            return None
        self.support = tuple(int(i) for i in np.flatnonzero(lam > 0))
        promised = -float(grad @ dq + 0.5 * dq @ (self.k * dq))
        dtilt = dq[1:3]
        dxy = dq[3:5] / mech.metres if len(dq) > 3 else np.zeros(2)
        moved = (
            float(np.abs(dtilt).max()) * (mech.radius + mech.scene.bolt.z_max)
            + float(np.abs(dxy).max(initial=0.0))
            + abs(dq[0]) / mech.metres
        )
        return _Step(dq, lam, over, promised, dtilt, dxy, moved)

    def exhausted(self, step: _Step, f_res: float, m_res: float) -> bool:
        """Whether nothing is left to gain at the length tolerance: the step moves no bolt
        point by a millionth of it and promises next to nothing. The descent ends there, a
        rest state if it balances.

        (The balance asks for tilts far finer than the travel tolerance: 1e-6 F times the
        radius against a 1 N m/rad spring is 3e-8 rad, against 1e4 N m/rad 3e-12 rad.
        Steps that small are still Newton steps of the same model.)
        """
        mech = self.mech
        if step.moved <= 1e-6 * mech.tolerance and step.promised <= (
            1e-12 * self.f * self.thread_pitch_m
        ):
            self.converged = f_res <= BALANCE and m_res <= BALANCE
            return True
        return False

    def too_long(self, step: _Step) -> bool:
        """Whether the step goes far beyond what the linearised contacts can tell (a tilt
        of more than 5 degrees, or a pitch in height)."""
        mech = self.mech
        return (
            float(np.abs(step.dtilt).max()) > math.radians(5.0)
            or abs(step.dq[0]) / mech.metres > mech.spec.pitch
        )

    # -- the step tried -------------------------------------------------------------------
    def line_search(
        self,
        step: _Step,
        centre: NDArray[np.float64],
        G: NDArray[np.float64],
        gap: NDArray[np.float64],
    ) -> bool:
        """Tilt the bolt by the step, lower it onto the nut and keep the step or not
        (:meth:`accept`, :meth:`reject`); False once the descent ends.

        Only a step kept at its bracket's touch can be kept at the first touch, which is
        no lower: that touch is verified only then.
        """
        mech = self.mech
        new_tilt = self.tilt + step.dtilt
        if not mech.compliance.held_laterally:
            new_xy = self.d.xy + step.dxy
        else:
            new_xy = self.d.xy
        # Nudges add up: all of them since the collision queries last lowered the bolt
        # stay within the tolerance, so that no run of them walks into a contact it does
        # not know.
        nudge = self.nudged + step.moved <= mech.tolerance
        trial = self.lowered(step, new_tilt, new_xy, nudge, G, gap)
        if trial is None:
            self.prox *= 4
            return True
        u_new = mech.potential(trial.zc, new_tilt, new_xy, self.held)
        if self.kept(u_new, step.promised):
            trial = mech.verified(trial)
            u_new = mech.potential(trial.zc, new_tilt, new_xy, self.held)
        step_q = np.concatenate([[(trial.zc - self.d.zc) * mech.metres], step.dq[1:]])
        if self.kept(u_new, step.promised):
            return self.accept(trial, new_tilt, u_new, step, G, nudge)
        return self.reject(trial, step_q, centre)

    def lowered(
        self,
        step: _Step,
        new_tilt: NDArray[np.float64],
        new_xy: NDArray[np.float64],
        nudge: bool,
        G: NDArray[np.float64],
        gap: NDArray[np.float64],
    ) -> _Drop | None:
        """The bolt at the step's tilt lowered onto the nut: onto the pairs it knows when
        the step is a nudge (:meth:`Mechanics._nudged`), else by the collision queries from a
        little above where the linearised contacts put it (None: it passes the nut, or
        meets material above it can only leave by climbing)."""
        mech = self.mech
        span = max(4 * mech.tolerance, 0.25 * step.moved)
        over = step.over
        if over:
            # Under material, the lowering starts below it (where the linearised
            # contacts put it) and does not climb: the bolt is between two flanks.
            ahead_gap = (gap[over] + G[over] @ step.dq) / (
                mech.metres * mech._rate(self.near, over)
            )
            span = min(span, max(1e-3 * mech.tolerance, 0.5 * float(ahead_gap.min())))
        if nudge:
            return mech._nudged(self.d, mech._rotation(new_tilt, self.phase), new_xy)
        return mech.drop(
            mech._rotation(new_tilt, self.phase),
            new_xy,
            self.d.zc + step.dq[0] / mech.metres,
            span=span,
            verify=False,
            climb=not over,
            reach=step.moved,
        )

    def kept(self, u_new: float, promised: float) -> bool:
        """Whether a step to the potential ``u_new`` is kept: U fell by a tenth of what
        the model ``promised``, or, where the promise is below the mesh's noise, rose by no
        more than it (below the chord error the exact contact geometry of the model
        decides; the step stays feasible, as it was lowered onto the nut)."""
        u, noise = self.u, self.noise
        return (u - u_new >= 0.1 * promised and u_new < u) or (
            promised <= noise and u_new <= u + noise
        )

    def accept(
        self,
        trial: _Drop,
        new_tilt: NDArray[np.float64],
        u_new: float,
        step: _Step,
        G: NDArray[np.float64],
        nudge: bool,
    ) -> bool:
        """Move to the kept pose ``trial``: its contacts, whether it is in phase, the
        curvature learnt and the trust region widened; a state on the path where the
        touching contacts changed. False once it has left ``start`` too far
        (:meth:`gone`)."""
        mech = self.mech
        old_rows, old_sig = G[: len(self.near), 1:3], _touching_pairs(self.near, mech.touching)
        self.near = mech.contacts(trial)
        self.follow_phase(trial, new_tilt)
        self.d, self.tilt, self.u = trial, new_tilt, u_new
        if self.gone(trial):
            self.departed = True
            return False
        self.nudged = self.nudged + step.moved if nudge else 0.0
        self.ahead = []
        now = _touching_pairs(self.near, mech.touching)
        if now == old_sig and len(self.near) == len(old_rows):
            self.learn_curvature(old_rows, step)
        self.adjust_trust(step, now)
        if now != self.signature and not self.in_phase:
            self.record(now)
        return True

    def follow_phase(self, trial: _Drop, new_tilt: NDArray[np.float64]) -> None:
        """Whether the kept pose is in phase, as long as its contacts lie on the helices
        (a contact that leaves them, the bolt rolling back onto its end, ends the snap);
        the first pose in phase is a state of the path (kind ``in-phase``)."""
        mech = self.mech
        if mech.engaged(self.near) != self.in_phase:
            self.in_phase = not self.in_phase
            if self.in_phase and not any(p.kind == IN_PHASE for p in self.path):
                self.path.append(
                    mech.state(
                        IN_PHASE, UNSTABLE, trial, self.near, self.phase, self.held, new_tilt
                    )
                )

    def learn_curvature(self, old_rows: NDArray[np.float64], step: _Step) -> None:
        """Learn the contacts' geometric stiffness from a step that kept them: their
        moment changes with the tilt as their points slide (a rim's lowest point turns with
        the tilt's direction), and damped BFGS learns its rate (:func:`_bfgs`)."""
        mech = self.mech
        new_rows = mech._rows(self.near, np.array([*self.d.xy, self.d.zc]), self.tilt)[0][:, 1:3]
        _bfgs(
            self.curvature,
            step.dtilt,
            -(new_rows - old_rows).T @ step.lam[: len(old_rows)],
            1e3 * self.f * self.arm_m,
        )

    def adjust_trust(self, step: _Step, now: tuple[str, ...]) -> None:
        """The trust region after a kept step: narrowed where the step turned back on the
        last one (the contact model flickers between two poses, a contact at the touching
        threshold: damp to meet between), else widened, more while the same contacts touch
        (the model is good)."""
        if float(step.dq[1:3] @ self.last_step) < 0:
            self.prox *= 4
        else:
            self.prox = np.maximum(
                self.prox / (10 if now == self.signature else 3), self.prox0[: len(self.k)] * 1e-8
            )
        self.last_step = step.dq[1:3].copy()

    def record(self, now: tuple[str, ...]) -> None:
        """A state of the path where the touching contacts changed to ``now``: a new
        contact (the thesis's next contact) or, with fewer, a released one (its rolling
        pivot), with the axis's turn since the last state recorded."""
        mech = self.mech
        kind = "new-contact" if len(now) >= len(self.signature) else "rolling"
        axis = self.d.rotation[:, 2]
        turn = axis_angle(axis, self.last_axis)
        self.path.append(
            mech.state(
                kind, UNSTABLE, self.d, self.near, self.phase, self.held, self.tilt, turn=turn
            )
        )
        self.last_axis = axis.copy()
        self.signature = now

    def reject(
        self, trial: _Drop, step_q: NDArray[np.float64], centre: NDArray[np.float64]
    ) -> bool:
        """Refuse the step: a narrower trust region, and the contacts touching at the trial
        pose carried back to this pose by their linearisation (cutting planes), so that the
        next step knows what stopped this one. False once the trust region has shrunk past
        any use."""
        mech = self.mech
        self.prox *= 4
        if self.prox[1] > self.prox0[1] * 1e12:
            return False
        self.ahead = []
        for c in mech.contacts(trial):
            if c.gap > mech.touching:
                continue
            row, _ = mech._rows([c], centre, self.tilt)
            opening = -float(row[0] @ step_q)
            if opening > 0:
                self.ahead.append(replace(c, gap=opening / (mech.metres * mech._rate([c], [0])[0])))
        return True

    # -- the end --------------------------------------------------------------------------
    def finish(self) -> RestState:
        """The rest state where the descent ended, classed, with its forces, residuals and
        the contacts' curvature (for a continuation to start from); or the pose it
        departed at (kind ``departed``, unbalanced)."""
        mech = self.mech
        if self.departed:
            return self.result(
                mech.state("departed", UNSTABLE, self.d, [], self.phase, self.held, self.tilt),
                {"force": math.nan, "moment": math.nan, "converged": 0.0},
            )
        if not self.converged:
            self.within_mesh()
        d, wide = self.d, self.touching_gap
        centre = np.array([d.xy[0], d.xy[1], d.zc])
        forces, f_res, m_res = mech.forces(
            self.near, centre, self.tilt, d.xy, self.held, touching_gap=wide
        )
        turn = axis_angle(d.rotation[:, 2], self.last_axis)
        cls, kind = self.classify(forces, centre)
        curvature = self.curvature
        final = replace(
            mech.state(
                kind,
                cls,
                d,
                self.near,
                self.phase,
                self.held,
                self.tilt,
                forces,
                turn,
                touching_gap=wide,
            ),
            contact_curvature=(
                (float(curvature[0, 0]), float(curvature[0, 1])),
                (float(curvature[1, 0]), float(curvature[1, 1])),
            ),
        )
        # The first state is a rest state already when the descent did not move.
        if self.path and self.path[0].kind == "first-contact" and self.steps == 0:
            self.path.clear()
        balance = {"force": f_res, "moment": m_res, "converged": float(self.converged)}
        if wide is not None:
            balance["touching_gap"] = wide
        return self.result(final, balance)

    def within_mesh(self) -> None:
        """A descent from first contact that ended unbalanced: the rest state near the
        poses it passed whose contacts within the meshes' deviation of touching balance the
        load and the spring (mechanics.md, "Stop"). The meshes cannot tell such a gap from
        a touch.

        The passed poses are ranked: those whose non-negative forces on the contacts open
        by no more than the meshes' deviation balance within :data:`BALANCE` first, least
        in U first, then the others by their residual. The first
        :data:`WITHIN_MESH_TRIES` are tried: one that does not balance is tilted to where
        its contacts, as they are, would balance (:meth:`polished`) and lowered again, up
        to :data:`POLISH_STEPS` times; the first that balances and is a minimum
        (:meth:`is_minimum`) becomes the descent's end, converged, with its contacts
        counted touching to that gap (``touching_gap``). Only from first contact (a
        continued descent's end feeds the continuation's decisions, which stand as its
        descents leave them), not in phase, nor with the nut's material over the bolt
        within that gap (the probes lower the bolt from above), nor with the bolt free
        laterally (the probes tilt it only).
        """
        mech = self.mech
        if self.start is not None or not mech.compliance.held_laterally:
            return
        wide = max(mech.scene.deviation, mech.touching)
        ranked = []
        for u, d, near, tilt in [*self.passed, (self.u, self.d, self.near, self.tilt)]:
            residual = self.wide_residual(d, near, tilt, wide)
            if residual is not None:
                rank = (residual > BALANCE, u if residual <= BALANCE else residual)
                ranked.append((rank, u, d, near, tilt))
        ranked.sort(key=lambda item: item[0])
        seen: set[float] = set()
        for _, u, d, near, tilt in ranked:
            if u in seen:
                continue
            seen.add(u)
            if len(seen) > WITHIN_MESH_TRIES:
                break
            for _ in range(POLISH_STEPS + 1):
                residual = self.wide_residual(d, near, tilt, wide)
                if residual is None:
                    break
                if residual <= BALANCE:
                    if self.is_minimum(u, d, tilt):
                        self.d, self.near, self.tilt, self.u = d, near, tilt, u
                        self.touching_gap = wide
                        self.converged = True
                        return
                    break
                polished = self.polished(d, near, tilt, wide)
                if polished is None:
                    break
                u, d, near, tilt = polished

    def wide_residual(
        self, d: _Drop, near: list[_Near], tilt: NDArray[np.float64], wide: float
    ) -> float | None:
        """The larger residual (force, moment) of the balance on the contacts of the pose
        ``d`` open by no more than ``wide``; None where the look back does not judge the
        pose (in phase, or the nut's material over the bolt within ``wide``)."""
        mech = self.mech
        if any(c.upper and c.gap <= wide for c in near):
            return None
        centre = np.array([d.xy[0], d.xy[1], d.zc])
        forces, f_res, m_res = mech.forces(near, centre, tilt, d.xy, self.held, touching_gap=wide)
        if mech.engaged(near, forces):
            return None
        return max(f_res, m_res)

    def polished(
        self, d: _Drop, near: list[_Near], tilt: NDArray[np.float64], wide: float
    ) -> tuple[float, _Drop, list[_Near], NDArray[np.float64]] | None:
        """The pose tilted to where the contacts of ``d`` open by no more than ``wide``,
        with their points and normals as they are, balance the spring: the moment they can
        give with the load in height (the nearest, by non-negative least squares) over the
        springs' stiffness. Lowered onto the nut from above, with its contacts and U; None
        when that tilt is more than :data:`POLISH_REACH` away or the bolt passes the nut."""
        mech = self.mech
        on = [c for c in near if c.gap <= wide]
        stiffness = self.k[1:3]
        if not on or np.any(stiffness <= 0):
            return None
        centre = np.array([d.xy[0], d.xy[1], d.zc])
        G, _ = mech._rows(on, centre, tilt)
        grad = mech._gradient(tilt, d.xy, self.held)
        # The height's balance held (weighted), the moments as near as the contacts reach.
        weight = mech._balance_scale(len(grad))
        weight[0] *= 1e4
        lam, _ = nnls((G * weight).T, grad * weight)
        dtilt = (G[:, 1:3].T @ lam - grad[1:3]) / stiffness
        if float(np.abs(dtilt).max()) > math.radians(POLISH_REACH):
            return None
        new_tilt = tilt + dtilt
        lowered = mech.drop(mech._rotation(new_tilt, self.phase), d.xy, None)
        if lowered is None:
            return None
        u = mech.potential(lowered.zc, new_tilt, lowered.xy, self.held)
        return u, lowered, mech.contacts(lowered), new_tilt

    def is_minimum(self, u: float, d: _Drop, tilt: NDArray[np.float64]) -> bool:
        """Whether the pose ``d`` at ``tilt`` (potential ``u``) is a minimum: lowered onto
        the nut from above at its own tilt, the bolt comes to rest within the meshes'
        deviation of it (else the pose lies under material the probes from above cannot
        reach), and no tilt of :data:`PROBE_TILTS` away from it, in
        :data:`PROBE_DIRECTIONS` directions, lowered from above, lowers U below ``u`` by
        more than the load times the meshes' deviation (what they cannot tell)."""
        mech = self.mech
        slack = self.f * mech.scene.deviation * mech.metres
        itself = mech.drop(d.rotation, d.xy, None)
        if itself is None or abs(mech.potential(itself.zc, tilt, d.xy, self.held) - u) > slack:
            return False
        for size in PROBE_TILTS:
            for j in range(PROBE_DIRECTIONS):
                a = 2.0 * math.pi * j / PROBE_DIRECTIONS
                probe = tilt + math.radians(size) * np.array([math.cos(a), math.sin(a)])
                lowered = mech.drop(mech._rotation(probe, self.phase), d.xy, None)
                if lowered is None:
                    continue
                if mech.potential(lowered.zc, probe, d.xy, self.held) < u - slack:
                    return False
        return True

    def classify(self, forces: NDArray[np.float64], centre: NDArray[np.float64]) -> tuple[str, str]:
        """The class and kind of the end state (mechanics.md), from what carries it: in
        phase when the load-carrying contacts lie on the helices, stable when the
        contacts alone hold the load, quasi-stable else; unstable unless converged."""
        mech = self.mech
        if mech.engaged(self.near, forces):
            cls, kind = IN_PHASE, IN_PHASE
        elif mech.holds_without_compliance(
            self.near, centre, self.tilt, touching_gap=self.touching_gap
        ):
            cls, kind = STABLE, "rest"
        else:
            cls, kind = QUASI_STABLE, "rest"
        if not self.converged:
            cls = UNSTABLE
        return cls, kind


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
