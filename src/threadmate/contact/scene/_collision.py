"""The collision queries: the bolt and nut as trees of oriented boxes, built once, queried
by bolt pose.

The trees (:mod:`._obb`: FCL's kind of tree and FCL's tests, walked by compiled code that
returns the crossing triangle pairs as integers) are built once per analyser; a query
only names the bolt's pose. A process pool builds one analyser per worker.

The nut is held split into :data:`SECTORS` angular sectors about its axis (each face by
its centroid's angle), each its own tree, and every query is asked of the sectors. A
threaded pair is close to contact all round its circumference, so a query must prove
separation nearly everywhere, and the sectors' bounding volumes fit a ring of thread far
more tightly than those of one tree of the whole nut: a yes/no query of all the sectors,
and an enumeration of the pairs, costs less than one of the whole nut, with the same
answers (docs/validation.md, "Cost: meshes and queries"). The sectors serve two ends
besides. The turning stages look for a new contact while ignoring the interference beside
the contacts the bolt turns about: they leave those sectors out. And a search, once it
has a colliding pose, asks again only of the sectors that collide there. A yes/no query
asks first the sector that collided last: consecutive poses of a descent collide in the
same place.

The bolt is asked without its core where the pose allows: the triangles nearer its axis
than the nut's bore less the axis's sway at a tilt of :data:`CORE_TILT` (most of them:
the root's fillet takes many to follow within the chord), which cannot reach the nut's
material while the bolt's axis stays that close to the nut's. A query checks, from the
pose alone, that every point of the core lies nearer the nut's axis than any point of the
nut's mesh (:meth:`CollisionPair._core_clear`), and asks the whole bolt where it does not:
the answers are those of the whole meshes, at most of the cost. A core of fewer than
:data:`CORE_SHARE` of the bolt's faces (a mesh from CAD with a coarse root, say) is not
worth a second tree's memory: the bolt is then always asked whole.

Queries, each one yes/no question counted in :attr:`queries`:

- :meth:`collides`: whether the bolt intersects the nut;
- :meth:`collides_outside`: the same for every sector but the excluded ones;
- :meth:`colliding_sectors`: which sectors (of those not excluded) the bolt intersects;
- :meth:`pairs`: every intersecting bolt/nut triangle pair (their faces; the intersection
  geometry is computed from the triangles, see :mod:`._triangles`);
- :meth:`pairs_under_material`: the same, of only the nut faces turned down and the bolt
  faces that can face up at the bolt's tilt: every pair of the nut's material over the
  bolt, without asking of the flanks that carry the bolt, close to the nut all round,
  which a query spends most of its time proving apart;
- :meth:`pairs_below`: whether the bolt is free at one pose and the pairs at a lower one
  of the same rotation (two questions, one walk). The walk's boxes are swept between the
  two, and it keeps the leaves whose boxes meet (a :class:`Sweep`): the pairs crossing at
  any pose between are among them, and a lowering that asks again between (the
  verification of its touch: whether the bolt meets anything as it moves down from the
  top to its touch, the pairs crossing and the yes/no questions at heights between) is
  answered from them, with no walk of the trees.

A mesh from CAD is taken as given: where it does not follow the spec (a point, a
countersink or a chamfer the spec does not state) the spec's exact body is no measure of
what is inside it. :meth:`CollisionPair.signed_distance` measures from the mesh itself
(:class:`MeshSolid`).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import trimesh
from numpy.typing import NDArray
from scipy.spatial import ConvexHull, cKDTree

from ..._angles import TWO_PI
from ...geometry import Pose
from ._kernels import paired_triangles
from ._obb import (
    ALL,
    ANY,
    EACH,
    PAIR_KEY,
    CrossingQuery,
    ObbForest,
    obb_forest,
    unique_face_pairs,
)

__all__ = ["CollisionPair", "MeshSolid", "Sweep", "pair_keys", "upward"]

#: Angular sectors of the nut, each its own tree (see the module docstring).
SECTORS = 36
#: Triangles (by nearest centroid) whose nearest bounds a signed distance's search.
_NEAREST = 8
#: Size classes of a mesh's triangles (a factor of 2 each; the smallest take the rest).
_CLASSES = 8
#: Largest tilt of the bolt's axis from the nut's (degrees) at which
#: :meth:`CollisionPair.pairs_under_material` asks only the bolt faces that can face up.
UNDER_TILT = 20.0
#: Tilt of the bolt's axis (degrees, about its tip) up to which the bolt's core (module
#: docstring) stays inside the nut's bore.
CORE_TILT = 5.0
#: Least share of the bolt's faces in its core for a query to leave the core out.
CORE_SHARE = 0.25
#: Bands of height of the nut's bore (:meth:`CollisionPair.free_fall`).
BORE_BINS = 128


#: Some of the bolt's faces as a tree (:class:`._obb.ObbForest` and the tree's number in
#: it), and the same without the core's faces (None where the core holds none of them).
_Bolt = tuple[ObbForest, int, int | None]


class Sweep:
    """One walk of the trees swept between two poses of one rotation, origins ``low`` and
    ``high`` (:meth:`CollisionPair.pairs_below`): the pairs crossing at ``low``, and the
    leaf pairs whose swept boxes met, among which lie the pairs crossing at any pose
    between (:meth:`covers`), found there by the triangle test alone.

    Attributes
    ----------
    pairs : ndarray of int64
        The ``(bolt_face, nut_face)`` pairs crossing at the lower pose (sorted, unique).
    """

    def __init__(
        self,
        engine: CollisionPair,
        bolt: tuple[ObbForest, int],
        low: Pose,
        high: Pose,
        pairs: NDArray[np.int64],
        nodes: NDArray[np.int64],
    ) -> None:
        self.pairs = pairs
        self._engine = engine
        self._bolt = bolt
        self._whole = bolt[1] == engine._bolt[1]  # the whole bolt's tree, core and all
        self._poses = (low, high)
        self._rotation = low.rotation
        self._origin = low.origin
        self._heights = (min(low.origin[2], high.origin[2]), max(low.origin[2], high.origin[2]))
        self._nodes = nodes  # (bolt node, nut node, sector)

    def covers(self, pose: Pose) -> bool:
        """Whether ``pose`` lies between the walk's two: the same rotation and XY of the
        origin, its height between theirs, and the walk's tree of the bolt the whole one
        or the one a query at ``pose`` asks."""
        o, engine = pose.origin, self._engine
        return (
            self._heights[0] <= o[2] <= self._heights[1]
            and o[0] == self._origin[0]
            and o[1] == self._origin[1]
            and np.array_equal(pose.rotation, self._rotation)
            and (self._whole or engine._placed_at(engine._bolt, pose)[1] == self._bolt[1])
        )

    def pairs_at(self, pose: Pose, sectors: frozenset[int] | None = None) -> NDArray[np.int64]:
        """:meth:`CollisionPair.pairs` at a pose the walk covers (:meth:`covers`)."""
        nodes = self._nodes
        if sectors is not None:
            asked = np.zeros(SECTORS, dtype=bool)
            asked[list(sectors)] = True
            nodes = nodes[asked[nodes[:, 2]]]
        found = self._engine._nut.among(self._bolt[0], nodes, pose.rotation, pose.origin, ALL)
        return unique_face_pairs(found)

    def candidates(self) -> NDArray[np.int64]:
        """Every ``(bolt_face, nut_face)`` pair of the leaf pairs whose swept boxes met
        (sorted, unique): each pair that crosses at some pose between the walk's two is
        among them, whether or not it crosses at either."""
        forest, nut = self._bolt[0], self._engine._nut.nut
        bolt_node, nut_node = self._nodes[:, 0], self._nodes[:, 1]
        bolt_size, nut_size = forest.size[bolt_node], nut.size[nut_node]
        rows = [np.empty((0, 3), dtype=np.int64)]
        for a in range(int(bolt_size.max(initial=0))):
            for b in range(int(nut_size.max(initial=0))):
                has = (a < bolt_size) & (b < nut_size)
                rows.append(
                    np.column_stack(
                        [
                            forest.faces[forest.leaf[bolt_node[has]] + a],
                            nut.faces[nut.leaf[nut_node[has]] + b],
                            self._nodes[has, 2],
                        ]
                    )
                )
        return unique_face_pairs(np.concatenate(rows).astype(np.int64))

    def touching_within(self, pose: Pose, drop: float) -> NDArray[np.int64]:
        """The ``(bolt_face, nut_face)`` pairs (sorted, unique) that meet as the bolt is
        lowered from ``pose`` (a pose the walk covers) by up to ``drop``: every pair that
        touches between there and the walk's lower pose is among the leaf pairs kept
        (:meth:`candidates`), tested by one compiled pass
        (:meth:`._obb.CrossingQuery.among`)."""
        found = self._engine._nut.among(
            self._bolt[0], self._nodes, pose.rotation, pose.origin, ALL, drop
        )
        return unique_face_pairs(found)

    def narrowed(self, pose: Pose, drop: float) -> Sweep:
        """This walk kept to its leaf pairs of which a pair meets as the bolt is lowered
        from ``pose`` (a pose the walk covers) by up to ``drop`` (:meth:`touching_within`).

        Every pair that crosses at a pose between that one and ``drop`` below it, the
        pose free, met the other on the way: it lies in one of these leaf pairs, and
        :meth:`pairs_at` and :meth:`collides_at` there find what this walk's would, with
        the same test, asking far fewer."""
        tagged = self._nodes.copy()
        tagged[:, 2] = np.arange(len(tagged))  # each row's tag: its own position
        found = self._engine._nut.among(
            self._bolt[0], tagged, pose.rotation, pose.origin, ALL, drop
        )
        low, high = self._poses
        return Sweep(
            self._engine, self._bolt, low, high, self.pairs, self._nodes[np.unique(found[:, 2])]
        )

    def collides_at(self, pose: Pose) -> bool:
        """:meth:`CollisionPair.collides` at a pose the walk covers (:meth:`covers`)."""
        hit = self._engine._nut.among(self._bolt[0], self._nodes, pose.rotation, pose.origin, ANY)
        return len(hit) > 0


def pair_keys(pairs: NDArray[np.int64]) -> NDArray[np.int64]:
    """One integer per ``(bolt_face, nut_face)`` pair (bolt face major)."""
    return pairs[:, 0] * PAIR_KEY + pairs[:, 1]


def upward(triangles: NDArray[np.float64]) -> NDArray[np.float64]:
    """The Z part of each triangle's outward normal, unnormalised (the meshes wind their
    triangles outward): positive for a face turned up."""
    t = np.asarray(triangles, dtype=float)
    a, b = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    # ``np.cross(a, b)[:, 2]`` by its formula: the lowering asks a few triangles at a time,
    # where its axis handling costs more than the products.
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def _axis_distance(triangles: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each triangle's least distance from the Z axis: the distance from the origin to
    its projection on the XY plane (0 where that covers the origin)."""
    p = np.asarray(triangles, dtype=float)[..., :2]
    a, b = p, np.roll(p, -1, axis=1)  # each edge (a, b)
    ab = b - a
    length2 = np.einsum("ijk,ijk->ij", ab, ab)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.clip(np.where(length2 > 0, -np.einsum("ijk,ijk->ij", a, ab) / length2, 0.0), 0, 1)
    nearest = np.linalg.norm(a + t[..., None] * ab, axis=2).min(axis=1)
    # The origin is inside the projection where it lies on one side of all three edges.
    side = a[..., 0] * ab[..., 1] - a[..., 1] * ab[..., 0]
    inside = np.all(side > 0, axis=1) | np.all(side < 0, axis=1)
    return np.where(inside, 0.0, nearest)


