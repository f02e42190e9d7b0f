"""Meshes from CAD: their files (name, SHA-256, units) and how closely they follow the spec.

A CAD part is more than the spec describes: a bolt has a head and perhaps a shank, a nut
has hex flats, either may have a chamfer or a countersink the spec does not state. Those
faces lie far from the spec's exact surfaces, and measuring the mesh's deviation over the
whole mesh (:func:`threadmate.geometry.mesh_deviation`) would take their distance for
the mesh's error and blow every tolerance of the contact stages up.

The rule (:func:`mesh_fit`):

1. Each triangle's deviation is the largest distance from the exact surface over ten
   points of it (vertices, edge midpoints, centroid and three more barycentric points,
   as :func:`~threadmate.geometry.mesh_deviation` samples).
2. Only the *contact zone* can touch the other body: the triangles whose vertices all lie
   within the spec's body (bolt: ``0 <= z <= length``, ``r <= major/2``; nut:
   ``-height <= z <= 0``, ``minor/2 <= r <= major/2 + pitch/2`` or the countersink's
   radius if larger: the bore and the ring of the top face where a tilted bolt's tip
   lands), with a slack of :data:`COARSEST` pitches. A head, a bolt beyond the spec's
   length, the nut's flats (across flats is 1.5 to 1.8 diameters) and bottom lie outside.
3. In the zone, a triangle *follows* the spec when its deviation is at most
   ``FOLLOW_FACTOR x`` the zone's typical deviation, the 75th percentile of the deviations
   of the zone triangles within :data:`COARSEST` pitches of the exact surface (no coarser
   than the coarsest chord threadmate meshes a thread with). The mesh's deviation is the
   largest deviation of the triangles that follow.

Why not the whole zone's maximum, nor its 99th percentile: an unstated chamfer (or a
thread run-out) is *inside* the zone and may cover half of it (a bolt one pitch above its
point), so any quantile of the zone can land on it. Its distance from the spec grows
continuously from zero where it meets the thread, so there is no gap to cut at either;
what separates it is scale: triangles that follow a surface all err by the same order (a
chord, set by the tessellation, so the largest of them stays within a small multiple of
the 75th percentile), while the chamfer's triangles spread from zero to the chamfer's
depth. The 75th percentile of the triangles near the spec is a triangle that follows it
as long as three quarters of those do; three times it keeps every following triangle (so
a generated mesh written to a file measures its own deviation) and cuts the chamfer at
about three chords, so that a chamfered bolt, a countersunk nut, a bolt flaring into a
head or a hex nut read against a flat spec measure a few chords, not the depth of the
end (tests/test_cli_user_meshes.py checks a chamfered bolt).

Contacts farther than :attr:`ContactScene.off_spec_tolerance
<threadmate.contact.ContactScene>` from the exact surface are labelled by where they
lie (``point``, ``countersink``, ``other``; :func:`~._exact.off_spec_region`); the share
of the mesh's area, and of its contact zone's, that lies farther than that is reported.

The mechanics take such a mesh as given (:func:`off_spec`): where it does not follow the
spec, a contact's normal is the mesh's own (its face's, or across an edge where its faces
meet at more than :data:`~._exact.CREASE` degrees, the edge's), and whether a point lies
inside it is asked of the mesh (:class:`~._collision.MeshSolid`), not of the spec's
exact body, which has material where an unstated chamfer or countersink has none.
"""

from __future__ import annotations

import hashlib
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import trimesh
from numpy.typing import NDArray

from ..._errors import MeshError
from ..._units import MM_PER_UNIT, unit_scale
from ...geometry import ThreadBody, ThreadSpec, stl_units
from ._exact import CREASE, OffSpec

if TYPE_CHECKING:
    from ._scene import ContactScene

__all__ = [
    "COARSEST",
    "FOLLOW_FACTOR",
    "OFF_SPEC_WARNING",
    "MeshFit",
    "contact_zone",
    "describe",
    "face_deviation",
    "file_units",
    "mesh_fit",
    "off_spec",
    "sha256_of",
]

