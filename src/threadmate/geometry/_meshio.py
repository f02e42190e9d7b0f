"""Mesh files: binary STL out and in, and validated user meshes from CAD (STL, OBJ, PLY).

Binary STL follows the thesis's Figure 3.3: an 80-byte header, the facet count as a
little-endian uint32, then per facet 50 bytes: the unit normal and the three vertices as
twelve float32 and a uint16 attribute (unused, 0). STL carries no units; threadmate writes
the spec's units into the header (:func:`stl_header`: ``threadmate units=in bolt ...``),
where :func:`stl_units` and :func:`load_mesh` read them back.

A user mesh (a bolt or nut exported from CAD) is accepted only if its vertices are finite
numbers, it has at most ``threadmate._validate.MAX_FACES`` triangles unless told otherwise
(a warning above ``WARN_FACES``), it is one closed volume (every edge shared by exactly two
triangles, one shell, no void inside), consistently wound, of plausible size for the spec
where its thread is, and in its body's frame (conventions.md). Two repairs lose nothing and
are made with a warning (:class:`MeshWarning`) rather than refused:

- triangles of zero area (a repeated vertex, or three in a line) are dropped when the
  mesh is still closed without them;
- a closed, consistently wound mesh whose normals all point inward (negative volume) is
  turned inside out: the winding is a global convention of the exporter.

Anything else raises :class:`~threadmate._errors.MeshError` with one message naming the
problem and, where there is one, the count.

The size check reads the mesh where the spec's thread is: a bolt's largest radius over
the spec's bolt length from its tip (``0 <= z <= bolt.length``; a head or a flange above
it does not count), a nut's smallest over its height (the bore). Either must lie within
:data:`SIZE_BAND` of the spec's major (bolt) or minor (nut) radius.
"""

from __future__ import annotations

import os
import re
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np
import trimesh
from numpy.typing import NDArray

from .._errors import MeshError
from .._io import atomic_write_bytes
from .._units import MM_PER_UNIT, unit_scale
from .._validate import MAX_FACES, WARN_FACES, check_max_faces
from ._spec import filled

if TYPE_CHECKING:
    from ._spec import ThreadSpec

__all__ = [
    "write_stl",
    "read_stl",
    "load_mesh",
    "stl_header",
    "stl_units",
    "STL_FACET",
    "SIZE_BAND",
    "MeshWarning",
]

#: One binary-STL facet (the thesis's Figure 3.3): 50 bytes.
STL_FACET = np.dtype(
    [
        ("normal", "<f4", (3,)),
        ("vertices", "<f4", (3, 3)),
        ("attribute", "<u2"),
    ]
)

_FORMATS = {".stl": "stl", ".obj": "obj", ".ply": "ply"}
# A "units=WORD" word of an STL header (binary: the 80 bytes; ASCII: the "solid" line),
# as stl_header writes it.
_UNITS_RE = re.compile(rb"(?:^|\s)units=(\S*)", re.IGNORECASE)
# The words that name a length unit threadmate knows.
_UNIT_WORDS = {
    "in": "in",
    "inch": "in",
    "inches": "in",
    "mm": "mm",
    "millimeter": "mm",
    "millimeters": "mm",
    "millimetre": "mm",
    "millimetres": "mm",
}
#: A user mesh's radius where its thread is may differ from the spec's by tolerances and
#: modelling choices, not by a factor: outside this band (ratio to the spec's) its size is
#: implausible.
SIZE_BAND = (0.8, 1.25)
# Height over longest edge below which a triangle has no area (of the mesh's size).
_DEGENERATE = 1e-9
# Most triangles of three vertices in a line that are closed one by one (each a pass).
_MAX_SLIVERS = 1000


class MeshWarning(UserWarning):
    """A user mesh taken with a repair or a caution (dropped zero-area triangles, turned
    outward, very many triangles): the message says which."""


def write_stl(
    mesh: trimesh.Trimesh, path: str | os.PathLike[str], header: str = "threadmate"
) -> Path:
    """Write ``mesh`` as binary STL (Figure 3.3 layout), atomically.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The triangles to write; vertices are stored as float32.
    path : path-like
        Destination; appears whole or not at all.
    header : str
        Up to 80 ASCII characters (padded with spaces). It must not begin with
        ``solid``, which readers take as the mark of an ASCII STL.

    Returns
    -------
    Path
        ``path``.
    """
    return atomic_write_bytes(path, stl_bytes(mesh, header))


