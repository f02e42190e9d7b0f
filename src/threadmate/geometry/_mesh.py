"""Watertight triangle meshes of the exact bolt and nut, within a chord tolerance.

The lateral thread surface is the helical sweep of the profile. It is tessellated on a
grid of *meridians* (half-planes through the axis, at angles ``theta_j``) crossed with the
profile's *stations* (``t`` values whose polyline is within the chord of the profile:
the corners of the flats and flanks and the points that split each fillet arc). On a
meridian the stations sit at heights ``z = t_i + k p + s_j``, ``s_j = hand lead theta_j /
(2 pi)``; the coordinate ``tau = z - s_j`` (the unwrapped profile coordinate) labels the
helix each vertex lies on. Neighbouring meridians are stitched by a zipper that merges
their vertices in ``tau`` order, so every lateral triangle runs along the helices (whose
radius is constant) and the error is only the circumferential sagitta plus the twist of
the helicoid between two meridians.

A mesh is planned (:mod:`._mesh_plan`: stations, meridian grid, inserted meridians; bolt
and nut never on the same meridian planes), trimmed where the body has a point or a
countersink (:mod:`._mesh_trim`: the ridge where thread and envelope meet), stitched
(:mod:`._mesh_stitch`: strips, caps, one watertight mesh), and its deviation from the
exact surface measured (:func:`mesh_deviation`); a mesh past the chord is rebuilt on more
meridians.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import NDArray

from .._errors import InputError
from ._body import ThreadBody, bolt_body, nut_body
from ._chord import check_chord
from ._mesh_plan import (
    BOLT_GRID,
    NUT_GRID,
    MeridianGrid,
    crossing_angles,
    plan_grid,
    prime,
    profile_stations,
    shares,
)
from ._mesh_stitch import assemble
from ._mesh_trim import trim_plan
from ._spec import ThreadSpec

__all__ = [
    "TessellatedBody",
    "bolt_mesh",
    "nut_mesh",
    "thread_meshes",
    "mesh_deviation",
]

# Rebuilds on more meridians before a mesh past the chord is refused.
_MAX_REFINEMENTS = 6


@dataclass(frozen=True)
class TessellatedBody:
    """A body's triangle mesh with the bound of its deviation from the exact surface.

    Attributes
    ----------
    mesh : trimesh.Trimesh
        Watertight, consistently wound, outward normals, float64 vertices in the body's
        own frame and the spec's units. Shared by the cache of :func:`thread_meshes`:
        copy it before changing it.
    body : ThreadBody
        The exact body it tessellates.
    chord : float
        The chord tolerance asked for.
    max_deviation : float
        Largest distance from the mesh to the exact surface found by
        :func:`mesh_deviation` (at most ``chord``).
    """

    mesh: trimesh.Trimesh
    body: ThreadBody
    chord: float
    max_deviation: float

    @property
    def triangles(self) -> int:
        """Number of triangles."""
        return int(len(self.mesh.faces))


# -- public API --------------------------------------------------------------------------
def bolt_mesh(spec: ThreadSpec, chord: float | None = None) -> TessellatedBody:
    """Tessellate the bolt of ``spec`` in its frame (``0 <= z <= bolt.length``).

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair.
    chord : float, optional
        Largest allowed distance from the mesh to the exact surface, in the spec's units
        (default :data:`DEFAULT_CHORD` for the units).

    Returns
    -------
    TessellatedBody
        The mesh and its verified deviation bound.
    """
    chord = check_chord(spec, chord)
    return _tessellate(bolt_body(spec), chord, BOLT_GRID)


def nut_mesh(spec: ThreadSpec, chord: float | None = None) -> TessellatedBody:
    """Tessellate the nut of ``spec`` in the fixed frame (``-nut.height <= z <= 0``).

    The threaded bore, the flat top face (``surface``) at z = 0, the bottom face and the
    outer cylinder at ``nut.outer_radius``. See :func:`bolt_mesh` for the parameters.
    """
    chord = check_chord(spec, chord)
    return _tessellate(nut_body(spec), chord, NUT_GRID)


def thread_meshes(
    spec: ThreadSpec, chord: float | None = None
) -> tuple[TessellatedBody, TessellatedBody]:
    """``(bolt, nut)`` meshes of ``spec``, cached per ``(spec, chord)``.

    The contact, sweep and command-line stages call this repeatedly; the meshes are built
    once per process. Do not modify the returned meshes in place (copy them).
    """
    return _cached_pair(spec, check_chord(spec, chord))


def mesh_deviation(mesh: trimesh.Trimesh, body: ThreadBody) -> float:
    """Upper bound on the distance from ``mesh`` to the exact surface of ``body``.

    Samples every triangle at its vertices, edge midpoints, centroid and three more
    barycentric points and takes the largest :meth:`ThreadBody.surface_distance` (itself
    an upper bound on the true distance). Both in the body's frame.
    """
    v = np.asarray(mesh.vertices, dtype=float)
    f = np.asarray(mesh.faces, dtype=np.int64)
    if len(f) == 0:
        return float("inf")
    pairs = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    # Each edge once, by one integer key (numpy's unique of rows is far slower).
    edges = np.unique(pairs[:, 0] * len(v) + pairs[:, 1])
    worst = _max_distance(body, v)
    worst = max(worst, _max_distance(body, 0.5 * (v[edges // len(v)] + v[edges % len(v)])))
    tri = v[f]
    for w in _BARYCENTRIC:
        worst = max(worst, _max_distance(body, np.einsum("k,nkd->nd", w, tri)))
    return worst


# -- internals ---------------------------------------------------------------------------
_BARYCENTRIC = np.array(
    [
        [1 / 3, 1 / 3, 1 / 3],
        [2 / 3, 1 / 6, 1 / 6],
        [1 / 6, 2 / 3, 1 / 6],
        [1 / 6, 1 / 6, 2 / 3],
    ]
)


@functools.lru_cache(maxsize=16)
def _cached_pair(spec: ThreadSpec, chord: float) -> tuple[TessellatedBody, TessellatedBody]:
    return bolt_mesh(spec, chord), nut_mesh(spec, chord)


def _max_distance(body: ThreadBody, points: NDArray[np.float64], chunk: int = 200_000) -> float:
    worst = 0.0
    for start in range(0, len(points), chunk):
        p = points[start : start + chunk]
        # surface_distance measures the end faces and the outer cylinder only from points
        # within the body's extent; a point a hair outside (float32 STL rounding) is first
        # moved onto the extent, and the move added (triangle inequality).
        q = p.copy()
        q[:, 2] = np.clip(q[:, 2], body.z_min, body.z_max)
        if body.outer_radius is not None:
            r = np.hypot(q[:, 0], q[:, 1])
            scale = np.where(r > body.outer_radius, body.outer_radius / np.maximum(r, 1e-300), 1.0)
            q[:, :2] *= scale[:, None]
        moved = np.linalg.norm(p - q, axis=1)
        worst = max(worst, float(np.max(moved + body.surface_distance(q))))
    return worst


def _tessellate(body: ThreadBody, chord: float, grid: MeridianGrid) -> TessellatedBody:
    """Plan, trim and stitch ``body``'s mesh; rebuild it on more meridians while its
    measured deviation exceeds ``chord``."""
    count, pieces = plan_grid(body, chord)
    stations = profile_stations(body.profile, chord, pieces)
    trim = trim_plan(body, stations, shares(body)[1] * chord)
    crossings = crossing_angles(body, stations, trim)
    count = prime(count, grid.residue)
    for _ in range(_MAX_REFINEMENTS):
        mesh = assemble(body, stations, crossings, count, grid.turn, chord, trim)
        deviation = mesh_deviation(mesh, body)
        if deviation <= chord:
            return TessellatedBody(mesh, body, chord, deviation)
        # The twist term falls linearly with the meridian spacing, the sagitta as its
        # square: scaling the count by the excess covers both.
        count = prime(math.ceil(count * deviation / chord * 1.02), grid.residue)
    raise InputError(
        f"could not tessellate the {body.kind} within a chord of {chord:g} "
        f"(reached {deviation:.3g}); give a larger chord"
    )