#: Coarsest chord threadmate meshes a thread with, in pitches (``check_chord``): a
#: triangle farther than this from the exact surface no longer follows the thread.
COARSEST = 0.02
#: A triangle follows the spec when its deviation is at most this times the zone's
#: 75th percentile (see the module docstring).
FOLLOW_FACTOR = 3.0
#: Share of a mesh's contact zone (by area) off the spec above which the user is warned.
OFF_SPEC_WARNING = 0.1

# Barycentric sample points of a triangle: vertices, edge midpoints, centroid, three more.
_SAMPLES = np.array(
    [
        [1, 0, 0],
        [0, 1, 0],
        [0, 0, 1],
        [0.5, 0.5, 0],
        [0, 0.5, 0.5],
        [0.5, 0, 0.5],
        [1 / 3, 1 / 3, 1 / 3],
        [2 / 3, 1 / 6, 1 / 6],
        [1 / 6, 2 / 3, 1 / 6],
        [1 / 6, 1 / 6, 2 / 3],
    ]
)


def sha256_of(path: str | os.PathLike[str]) -> str:
    """The SHA-256 of a file's bytes (hex)."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def file_units(path: str | os.PathLike[str], units: str | None, spec: ThreadSpec) -> str:
    """The length units a mesh file is in: ``units`` if given, else those a threadmate STL
    declares in its header, else the spec's. A header that declares other units than
    ``units`` is refused (:class:`MeshError`): one of the two is wrong."""
    header = stl_units(path) if Path(path).suffix.lower() == ".stl" else None
    if units is None:
        return header or spec.units
    if units not in MM_PER_UNIT:
        raise MeshError(f"mesh units must be 'in' or 'mm', got {units!r}")
    if header is not None and header != units:
        raise MeshError(
            f"{Path(path).name}: its STL header declares units={header} but the mesh "
            f"units given are {units}; give the units the file is in"
        )
    return units


@dataclass(frozen=True)
class MeshFit:
    """How a mesh follows the spec's exact body (see the module docstring).

    Attributes
    ----------
    deviation : float
        Largest deviation of the contact zone's triangles that follow the spec.
    face_deviation : ndarray
        Each triangle's deviation (upper bound, sampled).
    area : ndarray
        Each triangle's area.
    zone : ndarray of bool
        The triangles in the contact zone.
    """

    deviation: float
    face_deviation: NDArray[np.float64]
    area: NDArray[np.float64]
    zone: NDArray[np.bool_]

    def off_spec_share(self, tolerance: float) -> tuple[float, float]:
        """Shares of the mesh's area, and of its contact zone's, farther than
        ``tolerance`` from the exact surface."""
        off = self.face_deviation > tolerance
        total = float(self.area.sum())
        zone = float(self.area[self.zone].sum())
        mesh_share = float(self.area[off].sum()) / total if total > 0 else 0.0
        zone_share = float(self.area[off & self.zone].sum()) / zone if zone > 0 else 0.0
        return mesh_share, zone_share


def _distances(body: ThreadBody, points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Upper bounds on the distance of points (body frame) from the exact surface; points
    a hair outside the body's extent (float32 rounding, a part longer than the spec) are
    first moved onto it and the move added (triangle inequality)."""
    q = points.copy()
    q[:, 2] = np.clip(q[:, 2], body.z_min, body.z_max)
    if body.outer_radius is not None:
        r = np.hypot(q[:, 0], q[:, 1])
        scale = np.where(r > body.outer_radius, body.outer_radius / np.maximum(r, 1e-300), 1.0)
        q[:, :2] *= scale[:, None]
    return np.linalg.norm(points - q, axis=1) + body.surface_distance(q)