def stl_header(body: str, spec: ThreadSpec, chord: float | None = None) -> str:
    """The 80-character header threadmate writes into a body's binary STL.

    ``threadmate units=<in|mm> <body> <designation or "spec"> chord=<chord>``: the units
    come first so that a long designation can never push them past the 80 bytes, and
    CAD users (and :func:`stl_units`) can read them with any hex viewer.
    """
    label = spec.designation or "spec"
    tail = f" chord={chord:g}" if chord is not None else ""
    head = f"threadmate units={spec.units} {body} "
    room = 80 - len(head) - len(tail)
    if len(label) > room:
        label = label[: max(room - 3, 0)] + "..."
    return f"{head}{label}{tail}"[:80]


def stl_units(path: str | os.PathLike[str]) -> str | None:
    """The length units (``"in"`` or ``"mm"``) an STL file's header declares, or None.

    Reads a ``units=...`` word (as :func:`stl_header` writes it) in a binary STL's 80-byte
    header or on an ASCII STL's ``solid`` line; ``inch``, ``inches``, ``millimeter`` and
    the like are read as ``in`` and ``mm``. A file without the word declares none.

    Raises
    ------
    MeshError
        The header declares units threadmate does not know (``units=furlong``): the
        lengths cannot be read.
    """
    try:
        with open(path, "rb") as fh:
            head = fh.read(1024)
    except OSError:
        return None
    if head.lstrip().lower().startswith(b"solid"):
        line = head.lstrip().split(b"\n", 1)[0]  # ASCII STL: the "solid NAME" line
    else:
        line = head[:80]
    match = _UNITS_RE.search(line.rstrip(b" \0\r"))
    if match is None:
        return None
    word = match.group(1).decode("ascii", errors="replace")
    known = _UNIT_WORDS.get(word.lower())
    if known is None:
        raise MeshError(
            f"{Path(path).name}: its STL header declares units={word}, which threadmate "
            "does not know (it reads in or mm); convert the file, or correct its header"
        )
    return known


def stl_bytes(mesh: trimesh.Trimesh, header: str = "threadmate") -> bytes:
    """The binary STL bytes of ``mesh`` (see :func:`write_stl`)."""
    text = header.encode("ascii", errors="replace")[:80]
    if text.lower().startswith(b"solid"):
        text = (b"binary " + text)[:80]
    faces = np.asarray(mesh.faces, dtype=np.int64)
    records = np.zeros(len(faces), dtype=STL_FACET)
    records["normal"] = np.asarray(mesh.face_normals, dtype=float)
    records["vertices"] = np.asarray(mesh.vertices, dtype=float)[faces]
    return text.ljust(80, b" ") + np.uint32(len(faces)).astype("<u4").tobytes() + records.tobytes()


def read_stl(path: str | os.PathLike[str]) -> trimesh.Trimesh:
    """Read a binary or ASCII STL file into a mesh with shared (welded) vertices.

    Raises
    ------
    MeshError
        If the file does not exist or is not a readable STL.
    """
    return _read(Path(path), "stl")


