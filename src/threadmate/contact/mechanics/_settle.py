"""Rest states of the compliance-held bolt: an active-set descent of the potential.

docs/mechanics.md fixes the model. The bolt's free coordinates are the height ``z_C`` of
the compliance centre C and the tilt ``(roll, pitch)`` (and ``x_C, y_C`` when the
compliance has a lateral stiffness); the driver holds the phase. The potential is

    U = F z_C + k_roll/2 (roll - roll0)^2 + k_pitch/2 (pitch - pitch0)^2 (+ k_t/2 |xy|^2)

and a rest state is a local minimiser of U over the poses where bolt and nut do not
interpenetrate.

:class:`Mechanics` is composed by concern, one private module each, every layer standing
on those before it:

- :mod:`._held_bolt`: the thread pair, compliance, scene and tolerances; the bolt's pose;
- :mod:`._lowering`: the bolt lowered onto the nut at a tilt, exact for the meshes
  (:meth:`Mechanics.drop`, :meth:`Mechanics.verified`);
- :mod:`._contact_set`: the distinct contacts of a pose, with their normals and regions
  from the exact bodies (:meth:`Mechanics.contacts`);
- :mod:`._forces`: the potential, the contact rows and the forces that balance the load
  and the spring (:meth:`Mechanics.forces`, :meth:`Mechanics.driver_torque`);
- :mod:`._seat`: in phase on the helices (:meth:`Mechanics.engaged`), or seated upright;
- :mod:`._descent`: the descent itself, as named steps (:meth:`Mechanics.settle`).

This module holds the class, what it reports of a pose (:meth:`Mechanics.state`), where a
continuation looks for the next rest state (:meth:`Mechanics.predicted`), and the
functions :func:`mechanics` and :func:`settle`.

Classes (mechanics.md), from the forces and the minimum, never from the way there:

- ``in-phase`` (engaged): every contact that carries the load lies on the helices
  (:func:`._contact_set.on_helix`: a bolt flank on the nut's thread or on the edge where
  it meets the nut's entry, or the bolt's end on a nut flank), so that turning moves the
  bolt along the helix (the snap lands here);
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
from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint, minimize

from ..._errors import InputError
from ..._units import MJ_PER_J
from ...geometry import ThreadSpec
from ..scene import as_vec
from ._compliance import Compliance
from ._contact_set import _Near
from ._descent import BALANCE, _Descent
from ._lowering import _Drop
from ._rest_state import LoadedContact, MechanicalState, RestState
from ._seat import _Seat

__all__ = ["Mechanics", "mechanics", "settle"]


class Mechanics(_Seat):
    """Rest states and the counter-clockwise search of one thread pair and compliance.

    Its world (exact bodies, meshes, the collision queries, the tolerances) is a
    :class:`ContactScene`, built once per process and shared with the thesis's procedure;
    one instance per process (building the meshes and their collision trees is the cost).
    Its methods come from the layers the module docstring lists, :class:`._seat._Seat` and
    those it stands on; the descent of :meth:`settle` is a :class:`._descent._Descent`.

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
        touching_gap: float | None = None,
    ) -> MechanicalState:
        """A :class:`MechanicalState` of the pose ``d`` (forces None: not at rest).
        ``touching_gap``: the gap below which the balance counted a contact (default the
        touching gap; the meshes' deviation for a rest state found within their accuracy,
        :meth:`._descent._Descent.within_mesh`). Contacts open by more than the touching
        gap keep their gap in the state, with the force the balance gave them."""
        pose = self._pose(d.rotation, d.xy, d.zc)
        centre = np.array([d.xy[0], d.xy[1], d.zc])
        torque = friction = math.nan
        singular = False
        if forces is None:
            forces = np.full(len(near), math.nan)
        else:
            forces, singular = self.bounded(
                near, forces, centre, tilt, d.xy, held, touching_gap=touching_gap
            )
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
        from ``start``'s, and at once where the lowering from ``start`` meets the nut more
        than ``fall`` above it: the bisection asks only whether the rest state is near the
        state it leaves, and a descent that has gone this far on its way down
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
        return _Descent(self, roll, pitch, phase, start=start, leave=leave, arrive=arrive).run()


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