def face_deviation(
    mesh: trimesh.Trimesh | NDArray[np.float64], body: ThreadBody, chunk: int = 100_000
) -> NDArray[np.float64]:
    """Each triangle's largest sampled distance from the exact surface of ``body``
    (``mesh``: a mesh, or its triangles as an ``(n, 3, 3)`` array)."""
    if isinstance(mesh, trimesh.Trimesh):
        tri = np.asarray(mesh.vertices, dtype=float)[np.asarray(mesh.faces, dtype=np.int64)]
    else:
        tri = np.asarray(mesh, dtype=float).reshape(-1, 3, 3)
    out = np.empty(len(tri))
    for start in range(0, len(tri), chunk):
        t = tri[start : start + chunk]
        pts = np.einsum("sk,nkd->snd", _SAMPLES, t).reshape(-1, 3)
        out[start : start + chunk] = _distances(body, pts).reshape(len(_SAMPLES), -1).max(0)
    return out


def contact_zone(mesh: trimesh.Trimesh, body: ThreadBody, spec: ThreadSpec) -> NDArray[np.bool_]:
    """The triangles whose vertices all lie in the body's contact zone (module docstring)."""
    v = np.asarray(mesh.vertices, dtype=float)
    r = np.hypot(v[:, 0], v[:, 1])
    z = v[:, 2]
    slack = COARSEST * spec.pitch
    inside = (z >= body.z_min - slack) & (z <= body.z_max + slack)
    if body.kind == "bolt":
        inside &= r <= spec.bolt.major / 2 + slack
    else:
        sink = spec.nut.countersink
        outer = (
            max(spec.nut.major + spec.pitch, (sink.diameter or 0.0) if sink else 0.0) / 2 + slack
        )
        inside &= (r >= spec.nut.minor / 2 - slack) & (r <= outer)
    return np.asarray(inside[np.asarray(mesh.faces, dtype=np.int64)].all(axis=1))


def mesh_fit(
    mesh: trimesh.Trimesh, body: ThreadBody, spec: ThreadSpec, name: str = "mesh"
) -> MeshFit:
    """How ``mesh`` follows the exact ``body`` of ``spec`` (see the module docstring).

    Raises
    ------
    MeshError
        No triangle of the mesh's contact zone lies within :data:`COARSEST` pitches of the
        exact surface: the mesh is not of this spec's thread (or is far too coarse).
    """
    dev = face_deviation(mesh, body)
    zone = contact_zone(mesh, body, spec)
    near = dev[zone & (dev <= COARSEST * spec.pitch)]
    if len(near) == 0:
        raise MeshError(
            f"{name} does not follow the spec's thread anywhere: no triangle where it can "
            f"touch the other body lies within {COARSEST * spec.pitch:.3g} {spec.units} "
            "of the exact surface (another thread, or exported too coarsely)"
        )
    cutoff = FOLLOW_FACTOR * float(np.quantile(near, 0.75))
    deviation = float(near[near <= cutoff].max())
    return MeshFit(deviation, dev, np.asarray(mesh.area_faces, dtype=float), zone)


# Distances (relative to the point's size) within which triangles are equally near.
_TIE = 1e-12