def load_mesh(
    path: str | os.PathLike[str],
    body: Literal["bolt", "nut"],
    spec: ThreadSpec | None = None,
    units: str | None = None,
    max_faces: int | None = MAX_FACES,
) -> trimesh.Trimesh:
    """Load and validate a user mesh of a bolt or nut (STL, OBJ or PLY).

    Parameters
    ----------
    path : path-like
        The mesh file; the format follows the suffix.
    body : {"bolt", "nut"}
        Which body it is. A bolt must have its tip face at z = 0 and lie in z >= 0; a nut
        its top face at z = 0 and lie in z <= 0; both with the axis along Z.
    spec : ThreadSpec, optional
        The thread pair the mesh should model: its diameters check the mesh's size where
        the thread is (an inch spec with a mesh 25.4 times too large is refused as "looks
        like mm"; a head does not count).
    units : {"in", "mm"}, optional
        The file's length units when they differ from the spec's: the mesh is scaled
        into the spec's units. Default: the units an STL declares in its header
        (:func:`stl_units`), else the spec's.
    max_faces : int, optional
        Most triangles taken (default, and None: ``threadmate._validate.MAX_FACES``);
        above ``threadmate._validate.WARN_FACES`` (or ``max_faces``, if lower) a
        :class:`MeshWarning` says the contact stages will be slow.

    Returns
    -------
    trimesh.Trimesh
        The validated mesh (float64 vertices, outward normals) in the spec's units.

    Raises
    ------
    MeshError
        A missing or unreadable file, or a mesh with non-finite vertices, too many
        triangles, open, of more than one shell or with a void, inconsistently wound, of
        implausible size or out of its frame.

    Warns
    -----
    MeshWarning
        Zero-area triangles dropped, a mesh turned outward, very many triangles.
    """
    if body not in ("bolt", "nut"):
        raise MeshError(f"body must be 'bolt' or 'nut', got {body!r}")
    if units is not None and units not in MM_PER_UNIT:
        raise MeshError(f"units must be 'in' or 'mm', got {units!r}")
    max_faces = check_max_faces(max_faces)
    path = Path(path)
    kind = _FORMATS.get(path.suffix.lower())
    if kind is None:
        raise MeshError(
            f"{path}: unsupported mesh format {path.suffix!r} (give .stl, .obj or .ply)"
        )
    name = f"{body} mesh {path.name}"
    if kind == "stl" and path.is_file():
        _check_count(_stl_count(path), max_faces, name)
        if units is None:
            units = stl_units(path)
    mesh = _read(path, kind, name)
    _check_count(len(mesh.faces), max_faces, name)
    mesh = _drop_degenerate(mesh, name)
    _check_closed(mesh, name)
    if mesh.volume < 0:
        # Consistently wound but inside out: see the module docstring.
        in_units = units or (spec.units if spec is not None else None)
        volume = f", {mesh.volume:.4g} {in_units}^3" if in_units else ""
        mesh.invert()
        warnings.warn(
            f"{name}: its triangles are wound inward (negative volume{volume}); turned outward",
            MeshWarning,
            stacklevel=2,
        )
    if spec is not None:
        if units is not None and units != spec.units:
            mesh.apply_scale(unit_scale(units, spec.units))
        _check_size(mesh, body, spec, name)
    _check_frame(mesh, body, name)
    return mesh


# -- internals ---------------------------------------------------------------------------
def _read(path: Path, kind: str, name: str | None = None) -> trimesh.Trimesh:
    if not path.exists():
        raise MeshError(f"mesh file not found: {path}")
    if not path.is_file():
        raise MeshError(f"mesh path is not a file: {path}")
    data = path.read_bytes()
    if kind == "stl" and not _looks_like_stl(data):
        raise MeshError(
            f"{path}: not an STL file (neither binary STL of consistent size nor ASCII STL)"
        )
    if kind == "obj":
        try:
            data.decode("utf-8")
        except UnicodeDecodeError:
            raise MeshError(f"{path}: not an OBJ file (OBJ is text; this is binary)") from None
    try:
        # Unprocessed: trimesh's processing drops non-finite vertices (and so opens the
        # mesh) before they can be counted.
        loaded = trimesh.load(path, file_type=kind, force="mesh", process=False)
    except Exception as exc:  # trimesh raises many types on corrupt input
        raise MeshError(f"{path}: could not read it as {kind.upper()}: {exc}") from None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise MeshError(f"{path}: contains no triangles")
    vertices = np.asarray(loaded.vertices, dtype=np.float64)
    faces = np.asarray(loaded.faces, dtype=np.int64)
    finite = np.asarray(np.isfinite(vertices).all(axis=1))
    if not finite.all():
        bad, total = int(np.count_nonzero(~finite)), len(vertices)
        if kind == "stl":
            # An STL repeats each vertex per facet: its distinct points (NaN equal to NaN).
            key = np.where(np.isnan(vertices), np.finfo(float).max, vertices)
            bad, total = len(np.unique(key[~finite], axis=0)), len(np.unique(key, axis=0))
        touched = int(np.count_nonzero(~finite[faces].all(axis=1)))
        raise MeshError(
            f"{name or path}: {bad} of its {total} vertices are not finite numbers "
            f"(NaN or inf), in {touched} of its {len(faces)} triangles"
        )
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    mesh.merge_vertices()  # STL repeats each vertex per facet; weld them
    return mesh