def closest_on_triangles(
    p: NDArray[np.float64], a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """The point of each triangle ``(a, b, c)`` closest to ``p`` (all ``(n, 3)``) and the
    feature it lies on: 0 the face, 1-3 the vertex a, b, c, 4-6 the edge ab, bc, ca.

    Ericson's Voronoi-region test (Real-Time Collision Detection, 5.1.5), vectorised.
    """
    ab, ac, ap = b - a, c - a, p - a
    d1 = np.einsum("ij,ij->i", ab, ap)
    d2 = np.einsum("ij,ij->i", ac, ap)
    bp = p - b
    d3 = np.einsum("ij,ij->i", ab, bp)
    d4 = np.einsum("ij,ij->i", ac, bp)
    cp = p - c
    d5 = np.einsum("ij,ij->i", ab, cp)
    d6 = np.einsum("ij,ij->i", ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        den = va + vb + vc
        v = np.where(den != 0, vb / den, 0.0)
        w = np.where(den != 0, vc / den, 0.0)
        t_ab = np.where(d1 - d3 != 0, d1 / (d1 - d3), 0.0)
        t_ac = np.where(d2 - d6 != 0, d2 / (d2 - d6), 0.0)
        t_bc = np.where((d4 - d3) + (d5 - d6) != 0, (d4 - d3) / ((d4 - d3) + (d5 - d6)), 0.0)
    q = a + v[:, None] * ab + w[:, None] * ac
    kind = np.zeros(len(p), dtype=np.intp)
    # From the last test to the first, so that the first that holds wins.
    on_bc = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)
    q = np.where(on_bc[:, None], b + t_bc[:, None] * (c - b), q)
    kind[on_bc] = 5
    on_ca = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
    q = np.where(on_ca[:, None], a + t_ac[:, None] * ac, q)
    kind[on_ca] = 6
    at_c = (d6 >= 0) & (d5 <= d6)
    q = np.where(at_c[:, None], c, q)
    kind[at_c] = 3
    on_ab = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
    q = np.where(on_ab[:, None], a + t_ab[:, None] * ab, q)
    kind[on_ab] = 4
    at_b = (d3 >= 0) & (d4 <= d3)
    q = np.where(at_b[:, None], b, q)
    kind[at_b] = 2
    at_a = (d1 <= 0) & (d2 <= 0)
    q = np.where(at_a[:, None], a, q)
    kind[at_a] = 1
    return q, kind


class MeshSolid:
    """Signed distance from a closed, outward-wound mesh (negative inside its material).

    The distance is to the nearest triangle; its sign is that of the offset along the
    angle-weighted pseudonormal of the feature (face, edge or vertex) the nearest point
    lies on, which is exact for a closed manifold mesh (Baerentzen and Aanaes, IEEE TVCG
    11, 2005). The nearest of the triangles of the nearest centroids bounds the distance;
    the nearest triangle's centroid lies within that bound plus its own radius
    (centroid to farthest vertex), so it is among those found by a ball search in each
    size class of the triangles (radii within a factor of 2) widened by the class's
    largest radius: the few large faces of a CAD part do not widen every search.

    Parameters
    ----------
    vertices, faces : ndarray
        The mesh, closed and wound outward (as :func:`threadmate.geometry.load_mesh`
        returns it).
    """

    def __init__(self, vertices: NDArray[np.float64], faces: NDArray[np.int64]) -> None:
        v = np.asarray(vertices, dtype=float)
        f = np.asarray(faces, dtype=np.int64)
        tri = v[f]
        #: The vertices, the triangles' vertex indices and the triangles, ``(n, 3, 3)``.
        self.vertices = v
        self.faces = f
        self.triangles = tri
        cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        norm = np.linalg.norm(cross, axis=1)
        normal = cross / np.maximum(norm, 1e-300)[:, None]
        #: Each triangle's outward unit normal.
        self.face_normals = normal
        # Edge pseudonormals: the sum of the two faces' normals, per face and local edge.
        edges = np.sort(f[:, [[0, 1], [1, 2], [2, 0]]], axis=2).reshape(-1, 2)
        _, inverse = np.unique(edges, axis=0, return_inverse=True)
        inverse = inverse.reshape(-1)
        summed = np.zeros((int(inverse.max()) + 1, 3))
        np.add.at(summed, inverse, np.repeat(normal, 3, axis=0))
        self._edge_normal = summed[inverse].reshape(-1, 3, 3)
        # Vertex pseudonormals: the face normals weighted by the faces' angles there.
        angles = np.empty((len(f), 3))
        for k in range(3):
            u = tri[:, (k + 1) % 3] - tri[:, k]
            w = tri[:, (k + 2) % 3] - tri[:, k]
            cosine = np.einsum("ij,ij->i", u, w) / np.maximum(
                np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1), 1e-300
            )
            angles[:, k] = np.arccos(np.clip(cosine, -1.0, 1.0))
        vertex = np.zeros((len(v), 3))
        for k in range(3):
            np.add.at(vertex, f[:, k], normal * angles[:, k : k + 1])
        self._vertex_normal = vertex[f]
        centroid = tri.mean(axis=1)
        radius = np.linalg.norm(tri - centroid[:, None], axis=2).max(axis=1)
        self._centroids = cKDTree(centroid)
        # Size classes (radius within a factor of 2), each its own tree: a ball search
        # widened by a class's largest radius, not the mesh's.
        level = np.floor(np.log2(np.maximum(radius, 1e-300) / max(float(radius.max()), 1e-300)))
        level = np.maximum(level, -_CLASSES + 1)
        self._classes = []
        for lv in np.unique(level).tolist():
            ids = np.flatnonzero(level == lv)
            self._classes.append((ids, cKDTree(centroid[ids]), float(radius[ids].max())))

    def signed_distance(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Signed distance of each point (the mesh's frame) from the mesh's surface,
        negative inside."""
        return self.nearest(points)[0]

    def normal(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """The mesh's outward unit normal nearest each point: the face's, or where the
        nearest point is on an edge or a vertex, its pseudonormal (the faces' directions
        there averaged)."""
        return self.nearest(points)[1]

    def nearest(
        self, points: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
        """For each point (the mesh's frame): the signed distance, the unit normal
        (:meth:`normal`) and the triangle of the mesh's nearest point."""
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        if len(p) == 0:
            return np.empty(0), np.empty((0, 3)), np.empty(0, dtype=np.intp)
        # An upper bound of each distance: the nearest of the nearest centroids' triangles.
        k = min(_NEAREST, len(self.faces))
        _, found = self._centroids.query(p, k=k)
        idx = np.asarray(found, dtype=np.intp).reshape(len(p), k)
        bound, _, _ = self._nearest(p, np.repeat(np.arange(len(p)), k), idx.reshape(-1))
        # The nearest triangle's centroid lies within its distance plus its radius: in each
        # size class, the ball of the bound plus the class's largest radius holds it.
        owners, which = [], []
        for ids, tree, reach in self._classes:
            balls = tree.query_ball_point(p, np.abs(bound) + reach)
            counts = np.fromiter((len(b) for b in balls), dtype=np.intp, count=len(p))
            if counts.sum() == 0:
                continue
            owners.append(np.repeat(np.arange(len(p)), counts))
            which.append(ids[np.fromiter(itertools.chain.from_iterable(balls), dtype=np.intp)])
        return self._nearest(p, np.concatenate(owners), np.concatenate(which))

    def faces_within(
        self, point: NDArray[np.float64], radius: float
    ) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
        """The triangles within ``radius`` of ``point`` (the mesh's frame) and their
        distances from it."""
        p = np.asarray(point, dtype=float).reshape(3)
        ids = np.concatenate(
            [
                ids[np.asarray(tree.query_ball_point(p, radius + reach), dtype=np.intp)]
                for ids, tree, reach in self._classes
            ]
        )
        tri = self.triangles[ids]
        q, _ = closest_on_triangles(
            np.broadcast_to(p, (len(ids), 3)), tri[:, 0], tri[:, 1], tri[:, 2]
        )
        dist = np.linalg.norm(q - p, axis=1)
        keep = dist <= radius
        return ids[keep], dist[keep]

    def _nearest(
        self, p: NDArray[np.float64], owner: NDArray[np.intp], which: NDArray[np.intp]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
        """The signed distance of each of ``p`` to the nearest of its candidate triangles
        ``which[owner == i]``, the unit pseudonormal there and that triangle."""
        tri = self.triangles[which]
        q, kind = closest_on_triangles(p[owner], tri[:, 0], tri[:, 1], tri[:, 2])
        offset = p[owner] - q
        dist = np.linalg.norm(offset, axis=1)
        pseudo = np.empty_like(q)
        face = kind == 0
        pseudo[face] = self.face_normals[which[face]]
        corner = (kind >= 1) & (kind <= 3)
        pseudo[corner] = self._vertex_normal[which[corner], kind[corner] - 1]
        edge = kind >= 4
        pseudo[edge] = self._edge_normal[which[edge], kind[edge] - 4]
        # Nearest per point: sort by (point, distance), take each point's first.
        order = np.lexsort((dist, owner))
        first = order[np.r_[True, owner[order][1:] != owner[order][:-1]]]
        side = np.einsum("ij,ij->i", offset[first], pseudo[first])
        unit = pseudo[first] / np.maximum(np.linalg.norm(pseudo[first], axis=1), 1e-300)[:, None]
        return np.where(side < 0, -dist[first], dist[first]), unit, which[first]


class CollisionPair:
    """The bolt (in its frame) and nut (in the fixed frame) as trees of oriented boxes.

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
        #: The nut mesh's least distance from its axis (F): the bore.
        self.nut_bore = float(_axis_distance(self.nut_vertices[self.nut_faces]).min())
        tri = self.bolt_vertices[self.bolt_faces]
        outer = np.hypot(tri[..., 0], tri[..., 1]).max(axis=1)
        height = tri[..., 2]
        sway = float(height.max() - height.min()) * np.sin(np.radians(CORE_TILT))
        #: The bolt's core (module docstring): its faces, and their largest distance from
        #: the bolt's axis and their lowest and highest points' heights (B).
        self._core_faces = outer < self.nut_bore - sway
        if self._core_faces.mean() < CORE_SHARE:
            self._core_faces[:] = False
        core = self._core_faces
        self._core = (
            float(outer[core].max(initial=0.0)),
            float(height[core].min(initial=0.0)),
            float(height[core].max(initial=0.0)),
        )
        self._bolt = self._without_core(np.ones(len(self.bolt_faces), dtype=bool))
        #: The bolt's tree asked at the last pose placed (:meth:`_place`), and the pose.
        self._placed = (self._bolt[0], self._bolt[1])
        self._pose = Pose(np.eye(3), np.zeros(3))
        centroid = self.nut_vertices[self.nut_faces].mean(axis=1)
        angle = np.arctan2(centroid[:, 1], centroid[:, 0])
        #: Sector (0 .. SECTORS-1, counter-clockwise from -pi) of each nut face.
        sector = np.floor((angle + np.pi) / TWO_PI * SECTORS).astype(np.intp)
        self.nut_sector = sector % SECTORS
        #: The sectors that hold faces, each its own tree of the nut's query (in order).
        self._sectors = [k for k in range(SECTORS) if np.any(self.nut_sector == k)]
        self._tree = {k: i for i, k in enumerate(self._sectors)}
        self._nut = CrossingQuery(
            obb_forest(
                self.nut_vertices,
                self.nut_faces,
                [np.flatnonzero(self.nut_sector == k) for k in self._sectors],
            )
        )
        #: The sectors in the order a yes/no query asks them: the last to collide first.
        self._order = list(self._sectors)
        #: The Z part of each nut face's outward normal (unnormalised; F): the nut does
        #: not move, so whether a face is turned down is known once.
        self.nut_upward = upward(self.nut_vertices[self.nut_faces])
        # The faces :meth:`pairs_under_material` asks, built on its first use.
        self._under_material: tuple[_Bolt, CrossingQuery] | None = None
        #: Collision queries spent since construction (or the last reset).
        self.queries = 0
        # Bounding radius of the bolt about its origin: bounds the motion of any bolt point.
        self.bolt_radius = float(np.linalg.norm(self.bolt_vertices, axis=1).max())
        # The lowest point of the bolt at any attitude is a vertex of its convex hull: a
        # tenth of the vertices, asked at every lowering.
        hull = ConvexHull(self.bolt_vertices).vertices
        self._bolt_hull = np.ascontiguousarray(self.bolt_vertices[np.unique(hull)])
        self._solids: dict[str, MeshSolid] = {}
        # The nut's bore by height (:meth:`free_fall`), made on first use.
        self._bore: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None

    def solid(self, body: str) -> MeshSolid:
        """The ``body`` mesh (``"bolt"``, in the bolt's frame, or ``"nut"``, in the fixed
        frame) as a :class:`MeshSolid`, built on first use."""
        solid = self._solids.get(body)
        if solid is None:
            if body == "bolt":
                solid = MeshSolid(self.bolt_vertices, self.bolt_faces)
            else:
                solid = MeshSolid(self.nut_vertices, self.nut_faces)
            self._solids[body] = solid
        return solid

    def signed_distance(self, body: str, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Signed distance (negative inside) of ``points`` from the ``body`` mesh, measured
        on the mesh itself (see :meth:`solid` for the frames)."""
        return self.solid(body).signed_distance(points)

    def _without_core(self, faces: NDArray[np.bool_]) -> _Bolt:
        """The bolt's ``faces`` as a tree, and without the core's (None where the core
        holds none of them)."""
        rim = faces & ~self._core_faces
        groups = [np.flatnonzero(faces)]
        if rim.sum() < faces.sum():
            groups.append(np.flatnonzero(rim))
        forest = obb_forest(self.bolt_vertices, self.bolt_faces, groups)
        return forest, 0, (1 if len(groups) == 2 else None)

    def _core_clear(self, pose: Pose) -> bool:
        """Whether every point of the bolt's core at ``pose`` lies nearer the Z axis than
        the nut's bore: a point at radius r from the bolt's axis, at height h, lies within
        r of the axis's point at h (a rotation moves no vector's XY part farther), and the
        axis's points between two heights lie within the farther of the two ends'."""
        radius, low, high = self._core
        # In plain floats (asked at every query; numpy's per-call cost is most of it).
        s0, s1 = float(pose.rotation[0, 2]), float(pose.rotation[1, 2])
        f0, f1 = float(pose.origin[0]), float(pose.origin[1])
        reach = max(
            math.hypot(f0 + low * s0, f1 + low * s1), math.hypot(f0 + high * s0, f1 + high * s1)
        )
        return reach + radius < self.nut_bore * (1 - 1e-9)

    def _placed_at(self, bolt: _Bolt, pose: Pose) -> tuple[ObbForest, int]:
        """``bolt`` (:meth:`_without_core`) at ``pose``: its tree without the core where
        that cannot reach the nut."""
        forest, whole, rim = bolt
        return forest, (rim if rim is not None and self._core_clear(pose) else whole)

    def _place(self, pose: Pose) -> None:
        self._placed = self._placed_at(self._bolt, pose)
        self._pose = pose

    def _ask(self, sectors: list[int], mode: int) -> NDArray[np.int64]:
        """The crossing pairs of the bolt as placed and the nut's ``sectors`` (in that
        order; :class:`._obb.CrossingQuery`): ``(bolt face, nut face, sector)`` rows."""
        forest, tree = self._placed
        found = self._nut(
            forest,
            tree,
            np.array([self._tree[k] for k in sectors], dtype=np.int64),
            self._pose.rotation,
            self._pose.origin,
            mode,
        )
        found[:, 2] = np.asarray(sectors, dtype=np.int64)[found[:, 2]]
        return found

    def collides(self, pose: Pose) -> bool:
        """Whether the bolt at ``pose`` intersects the nut (one query)."""
        self._place(pose)
        self.queries += 1
        hit = self._ask(self._order, ANY)
        if len(hit):
            order = self._order
            order.insert(0, order.pop(order.index(int(hit[0, 2]))))
        return len(hit) > 0

    def collides_outside(self, pose: Pose, excluded: frozenset[int]) -> bool:
        """Whether the bolt at ``pose`` intersects the nut outside the ``excluded`` sectors
        (one query)."""
        if not excluded:
            return self.collides(pose)
        self._place(pose)
        self.queries += 1
        return len(self._ask([k for k in self._sectors if k not in excluded], ANY)) > 0

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
        keys = self._sectors if among is None else sorted(among & set(self._sectors))
        hit = self._ask([k for k in keys if k not in excluded], EACH)
        return frozenset(hit[:, 2].tolist())

    def sectors_near(
        self, points: NDArray[np.float64], reach: float, min_radius: float
    ) -> frozenset[int]:
        """Sectors within arc length ``reach`` of any of ``points`` (F), measured at each
        point's radius (not below ``min_radius``)."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        width = TWO_PI / SECTORS
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
        found = set(self.nut_sector[pairs[:, 1]].tolist())
        return frozenset((k + step) % SECTORS for k in found for step in (-1, 0, 1))

    def pairs(self, pose: Pose, sectors: frozenset[int] | None = None) -> NDArray[np.int64]:
        """Intersecting ``(bolt_face, nut_face)`` index pairs at ``pose``, over the whole
        nut or only its ``sectors`` (one query)."""
        self._place(pose)
        self.queries += 1
        asked = self._sectors if sectors is None else [k for k in self._sectors if k in sectors]
        return unique_face_pairs(self._ask(asked, ALL))

    def pairs_below(self, pose: Pose, above: Pose, free: bool = False) -> Sweep | None:
        """None where the bolt at ``above`` (the same rotation as ``pose``) intersects the
        nut (:meth:`collides`; not asked where it is known ``free``); else the
        intersecting pairs at ``pose`` (:meth:`pairs`), as the :class:`Sweep` that also
        answers between the two. Two queries (one where ``above`` intersects, one where it
        is known free) asked in one walk of the trees."""
        self._place(pose)
        forest, tree = self._placed
        if tree != self._placed_at(self._bolt, above)[1]:
            tree = self._bolt[1]  # the whole bolt: its core can reach the nut at one pose
        order = self._order
        hit, found, nodes = self._nut.below(
            forest,
            tree,
            np.array([self._tree[k] for k in order], dtype=np.int64),
            pose.rotation,
            pose.origin,
            above.origin,
            free,
        )
        self.queries += 0 if free else 1
        if hit:
            order.insert(0, order.pop(int(found[0, 2])))
            return None
        self.queries += 1
        nodes[:, 2] = np.asarray(order, dtype=np.int64)[nodes[:, 2]]
        return Sweep(self, (forest, tree), pose, above, unique_face_pairs(found), nodes)

    def pairs_under_material(self, pose: Pose) -> NDArray[np.int64]:
        """Intersecting ``(bolt_face, nut_face)`` index pairs at ``pose`` of a nut face
        turned down and a bolt face that can face up at the bolt's tilt (one query): every
        pair :meth:`pairs` finds of a bolt face turned up and a nut face turned down, and
        some more (bolt faces turned a little down). Tilted beyond :data:`UNDER_TILT`,
        all pairs (:meth:`pairs`).

        The nut's material over the bolt is looked for at every lowering in the thread,
        and mostly not found: the flanks below, close to the nut all round, are what
        a query spends its time proving apart, and they are not asked.
        """
        if pose.rotation[2, 2] < np.cos(np.radians(UNDER_TILT)):
            return self.pairs(pose)
        if self._under_material is None:
            # The faces that can meet from either side of the nut's material over the
            # bolt: the nut's turned down, and the bolt's whose normal lies within
            # UNDER_TILT of horizontal or above it (in the bolt's frame), the only ones
            # that can face up while the bolt's axis is tilted by no more than that. The
            # threads' flanks that carry the bolt, close to the nut all round, are in
            # neither.
            tri = self.bolt_vertices[self.bolt_faces]
            cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
            steep = np.sin(np.radians(UNDER_TILT + 1.0)) * np.linalg.norm(cross, axis=1)
            down = np.flatnonzero(self.nut_upward < 0)
            self._under_material = (
                self._without_core(cross[:, 2] >= -steep),
                CrossingQuery(obb_forest(self.nut_vertices, self.nut_faces, [down])),
            )
        bolt, nut = self._under_material
        forest, tree = self._placed_at(bolt, pose)
        self.queries += 1
        found = nut(forest, tree, np.zeros(1, dtype=np.int64), pose.rotation, pose.origin, ALL)
        return unique_face_pairs(found)

    def triangles(
        self, pose: Pose, pairs: NDArray[np.int64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Vertices (fixed frame) of the paired bolt and nut triangles, each ``(n, 3, 3)``."""
        return paired_triangles(
            self.bolt_vertices,
            self.bolt_faces,
            self.nut_vertices,
            self.nut_faces,
            pairs,
            pose.rotation,
            pose.origin,
        )

    def _bore_by_height(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The nut's bore from its top face down, in :data:`BORE_BINS` bands of height: the
        bands' edges (the last the nut's top), and the least distance from the axis of the
        nut's surface at the lower edge of each band or anywhere above, rising with height
        (a nut point lies no nearer the axis: going in from it, one meets the surface at
        its height no farther out). The surface's points counted: its vertices and where
        its triangles' edges cross the bands' edges (a triangle's points nearer the axis
        between lie within the meshes' chord deviation of those)."""
        if self._bore is None:
            a = self.nut_vertices[self.nut_faces]
            b = np.roll(a, -1, axis=1).reshape(-1, 3)
            a = a.reshape(-1, 3)
            edges = np.linspace(a[:, 2].min(), a[:, 2].max(), BORE_BINS + 1)
            spacing = edges[1] - edges[0]
            low, high = np.minimum(a[:, 2], b[:, 2]), np.maximum(a[:, 2], b[:, 2])
            # Each triangle's edges where they cross the bands' edges.
            first = np.ceil((low - edges[0]) / spacing).astype(np.int64)
            last = np.floor((high - edges[0]) / spacing).astype(np.int64)
            count = np.where(high > low, np.maximum(last - first + 1, 0), 0)
            edge = np.repeat(np.arange(len(a)), count)
            k = first[edge] + np.arange(len(edge)) - np.repeat(np.cumsum(count) - count, count)
            t = (edges[k] - a[edge, 2]) / (b[edge, 2] - a[edge, 2])
            cut = a[edge, :2] + t[:, None] * (b[edge, :2] - a[edge, :2])
            # Each point counts for the band it lies in and every band below (a cut on a
            # band's lower edge lies in that band).
            band = np.concatenate([k, np.floor((a[:, 2] - edges[0]) / spacing).astype(np.int64)])
            reach = np.concatenate([np.hypot(cut[:, 0], cut[:, 1]), np.hypot(a[:, 0], a[:, 1])])
            band = np.clip(band, 0, BORE_BINS - 1)
            order = np.argsort(band, kind="stable")
            starts = np.searchsorted(band[order], np.arange(BORE_BINS))
            least = np.full(BORE_BINS, np.inf)
            held = starts < len(order)
            least[held] = np.minimum.reduceat(reach[order], starts[held])
            # (An empty band takes the first point of the next band that holds one: the
            # running minimum from the top counts that point there anyway.)
            self._bore = (edges, np.minimum.accumulate(least[::-1])[::-1].copy())
        return self._bore

    def free_fall(self, pose: Pose) -> float:
        """How far the bolt at ``pose`` (its lowest point above the nut's top face) can be
        lowered with every vertex of its convex hull within the nut's bore, as near the axis
        as no nut face at any height it passes (:meth:`_bore_by_height`); 0 where none.

        A guess, from the hull's vertices alone: a lowering asks one walk of the trees
        whether the bolt meets anything on the way (:meth:`pairs_below`)."""
        edges, bore = self._bore_by_height()
        points = self._bolt_hull @ pose.rotation.T + pose.origin
        radius = np.hypot(points[:, 0], points[:, 1])
        # The lowest band from which up the bore is wider than each point's radius (none:
        # the point stops at the nut's top).
        band = np.searchsorted(bore, radius, side="right")
        return max(float((points[:, 2] - edges[band]).min()), 0.0)

    def lowest_bolt_z(self, rotation: NDArray[np.float64]) -> float:
        """Lowest bolt vertex height (fixed frame) for a bolt at the origin turned by
        ``rotation``."""
        return float((self._bolt_hull @ rotation[2]).min())
