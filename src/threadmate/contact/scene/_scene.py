"""The contact scene: the one world both contact models see.

A :class:`ContactScene` holds, for one thread pair, what the thesis's fixed-pivot
procedure (:class:`._analyzer.ContactAnalyzer`) and the mechanics of the held bolt
(:class:`._settle.Mechanics`) both stand on:

- the spec and its exact bodies (regions, normals and edge contact points come from
  them, also under a mesh from CAD, which the spec describes where the mesh follows it);
- the two meshes: generated within a chord tolerance of the exact surfaces, or from CAD
  (validated, scaled into the spec's units, with their fit to the spec: :mod:`._cad`);
- the collision queries on them (:class:`._collision.CollisionPair`);
- the tolerances that follow from the meshes: the travel tolerance of bisections, the
  feature tolerance within which a point lies on a face or edge, and, with a mesh from
  CAD, the distance beyond which a contact lies where the mesh does not follow the spec.

:func:`contact_scene` builds a scene once per (spec, chord, mesh files) in a process and
hands the same one out again: building the meshes and their collision trees is the cost,
so each worker process builds its own, once.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path
from typing import Any, Literal

import numpy as np
import trimesh

from ..._errors import InputError
from ..._units import MM_PER_UNIT, unit_scale
from ..._validate import check_max_faces
from ...geometry import (
    DEFAULT_CHORD,
    ThreadBody,
    ThreadSpec,
    bolt_body,
    load_mesh,
    nut_body,
    thread_meshes,
)
from ._cad import OFF_SPEC_WARNING, MeshFit, OffSpec, describe, file_units, mesh_fit, off_spec
from ._collision import CollisionPair

__all__ = [
    "OFF_SPEC_FACTOR",
    "TRAVEL_TOLERANCE",
    "ContactScene",
    "check_mesh_file",
    "contact_scene",
    "scene_for",
]

#: Bisection tolerance on travel (bolt motion), per unit.
TRAVEL_TOLERANCE = {u: 1e-7 * unit_scale("in", u) for u in MM_PER_UNIT}
#: With a mesh from CAD, a contact farther than the feature tolerance plus this many mesh
#: deviations from the exact surface lies where the mesh does not follow the spec. A
#: contact point lies on both meshes (:func:`._triangles.cluster_location`), so within a
#: deviation of each exact surface where the mesh follows it; the feature tolerance (two
#: deviations and the travel) plus three more leaves a margin of five over that.
OFF_SPEC_FACTOR = 3.0


def _user_mesh(
    mesh: Any,
    kind: Literal["bolt", "nut"],
    spec: ThreadSpec,
    units: str | None = None,
    max_faces: int | None = None,
) -> trimesh.Trimesh:
    """A user mesh from a path (validated by :func:`threadmate.geometry.load_mesh`, in
    ``units``: see :func:`._cad.file_units`; at most ``max_faces`` triangles) or a Trimesh
    (in ``units``, default the spec's; checked to sit in its frame)."""
    if isinstance(mesh, str | Path):
        units = file_units(mesh, units, spec)
        return load_mesh(mesh, kind, spec=spec, units=units, max_faces=max_faces)
    if not isinstance(mesh, trimesh.Trimesh):
        raise InputError(
            f"{kind}_mesh must be a mesh file path or a trimesh.Trimesh, got {type(mesh).__name__}"
        )
    if units is not None and units != spec.units:
        mesh = mesh.copy()
        mesh.apply_scale(unit_scale(units, spec.units))
    lo, hi = mesh.bounds
    size = float(np.max(hi - lo))
    slack = 1e-6 * max(size, spec.pitch)
    centred = np.all(np.abs(0.5 * (lo[:2] + hi[:2])) <= 0.05 * size)
    if kind == "bolt":
        framed = abs(lo[2]) <= slack and centred
        where = "tip face at z = 0, body in z >= 0, axis along Z"
    else:
        framed = abs(hi[2]) <= slack and centred
        where = "top face at z = 0, body in z <= 0, axis along Z"
    if not framed:
        raise InputError(
            f"{kind} mesh is not in its frame ({where}); its bounds are "
            f"{lo.round(6).tolist()} to {hi.round(6).tolist()}"
        )
    if not mesh.is_watertight:
        raise InputError(f"{kind} mesh is not a closed volume (not watertight)")
    return mesh


def _cad_mesh(
    given: Any,
    kind: Literal["bolt", "nut"],
    spec: ThreadSpec,
    body: ThreadBody,
    units: str | None,
    max_faces: int | None = None,
) -> tuple[trimesh.Trimesh, MeshFit, dict[str, Any]]:
    """A mesh from CAD, validated, with how it follows ``body`` and its description."""
    path = given if isinstance(given, str | Path) else None
    resolved = file_units(path, units, spec) if path is not None else (units or spec.units)
    mesh = _user_mesh(given, kind, spec, units, max_faces)
    name = f"{kind} mesh {Path(path).name}" if path is not None else f"{kind} mesh"
    fit = mesh_fit(mesh, body, spec, name)
    info = describe(path, resolved, spec)
    info["deviation"] = fit.deviation
    return mesh, fit, info


def _check_mesh_units(units: str | None) -> None:
    if units is not None and units not in MM_PER_UNIT:
        raise InputError(f"mesh_units must be 'in' or 'mm', got {units!r}")


def check_mesh_file(
    path: str | Path,
    kind: Literal["bolt", "nut"],
    spec: ThreadSpec,
    units: str | None = None,
    *,
    max_faces: int | None = None,
) -> dict[str, Any]:
    """Validate a mesh file as :class:`ContactScene` would (format, triangle count,
    closed volume, size, frame, units, that it follows the spec somewhere) without
    building anything, and describe it: ``{"file", "path", "sha256", "units", "scale",
    "deviation"}``. ``max_faces``: as :func:`threadmate.geometry.load_mesh`'s.

    For a caller that hands the path on to other processes (the library sweep): the
    refusal comes here, before anything is written.
    """
    _check_mesh_units(units)
    body = bolt_body(spec) if kind == "bolt" else nut_body(spec)
    return _cad_mesh(path, kind, spec, body, units, max_faces)[2]


class ContactScene:
    """One thread pair as the contact models see it: exact bodies, meshes, the collision
    pair and the tolerances (see the module docstring).

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair (lengths in ``spec.units``).
    chord : float, optional
        Chord tolerance of the generated meshes (default
        :data:`threadmate.geometry.DEFAULT_CHORD`, 5e-6 in).
    bolt_mesh, nut_mesh : path or trimesh.Trimesh, optional
        Meshes from CAD instead of generated ones, each in its own frame (bolt tip face at
        z = 0, nut top face at z = 0, axes along Z); refused with :class:`InputError`
        otherwise. The deviation that sets the tolerances is measured only where such a
        mesh follows the spec (:mod:`._cad`); a contact farther than
        :attr:`off_spec_tolerance` from the spec's surface is labelled ``point``,
        ``countersink`` or ``other``.
    mesh_units : {"in", "mm"}, optional
        Length units of the mesh files (default: the units a threadmate STL declares in
        its header, else the spec's; a header that disagrees is refused). A mesh in other
        units than the spec's is scaled into them.
    max_faces : int, optional
        Most triangles a mesh file may have (default ``threadmate._validate.MAX_FACES``;
        see :func:`threadmate.geometry.load_mesh`).

    Attributes
    ----------
    spec, units, chord
    bolt, nut : ThreadBody
        The exact bodies.
    engine : CollisionPair
        The collision queries on the two meshes (its query counter is the scene's cost).
    deviation : float
        The meshes' largest deviation from the exact surfaces (where they follow them).
    travel : float
        Bisection tolerance on travel (:data:`TRAVEL_TOLERANCE`).
    feature_tolerance : float
        Distance within which a contact point is taken to lie on a face or edge.
    off_spec_tolerance : float or None
        With a mesh from CAD, the distance from the exact surface beyond which a contact
        lies where the mesh does not follow the spec (None: generated meshes).
    off_spec : OffSpec or None
        Where the CAD meshes do not follow the spec (:func:`._cad.off_spec`).
    """

    def __init__(
        self,
        spec: ThreadSpec,
        *,
        chord: float | None = None,
        bolt_mesh: Any = None,
        nut_mesh: Any = None,
        mesh_units: str | None = None,
        max_faces: int | None = None,
    ) -> None:
        if not isinstance(spec, ThreadSpec):
            raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
        _check_mesh_units(mesh_units)
        if max_faces is not None:
            check_max_faces(max_faces)
        self.spec = spec
        self.units = spec.units
        self.bolt = bolt_body(spec)
        self.nut = nut_body(spec)
        generated = None
        if bolt_mesh is None or nut_mesh is None:
            generated = dict(zip(("bolt", "nut"), thread_meshes(spec, chord), strict=True))
        self.chord = float(chord if chord is not None else DEFAULT_CHORD[spec.units])
        self._mesh_info: dict[str, dict[str, Any]] = {}
        fits: dict[str, MeshFit] = {}
        meshes: dict[str, trimesh.Trimesh] = {}
        sources: tuple[tuple[Literal["bolt", "nut"], Any, ThreadBody], ...] = (
            ("bolt", bolt_mesh, self.bolt),
            ("nut", nut_mesh, self.nut),
        )
        for kind, given, body in sources:
            if given is None:
                assert generated is not None
                tb = generated[kind]
                meshes[kind] = tb.mesh
                self._mesh_info[kind] = {
                    "generated": True,
                    "chord": float(tb.chord),
                    "deviation": float(tb.max_deviation),
                }
                continue
            meshes[kind], fits[kind], self._mesh_info[kind] = _cad_mesh(
                given, kind, spec, body, mesh_units, max_faces
            )
        self.deviation = max(0.0, *(float(i["deviation"]) for i in self._mesh_info.values()))
        self.engine = CollisionPair(meshes["bolt"], meshes["nut"])
        self.travel = TRAVEL_TOLERANCE[spec.units]
        bound = max(self.deviation, 1e-9 * spec.pitch)
        self.feature_tolerance = 2.0 * bound + 10.0 * self.travel
        self.off_spec_tolerance: float | None = None
        if fits:
            self.off_spec_tolerance = self.feature_tolerance + OFF_SPEC_FACTOR * bound
            for name, fit in fits.items():
                self._describe_fit(name, fit)
        self.off_spec: OffSpec | None = off_spec(self)

    def _describe_fit(self, kind: str, fit: MeshFit) -> None:
        """The off-spec shares of a CAD mesh, and a warning when much of its contact zone
        lies off the spec."""
        assert self.off_spec_tolerance is not None
        share, zone_share = fit.off_spec_share(self.off_spec_tolerance)
        info = self._mesh_info[kind]
        info["off_spec_share"] = share
        info["zone_off_spec_share"] = zone_share
        info["warning"] = None
        if zone_share > OFF_SPEC_WARNING:
            what = {"bolt": "point", "nut": "countersink"}[kind]
            info["warning"] = (
                f"{kind} mesh {info['file'] or '(object)'}: {zone_share:.0%} of its contact "
                f"zone lies off the spec (farther than {self.off_spec_tolerance:.3g} "
                f"{self.units} from its exact surface); contacts there are labelled "
                f"{what}/other. If the part has a {what} the spec does not state, state it."
            )

    @property
    def mesh_info(self) -> dict[str, Any]:
        """The meshes used: per body either ``{"generated": True, "chord", "deviation"}``
        or, for a mesh from CAD, ``{"file", "path", "sha256", "units", "scale",
        "deviation", "off_spec_share", "zone_off_spec_share", "warning"}`` (``file``,
        ``path`` and ``sha256`` None for a mesh given as an object; the shares by area,
        of the whole mesh and of its contact zone, farther than the off-spec tolerance
        from the exact surface); and ``off_spec_tolerance`` (None without CAD meshes).
        Lengths in the spec's units."""
        return {
            "bolt": dict(self._mesh_info["bolt"]),
            "nut": dict(self._mesh_info["nut"]),
            "off_spec_tolerance": self.off_spec_tolerance,
        }

    @property
    def mesh_warnings(self) -> list[str]:
        """Warnings about CAD meshes much of whose contact zone is off the spec."""
        return [w for info in self._mesh_info.values() if (w := info.get("warning"))]


def _file_key(given: Any) -> Any:
    """What identifies a mesh argument for the cache: a path by its resolved name, size
    and modification time (a file changed on disk is read again); an object is not
    cached (None)."""
    if given is None:
        return ()
    if isinstance(given, str | Path):
        try:
            st = os.stat(given)
        except OSError:
            return None  # let the scene's own loading refuse it
        return (str(Path(given).resolve()), st.st_size, st.st_mtime_ns)
    return None


@functools.lru_cache(maxsize=4)
def _cached(spec: ThreadSpec, chord: float | None, meshes: tuple[Any, ...]) -> ContactScene:
    (bolt, _), (nut, _), units, max_faces = meshes
    return ContactScene(
        spec, chord=chord, bolt_mesh=bolt, nut_mesh=nut, mesh_units=units, max_faces=max_faces
    )


def contact_scene(
    spec: ThreadSpec,
    *,
    chord: float | None = None,
    bolt_mesh: Any = None,
    nut_mesh: Any = None,
    mesh_units: str | None = None,
    max_faces: int | None = None,
) -> ContactScene:
    """The :class:`ContactScene` of these arguments, built once per process and kept
    (the last few); meshes given as objects are not kept, a scene is built for them."""
    keys = (_file_key(bolt_mesh), _file_key(nut_mesh))
    if any(k is None for k in keys):
        return ContactScene(
            spec,
            chord=chord,
            bolt_mesh=bolt_mesh,
            nut_mesh=nut_mesh,
            mesh_units=mesh_units,
            max_faces=max_faces,
        )
    meshes = ((bolt_mesh, keys[0]), (nut_mesh, keys[1]), mesh_units, max_faces)
    # The default chord by its value: a scene asked with it and one asked without are one.
    return _cached(spec, chord if chord is not None else DEFAULT_CHORD[spec.units], meshes)


def scene_for(
    spec: ThreadSpec,
    scene: ContactScene | None,
    *,
    chord: float | None = None,
    bolt_mesh: Any = None,
    nut_mesh: Any = None,
    mesh_units: str | None = None,
    max_faces: int | None = None,
) -> ContactScene:
    """The scene a contact model stands on: ``scene`` when given (its spec must be
    ``spec``), else :func:`contact_scene` of the spec, chord and meshes.

    Raises
    ------
    InputError
        If ``scene`` is of another spec.
    """
    if scene is None:
        return contact_scene(
            spec,
            chord=chord,
            bolt_mesh=bolt_mesh,
            nut_mesh=nut_mesh,
            mesh_units=mesh_units,
            max_faces=max_faces,
        )
    if scene.spec != spec:
        raise InputError("the scene's spec differs from the spec given")
    return scene
