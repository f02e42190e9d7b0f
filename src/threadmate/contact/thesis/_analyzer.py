"""The contact analyser: meshes and BVHs built once, three stages per configuration.

The stages are the thesis's fixed-pivot procedure (each turns about an axis fixed in
space, the compliance is ignored) and the classes its criteria of section 4.2
(:mod:`._stability`); the physical model is the mechanics' (``threadmate settle``).
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull, QhullError, cKDTree

from ..._errors import InputError
from ..._validate import (
    check_configuration,
    check_length,
    check_open_range,
)
from ...geometry import (
    Pose,
    ThreadSpec,
    bolt_rotation,
)
from ..scene import (
    IN_PHASE,
    NO_CONTACT,
    ContactScene,
    as_vec,
    contact_normal,
    engagement_outline,
    intersection_segments,
    region_at,
    scene_for,
    turn_axis_tangent,
)
from ._result import Contact, ContactResult, StageResult
from ._stability import classify, interference_depth, is_rolling, pivot_offset
from ._stages import (
    Cluster,
    Search,
    first_contact,
    lowering_direction,
    turn_to_new_contact,
)

__all__ = ["ContactAnalyzer", "analyze"]


def _positive(name: str, value: float | None) -> float | None:
    if value is None:
        return None
    return check_open_range(name, value, 0.0, math.inf)


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

    Its world (exact bodies, meshes and their collision trees, tolerances) is a
    :class:`ContactScene`, built once per process and reused by every :meth:`analyze`
    call (the bolt only moves) and by the mechanics. Building the meshes and trees is
    the cost: one scene per process.

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
    scene : ContactScene, optional
        A scene already built (default :func:`contact_scene` of the spec, chord and
        meshes, built once per process); its spec must be ``spec``.
    """

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
        scene: ContactScene | None = None,
    ) -> None:
        if not isinstance(spec, ThreadSpec):
            raise InputError(f"spec must be a ThreadSpec, got {type(spec).__name__}")
        compliance_z = check_length("compliance_z", compliance_z, spec.units, signed=True)
        if not (isinstance(max_turn, int | float) and 0 < max_turn <= 90):
            raise InputError(f"max_turn must be within (0, 90] degrees, got {max_turn!r}")
        scene = scene_for(
            spec,
            scene,
            chord=chord,
            bolt_mesh=bolt_mesh,
            nut_mesh=nut_mesh,
            mesh_units=mesh_units,
            max_faces=max_faces,
        )
        #: The exact bodies, meshes, collision pair and tolerances (:class:`ContactScene`).
        self.scene = scene
        self.spec = spec
        self.units = spec.units
        self.compliance_z = float(compliance_z)
        self.bolt, self.nut = scene.bolt, scene.nut
        self.chord = scene.chord
        self.engine = scene.engine
        self.deviation = scene.deviation
        self.feature_tolerance = scene.feature_tolerance
        self.off_spec_tolerance = scene.off_spec_tolerance
        self._bolt_tree = cKDTree(self.engine.bolt_vertices)
        # Where the bolt's teeth begin to engage, from the exact bodies (also under a CAD
        # mesh, which the spec describes where it follows it): in phase below the nut's.
        self._engagement, self._nut_engagement = engagement_outline(self.bolt, self.nut)
        self._nut_tree = cKDTree(self.engine.nut_vertices)
        self.search = Search(
            travel=scene.travel,
            separation=spec.pitch / 4,
            thread_pitch=spec.pitch,
            min_radius=0.5 * min(spec.nut.minor, spec.bolt.minor),
            max_turn=float(max_turn),
        )
        bound = max(self.deviation, 1e-9 * spec.pitch)
        self.quasi_tolerance = _positive("quasi_tolerance", quasi_tolerance) or spec.pitch / 10
        self.interference_tolerance = (
            _positive("interference_tolerance", interference_tolerance) or 4.0 * bound
        )

    @property
    def mesh_info(self) -> dict[str, Any]:
        """The meshes used: the scene's :attr:`ContactScene.mesh_info`."""
        return self.scene.mesh_info

    @property
    def mesh_warnings(self) -> list[str]:
        """Warnings about CAD meshes much of whose contact zone is off the spec."""
        return self.scene.mesh_warnings

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
                    as_vec(c.point),
                    as_vec(n),
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
            return done(NO_CONTACT)
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
            return done(IN_PHASE, first=first)

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
                return done(NO_CONTACT, first=first)
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