def _stl_count(path: Path) -> int:
    """The triangle count a binary STL's header states (0 for an ASCII STL, whose
    triangles are counted once read)."""
    with open(path, "rb") as fh:
        head = fh.read(84)
    if len(head) < 84 or head.lstrip().lower().startswith(b"solid"):
        return 0
    count = int(np.frombuffer(head[80:84], dtype="<u4")[0])
    # Only a count that matches the file's size is a binary STL's (else: _read refuses).
    return count if path.stat().st_size == 84 + STL_FACET.itemsize * count else 0


def _check_count(count: int, max_faces: int, name: str) -> None:
    if count > max_faces:
        raise MeshError(
            f"{name} has {count:,} triangles, more than the {max_faces:,} threadmate "
            "takes (the contact stages would take very long and much memory): export it "
            "more coarsely (a chord of a thousandth of the pitch is ample), or raise the "
            f"limit: max_faces={count}"
        )
    if count > min(WARN_FACES, max_faces):
        warnings.warn(
            f"{name} has {count:,} triangles (above {WARN_FACES:,}): the contact stages "
            "will be slow and use much memory; a coarser export (a chord of a thousandth "
            "of the pitch) serves as well",
            MeshWarning,
            stacklevel=3,
        )


def _flat_faces(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], size: float
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Triangles with a repeated vertex, and triangles of three distinct vertices in a
    line (height over the longest edge at most :data:`_DEGENERATE` of ``size``)."""
    tri = vertices[faces]
    longest = np.linalg.norm(tri[:, [1, 2, 0]] - tri, axis=2).max(axis=1)
    double_area = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    repeated = (
        (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0])
    )
    line = ~repeated & (double_area <= _DEGENERATE * size * np.maximum(longest, 1e-300))
    return repeated, line


def _split_slivers(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], size: float
) -> NDArray[np.int64] | None:
    """``faces`` with each triangle of three vertices in a line removed by splitting its
    neighbour across the long edge at the middle vertex (a T-junction closed: the
    sliver ``a c b`` with ``b`` on ``ac`` and the neighbour ``c a d`` become ``c b d`` and
    ``b a d``; orientation and closedness kept). None when a sliver has no single such
    neighbour, or the slivers do not run out."""
    tris: dict[int, tuple[int, int, int]] = {
        i: (int(f[0]), int(f[1]), int(f[2])) for i, f in enumerate(faces.tolist())
    }
    # Each directed edge's triangle (a closed, consistently wound mesh has one each).
    owner: dict[tuple[int, int], int] = {}
    for i, (u, v, w) in tris.items():
        for edge in ((u, v), (v, w), (w, u)):
            owner[edge] = i
    _, line = _flat_faces(vertices, faces, size)
    queue = np.flatnonzero(line).tolist()
    fresh = len(faces)

    def flat(t: tuple[int, int, int]) -> bool:
        return bool(_flat_faces(vertices, np.array([t], dtype=np.int64), size)[1][0])

    for _ in range(4 * len(queue) + 4):
        if not queue:
            return np.array(list(tris.values()), dtype=np.int64)
        k = queue.pop()
        if k not in tris:
            continue
        f = tris[k]
        pts = vertices[list(f)]
        lengths = np.linalg.norm(pts[[1, 2, 0]] - pts, axis=1)  # edges 01, 12, 20
        j = int(np.argmax(lengths))
        a, c, b = f[j], f[(j + 1) % 3], f[(j + 2) % 3]
        m = owner.get((c, a))
        if m is None or m == k:
            return None
        g = tris[m]
        d = next(v for v in g if v not in (a, c))
        for i, t in ((k, f), (m, g)):
            del tris[i]
            for edge in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                owner.pop(edge, None)
        for t in ((c, b, d), (b, a, d)):
            tris[fresh] = t
            for edge in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                owner[edge] = fresh
            if flat(t):
                queue.append(fresh)
            fresh += 1
    return None


def _drop_degenerate(mesh: trimesh.Trimesh, name: str) -> trimesh.Trimesh:
    """``mesh`` without its zero-area triangles, with a warning, when it is still closed
    without them (a triangle with a repeated vertex is dropped; three vertices in a line,
    a T-junction, closed by splitting the neighbour across the long edge); refused
    when not."""
    vertices = np.asarray(mesh.vertices, dtype=float)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    size = float(np.max(mesh.bounds[1] - mesh.bounds[0]))
    repeated, line = _flat_faces(vertices, faces, size)
    count = int(np.count_nonzero(repeated | line))
    if count == 0:
        return mesh
    if count == len(faces):
        raise MeshError(f"{name}: all its {count} triangles have zero area")
    kept_faces: NDArray[np.int64] | None = faces[~repeated]
    if line.any() and count <= _MAX_SLIVERS:
        kept_faces = _split_slivers(vertices, faces[~repeated], size)
    elif line.any():
        kept_faces = None
    kept = None
    if kept_faces is not None:
        kept = trimesh.Trimesh(vertices, kept_faces, process=False)
        kept.remove_unreferenced_vertices()
    if kept is None or not kept.is_watertight:
        detail = ""
        if kept is not None:
            detail = f" ({_edge_counts(kept)[0]} edges belong to a single triangle)"
        raise MeshError(
            f"{name} has {count} degenerate (zero-area) triangles, and without them it "
            f"is not closed{detail}: repair or re-export it"
        )
    warnings.warn(
        f"{name}: dropped {count} degenerate (zero-area) triangles; the mesh is closed "
        "without them",
        MeshWarning,
        stacklevel=3,
    )
    return kept


def _edge_counts(mesh: trimesh.Trimesh) -> tuple[int, int]:
    """Edges that belong to one triangle, and edges shared by more than two."""
    _, counts = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
    return int(np.sum(counts == 1)), int(np.sum(counts > 2))


def _looks_like_stl(data: bytes) -> bool:
    if len(data) >= 84:
        count = int(np.frombuffer(data[80:84], dtype="<u4")[0])
        if count > 0 and len(data) == 84 + STL_FACET.itemsize * count:
            return True
    head = data[:1024].lstrip().lower()
    return head.startswith(b"solid") and b"facet" in data[:4096].lower()


def _check_closed(mesh: trimesh.Trimesh, name: str) -> None:
    if not mesh.is_watertight:
        open_edges, shared = _edge_counts(mesh)
        what = []
        if open_edges:
            what.append(f"{open_edges} edges belong to a single triangle")
        if shared:
            what.append(f"{shared} edges are shared by more than two triangles")
        raise MeshError(
            f"{name} is not a closed volume (not watertight): "
            + (" and ".join(what) or "its edges do not pair up")
        )
    if not mesh.is_winding_consistent:
        raise MeshError(
            f"{name} has inconsistent winding: some triangles face the other "
            "way from their neighbours"
        )
    _check_shells(mesh, name)
    if abs(mesh.volume) <= 0:
        raise MeshError(f"{name} encloses no volume")


def _check_shells(mesh: trimesh.Trimesh, name: str) -> None:
    """One shell: not two bodies in one file, nor a body with a void inside it."""
    faces = np.asarray(mesh.faces, dtype=np.int64)
    labels = trimesh.graph.connected_component_labels(mesh.face_adjacency, len(faces))
    shells = int(labels.max()) + 1 if len(labels) else 0
    if shells <= 1:
        return
    # Each shell's signed volume: the outer one's sign is the mesh's; a void's is the other.
    tri = np.asarray(mesh.vertices)[faces]
    signed = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0
    volume = np.bincount(labels, weights=signed, minlength=shells)
    outward = np.sign(float(volume[np.argmax(np.abs(volume))]))
    voids = int(np.count_nonzero(np.sign(volume) != outward))
    if voids:
        raise MeshError(
            f"{name} has {voids} void{'s' if voids > 1 else ''} inside it ({shells} "
            "closed shells, one wound the other way): a solid part has none; fill it"
        )
    raise MeshError(
        f"{name} is {shells} separate bodies ({shells} closed shells): give one part per file"
    )


def _band(body: str, spec: ThreadSpec, scale: float = 1.0) -> tuple[float, float]:
    """The heights (the mesh's numbers, ``scale`` spec units each) where the thread is."""
    if body == "bolt":
        return 0.0, filled(spec.bolt.length) / scale
    return -filled(spec.nut.height) / scale, 0.0


def _radial_extent(mesh: trimesh.Trimesh, body: str, band: tuple[float, float]) -> float:
    """The bolt's largest radius, or the nut's smallest vertex radius, between the
    heights of ``band``; over the whole mesh when nothing of it lies there.

    The bolt's is exact: over a triangle clipped to the band (a convex polygon) the
    radius, a convex function, is largest at a corner: a vertex in the band or where an
    edge crosses one of its planes.
    """
    v = np.asarray(mesh.vertices, dtype=float)
    lo, hi = band
    z = v[:, 2]
    inside = (z >= lo) & (z <= hi)
    if body == "nut":
        r = np.hypot(v[inside, 0], v[inside, 1]) if inside.any() else np.hypot(v[:, 0], v[:, 1])
        return float(r.min())
    points = [v[inside]]
    a, b = v[mesh.edges_unique[:, 0]], v[mesh.edges_unique[:, 1]]
    for level in (lo, hi):
        cross = (a[:, 2] - level) * (b[:, 2] - level) < 0
        if cross.any():
            t = (level - a[cross, 2]) / (b[cross, 2] - a[cross, 2])
            points.append(a[cross] + t[:, None] * (b[cross] - a[cross]))
    found = np.concatenate(points)
    if len(found) == 0:
        found = v
    return float(np.hypot(found[:, 0], found[:, 1]).max())


def _check_size(mesh: trimesh.Trimesh, body: str, spec: ThreadSpec, name: str) -> None:
    expected = spec.bolt.major / 2 if body == "bolt" else spec.nut.minor / 2
    what = "major radius" if body == "bolt" else "bore (minor) radius"
    u = spec.units
    band = _band(body, spec)
    got = _radial_extent(mesh, body, band)
    lo, hi = SIZE_BAND
    if lo <= got / expected <= hi:
        return
    hint = ""
    mm_per_in = unit_scale("in", "mm")
    # In the other units, the thread lies over the band in those units' numbers.
    if spec.units == "in":
        other = _radial_extent(mesh, body, _band(body, spec, 1 / mm_per_in))
        if lo <= other / mm_per_in / expected <= hi:
            hint = ": it looks like mm (give its units, mesh_units='mm', or convert it)"
    else:
        other = _radial_extent(mesh, body, _band(body, spec, mm_per_in))
        if lo <= other * mm_per_in / expected <= hi:
            hint = ": it looks like inches (give its units, mesh_units='in', or convert it)"
    where = (
        f"z 0 to {band[1]:.6g} {u}, the spec's bolt length from the tip"
        if body == "bolt"
        else f"z {band[0]:.6g} to 0 {u}, the spec's nut height"
    )
    raise MeshError(
        f"{name} has implausible size for the spec: where its thread is ({where}) its "
        f"{what} is {got:.6g} {u} but the spec's is {expected:.6g} {u}{hint}"
    )


def _check_frame(mesh: trimesh.Trimesh, body: str, name: str) -> None:
    lo, hi = mesh.bounds
    half = 0.5 * float(np.max(hi[:2] - lo[:2]))
    size = float(np.max(hi - lo))
    # float32 files round coordinates to ~1e-7 of their size.
    slack = 1e-6 * size
    centre = 0.5 * (lo[:2] + hi[:2])
    if body == "bolt":
        face, where = float(lo[2]), "tip face at z = 0, body in z >= 0"
    else:
        face, where = float(hi[2]), "top face at z = 0, body in z <= 0"
    if abs(face) > slack or np.any(np.abs(centre) > 0.05 * half) or size <= 0:
        raise MeshError(
            f"{name} is not in its frame ({where}, axis along Z through the origin): its "
            f"bounds are {np.round(lo, 6).tolist()} to {np.round(hi, 6).tolist()}"
        )
