"""Meshes for display: the bolt and nut decimated, the contact zone kept at full detail.

A page draws the meshes the contact stage queries (:func:`threadmate.geometry.thread_meshes`),
which hold tens of thousands of triangles each. Away from the contacts they are thinned by
vertex clustering: the vertices in one cube of side ``cell`` are merged into their mean and
the triangles that collapse are dropped, so the surface stays connected. Within ``zone`` of
a contact point (in the body's own frame) every vertex is kept as it is.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from ..geometry import ThreadSpec, thread_meshes

__all__ = ["DisplayMesh", "decimate", "display_meshes"]

#: Side of the clustering cell away from the contacts, in pitches.
CELL_PITCHES = 1.0 / 14.0
#: Radius of the contact zone kept at full detail around each contact point, in pitches.
ZONE_PITCHES = 0.6


@dataclass(frozen=True)
class DisplayMesh:
    """A triangle mesh to draw.

    Attributes
    ----------
    vertices : (n, 3) array
        In the body's own frame (bolt: B; nut: F), the spec's units.
    faces : (m, 3) int array
        Vertex indices of each triangle.
    source_faces : int
        Triangles of the mesh it was thinned from.
    """

    vertices: NDArray[np.float64]
    faces: NDArray[np.int64]
    source_faces: int


def decimate(
    vertices: ArrayLike, faces: ArrayLike, cell: float, keep: ArrayLike | None = None
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Vertex clustering of a triangle mesh.

    Parameters
    ----------
    vertices : (n, 3) array
    faces : (m, 3) int array
    cell : float
        Side of the clustering cube (> 0), in the vertices' units.
    keep : (n,) bool array, optional
        Vertices kept as they are (each its own cluster).

    Returns
    -------
    (vertices, faces)
        The thinned mesh: each cluster's mean, the triangles whose three corners fall in
        three different clusters, each once.
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    if cell <= 0 or not np.isfinite(cell):
        raise ValueError(f"cell must be a positive length, got {cell!r}")
    kept = np.zeros(len(v), dtype=bool) if keep is None else np.asarray(keep, dtype=bool)
    key = np.floor(v / cell).astype(np.int64)
    # A kept vertex is a cluster of its own: its index in a fourth column (0 for the rest).
    own = np.where(kept, np.arange(1, len(v) + 1), 0)
    _, cluster = np.unique(np.column_stack([key, own]), axis=0, return_inverse=True)
    cluster = cluster.ravel()
    count = np.bincount(cluster).astype(float)
    out = np.column_stack([np.bincount(cluster, weights=v[:, i]) / count for i in range(3)])
    g = cluster[f]
    whole = (g[:, 0] != g[:, 1]) & (g[:, 1] != g[:, 2]) & (g[:, 0] != g[:, 2])
    g = g[whole]
    # The same triangle twice (two sheets merged): once. Sorted corners name it.
    _, first = np.unique(np.sort(g, axis=1), axis=0, return_index=True)
    g = g[np.sort(first)]
    used = np.unique(g)
    renumber = np.full(len(out), -1, dtype=np.int64)
    renumber[used] = np.arange(len(used))
    return out[used], renumber[g]


def _thinned(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    contacts: NDArray[np.float64],
    cell: float,
    zone: float,
) -> DisplayMesh:
    keep = np.zeros(len(vertices), dtype=bool)
    if len(contacts):
        distance, _ = cKDTree(contacts).query(vertices, k=1, distance_upper_bound=zone)
        keep = np.isfinite(distance)
    v, f = decimate(vertices, faces, cell, keep)
    return DisplayMesh(v, f, int(len(faces)))


def display_meshes(
    spec: ThreadSpec,
    contacts_nut: ArrayLike,
    contacts_bolt: ArrayLike,
    *,
    chord: float | None = None,
    cell: float | None = None,
    zone: float | None = None,
) -> tuple[DisplayMesh, DisplayMesh]:
    """``(bolt, nut)`` meshes of ``spec`` for display.

    Parameters
    ----------
    spec : ThreadSpec
    contacts_nut : (k, 3) array
        Contact points in F (the nut's frame): the nut is kept whole around them.
    contacts_bolt : (k, 3) array
        The same contacts in B (each through its state's pose): the bolt is kept whole
        around them.
    chord : float, optional
        The meshes' chord tolerance (spec units; default the spec's default).
    cell, zone : float, optional
        Clustering cell away from the contacts and the radius kept whole around them (spec
        units; default :data:`CELL_PITCHES` and :data:`ZONE_PITCHES` pitches).
    """
    cell = spec.pitch * CELL_PITCHES if cell is None else cell
    zone = spec.pitch * ZONE_PITCHES if zone is None else zone
    bolt, nut = thread_meshes(spec, chord)
    out = []
    for body, points in ((bolt, contacts_bolt), (nut, contacts_nut)):
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        mesh = body.mesh
        out.append(
            _thinned(
                np.asarray(mesh.vertices, dtype=float),
                np.asarray(mesh.faces, dtype=np.int64),
                pts,
                cell,
                zone,
            )
        )
    return out[0], out[1]
