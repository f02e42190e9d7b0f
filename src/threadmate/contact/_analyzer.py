"""The contact analyser: meshes and BVHs built once, three stages per configuration.

The stages are the thesis's fixed-pivot procedure (each turns about an axis fixed in
space, the compliance is ignored) and the classes its criteria of section 4.2
(:mod:`._stability`); the physical model is the mechanics' (``threadmate settle``).
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any, Literal

import numpy as np
import trimesh
from numpy.typing import NDArray
from scipy.spatial import ConvexHull, QhullError, cKDTree

from .._errors import InputError
from .._units import MM_PER_UNIT, unit_scale
from .._validate import (
    MAX_TILT,
    check_configuration,
    check_length,
    check_max_faces,
    check_open_range,
)
from ..geometry import (
    DEFAULT_CHORD,
    Pose,
    ThreadBody,
    ThreadSpec,
    bolt_body,
    bolt_rotation,
    load_mesh,
    nut_body,
    thread_meshes,
)
from ._cad import OFF_SPEC_WARNING, MeshFit, describe, file_units, mesh_fit
from ._collision import CollisionPair
from ._exact import contact_normal, engagement_outline, region_at, turn_axis_tangent
from ._result import Contact, ContactResult, StageResult, _vec
from ._stability import classify, interference_depth, is_rolling, pivot_offset
from ._stages import (
    Cluster,
    Search,
    first_contact,
    lowering_direction,
    turn_to_new_contact,
)
from ._triangles import intersection_segments

__all__ = [
    "ContactAnalyzer",
    "analyze",
    "check_mesh_file",
    "MAX_TILT",
    "OFF_SPEC_FACTOR",
    "TRAVEL_TOLERANCE",
]

#: Bisection tolerance on travel (bolt motion), per unit.
TRAVEL_TOLERANCE = {u: 1e-7 * unit_scale("in", u) for u in MM_PER_UNIT}
#: With a mesh from CAD, a contact farther than the feature tolerance plus this many mesh
#: deviations from the exact surface lies where the mesh does not follow the spec. A
#: contact point lies on both meshes (:func:`._triangles.cluster_location`), so within a
#: deviation of each exact surface where the mesh follows it; the feature tolerance (two
#: deviations and the travel) plus three more leaves a margin of five over that.
OFF_SPEC_FACTOR = 3.0


def _positive(name: str, value: float | None) -> float | None:
    if value is None:
        return None
    return check_open_range(name, value, 0.0, math.inf)


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


def check_mesh_file(
    path: str | Path,
    kind: Literal["bolt", "nut"],
    spec: ThreadSpec,
    units: str | None = None,
    *,
    max_faces: int | None = None,
) -> dict[str, Any]:
    """Validate a mesh file as :class:`ContactAnalyzer` would (format, triangle count,
    closed volume, size, frame, units, that it follows the spec somewhere) without
    building anything, and describe it: ``{"file", "path", "sha256", "units", "scale",
    "deviation"}``. ``max_faces``: as :func:`threadmate.geometry.load_mesh`'s.

    For a caller that hands the path on to other processes (the library sweep): the
    refusal comes here, before anything is written.
    """
    if units is not None and units not in MM_PER_UNIT:
        raise InputError(f"mesh_units must be 'in' or 'mm', got {units!r}")
    body = bolt_body(spec) if kind == "bolt" else nut_body(spec)
    return _cad_mesh(path, kind, spec, body, units, max_faces)[2]


def _share(cluster: Cluster, corners: NDArray[np.float64]) -> list[Cluster]:
    """Split an area contact into distinct contacts at ``corners``: each pair goes to the
    nearest corner."""
    ends = cluster.ends
    n = len(ends) // 2
    mid = 0.5 * (ends[:n] + ends[n:])
    near = np.argmin(np.linalg.norm(mid[:, None] - corners[None], axis=-1), axis=1)
    return [
        Cluster(
            corners[j],
            int((near == j).sum()),
            np.concatenate([ends[:n][near == j], ends[n:][near == j]]),
        )
        for j in range(len(corners))
    ]


def _flat_support(
    cluster: Cluster, centre: NDArray[np.float64], separation: float
) -> list[Cluster] | tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """How a tip face resting flat over an area supports the compliance centre.

    The area's horizontal convex hull either surrounds the compliance centre (the bolt
    rests on it: three distinct contacts at hull vertices whose triangle holds the
    centre), or not (the bolt tips over the hull edge facing the centre: the edge's two
    ends as two distinct contacts, or the edge as a turn axis ``(point, direction)`` when
    its ends are closer than ``separation``). None when the area has no proper hull.
    """
    ends = cluster.ends
    try:
        hull = ConvexHull(ends[:, :2])
    except QhullError:
        return None
    c = centre[:2]
    dist = hull.equations[:, :2] @ c + hull.equations[:, 2]  # > 0 outside the facet
    if dist.max() < 0:
        v = hull.vertices
        for k in range(1, len(v) - 1):
            tri = ends[[v[0], v[k], v[k + 1]], :2]
            m = np.column_stack([tri[1] - tri[0], tri[2] - tri[0]])
            b = np.linalg.solve(m, c - tri[0])
            if b.min() >= 0 and b.sum() <= 1:
                return _share(cluster, ends[[v[0], v[k], v[k + 1]]])
        return None
    a, b = ends[hull.simplices[int(np.argmax(dist))]]
    if np.linalg.norm(b - a) > separation:
        return _share(cluster, np.array([a, b]))
    return a, b - a


class ContactAnalyzer:
    """First, second and third contact of a bolt on its nut, for any orientation: the
    thesis's fixed-pivot procedure, classified by its criteria of section 4.2.

    Meshes and their python-fcl BVHs are built once here and reused by every
    :meth:`analyze` call (the bolt only moves). One analyser per process: fcl objects
    neither pickle nor release the GIL.

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair (lengths in ``spec.units``).
    chord : float, optional
        Chord tolerance of the generated meshes (default
        :data:`threadmate.geometry.DEFAULT_CHORD`, 5e-6 in).
    compliance_z : float
        Compliance centre on the bolt axis, bolt frame (default 0: the tip centre).
    bolt_mesh, nut_mesh : path or trimesh.Trimesh, optional
        Meshes from CAD instead of generated ones, each in its own frame (bolt tip face at
        z = 0, nut top face at z = 0, axes along Z); refused with :class:`InputError`
        otherwise. Regions and normals still come from the exact bodies of ``spec``. The
        deviation that sets the tolerances is measured only where such a mesh follows the
        spec (:mod:`._cad`); a contact farther than :attr:`off_spec_tolerance` from the
        spec's surface is labelled ``point``, ``countersink`` or ``other``.
    mesh_units : {"in", "mm"}, optional
        Length units of the mesh files (default: the units a threadmate STL declares in
        its header, else the spec's; a header that disagrees is refused). A mesh in other
        units than the spec's is scaled into them.
    max_faces : int, optional
        Most triangles a mesh file may have (default ``threadmate._validate.MAX_FACES``;
        see :func:`threadmate.geometry.load_mesh`).
    quasi_tolerance : float, optional
        Largest pivot offset of a quasi-stable two-point state (default pitch / 10).
    interference_tolerance : float, optional
        Noise floor of the interference: an embedding at most this deep counts as none
        when comparing it with the origin drop (default 4 x the mesh deviation bound).
    max_turn : float
        Search range of the second and third stages (degrees, default 30).
    """

    #: Distance from the exact surface beyond which a contact on a CAD mesh lies where the
    #: mesh does not follow the spec (None: generated meshes, which always do): the feature
    #: tolerance plus :data:`OFF_SPEC_FACTOR` mesh deviations.
    off_spec_tolerance: float | None

    def __init__(
        self,
        spec: ThreadSpec,
        *,
        chord: float | None = None,
        compliance_z: float = 0.0,
        bolt_mesh: Any = None,
        nut_mesh: Any = None,
        quasi_tolerance: float | None = None,
        interference_tolerance: float | None = None,
        max_turn: float = 30.0,
        mesh_units: str | None = None,
        max_faces: int | None = None,
    ) -> None:
        if not isinstance(spec, ThreadSpec):
            raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
        chord = _positive("chord", chord)
        max_faces = check_max_faces(max_faces)  # before any mesh is built
        compliance_z = check_length("compliance_z", compliance_z, spec.units, signed=True)
        if not (isinstance(max_turn, int | float) and 0 < max_turn <= 90):
            raise InputError(f"max_turn must be within (0, 90] degrees, got {max_turn!r}")
        self.spec = spec
        self.units = spec.units
        self.compliance_z = float(compliance_z)
        self.bolt = bolt_body(spec)
        self.nut = nut_body(spec)

        if mesh_units is not None and mesh_units not in MM_PER_UNIT:
            raise InputError(f"mesh_units must be 'in' or 'mm', got {mesh_units!r}")
        generated = None
        if bolt_mesh is None or nut_mesh is None:
            generated = dict(zip(("bolt", "nut"), thread_meshes(spec, chord), strict=True))
        self.chord = float(chord if chord is not None else DEFAULT_CHORD[spec.units])
        #: Where each mesh came from and how it follows the spec (:attr:`mesh_info`).
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
        deviation = max(float(info["deviation"]) for info in self._mesh_info.values())
        self._setup(
            meshes["bolt"],
            meshes["nut"],
            max(deviation, 0.0),
            quasi_tolerance,
            interference_tolerance,
            max_turn,
        )
        if fits:
            self.off_spec_tolerance = self.feature_tolerance + OFF_SPEC_FACTOR * max(
                self.deviation, 1e-9 * spec.pitch
            )
            for name, fit in fits.items():
                self._describe_fit(name, fit)

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

    def _setup(
        self,
        bolt_mesh: trimesh.Trimesh,
        nut_mesh: trimesh.Trimesh,
        deviation: float,
        quasi_tolerance: float | None,
        interference_tolerance: float | None,
        max_turn: float,
    ) -> None:
        spec = self.spec
        self.deviation = deviation
        self.engine = CollisionPair(bolt_mesh, nut_mesh)
        self._bolt_tree = cKDTree(self.engine.bolt_vertices)
        # Where the bolt's teeth begin to engage, from the exact bodies (also under a CAD
        # mesh, which the spec describes where it follows it): in phase below the nut's.
        self._engagement, self._nut_engagement = engagement_outline(self.bolt, self.nut)
        self._nut_tree = cKDTree(self.engine.nut_vertices)
        travel = TRAVEL_TOLERANCE[spec.units]
        self.search = Search(
            travel=travel,
            separation=spec.pitch / 4,
            pitch=spec.pitch,
            min_radius=0.5 * min(spec.nut.minor, spec.bolt.minor),
            max_turn=float(max_turn),
        )
        bound = max(deviation, 1e-9 * spec.pitch)
        #: Distance within which a contact point is taken to lie on a face or edge.
        self.feature_tolerance = 2.0 * bound + 10.0 * travel
        self.off_spec_tolerance = None
        self.quasi_tolerance = _positive("quasi_tolerance", quasi_tolerance) or spec.pitch / 10
        self.interference_tolerance = (
            _positive("interference_tolerance", interference_tolerance) or 4.0 * bound
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

    @property
    def tolerances(self) -> dict[str, float]:
        """Tolerances in force (spec units)."""
        return {
            "travel": self.search.travel,
            "separation": self.search.separation,
            "feature": self.feature_tolerance,
            "interference": self.interference_tolerance,
            "quasi": self.quasi_tolerance,
            "mesh_deviation": self.deviation,
        }

    # -- pieces ---------------------------------------------------------------------------
    def _contacts(self, pose: Pose, clusters: list[Cluster]) -> list[Contact]:
        if not clusters:
            return []
        tol = self.feature_tolerance
        out = []
        for c in clusters:
            n, fn, fb = contact_normal(self.nut, self.bolt, pose, c.point, tol)
            out.append(
                Contact(
                    _vec(c.point),
                    _vec(n),
                    c.pairs,
                    region_at(self.bolt, pose.to_bolt(c.point), fb, self.off_spec_tolerance),
                    region_at(self.nut, c.point, fn, self.off_spec_tolerance),
                    fb.kind,
                    fn.kind,
                )
            )
        return out

    def _centre(self, pose: Pose) -> NDArray[np.float64]:
        return pose.to_fixed(np.array([0.0, 0.0, self.compliance_z]))

    def _interference(self, pose: Pose, sectors: frozenset[int] | None) -> float:
        eng = self.engine
        pairs = eng.pairs(pose, sectors)
        if len(pairs) == 0:
            return 0.0
        bolt_tris_f, nut_tris = eng.triangles(pose, pairs)
        segs = intersection_segments(bolt_tris_f, nut_tris)
        ends = np.concatenate([segs.start, segs.end])
        bolt_tris_b = eng.bolt_vertices[eng.bolt_faces[np.unique(pairs[:, 0])]]
        nut_tris_f = eng.nut_vertices[eng.nut_faces[np.unique(pairs[:, 1])]]
        return interference_depth(
            self.bolt,
            self.nut,
            pose,
            eng.bolt_vertices,
            self._bolt_tree,
            eng.nut_vertices,
            self._nut_tree,
            bolt_tris_b,
            nut_tris_f,
            ends,
            self.search.separation,
        )

    def _turn(
        self,
        name: str,
        start: Pose,
        existing: list[tuple[Contact, Cluster]],
        axis_point: NDArray[np.float64],
        axis: NDArray[np.float64],
    ) -> tuple[StageResult, Pose, list[tuple[Contact, Cluster]], frozenset[int] | None] | None:
        out = turn_to_new_contact(
            self.engine, start, axis_point, axis, [cl for _, cl in existing], self.search
        )
        if out is None:
            return None
        found = [c for c in out.existing if c is not None] + out.new
        fresh = iter(zip(self._contacts(out.contact, found), found, strict=True))
        # An existing contact without pairs left lies on the turn axis: it stays put.
        kept = [
            next(fresh) if c is not None else old
            for c, old in zip(out.existing, existing, strict=True)
        ]
        both = kept + list(fresh)
        stage = StageResult.at(
            name,
            out.free,
            tuple(c for c, _ in both),
            out.angle,
            out.queries,
            axis=(axis_point, axis),
        )
        return stage, out.contact, both, out.sectors

    # -- the analysis ---------------------------------------------------------------------
    def analyze(self, roll: float, pitch: float, phase: float) -> ContactResult:
        """The three fixed-pivot contact stages and the thesis's 4.2 classification of one
        configuration.

        Parameters
        ----------
        roll, pitch : float
            Tilt of the bolt axis about fixed X and Y (degrees, within +/-45).
        phase : float
            Spin of the bolt about its own axis (degrees, any finite value).

        Returns
        -------
        ContactResult
        """
        roll, pitch, phase = check_configuration(roll, pitch, phase)
        eng = self.engine
        q0 = eng.queries
        rotation = bolt_rotation(roll, pitch, phase)
        floor = (
            -float(self.nut.z_max - self.nut.z_min)
            - float((eng.bolt_vertices @ rotation[2]).max())
            - self.spec.pitch
        )
        none = {name: StageResult(name, False) for name in ("first", "second", "third")}
        common: dict[str, Any] = dict(
            units=self.units,
            roll=roll,
            pitch=pitch,
            phase=phase,
            compliance_z=self.compliance_z,
            tolerances=self.tolerances,
        )

        def done(cls: str, **kw: Any) -> ContactResult:
            stages = {**none, **{k: v for k, v in kw.items() if k in none}}
            rest = {k: v for k, v in kw.items() if k not in none}
            return ContactResult(
                classification=cls, queries=eng.queries - q0, **stages, **common, **rest
            )

        s1 = first_contact(eng, rotation, self.search, floor)
        if s1 is None or not s1.clusters:
            return done("no-contact")
        clusters = s1.clusters
        c1 = tuple(self._contacts(s1.contact, clusters))
        centre = self._centre(s1.contact)
        turn_line = None
        if (
            len(clusters) == 1
            and np.ptp(clusters[0].ends, axis=0).max() > self.search.separation
            and c1[0].bolt_feature == "cap"
        ):
            # The tip face itself touches over an area (an upright bolt flat on the top
            # face): the area's hull decides the support (see _flat_support).
            support = _flat_support(clusters[0], centre, self.search.separation)
            if isinstance(support, list):
                clusters = support
                c1 = tuple(self._contacts(s1.contact, clusters))
            elif support is not None:
                turn_line = support
        held = list(zip(c1, clusters, strict=True))
        first = StageResult.at("first", s1.free, c1, 0.0, s1.queries)
        tol = self.feature_tolerance
        # In phase: the whole tip face went below the nut's top face before touching (with
        # a point or a countersink: the bolt's teeth below the nut's first full tooth).
        if s1.free.origin[2] + float((self._engagement @ rotation[2]).max()) < (
            self._nut_engagement - tol
        ):
            return done("in-phase", first=first)

        # Second contact: turn about the nut's tangent at the first contact.
        if len(c1) >= 2:
            second, pose2 = StageResult.at("second", s1.free, c1, 0.0, 0), s1.contact
        else:
            if turn_line is None:
                pivot = np.array(c1[0].point)
                tangent = turn_axis_tangent(self.nut, self.bolt, s1.contact, pivot, tol)
            else:
                pivot, tangent = turn_line
            axis = lowering_direction(pivot, tangent, centre)
            turned = self._turn("second", s1.contact, held, pivot, axis)
            if turned is None:
                return done("no-contact", first=first)
            second, pose2, held, _ = turned

        # Third contact: turn about the pivot axis through the two contacts.
        c2 = second.contacts
        p1, p2 = np.array(c2[0].point), np.array(c2[1].point)
        offset = pivot_offset(p1, p2, self._centre(pose2))
        sectors: frozenset[int] | None = None  # where the third pose meets the nut
        rolling = False  # the thesis's rolling axis: a pivot contact gained triangle pairs
        if len(c2) >= 3:
            third = StageResult.at("third", second.found_pose, c2, 0.0, 0)
        else:
            axis = lowering_direction(p1, p2 - p1, self._centre(pose2))
            turned = self._turn("third", pose2, held[:2], p1, axis)
            if turned is not None:
                third, sectors = turned[0], turned[3]
                rolling = is_rolling(
                    [c.pairs for c in c2[:2]], [c.pairs for c in third.contacts[:2]]
                )
            else:
                third = StageResult("third", False)
        interference = math.nan
        drop = math.nan
        if third.found:
            interference = self._interference(third.found_pose, sectors)
            drop = float(second.found_origin[2] - third.found_origin[2])
        cls = classify(
            first_found=True,
            in_phase=False,
            second_found=True,
            offset=offset,
            third_found=third.found,
            interference=interference,
            origin_drop=drop,
            quasi_tolerance=self.quasi_tolerance,
            interference_tolerance=self.interference_tolerance,
        )
        return done(
            cls,
            first=first,
            second=second,
            third=third,
            interference=interference,
            origin_drop=drop,
            pivot_offset=offset,
            rolling=rolling,
        )


@functools.lru_cache(maxsize=4)
def _cached(
    spec: ThreadSpec, chord: float | None, compliance_z: float, quasi_tolerance: float | None
) -> ContactAnalyzer:
    return ContactAnalyzer(
        spec, chord=chord, compliance_z=compliance_z, quasi_tolerance=quasi_tolerance
    )


def analyze(
    spec: ThreadSpec,
    *,
    roll: float = 0.0,
    pitch: float = 0.0,
    phase: float = 0.0,
    chord: float | None = None,
    compliance_z: float = 0.0,
    quasi_tolerance: float | None = None,
) -> ContactResult:
    """The contact stages of one configuration (a cached :class:`ContactAnalyzer` per
    spec and settings).

    Examples
    --------
    >>> from threadmate.geometry import spec_from_designation
    >>> from threadmate.contact import analyze
    >>> result = analyze(spec_from_designation("1/4-20 UNC-2A/2B"), roll=4, pitch=0,
    ...                  phase=185)                                      # doctest: +SKIP
    >>> result.classification, result.third.contacts[0].point           # doctest: +SKIP
    """
    return _cached(spec, chord, compliance_z, quasi_tolerance).analyze(roll, pitch, phase)
