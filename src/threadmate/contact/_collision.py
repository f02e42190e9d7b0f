"""python-fcl wrapper: the bolt and nut BVHs, built once, queried by bolt pose.

The BVHs are built once per analyser; a query only moves the bolt's collision object with
``setTransform``. fcl objects neither pickle nor release the GIL, so a process pool builds
one analyser per worker. Two kinds of query, both counted in :attr:`queries`:

- :meth:`collides`: yes/no (``num_max_contacts=1``, no contact geometry);
- :meth:`pairs`: every intersecting bolt/nut triangle pair (python-fcl still reports the
  triangle ids ``b1``/``b2`` with ``enable_contact=False``; we compute the intersection
  geometry ourselves, see :mod:`._triangles`);
- :meth:`collides_outside`: yes/no against the nut with some of its angular sectors left
  out. The nut's triangles are also split, once, into :data:`SECTORS` sectors about its
  axis (by centroid angle), each its own BVH; a query registers the sectors it keeps in a
  python-fcl dynamic AABB tree and stops at the first collision. This is how the turning
  stages look for a new contact while ignoring the interference beside the contacts the
  bolt turns about, without enumerating those pairs.

``continuousCollide`` (wrong times on thread meshes, alters models in place) and
``penetration_depth`` (a per-triangle figure) are deliberately not used.
"""

from __future__ import annotations

import fcl
import numpy as np
import trimesh
from numpy.typing import NDArray

from ..geometry import Pose

__all__ = ["CollisionPair"]

#: Pair enumeration stops here; far more than any contact the stages look at.
MAX_PAIRS = 200_000
#: Angular sectors of the nut for :meth:`CollisionPair.collides_outside`.
SECTORS = 36


def _bvh(vertices: NDArray[np.float64], faces: NDArray[np.int64]) -> fcl.BVHModel:
    model = fcl.BVHModel()
    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    model.beginModel(len(vertices), len(faces))
    model.addSubModel(vertices, faces)
    model.endModel()
    return model


class CollisionPair:
    """The bolt (in its frame) and nut (in the fixed frame) as python-fcl objects.

    Parameters
    ----------
    bolt_mesh, nut_mesh : trimesh.Trimesh
        Closed meshes in their own frames (conventions.md).
    """

    def __init__(self, bolt_mesh: trimesh.Trimesh, nut_mesh: trimesh.Trimesh) -> None:
        self.bolt_vertices = np.asarray(bolt_mesh.vertices, dtype=float)
        self.bolt_faces = np.asarray(bolt_mesh.faces, dtype=np.int64)
        self.nut_vertices = np.asarray(nut_mesh.vertices, dtype=float)
        self.nut_faces = np.asarray(nut_mesh.faces, dtype=np.int64)
        self._bolt = fcl.CollisionObject(_bvh(self.bolt_vertices, self.bolt_faces),
                                         fcl.Transform())
        self._nut = fcl.CollisionObject(_bvh(self.nut_vertices, self.nut_faces),
                                        fcl.Transform())
        centroid = self.nut_vertices[self.nut_faces].mean(axis=1)
        angle = np.arctan2(centroid[:, 1], centroid[:, 0])
        #: Sector (0 .. SECTORS-1, counter-clockwise from -pi) of each nut face.
        sector = np.floor((angle + np.pi) / (2 * np.pi) * SECTORS).astype(np.intp)
        self.nut_sector = sector % SECTORS
        self._sectors = []
        for k in range(SECTORS):
            faces = self.nut_faces[self.nut_sector == k]
            if len(faces) == 0:
                self._sectors.append(None)
                continue
            used, local = np.unique(faces, return_inverse=True)
            self._sectors.append(fcl.CollisionObject(
                _bvh(self.nut_vertices[used], local.reshape(-1, 3)), fcl.Transform()))
        self._managers: dict[frozenset[int], fcl.DynamicAABBTreeCollisionManager] = {}
        self._yes_no = fcl.CollisionRequest(num_max_contacts=1, enable_contact=False)
        self._all = fcl.CollisionRequest(num_max_contacts=MAX_PAIRS, enable_contact=False)
        #: Collision queries spent since construction (or the last reset).
        self.queries = 0
        # Bounding radius of the bolt about its origin: bounds the motion of any bolt point.
        self.bolt_radius = float(np.linalg.norm(self.bolt_vertices, axis=1).max())

    def _place(self, pose: Pose) -> None:
        self._bolt.setTransform(fcl.Transform(pose.rotation, pose.origin))

    def collides(self, pose: Pose) -> bool:
        """Whether the bolt at ``pose`` intersects the nut (one query)."""
        self._place(pose)
        self.queries += 1
        return fcl.collide(self._bolt, self._nut, self._yes_no, fcl.CollisionResult()) > 0

    def collides_outside(self, pose: Pose, excluded: frozenset[int]) -> bool:
        """Whether the bolt at ``pose`` intersects the nut outside the ``excluded`` sectors
        (one query)."""
        manager = self._managers.get(excluded)
        if manager is None:
            if len(self._managers) > 64:
                self._managers.clear()
            manager = fcl.DynamicAABBTreeCollisionManager()
            manager.registerObjects([o for k, o in enumerate(self._sectors)
                                     if o is not None and k not in excluded])
            manager.setup()
            self._managers[excluded] = manager
        self._place(pose)
        self.queries += 1
        data = fcl.CollisionData(request=self._yes_no)
        manager.collide(self._bolt, data, fcl.defaultCollisionCallback)
        return bool(data.result.is_collision)

    def sectors_near(self, points: NDArray[np.float64], reach: float,
                     min_radius: float) -> frozenset[int]:
        """Sectors within arc length ``reach`` of any of ``points`` (F), measured at each
        point's radius (not below ``min_radius``)."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        width = 2 * np.pi / SECTORS
        angle = np.arctan2(pts[:, 1], pts[:, 0]) + np.pi
        half = reach / np.maximum(np.hypot(pts[:, 0], pts[:, 1]), min_radius)
        lo = np.floor((angle - half) / width).astype(np.intp)
        hi = np.floor((angle + half) / width).astype(np.intp)
        out: set[int] = set()
        for a, b in zip(lo.tolist(), hi.tolist(), strict=True):
            out.update(k % SECTORS for k in range(a, b + 1))
        return frozenset(out)

    def pairs(self, pose: Pose) -> NDArray[np.int64]:
        """Intersecting ``(bolt_face, nut_face)`` index pairs at ``pose`` (one query)."""
        self._place(pose)
        self.queries += 1
        result = fcl.CollisionResult()
        fcl.collide(self._bolt, self._nut, self._all, result)
        if not result.contacts:
            return np.empty((0, 2), dtype=np.int64)
        ids = np.array([(c.b1, c.b2) for c in result.contacts], dtype=np.int64)
        return np.unique(ids, axis=0)

    def triangles(self, pose: Pose, pairs: NDArray[np.int64]
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Vertices (fixed frame) of the paired bolt and nut triangles, each ``(n, 3, 3)``."""
        bolt = pose.to_fixed(self.bolt_vertices[self.bolt_faces[pairs[:, 0]]])
        nut = self.nut_vertices[self.nut_faces[pairs[:, 1]]]
        return bolt, nut

    def lowest_bolt_z(self, rotation: NDArray[np.float64]) -> float:
        """Lowest bolt vertex height (fixed frame) for a bolt at the origin turned by
        ``rotation``."""
        return float((self.bolt_vertices @ rotation[2]).min())
