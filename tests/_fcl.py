"""python-fcl objects the tests build themselves, as the independent reference: one BVH
of a whole mesh (no sectors, none of the engine's strategy), and the bolt and nut of a
spec's generated meshes as such (:func:`collider`, one per spec)."""

from __future__ import annotations

import functools
import math
from typing import Any

import fcl
import numpy as np

from _exact_geometry import rot
from threadmate.geometry import thread_meshes


def bvh(mesh: Any) -> fcl.BVHModel:
    """A python-fcl BVH of a trimesh mesh, whole."""
    model = fcl.BVHModel()
    model.beginModel(len(mesh.faces), len(mesh.vertices))  # (triangles, vertices)
    model.addSubModel(np.asarray(mesh.vertices, float), np.asarray(mesh.faces, np.int64))
    model.endModel()
    return model


class Collider:
    """python-fcl BVHs of the spec's generated meshes, built here, whole (no sectors)."""

    def __init__(self, spec):
        bolt, nut = thread_meshes(spec)
        self.bolt = fcl.CollisionObject(bvh(bolt.mesh), fcl.Transform())
        self.nut = fcl.CollisionObject(bvh(nut.mesh), fcl.Transform())

    def collides(self, rotation, origin):
        """Whether the bolt at (rotation, origin) intersects the nut (yes/no query)."""
        self.bolt.setTransform(
            fcl.Transform(np.asarray(rotation, dtype=float), np.asarray(origin, dtype=float))
        )
        request = fcl.CollisionRequest(num_max_contacts=1, enable_contact=False)
        return fcl.collide(self.bolt, self.nut, request, fcl.CollisionResult()) > 0

    def contacts(self, rotation, origin):
        """Where the bolt at (rotation, origin) intersects the nut (empty: it does not)."""
        self.bolt.setTransform(
            fcl.Transform(np.asarray(rotation, dtype=float), np.asarray(origin, dtype=float))
        )
        request = fcl.CollisionRequest(num_max_contacts=100000, enable_contact=True)
        result = fcl.CollisionResult()
        fcl.collide(self.bolt, self.nut, request, result)
        return np.array([c.pos for c in result.contacts], dtype=float).reshape(-1, 3)

    def pairs(self, rotation, origin):
        """Every intersecting (bolt face, nut face) pair at (rotation, origin), as a set
        (python-fcl reports the triangles' numbers in the meshes as given)."""
        self.bolt.setTransform(
            fcl.Transform(np.asarray(rotation, dtype=float), np.asarray(origin, dtype=float))
        )
        request = fcl.CollisionRequest(num_max_contacts=1_000_000, enable_contact=False)
        result = fcl.CollisionResult()
        fcl.collide(self.bolt, self.nut, request, result)
        return {(c.b1, c.b2) for c in result.contacts}

    def first_touch(self, rotation, x, y, z_guess, reach):
        """Height of the bolt's origin where the bolt at ``rotation``, over ``(x, y)``,
        first touches the nut lowered from above: the yes/no query bisected to the last
        bit, from a bracket ``reach`` either side of ``z_guess`` widened until it holds.
        The free end is returned."""
        lo, hi = z_guess - reach, z_guess + reach
        while not self.collides(rotation, (x, y, lo)):
            lo -= reach
        while self.collides(rotation, (x, y, hi)):
            hi += reach
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if self.collides(rotation, (x, y, mid)):
                lo = mid
            else:
                hi = mid
        return hi

    def potential(self, compliance, held, phase, roll, pitch, z_guess, reach, metres):
        """U (J) of the bolt at ``(roll, pitch)`` and ``phase`` (degrees) lowered to first
        touch (:meth:`first_touch`, from ``z_guess`` with ``reach``), its compliance centre
        the tip's centre (``compliance_z`` 0, the bolt's origin) held at x = y = 0:
        ``F z_C + k/2 |tilt - held|^2``, ``held`` the held (roll, pitch) and ``metres``
        the metres per spec unit."""
        assert compliance.compliance_z == 0.0
        z = self.first_touch(rot(roll, pitch, phase), 0.0, 0.0, z_guess, reach)
        return (
            compliance.force * z * metres
            + 0.5 * compliance.roll_stiffness * math.radians(roll - held[0]) ** 2
            + 0.5 * compliance.pitch_stiffness * math.radians(pitch - held[1]) ** 2
        )


@functools.lru_cache(maxsize=8)
def collider(spec):
    """The :class:`Collider` of ``spec`` (built once per test process)."""
    return Collider(spec)
