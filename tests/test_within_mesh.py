"""A rest state found within the meshes' accuracy (docs/mechanics.md, "Stop"): a descent
that ends unbalanced takes, of the poses it passed, one whose contacts within the meshes'
deviation of touching balance the load and the spring, if it is a minimum.

Checked without the descent's own machinery, on the #10-32 held (1, -1) at 90 degrees,
where three contacts balance with their own normals and one of them lies open by less
than the meshes' deviation, and on the default run's 1/4-20 held (1, 1) at 100 degrees,
where the chamfer's kink rests on the countersink's kink at two places, one of them open
by less than the deviation:

- no interpenetration: python-fcl BVHs of the two whole meshes built here (``_fcl``), free
  1e-8 in above the pose and colliding 1e-6 in below it;
- the forces non-negative, on contacts touching or open by no more than the meshes'
  deviation, and the balance of load and spring recomputed from the reported points and
  normals (R = Rx(roll) Ry(pitch) Rz(phase) written out here) within 1e-6 F;
- a minimum: tilts 0.01, 0.05 and 0.2 degree away in 8 directions, each lowered to first
  touch by bisection on the fcl query of the whole meshes, never lower U by more than
  F x the meshes' deviation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from _exact_geometry import rot
from _fcl import collider
from threadmate.contact import Compliance, Mechanics
from threadmate.geometry import spec_from_designation

INCH_M = 0.0254
DEFAULT = Compliance()


# (designation, held roll, held pitch, phase, contacts carrying the load)
STARTS = [("#10-32 UNF-2A/2B", 1.0, -1.0, 90.0, 3), ("1/4-20 UNC-2A/2B", 1.0, 1.0, 100.0, 2)]


@pytest.mark.parametrize("designation, roll0, pitch0, phase, carried", STARTS)
def test_rest_state_within_the_meshes_accuracy_is_a_balanced_minimum(
    designation, roll0, pitch0, phase, carried
):
    # Standard chamfered point and countersink (the default run's parts).
    spec = spec_from_designation(designation)
    mech = Mechanics(spec, DEFAULT)
    assert spec.units == "in"
    rest = mech.settle(roll0, pitch0, phase)
    s = rest.state
    deviation = mech.scene.deviation
    assert rest.balance["converged"], rest.balance
    assert rest.balance["touching_gap"] == max(deviation, mech.touching)
    assert s.classification in ("stable", "quasi-stable")
    carrying = [c for c in s.contacts if c.force > 0]
    assert len(carrying) == carried
    # One of them lies open by more than the touching gap, less than the meshes' deviation:
    # reported with its gap, and among the state's touching contacts.
    assert any(mech.touching < c.gap <= deviation for c in carrying)
    assert all(c.gap <= deviation for c in carrying)
    assert set(carrying) <= set(s.touching)
    R = np.array(s.rotation)
    np.testing.assert_allclose(R, rot(s.roll, s.pitch, phase), atol=1e-12)
    origin = np.array(s.origin)
    col = collider(spec)
    up = np.array([0.0, 0.0, 1.0])
    assert not col.collides(R, origin + 1e-8 * up)
    assert col.collides(R, origin - 1e-6 * up)
    # Forces and the balance, from the reported points and normals.
    f, k = DEFAULT.force, DEFAULT.roll_stiffness
    centre = np.array(s.centre)
    pitch_axis = rot(s.roll, 0.0, 0.0)[:, 1]
    total = np.zeros(3)
    for c in s.contacts:
        assert math.isfinite(c.force) and c.force >= 0.0, c
        n = np.array(c.normal)
        moment = np.cross((np.array(c.point) - centre) * INCH_M, n)
        total += c.force * np.array([n[2], moment[0], pitch_axis @ moment])
    load = np.array([f, k * math.radians(s.roll - roll0), k * math.radians(s.pitch - pitch0)])
    radius = 0.5 * spec.bolt.major * INCH_M
    resid = total - load
    assert abs(resid[0]) <= 1e-6 * f, resid
    assert np.abs(resid[1:]).max() <= 1e-6 * f * radius, resid

    # A minimum: perturbed tilts, each lowered to first touch on the whole meshes.
    def potential(roll, pitch):
        return col.potential(
            DEFAULT, (roll0, pitch0), phase, roll, pitch, s.origin[2], 2e-3, INCH_M
        )

    np.testing.assert_allclose(s.centre, s.origin, atol=1e-12)  # C at the tip's centre
    u0 = potential(s.roll, s.pitch)
    tol = f * deviation * INCH_M
    assert abs(u0 - s.potential * 1e-3) <= tol
    for d in (0.01, 0.05, 0.2):
        for a in range(0, 360, 45):
            du = (
                potential(
                    s.roll + d * math.cos(math.radians(a)), s.pitch + d * math.sin(math.radians(a))
                )
                - u0
            )
            assert du >= -tol, (designation, d, a, du / tol)
