"""The potential and the contact forces: what balances the load and the spring.

The potential of the held bolt (docs/mechanics.md) in its free coordinates ``q = (z_C,
roll, pitch[, x_C, y_C])`` is

    U = F z_C + k_roll/2 (roll - roll0)^2 + k_pitch/2 (pitch - pitch0)^2 (+ k_t/2 |xy|^2)

(:meth:`_Forces.potential`, :meth:`_Forces._gradient`). A contact ``i`` at ``p_i`` with
normal ``n_i`` (nut into bolt) opens at the rate ``G_i . dq`` for a small motion ``dq``,
with ``G_i = (n_z, X . (r_i x n_i), Y' . (r_i x n_i)[, n_x, n_y])``, ``r_i = p_i - C``,
``X`` the roll axis and ``Y' = Rx(roll) Y`` the pitch axis (:meth:`_Forces._rows`). The
contact forces are the non-negative multipliers that best balance the gradient of U on
these rows (:meth:`_Forces.forces`); bounded where the rigid balance is near-singular
(:meth:`_Forces.bounded`); enough on their own, with a margin, for a ``stable`` state
(:meth:`_Forces.holds_without_compliance`); and, with friction, the driver's torque
(:meth:`_Forces.driver_torque`). Friction does not enter the equilibrium: with C at the
tip the sliding friction of the spin acts nearly through C.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import lsq_linear, nnls

from ..._vectors import cross3
from ...geometry import rot_x
from ..scene import contact_rows
from ._contact_set import _Near
from ._held_bolt import _HeldBolt

__all__ = ["NEAR_SINGULAR"]

#: Largest contact force the model reports, in units of what the load and the spring can
#: press a contact with (:meth:`Mechanics.force_bound`): beyond it the rigid balance is
#: near-singular and the forces are bounded (:meth:`Mechanics.bounded`).
NEAR_SINGULAR = 3.0


class _Forces(_HeldBolt):
    """The potential and the contact forces (module docstring): a layer of
    :class:`Mechanics`."""

    def _rows(
        self, near: list[_Near], centre: NDArray[np.float64], tilt: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Contact rows ``G`` (SI: per m and per rad) and normal gaps (m)."""
        width = 3 if self.compliance.held_laterally else 5
        if not near:
            return np.zeros((0, width)), np.zeros(0)
        return contact_rows(
            np.array([c.normal for c in near], dtype=float),
            np.array([c.point for c in near], dtype=float),
            np.array([c.gap for c in near], dtype=float),
            self._rate(near, range(len(near))),
            np.asarray(centre, dtype=float),
            float(self.metres),
            rot_x(math.degrees(tilt[0]))[:, 1],
            width,
        )

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
        touching_gap: float | None = None,
    ) -> tuple[NDArray[np.float64], float, float]:
        """Non-negative normal forces (N) of the touching contacts that best balance the
        load and the spring, and the force and moment residuals relative to the load.
        ``touching_gap``: the gap below which a contact counts as touching (default the
        touching gap; :meth:`_Descent.within_mesh` widens it to the meshes' deviation)."""
        reach = self.touching if touching_gap is None else touching_gap
        touching = [c for c in near if c.gap <= reach]
        grad = self._gradient(tilt, xy, held)
        f = self.compliance.force
        scale = self._balance_scale(len(grad))
        if not touching:
            return np.zeros(len(near)), 1.0, float(np.abs(grad[1:3]).max() * scale[1] / f)
        G, _ = self._rows(touching, centre, tilt)
        lam, _ = nnls((G * scale).T, grad * scale)
        resid = (G.T @ lam - grad) * scale / f
        forces = np.zeros(len(near))
        forces[[i for i, c in enumerate(near) if c.gap <= reach]] = lam
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
        touching_gap: float | None = None,
    ) -> tuple[NDArray[np.float64], bool]:
        """``forces`` of a rest state, and whether its rigid balance is near-singular.

        Where two contacts' line passes (nearly) through the compliance centre, or a
        contact's normal lies (nearly) level, the rigid balance asks for forces hundreds of
        times the load: the rigid model cannot tell them (a hair of contact compliance or
        friction would carry the load instead). The model bounds them: each contact force
        at most :meth:`force_bound`, the balance met as closely as the bound lets it
        (bounded least squares), and the state marked near-singular. Reported forces,
        the driver's torque and its work then come from the bounded forces.
        ``touching_gap`` as in :meth:`forces`.
        """
        bound = self.force_bound(tilt, held)
        if not len(forces) or float(np.max(forces)) <= bound:
            return forces, False
        reach = self.touching if touching_gap is None else touching_gap
        on = [i for i, c in enumerate(near) if c.gap <= reach]
        G, _ = self._rows([near[i] for i in on], centre, tilt)
        grad = self._gradient(tilt, xy, held)
        scale = self._balance_scale(len(grad))
        fit = lsq_linear((G * scale).T, grad * scale, bounds=(0.0, bound))
        out = np.zeros(len(near))
        out[on] = np.clip(fit.x, 0.0, bound)
        return out, True

    def holds_without_compliance(
        self,
        near: list[_Near],
        centre: NDArray[np.float64],
        tilt: NDArray[np.float64],
        touching_gap: float | None = None,
    ) -> bool:
        """Whether the touching contacts alone hold the load with a margin (``stable``);
        ``touching_gap`` as in :meth:`forces`."""
        reach = self.touching if touching_gap is None else touching_gap
        touching = [c for c in near if c.gap <= reach]
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
            v = cross3(axis, r)
            v = v - (v @ c.normal) * c.normal
            speed = float(np.linalg.norm(v))
            normal -= float(axis @ cross3(r, lam * c.normal))
            if speed > 0:
                friction -= float(axis @ cross3(r, -mu * lam * v / speed))
        return normal + friction, friction
