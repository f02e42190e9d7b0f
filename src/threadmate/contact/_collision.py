"""python-fcl wrapper: the bolt and nut BVHs, built once, queried by bolt pose.

The BVHs are built once per analyser; a query only moves the bolt's collision object with
``setTransform``. fcl objects neither pickle nor release the GIL, so a process pool builds
one analyser per worker.

The nut is held split into :data:`SECTORS` angular sectors about its axis (each face by
its centroid's angle), each its own BVH, and every query is asked of the sectors. A
threaded pair is close to contact all round its circumference, so a query must prove
separation nearly everywhere, and the sectors' bounding volumes fit a ring of thread far
more tightly than those of one BVH of the whole nut: a yes/no query of all the sectors
costs 10-30 % less than one of the whole nut, an enumeration of the pairs up to 15 % less
over a sweep, with the same answers. The sectors serve two ends besides. The turning
stages look for a new contact while ignoring the interference beside the contacts the
bolt turns about: they leave those sectors out. And a search, once it has a colliding
pose, asks again only of the sectors that collide there. A yes/no query asks first the
sector that collided last: consecutive poses of a descent collide in the same place.

Queries, each one yes/no question counted in :attr:`queries`:

- :meth:`collides`: whether the bolt intersects the nut;
- :meth:`collides_outside`: the same for every sector but the excluded ones;
- :meth:`colliding_sectors`: which sectors (of those not excluded) the bolt intersects;
- :meth:`pairs`: every intersecting bolt/nut triangle pair (python-fcl still reports the
  triangle ids ``b1``/``b2`` with ``enable_contact=False``; we compute the intersection
  geometry ourselves, see :mod:`._triangles`).

``continuousCollide`` (wrong times on thread meshes, alters models in place) and
``penetration_depth`` (a per-triangle figure) are deliberately not used.
"""

from __future__ import annotations

import fcl
import numpy as np
import trimesh
from numpy.typing import NDArray

from ..geometry import Pose

__all__ = ["CollisionPair", "pair_keys"]

#: Pair enumeration stops here; far more than any contact the stages look at.
MAX_PAIRS = 200_000
#: Angular sectors of the nut, each its own BVH (see the module docstring).
SECTORS = 36
#: Multiplier of the bolt face in a pair's integer key (above any nut face count).
_KEY = 1 << 31


def pair_keys(pairs: NDArray[np.int64]) -> NDArray[np.int64]:
    """One integer per ``(bolt_face, nut_face)`` pair (bolt face major)."""
    return pairs[:, 0] * _KEY + pairs[:, 1]


def _pair_keys_of(
    bolt: fcl.CollisionObject,
    nut: fcl.CollisionObject,
    request: fcl.CollisionRequest,
    nut_ids: NDArray[np.int64],
) -> NDArray[np.int64]:
    """Keys (:func:`pair_keys`) of the intersecting (bolt face, nut face) pairs, with
    repeats; ``nut_ids`` maps a sector's local face numbers to the nut's."""
    result = fcl.CollisionResult()
    fcl.collide(bolt, nut, request, result)
    if not result.contacts:
        return np.empty(0, dtype=np.int64)
    ids = np.array([(c.b1, c.b2) for c in result.contacts], dtype=np.int64)
    return ids[:, 0] * _KEY + nut_ids[ids[:, 1]]


