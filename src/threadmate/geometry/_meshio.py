"""Mesh files: binary STL out and in, and validated user meshes from CAD (STL, OBJ, PLY).

Binary STL follows the thesis's Figure 3.3: an 80-byte header, the facet count as a
little-endian uint32, then per facet 50 bytes: the unit normal and the three vertices as
twelve float32 and a uint16 attribute (unused, 0). STL carries no units; threadmate writes
the spec's units into the header (:func:`stl_header`: ``threadmate units=in bolt ...``),
where :func:`stl_units` and :func:`load_mesh` read them back.

A user mesh (a bolt or nut exported from CAD) is accepted only if it is a closed volume
(every edge shared by exactly two triangles), consistently wound, of plausible size for
the spec and in its body's frame (conventions.md). A closed, consistently wound mesh whose
normals all point inward (negative volume) is turned inside out rather than refused: the
winding is a global convention of the exporter and inverting it loses nothing. Anything
else raises :class:`~threadmate._errors.MeshError` with one message naming the problem.
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np
import trimesh

from .._errors import MeshError
from .._io import atomic_write_bytes
from .._units import MM_PER_UNIT

if TYPE_CHECKING:
    from ._spec import ThreadSpec

__all__ = ["write_stl", "read_stl", "load_mesh", "stl_header", "stl_units", "STL_FACET"]

#: One binary-STL facet (the thesis's Figure 3.3): 50 bytes.
STL_FACET = np.dtype(
    [
        ("normal", "<f4", (3,)),
        ("vertices", "<f4", (3, 3)),
        ("attribute", "<u2"),
    ]
)

_FORMATS = {".stl": "stl", ".obj": "obj", ".ply": "ply"}
# "units=in" or "units=mm" as a word of a binary STL header (written by stl_header).
_UNITS_RE = re.compile(rb"(?:^|\s)units=(in|mm)(?=\s|$)")
# A user mesh's radius may differ from the spec's by tolerances and modelling choices,
# not by a factor: outside this band its size is implausible.
_SIZE_BAND = (0.8, 1.25)


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
    """The length units (``"in"`` or ``"mm"``) a binary STL's header declares, or None.

    Reads the ``units=...`` word that :func:`stl_header` writes; other files (ASCII STL,
    CAD exports) declare none.
    """
    try:
        with open(path, "rb") as fh:
            head = fh.read(80)
    except OSError:
        return None
    if head.lstrip().lower().startswith(b"solid"):
        return None  # ASCII STL: its first line names the solid, not the units
    match = _UNITS_RE.search(head.rstrip(b" \0"))
    return match.group(1).decode("ascii") if match else None


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
        The thread pair the mesh should model: its diameters check the mesh's size (an
        inch spec with a mesh 25.4 times too large is refused as "looks like mm").
    units : {"in", "mm"}, optional
        The file's length units when they differ from the spec's: the mesh is scaled
        into the spec's units. Default: the units a threadmate STL declares in its
        header (:func:`stl_units`), else the spec's units.

    Returns
    -------
    trimesh.Trimesh
        The validated mesh (float64 vertices, outward normals) in the spec's units.

    Raises
    ------
    MeshError
        A missing or unreadable file, or a mesh that is open, inconsistently wound, of
        implausible size or out of its frame.
    """
    if body not in ("bolt", "nut"):
        raise MeshError(f"body must be 'bolt' or 'nut', got {body!r}")
    if units is not None and units not in ("in", "mm"):
        raise MeshError(f"units must be 'in' or 'mm', got {units!r}")
    path = Path(path)
    kind = _FORMATS.get(path.suffix.lower())
    if kind is None:
        raise MeshError(
            f"{path}: unsupported mesh format {path.suffix!r} (give .stl, .obj or .ply)"
        )
    mesh = _read(path, kind)
    if units is None and kind == "stl":
        units = stl_units(path)
    name = f"{body} mesh {path.name}"
    _check_closed(mesh, name)
    if mesh.volume < 0:
        mesh.invert()  # consistently wound but inside out: see the module docstring
    if spec is not None:
        if units is not None and units != spec.units:
            mesh.apply_scale(MM_PER_UNIT[units] / MM_PER_UNIT[spec.units])
        _check_size(mesh, body, spec, name)
    _check_frame(mesh, body, name)
    return mesh


# -- internals ---------------------------------------------------------------------------
def _read(path: Path, kind: str) -> trimesh.Trimesh:
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
        loaded = trimesh.load(path, file_type=kind, force="mesh", process=True)
    except Exception as exc:  # trimesh raises many types on corrupt input
        raise MeshError(f"{path}: could not read it as {kind.upper()}: {exc}") from None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise MeshError(f"{path}: contains no triangles")
    if not np.all(np.isfinite(loaded.vertices)):
        raise MeshError(f"{path}: has vertices that are not finite numbers")
    mesh = trimesh.Trimesh(
        np.asarray(loaded.vertices, dtype=np.float64),
        np.asarray(loaded.faces, dtype=np.int64),
        process=True,
    )
    mesh.merge_vertices()  # STL repeats each vertex per facet; weld them
    return mesh


def _looks_like_stl(data: bytes) -> bool:
    if len(data) >= 84:
        count = int(np.frombuffer(data[80:84], dtype="<u4")[0])
        if count > 0 and len(data) == 84 + STL_FACET.itemsize * count:
            return True
    head = data[:1024].lstrip().lower()
    return head.startswith(b"solid") and b"facet" in data[:4096].lower()


def _check_closed(mesh: trimesh.Trimesh, name: str) -> None:
    if not mesh.is_watertight:
        edges = mesh.edges_sorted
        _, counts = np.unique(edges, axis=0, return_counts=True)
        open_edges = int(np.sum(counts == 1))
        raise MeshError(
            f"{name} is not a closed volume (not watertight): {open_edges} "
            "edges belong to a single triangle"
        )
    if not mesh.is_winding_consistent:
        raise MeshError(
            f"{name} has inconsistent winding: some triangles face the other "
            "way from their neighbours"
        )
    if abs(mesh.volume) <= 0:
        raise MeshError(f"{name} encloses no volume")


def _radial_extent(mesh: trimesh.Trimesh, body: str) -> float:
    r = np.hypot(mesh.vertices[:, 0], mesh.vertices[:, 1])
    # The bolt reaches out to its major radius; the nut's bore comes in to its minor one.
    return float(r.max() if body == "bolt" else r.min())


def _check_size(mesh: trimesh.Trimesh, body: str, spec: ThreadSpec, name: str) -> None:
    expected = spec.bolt.major / 2 if body == "bolt" else spec.nut.minor / 2
    what = "major radius" if body == "bolt" else "bore (minor) radius"
    got = _radial_extent(mesh, body)
    ratio = got / expected
    lo, hi = _SIZE_BAND
    if lo <= ratio <= hi:
        return
    hint = ""
    mm_per_in = MM_PER_UNIT["in"]
    if spec.units == "in" and lo <= ratio / mm_per_in <= hi:
        hint = ": it looks like mm (give units='mm', --mesh-units mm, or convert it)"
    elif spec.units == "mm" and lo <= ratio * mm_per_in <= hi:
        hint = ": it looks like inches (give units='in', --mesh-units in, or convert it)"
    raise MeshError(
        f"{name} has implausible size for the spec: its {what} is {got:.6g} "
        f"but the spec's is {expected:.6g} {spec.units}{hint}"
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
