"""What a contact point touches on each exact body: feature, region, normal, tangent.

The meshes only say where the bodies cross; everything a contact reports beyond its
location comes from the exact helical bodies (:class:`threadmate.geometry.ThreadBody`).

Features. A point (in a body's own frame) within ``tol`` of a body's surface lies on

- ``rim``: the edge where the end face (bolt ``base``, nut ``surface``) meets the thread;
- ``cap``: the end face itself;
- ``corner``: a sharp (unfilleted) corner of the profile swept along the helix;
- ``thread``: the smooth helical thread surface;
- ``bevel``: the surface of the bolt's point (chamfer cone, round) or the nut's countersink;
- ``kink``: the edge where the bevel meets the thread;
- ``mesh``, ``mesh-edge``: with a mesh from CAD, where the mesh does not follow the spec
  (:class:`OffSpec`: a point, countersink or chamfer the spec does not state, a head,
  flats): the mesh's own face there, with the mesh's normal, or its edge where faces
  meet at more than :data:`CREASE` degrees (where an unstated chamfer meets the thread
  or the tip face). An exact edge touching a ``mesh`` face is refined against the mesh's
  surface; a ``mesh-edge`` is not refined.

With a point or countersink the end face's outline is a circle (the rim), inside the
thread's band. Rims, corners and kinks are edges, the others faces. ``tol`` is a few
chord tolerances: the contact point sits within the meshes' deviation of both exact
surfaces.

Regions come from the exact profile with the rule of :meth:`ThreadBody.region_of`: a
point on the end face or its rim has the end face's region (``base`` / ``surface``; the
thesis names the tip rim landing on the nut's top ``base/surface``), any other the
profile's region (:meth:`Profile.region`) at its helix coordinate ``t``.

Common normal (fixed frame, unit, from the nut into the bolt), by features:

1. the nut touches with a face: the nut's exact outward normal there;
2. else the bolt touches with a face: minus the bolt's exact outward normal;
3. else (edge on edge) the cross product of the two edge tangents (thesis 3.11), oriented
   along the nut's outward side and against the bolt's.

The helical surface ``r = R(t)``, ``t = z - hand * lead * theta / 2 pi``, has the gradient
``e_r + R'(t) hand lead / (2 pi r) e_theta - R'(t) e_z`` (pointing out of the bolt's
material and into the nut's).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from ..._angles import TWO_PI
from ..._vectors import cross3
from ...geometry import Pose, ThreadBody
from ._kernels import (
    CIRCLE,
    HELIX,
    KINK,
    RIM,
    EdgeCurve,
    _arrays,
    closest_on_edge,
    crossing_of_edges,
    edge_points,
    feature,
    least_on_grid,
    window_grid,
)

__all__ = [
    "EDGE_FEATURE_KINDS",
    "Feature",
    "OffSpec",
    "CREASE",
    "feature_at",
    "contact_normal",
    "region_at",
    "off_spec_region",
    "OFF_SPEC_REGIONS",
    "turn_axis_tangent",
    "refine_on_edge",
    "refined_contact",
    "edge_crossing",
    "lowest_on_rim",
    "engagement_outline",
    "on_thread",
]

#: Angle (degrees) between a CAD mesh's faces above which they meet at an edge (a
#: ``mesh-edge``); below it they tessellate one smooth surface (a chord of a thousandth
#: of a radius turns the faces by some 5 degrees).
CREASE = 30.0


#: Kinds of :class:`Feature` that are edges: the rim, a sharp corner of the thread, a
#: kink (where a point or countersink meets the thread), a CAD mesh's edge.
EDGE_FEATURE_KINDS = frozenset({"rim", "corner", "kink", "mesh-edge"})


@dataclass(frozen=True)
class Feature:
    """The feature of one exact body at a point (vectors in that body's frame).

    Attributes
    ----------
    kind : {"rim", "cap", "corner", "thread", "bevel", "kink", "mesh", "mesh-edge"}
    normal : (3,) array or None
        Outward unit normal for a face (None for an edge).
    tangent : (3,) array or None
        Unit tangent for an edge (None for a face).
    side : (3,) array
        Outward direction of the material at the point (the face normal, or for an edge
        the sum of its two faces' normals); orients edge-on-edge normals.
    """

    kind: str
    normal: NDArray[np.float64] | None
    tangent: NDArray[np.float64] | None
    side: NDArray[np.float64]

    @property
    def is_edge(self) -> bool:
        """Whether the feature is an edge (:data:`EDGE_FEATURE_KINDS`)."""
        return self.kind in EDGE_FEATURE_KINDS

    @property
    def face_normal(self) -> NDArray[np.float64]:
        """``normal`` of a face feature (not for an edge, which has none)."""
        assert self.normal is not None, f"a {self.kind} feature has no normal"
        return self.normal

    @property
    def edge_tangent(self) -> NDArray[np.float64]:
        """``tangent`` of an edge feature (not for a face, which has none)."""
        assert self.tangent is not None, f"a {self.kind} feature has no tangent"
        return self.tangent


@dataclass(frozen=True)
class OffSpec:
    """Where meshes from CAD do not follow the spec: the ``mesh`` feature.

    A point of such a mesh lies off the spec where it is farther than ``tolerance`` from
    the exact surface, or where a triangle of the mesh there does not follow the spec
    (its deviation exceeds the mesh's, :func:`._cad.mesh_fit`; see :func:`._cad.off_spec`):
    a triangle of an unstated chamfer that meets the thread has a corner on the spec's
    flank, and its points near that corner lie near the flank without lying on it.

    Attributes
    ----------
    tolerance : float
        Distance from a body's exact surface beyond which its mesh does not follow it
        (:attr:`ContactAnalyzer.off_spec_tolerance
        <threadmate.contact.ContactAnalyzer>`).
    bodies : frozenset of str
        The bodies (``"bolt"``, ``"nut"``) whose meshes come from CAD.
    surface : callable
        ``surface(kind, point)``: for a point (``(3,)``, in that body's frame) the
        ``kind`` mesh's outward unit normal nearest it (the faces' there summed), the
        tangent of the mesh's edge there when its faces meet at more than
        :data:`CREASE` degrees (else None), and whether the triangles there follow the
        spec.
    distance : callable
        ``distance(kind, points)``: the signed distance (negative inside) of points
        (``(n, 3)``, in that body's frame) from the ``kind`` mesh.
    """

    tolerance: float
    bodies: frozenset[str]
    surface: Callable[
        [str, NDArray[np.float64]],
        tuple[NDArray[np.float64], NDArray[np.float64] | None, bool],
    ]
    distance: Callable[[str, NDArray[np.float64]], NDArray[np.float64]]

    def feature(self, body: ThreadBody, point: NDArray[np.float64]) -> Feature | None:
        """The ``mesh`` feature of ``body`` at ``point`` (body frame) where its CAD mesh
        does not follow the spec, else None (the exact body's features apply)."""
        if body.kind not in self.bodies:
            return None
        p = np.asarray(point, dtype=float)
        normal, tangent, follows = self.surface(body.kind, p)
        if follows and float(body.surface_distance(p)) <= self.tolerance:
            return None
        n = _unit(np.asarray(normal, dtype=float).reshape(3))
        if tangent is not None:
            return Feature("mesh-edge", None, _unit(np.asarray(tangent, dtype=float)), n)
        return Feature("mesh", n, None, n)


def _t_of(body: ThreadBody, theta: float, z: float) -> float:
    """:meth:`ThreadBody.t_of` of one point, in plain floats (the same operations: the
    contact code asks one point at a time, where numpy's overhead is most of the cost)."""
    t = z - body.hand * body.lead * theta / TWO_PI
    thread_pitch = body.profile.pitch
    return t - thread_pitch * math.floor(t / thread_pitch + 0.5)


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    n = math.sqrt(float(v @ v))  # ``np.linalg.norm`` of a vector, without its overhead
    return v / n if n > 0 else v


def _helix_tangent(body: ThreadBody, p: NDArray[np.float64]) -> NDArray[np.float64]:
    r = math.hypot(p[0], p[1])
    theta = math.atan2(p[1], p[0])
    return _unit(
        np.array([-r * math.sin(theta), r * math.cos(theta), body.hand * body.lead / TWO_PI])
    )


def _sharp_corners(body: ThreadBody) -> list[float]:
    """``|t|`` of the profile's sharp corners (a zero fillet keeps its corner)."""
    prof = body.profile
    a1, _, _, a4 = prof.breakpoints
    out = []
    if prof.fillet_hi <= 0:
        out.append(a1)
    if prof.fillet_lo <= 0:
        out.append(a4)
    return out


def _thread_distance(body: ThreadBody, p: NDArray[np.float64]) -> tuple[float, float, float]:
    """The helix coordinate ``t`` of ``p`` (body frame), the profile radius there and the
    distance to the thread in the axial section: the radial offset projected on the
    profile's normal (exact on flats and flanks; contact points lie within a tolerance)."""
    prof = body.profile
    t = _t_of(body, math.atan2(p[1], p[0]), float(p[2]))
    R = float(prof.radius(t))
    return t, R, abs(math.hypot(p[0], p[1]) - R) / math.hypot(1.0, float(prof.slope(t)))


def on_thread(body: ThreadBody, point: NDArray[np.float64], feature: Feature, tol: float) -> bool:
    """Whether ``feature`` at ``point`` (body frame) belongs to the body's thread: a face
    of the thread or a corner between two (the helix), or an edge where the thread meets
    the end face or the point or countersink (a rim on the thread, a kink)."""
    if feature.kind in ("thread", "corner", "kink"):
        return True
    return feature.kind == "rim" and _thread_distance(body, np.asarray(point, float))[2] <= tol


def feature_at(
    body: ThreadBody, point: NDArray[np.float64], tol: float, off_spec: OffSpec | None = None
) -> Feature:
    """The feature of ``body`` at ``point`` (body frame); see the module docstring.
    ``off_spec``: where a CAD mesh does not follow the spec, its ``mesh`` feature.

    Compiled (:func:`._kernels.feature`): the point's helix coordinate and its distances
    to the thread, the end face and the point or countersink decide the kind; a face's
    normal is the thread's helical normal, the end face's or the envelope's, an edge's
    side the sum of its two faces' normals."""
    p = np.asarray(point, dtype=float)
    if off_spec is not None:
        found = off_spec.feature(body, p)
        if found is not None:
            return found
    kind, v = feature(body, float(p[0]), float(p[1]), float(p[2]), float(tol))
    if kind in EDGE_FEATURE_KINDS:
        return Feature(kind, None, v[3:6], v[6:9])
    n = v[:3]
    return Feature(kind, n, None, n)


def contact_normal(
    nut: ThreadBody,
    bolt: ThreadBody,
    pose: Pose,
    point_f: NDArray[np.float64],
    tol: float,
    off_spec: OffSpec | None = None,
) -> tuple[NDArray[np.float64], Feature, Feature]:
    """Common normal at a contact (fixed frame, unit, from the nut into the bolt).

    Returns the normal and the nut's and bolt's features (each in its own frame);
    ``off_spec`` as for :func:`feature_at`.
    """
    fn = feature_at(nut, point_f, tol, off_spec)
    fb = feature_at(bolt, pose.to_bolt(point_f), tol, off_spec)
    return _common_normal(fn, fb, pose), fn, fb


def _common_normal(fn: Feature, fb: Feature, pose: Pose) -> NDArray[np.float64]:
    if not fn.is_edge:
        return fn.face_normal.copy()
    if not fb.is_edge:
        return -pose.vector_to_fixed(fb.face_normal)
    tb = pose.vector_to_fixed(fb.edge_tangent)
    side_b = pose.vector_to_fixed(fb.side)
    n = cross3(tb, fn.edge_tangent)
    if np.linalg.norm(n) < 1e-9:  # parallel edges: split the two sides
        n = fn.side - side_b
    n = _unit(n)
    if n @ fn.side - n @ side_b < 0:
        n = -n
    return n


def region_at(
    body: ThreadBody,
    point: NDArray[np.float64],
    feature: Feature,
    off_spec: float | None = None,
) -> str:
    """Region of ``body`` at ``point`` (body frame) from the exact profile: the end face's
    name (``base`` / ``surface``) on the cap and its rim, the point's or countersink's
    (``chamfer``, ``round``, ``countersink``) on its surface and on the edge where it meets
    the thread, else the profile region at the point's helix coordinate ``t``.

    ``off_spec``: with a mesh from CAD, a point farther than this from the exact surface
    lies where the mesh does not follow the spec; it is labelled by where it lies
    (:func:`off_spec_region`).
    """
    p = np.asarray(point, dtype=float)
    if off_spec is not None and float(body.surface_distance(p)) > off_spec:
        return off_spec_region(body, p)
    if feature.kind in ("mesh", "mesh-edge"):
        return off_spec_region(body, p)
    if feature.kind in ("cap", "rim"):
        return body.cap_region
    if feature.kind in ("bevel", "kink"):
        assert body.envelope is not None
        return body.envelope.region
    return str(body.profile.region(_t_of(body, math.atan2(p[1], p[0]), float(p[2]))))


#: Labels of contacts on a CAD mesh where it does not follow the spec's exact surfaces.
OFF_SPEC_REGIONS = ("point", "countersink", "other")


def off_spec_region(body: ThreadBody, point: NDArray[np.float64]) -> str:
    """Where a point of a CAD mesh off the spec's exact surfaces lies: ``point`` on the
    bolt's end (within its point, or one pitch of the tip for a flat one), ``countersink``
    on the nut's entry (within its countersink, or one pitch of the top face), else
    ``other`` (a head, the nut's flats, a thread run-out the spec does not have)."""
    reach = max(body.envelope.depth if body.envelope else 0.0, body.profile.pitch)
    z = float(np.asarray(point, dtype=float)[2]) - body.cap_z
    if body.kind == "bolt":
        return "point" if z <= reach else "other"
    return "countersink" if z >= -reach else "other"


def turn_axis_tangent(
    nut: ThreadBody, bolt: ThreadBody, pose: Pose, point_f: NDArray[np.float64], tol: float
) -> NDArray[np.float64]:
    """Tangent of the nut's surface or edge at a first contact: the second stage's axis.

    Rule (by the features at the contact):

    - the nut touches with an edge (its top rim, a sharp thread corner): that edge's
      tangent (the rim: the nut's top outline ``r = R_n(theta)``; a corner: its helix);
    - the nut touches with a face and the bolt with an edge (the bolt's tip rim or a sharp
      corner): the bolt edge's tangent projected onto the nut's tangent plane. Of all the
      tangents of the nut's face this is the one about which the bolt can turn without at
      once cutting into the face beside the contact (at the lowest point of a tilted rim
      resting on the top face, the rim's tangent is horizontal: it lies in the face);
    - face on face: on the top face the counter-clockwise circumferential direction
      (thesis eq. 3.74), on the thread the helix through the point.
    """
    p = np.asarray(point_f, dtype=float)
    fn = feature_at(nut, p, tol)
    if fn.is_edge:
        return fn.edge_tangent
    fb = feature_at(bolt, pose.to_bolt(p), tol)
    if fb.is_edge:
        t = pose.vector_to_fixed(fb.edge_tangent)
        t = t - (t @ fn.face_normal) * fn.face_normal
        if np.linalg.norm(t) > 1e-9:
            return _unit(t)
    if fn.kind in ("cap", "bevel"):  # faces of revolution: the circumferential direction
        theta = math.atan2(p[1], p[0])
        return np.array([-math.sin(theta), math.cos(theta), 0.0])
    return _helix_tangent(nut, p)


def refine_on_edge(
    nut: ThreadBody,
    bolt: ThreadBody,
    pose: Pose,
    point_f: NDArray[np.float64],
    tol: float,
    window: float,
) -> NDArray[np.float64]:
    """The exact contact point of an edge touching a face near ``point_f`` (fixed frame).

    A mesh locates an edge-on-face contact only to within a facet of the edge, and the
    facet it picks jumps as the pose moves. The exact point is where the edge (the exact
    rim or sharp corner helix) comes closest to, or deepest into, the other body's exact
    surface: searched along the edge within ``window`` (arc length) of ``point_f`` on
    shrinking grids. Contacts that are not edge-on-face are returned unchanged.
    """
    p = np.asarray(point_f, dtype=float)
    return _refine(
        nut,
        bolt,
        pose,
        p,
        tol,
        window,
        feature_at(nut, p, tol),
        feature_at(bolt, pose.to_bolt(p), tol),
    )


def refined_contact(
    nut: ThreadBody,
    bolt: ThreadBody,
    pose: Pose,
    point_f: NDArray[np.float64],
    tol: float,
    window: float,
    off_spec: OffSpec | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], Feature, Feature]:
    """:func:`refine_on_edge`, then :func:`contact_normal` at the refined point.

    A face-on-face contact is not moved: its features are then those already found, and
    are not looked up a second time (half the cost of a contact on the thread). Where a
    CAD mesh does not follow the spec (``off_spec``, :func:`feature_at`) its own surface
    is the face: an exact edge touching it is followed to where it comes closest to, or
    deepest into, the mesh.
    """
    p = np.asarray(point_f, dtype=float)
    fn = feature_at(nut, p, tol, off_spec)
    fb = feature_at(bolt, pose.to_bolt(p), tol, off_spec)
    if fn.is_edge or fb.is_edge:
        p = _refine(nut, bolt, pose, p, tol, window, fn, fb, off_spec)
        fn = feature_at(nut, p, tol, off_spec)
        fb = feature_at(bolt, pose.to_bolt(p), tol, off_spec)
    return _common_normal(fn, fb, pose), p, fn, fb


def _refine(
    nut: ThreadBody,
    bolt: ThreadBody,
    pose: Pose,
    p: NDArray[np.float64],
    tol: float,
    window: float,
    fn: Feature,
    fb: Feature,
    off_spec: OffSpec | None = None,
) -> NDArray[np.float64]:
    """:func:`refine_on_edge` with the features at ``p`` known; a ``mesh`` face is the
    CAD mesh's surface (``off_spec``)."""
    if "mesh-edge" in (fn.kind, fb.kind):
        return p  # a CAD mesh's own edge: no exact curve to follow
    if fn.is_edge and fb.is_edge:
        return _edge_crossing(nut, fn, bolt, fb, pose, p, window)[0]
    if fn.is_edge == fb.is_edge:
        return p
    if fn.is_edge:
        edge_body, edge, face_body, face, anchor = nut, fn, bolt, fb, p
    else:
        edge_body, edge, face_body, face, anchor = bolt, fb, nut, fn, pose.to_bolt(p)
    curve = _edge_curve(edge_body, edge, anchor)
    theta0 = math.atan2(anchor[1], anchor[0])
    half = window / max(math.hypot(anchor[0], anchor[1]), 1e-300)
    if face.kind == "mesh" and off_spec is not None:
        q = _closest_to_mesh(curve, face_body, pose, fn.is_edge, off_spec, theta0, half)
    else:
        got = _arrays(face_body)
        arrays = (got.prof, got.env, got.shape)
        q = closest_on_edge(curve, arrays, pose.rotation, pose.origin, fn.is_edge, theta0, half)
    return q if fn.is_edge else pose.to_fixed(q.reshape(1, 3))[0]


def _closest_to_mesh(
    curve: EdgeCurve,
    face_body: ThreadBody,
    pose: Pose,
    into_bolt: bool,
    off_spec: OffSpec,
    best: float,
    half: float,
) -> NDArray[np.float64]:
    """:func:`._kernels.closest_on_edge` against a CAD mesh's own surface
    (``off_spec``) where it does not follow the spec: the same windows, the mesh's signed
    distance in place of the exact body's."""
    for _ in range(3):
        angles = window_grid(best, half)
        points = edge_points(curve, angles)
        moved = pose.to_bolt(points) if into_bolt else pose.to_fixed(points)
        best = least_on_grid(angles, off_spec.distance(face_body.kind, moved))
        half /= 8
    return edge_points(curve, np.array([best]))[0]


def _edge_curve(body: ThreadBody, feature: Feature, anchor: NDArray[np.float64]) -> EdgeCurve:
    """The exact edge of ``feature`` through ``anchor`` (body frame), as the compiled
    kernels follow it (:func:`._kernels.crossing_of_edges`, :func:`._kernels.closest_on_edge`)."""
    got = _arrays(body)
    hand_lead = float(body.hand * body.lead)
    env = body.envelope
    curve = partial(EdgeCurve, prof=got.prof, env=got.env, rise=got.rise, hand_lead=hand_lead)
    if env is not None and feature.kind == "kink":
        return curve(KINK, radius=0.0, height=float(anchor[2]), angle=0.0)
    if env is not None and feature.kind == "rim":
        return curve(CIRCLE, radius=env.face_radius, height=body.cap_z, angle=0.0)
    if feature.kind == "rim":
        return curve(RIM, radius=0.0, height=body.cap_z, angle=0.0)
    theta0 = math.atan2(anchor[1], anchor[0])
    r = math.hypot(anchor[0], anchor[1])
    z0 = float(anchor[2])
    corners = _sharp_corners(body)
    if corners:
        t0 = _t_of(body, theta0, z0)
        uc = min(corners, key=lambda u: abs(abs(t0) - u))
        r = float(body.profile.radius(uc))
    return curve(HELIX, radius=r, height=z0, angle=theta0)


def _edge_crossing(
    nut: ThreadBody,
    fn: Feature,
    bolt: ThreadBody,
    fb: Feature,
    pose: Pose,
    point_f: NDArray[np.float64],
    window: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Where two exact edges cross, seen along Z (an edge-on-edge contact under a vertical
    approach): Gauss-Newton on the two edges' polar angles from the mesh's point. Returns
    the nut edge's point and the bolt edge's above or below it (fixed frame);
    ``(point_f, None)`` when it does not converge within ``window``."""
    anchor_b = pose.to_bolt(point_f)
    a = math.atan2(point_f[1], point_f[0])
    b = math.atan2(anchor_b[1], anchor_b[0])
    found = crossing_of_edges(
        _edge_curve(nut, fn, point_f),
        _edge_curve(bolt, fb, anchor_b),
        pose.rotation,
        pose.origin,
        a,
        b,
    )
    if found is None:
        return point_f, None
    q, w = found
    if not np.all(np.isfinite(q)) or float(np.linalg.norm(q - point_f)) > window:
        return point_f, None
    return q, w


def edge_crossing(
    nut: ThreadBody,
    bolt: ThreadBody,
    pose: Pose,
    nut_point: NDArray[np.float64],
    bolt_point_f: NDArray[np.float64],
    tol: float,
    window: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Where the nut's edge through ``nut_point`` and the bolt's edge through
    ``bolt_point_f`` (both fixed frame) cross, seen along Z: the nut's point and the
    bolt's point above it (the latter None: not two edges, or no crossing within
    ``window``)."""
    fn = feature_at(nut, nut_point, tol)
    fb = feature_at(bolt, pose.to_bolt(bolt_point_f), tol)
    if not (fn.is_edge and fb.is_edge):
        return nut_point, None
    return _edge_crossing(nut, fn, bolt, fb, pose, nut_point, window)


def lowest_on_rim(
    bolt: ThreadBody, pose: Pose, point_f: NDArray[np.float64], window: float
) -> NDArray[np.float64]:
    """The lowest point (fixed frame) of the bolt's exact tip rim within ``window`` (arc
    length) of ``point_f``."""
    anchor = pose.to_bolt(point_f)
    rim = Feature("rim", None, None, np.zeros(3))
    theta0 = math.atan2(anchor[1], anchor[0])
    half = window / max(math.hypot(anchor[0], anchor[1]), 1e-300)
    best = theta0
    up = pose.rotation[2]  # only heights are compared: the transform's third row
    curve = _edge_curve(bolt, rim, anchor)
    for _ in range(3):
        angles = window_grid(best, half)
        heights = edge_points(curve, angles) @ up
        best = float(angles[int(np.argmin(heights))])
        half /= 8
    return pose.to_fixed(edge_points(curve, np.array([best])))[0]


def engagement_outline(bolt: ThreadBody, nut: ThreadBody) -> tuple[NDArray[np.float64], float]:
    """Where the teeth begin to engage: the bolt's outline (bolt frame) and the nut's
    plane (fixed frame). The bolt is in phase when the whole outline is below the plane.

    With the thesis's flat ends, the tip face's outline and the nut's top face: the whole
    tip face below the top face. A point passes into the bore, and a countersink takes the
    tip, long before the threads engage; teeth engage where both bodies have material
    between the nut's minor radius and the bolt's major radius. Both are taken at the
    *engagement radius*, a quarter of the way from the one to the other: the bolt's outline
    at the height where its point reaches that radius, the nut's plane where its
    countersink does. A point resting on the edge of the bore or in the countersink keeps
    its outline above that plane; once its teeth have dropped beside the nut's, the
    outline is below it.
    """
    r_nut, r_bolt = nut.profile.r_lo, bolt.profile.r_hi
    reach = r_nut + 0.25 * (r_bolt - r_nut)

    def level(body: ThreadBody) -> float:
        env = body.envelope
        if env is None or not float(env.radius(env.z_lo)) < reach < float(env.radius(env.z_hi)):
            return body.cap_z
        return float(brentq(lambda h: float(env.radius(h)) - reach, env.z_lo, env.z_hi, xtol=1e-15))

    return bolt.thread_outline(level(bolt)), level(nut)