def _bvh(vertices: NDArray[np.float64], faces: NDArray[np.int64]) -> fcl.BVHModel:
    model = fcl.BVHModel()
    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    model.beginModel(len(faces), len(vertices))  # (triangles, vertices): capacity hints
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
        self._bolt = fcl.CollisionObject(_bvh(self.bolt_vertices, self.bolt_faces), fcl.Transform())
        centroid = self.nut_vertices[self.nut_faces].mean(axis=1)
        angle = np.arctan2(centroid[:, 1], centroid[:, 0])
        #: Sector (0 .. SECTORS-1, counter-clockwise from -pi) of each nut face.
        sector = np.floor((angle + np.pi) / (2 * np.pi) * SECTORS).astype(np.intp)
        self.nut_sector = sector % SECTORS
        self._sectors: dict[int, tuple[fcl.CollisionObject, NDArray[np.int64]]] = {}
        for k in range(SECTORS):
            ids = np.flatnonzero(self.nut_sector == k)
            if len(ids) == 0:
                continue
            used, local = np.unique(self.nut_faces[ids], return_inverse=True)
            self._sectors[k] = (
                fcl.CollisionObject(
                    _bvh(self.nut_vertices[used], local.reshape(-1, 3)), fcl.Transform()
                ),
                ids,
            )
        #: The sectors in the order a yes/no query asks them: the last to collide first.
        self._order = list(self._sectors)
        self._yes_no = fcl.CollisionRequest(num_max_contacts=1, enable_contact=False)
        self._all = fcl.CollisionRequest(num_max_contacts=MAX_PAIRS, enable_contact=False)
        #: Collision queries spent since construction (or the last reset).
        self.queries = 0
        # Bounding radius of the bolt about its origin: bounds the motion of any bolt point.
        self.bolt_radius = float(np.linalg.norm(self.bolt_vertices, axis=1).max())

    def _place(self, pose: Pose) -> None:
        self._bolt.setTransform(fcl.Transform(pose.rotation, pose.origin))

    def _hits(self, other: fcl.CollisionObject) -> bool:
        return fcl.collide(self._bolt, other, self._yes_no, fcl.CollisionResult()) > 0

    def collides(self, pose: Pose) -> bool:
        """Whether the bolt at ``pose`` intersects the nut (one query)."""
        self._place(pose)
        self.queries += 1
        order = self._order
        for i, k in enumerate(order):
            if self._hits(self._sectors[k][0]):
                if i:
                    order.insert(0, order.pop(i))
                return True
        return False

    def collides_outside(self, pose: Pose, excluded: frozenset[int]) -> bool:
        """Whether the bolt at ``pose`` intersects the nut outside the ``excluded`` sectors
        (one query)."""
        if not excluded:
            return self.collides(pose)
        self._place(pose)
        self.queries += 1
        return any(self._hits(obj) for k, (obj, _) in self._sectors.items() if k not in excluded)

    def colliding_sectors(
        self,
        pose: Pose,
        excluded: frozenset[int] = frozenset(),
        among: frozenset[int] | None = None,
    ) -> frozenset[int]:
        """The sectors, other than ``excluded`` and within ``among`` when given, that the
        bolt at ``pose`` intersects (one query)."""
        self._place(pose)
        self.queries += 1
        keys = self._sectors.keys() if among is None else sorted(among & self._sectors.keys())
        return frozenset(k for k in keys if k not in excluded and self._hits(self._sectors[k][0]))

    def sectors_near(
        self, points: NDArray[np.float64], reach: float, min_radius: float
    ) -> frozenset[int]:
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

    def sectors_around(self, pairs: NDArray[np.int64]) -> frozenset[int]:
        """The sectors of the nut faces of ``pairs``, and the sector either side of each."""
        found = np.unique(self.nut_sector[pairs[:, 1]])
        return frozenset(((found[:, None] + np.arange(-1, 2)) % SECTORS).ravel().tolist())

    def pairs(self, pose: Pose, sectors: frozenset[int] | None = None) -> NDArray[np.int64]:
        """Intersecting ``(bolt_face, nut_face)`` index pairs at ``pose``, over the whole
        nut or only its ``sectors`` (one query)."""
        self._place(pose)
        self.queries += 1
        found = [
            _pair_keys_of(self._bolt, obj, self._all, nut_ids)
            for k, (obj, nut_ids) in self._sectors.items()
            if sectors is None or k in sectors
        ]
        # One integer key per pair (bolt face major), all sectors at once: a 1-D unique
        # sorts them as the rows' lexicographic unique would, at a fraction of its cost.
        key = np.unique(np.concatenate(found)) if found else np.empty(0, dtype=np.int64)
        return np.column_stack([key // _KEY, key % _KEY])

    def triangles(
        self, pose: Pose, pairs: NDArray[np.int64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Vertices (fixed frame) of the paired bolt and nut triangles, each ``(n, 3, 3)``."""
        bolt = pose.to_fixed(self.bolt_vertices[self.bolt_faces[pairs[:, 0]]])
        nut = self.nut_vertices[self.nut_faces[pairs[:, 1]]]
        return bolt, nut

    def lowest_bolt_z(self, rotation: NDArray[np.float64]) -> float:
        """Lowest bolt vertex height (fixed frame) for a bolt at the origin turned by
        ``rotation``."""
        return float((self.bolt_vertices @ rotation[2]).min())