def off_spec(scene: ContactScene) -> OffSpec | None:
    """Where the scene's CAD meshes do not follow the spec: their own surfaces there
    (:class:`._exact.OffSpec`), None without CAD meshes.

    A triangle follows the spec when its deviation (:func:`face_deviation`, found when
    first asked) is at most its mesh's (:func:`mesh_fit`). A point lies where the mesh
    follows the spec when every triangle within the feature tolerance of its nearest
    one's distance does: on the edge where an unstated countersink meets the thread's
    crest, the crest's triangle is nearest as often as the countersink's.
    """
    tolerance = scene.off_spec_tolerance
    info = scene.mesh_info
    kinds = frozenset(k for k in ("bolt", "nut") if not info[k].get("generated"))
    if tolerance is None or not kinds:
        return None
    engine = scene.engine
    bodies = {"bolt": scene.bolt, "nut": scene.nut}
    reach = scene.feature_tolerance
    # The fit's own cut (float rounding aside): a following triangle's deviation is at most
    # the mesh's, which is the largest of them.
    limit = {k: float(info[k]["deviation"]) * (1 + 1e-9) for k in kinds}
    known: dict[str, dict[int, bool]] = {k: {} for k in kinds}

    def follows(kind: str, faces: NDArray[np.intp]) -> bool:
        seen = known[kind]
        new = [f for f in faces.tolist() if f not in seen]
        if new:
            tri = engine.solid(kind).triangles[np.asarray(new, dtype=np.intp)]
            for f, d in zip(new, face_deviation(tri, bodies[kind]).tolist(), strict=True):
                seen[f] = d <= limit[kind]
        return all(seen[f] for f in faces.tolist())

    def surface(
        kind: str, point: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None, bool]:
        solid = engine.solid(kind)
        p = np.asarray(point, dtype=float).reshape(3)
        # A contact point lies on the mesh: the faces within the tolerance hold the nearest.
        around, dist = solid.faces_within(p, reach)
        if len(around) == 0:
            distance, _, _ = solid.nearest(p.reshape(1, 3))
            around, dist = solid.faces_within(p, abs(float(distance[0])) + reach)
        near = dist <= float(dist.min()) + reach
        around, dist = around[near], dist[near]
        edge = _crease(solid.faces[around], solid.face_normals[around], solid.vertices, p)
        if edge is None:
            # One smooth surface: the normal of the face nearest, or at a tie (the point on
            # an edge or a vertex, as contact points often are) the ties' summed.
            tie = float(dist.min()) + _TIE * max(float(np.linalg.norm(p)), 1.0)
            summed = solid.face_normals[around[dist <= tie]].sum(axis=0)
            normal = summed / max(float(np.linalg.norm(summed)), 1e-300)
            return normal, None, follows(kind, around)
        tangent, summed = edge
        return summed, tangent, follows(kind, around)

    return OffSpec(tolerance, kinds, surface, engine.signed_distance)


def _crease(
    faces: NDArray[np.int64],
    normals: NDArray[np.float64],
    vertices: NDArray[np.float64],
    point: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """The mesh edge nearest ``point`` among those two of ``faces`` share at more than
    :data:`._exact.CREASE` degrees: its unit direction and the unit sum of the two faces'
    normals; None when the faces meet at no such edge (they tessellate one surface)."""
    if len(faces) < 2:
        return None
    edges = np.sort(faces[:, [[0, 1], [1, 2], [2, 0]]], axis=2).reshape(-1, 2)
    owner = np.repeat(np.arange(len(faces)), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    edges, owner = edges[order], owner[order]
    same = np.flatnonzero((edges[1:] == edges[:-1]).all(axis=1))
    if len(same) == 0:
        return None
    f1, f2 = owner[same], owner[same + 1]
    cos = np.einsum("ij,ij->i", normals[f1], normals[f2])
    sharp = cos < math.cos(math.radians(CREASE))
    if not sharp.any():
        return None
    pairs, f1, f2 = edges[same][sharp], f1[sharp], f2[sharp]
    a, b = vertices[pairs[:, 0]], vertices[pairs[:, 1]]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
    k = int(np.argmin(np.linalg.norm(a + t[:, None] * ab - point, axis=1)))
    tangent = ab[k] / float(np.linalg.norm(ab[k]))
    summed = normals[f1[k]] + normals[f2[k]]
    return tangent, summed / max(float(np.linalg.norm(summed)), 1e-300)


def describe(path: str | os.PathLike[str] | None, units: str, spec: ThreadSpec) -> dict[str, Any]:
    """The file part of a mesh's description: name, SHA-256, units and scale into the
    spec's units (None for a mesh given as an object)."""
    return {
        "file": None if path is None else Path(path).name,
        "path": None if path is None else str(path),
        "sha256": None if path is None else sha256_of(path),
        "units": units,
        "scale": unit_scale(units, spec.units),
    }
