"""Exact features of a chamfered, rounded or countersunk end, against closed forms.

The bodies' surfaces of revolution are written out here from their definitions (a cone at
the chamfer angle from the tip circle, a sphere through it, a cone of the countersink's
included angle from the face circle) and the thread profile from conventions.md, not
taken from threadmate.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from _refine_reference import signed_distance_at
from threadmate.contact import (
    Compliance,
    Mechanics,
    engagement_outline,
    off_spec_region,
    region_at,
)
from threadmate.contact.scene import Feature, edge_crossing, feature_at, lowest_on_rim
from threadmate.contact.scene._exact import _edge_curve  # internals with no public form
from threadmate.contact.scene._kernels import edge_points
from threadmate.geometry import (
    BoltPoint,
    BoltSpec,
    Countersink,
    NutSpec,
    Pose,
    ThreadSpec,
    bolt_body,
    nut_body,
)

PITCH = 0.05


BOLT = dict(major=0.24485, pitch_diameter=0.21455, minor=0.1887)
NUT = dict(major=0.2500, pitch_diameter=0.21995, minor=0.2015)
TIP = 0.17  # tip diameter, inside the bolt's minor diameter
SINK = 0.27  # countersink diameter at the face, outside the nut's major diameter
TOL = 1e-6


def _polar(r: float, theta: float, z: float) -> np.ndarray:
    """One point ``(1, 3)`` at radius ``r``, polar angle ``theta`` (radians), height ``z``."""
    return np.array([[r * math.cos(theta), r * math.sin(theta), z]])


def _spec(point: BoltPoint, sink: Countersink | None) -> ThreadSpec:
    return ThreadSpec(
        units="in",
        pitch=PITCH,
        bolt=BoltSpec(**BOLT, point=point),
        nut=NutSpec(**NUT, countersink=sink),
    )


def _sharp_radius(t: float, body: str) -> float:
    """conventions.md's sharp profile, clamped; t wrapped into [-p/2, p/2)."""
    d = BOLT if body == "bolt" else NUT
    t = t - PITCH * math.floor(t / PITCH + 0.5)
    r = d["pitch_diameter"] / 2 + math.sqrt(3) * (PITCH / 4 - abs(t))
    return min(max(r, d["minor"] / 2), d["major"] / 2)


@pytest.fixture(scope="module")
def chamfered() -> ThreadSpec:
    return _spec(BoltPoint("chamfer", angle=45.0, diameter=TIP), Countersink(90.0, SINK))


def test_chamfer_face_normal_and_region(chamfered):
    bolt = bolt_body(chamfered)
    # A point on the cone r = TIP/2 + z tan 45, well inside the chamfer (z small).
    z = 0.004
    theta = 0.7
    r = TIP / 2 + z
    p = np.array([r * math.cos(theta), r * math.sin(theta), z])
    f = feature_at(bolt, p, TOL)
    assert f.kind == "bevel"
    expected = np.array([math.cos(theta), math.sin(theta), -1.0]) / math.sqrt(2)
    np.testing.assert_allclose(f.face_normal, expected, atol=1e-12)
    assert region_at(bolt, p, f) == "chamfer"


def test_chamfer_rim_is_the_tip_circle(chamfered):
    bolt = bolt_body(chamfered)
    theta = 2.1
    p = np.array([TIP / 2 * math.cos(theta), TIP / 2 * math.sin(theta), 0.0])
    f = feature_at(bolt, p, TOL)
    assert f.kind == "rim"
    np.testing.assert_allclose(f.edge_tangent, [-math.sin(theta), math.cos(theta), 0.0], atol=1e-12)
    assert region_at(bolt, p, f) == "base"
    # Inside the circle: the tip face.
    q = 0.5 * p
    assert feature_at(bolt, q, TOL).kind == "cap"


def test_chamfer_kink_lies_on_cone_and_thread(chamfered):
    """The edge where the cone meets the thread: at each angle the height solving
    R(t(theta, z)) = TIP/2 + z (found here by brentq on the closed forms)."""
    bolt = bolt_body(chamfered)
    lead = PITCH

    def gap(z: float, theta: float) -> float:
        return _sharp_radius(z - lead * theta / (2 * math.pi), "bolt") - (TIP / 2 + z)

    for theta in (0.3, 1.9, 4.0):
        # The lowest crossing: the cone leaves the thread's band (r < minor/2) below it.
        z_lo = BOLT["minor"] / 2 - TIP / 2
        z_hi = BOLT["major"] / 2 - TIP / 2
        zs = np.linspace(z_lo, z_hi, 400)
        g = [gap(z, theta) for z in zs]
        k = next(i for i in range(len(g) - 1) if g[i] > 0 >= g[i + 1])
        z = brentq(gap, zs[k], zs[k + 1], args=(theta,), xtol=1e-14)
        r = TIP / 2 + z
        p = np.array([r * math.cos(theta), r * math.sin(theta), z])
        f = feature_at(bolt, p, TOL)
        assert f.kind == "kink"
        assert region_at(bolt, p, f) == "chamfer"
        # Its tangent is perpendicular to both surfaces' normals.
        n_cone = np.array([math.cos(theta), math.sin(theta), -1.0]) / math.sqrt(2)
        assert abs(f.edge_tangent @ n_cone) < 1e-9


def test_signed_distance_is_the_meridian_distance_to_the_nearest_surface(chamfered):
    """The exact bodies' signed distance (negative in the material), which the edge
    refinement minimises, against the closed forms: on a flank, the distance in the axial
    section to the flank line, half the radial offset (the 60-degree profile); on the
    45-degree chamfer and the 90-degree countersink, the offset along the cone's normal;
    beyond the end faces, the distance to the face's outline."""
    bolt, nut = bolt_body(chamfered), nut_body(chamfered)
    lead = PITCH
    rng = np.random.default_rng(11)
    u_flank = 0.012  # mid-flank: the sharp profile's flank spans |t| 0.0038 to 0.0200
    for _ in range(40):
        theta = rng.uniform(-np.pi, np.pi)
        eps = rng.uniform(-1e-4, 1e-4)
        t = u_flank * rng.choice([-1.0, 1.0])
        z = t + lead * theta / (2 * math.pi)
        r = _sharp_radius(t, "bolt") + eps
        assert abs(signed_distance_at(bolt, _polar(r, theta, z + 4 * PITCH))[0] - eps / 2) < 1e-12
        r = _sharp_radius(t, "nut") + eps
        assert abs(signed_distance_at(nut, _polar(r, theta, z - 4 * PITCH))[0] + eps / 2) < 1e-12
        # The chamfer r = TIP/2 + z and the countersink r = SINK/2 + z (z < 0).
        zc = rng.uniform(0.001, 0.006)
        d = signed_distance_at(bolt, _polar(TIP / 2 + zc + eps, theta, zc))[0]
        assert abs(d - eps / math.sqrt(2)) < 1e-12
        zs = -rng.uniform(0.001, 0.004)
        d = signed_distance_at(nut, _polar(SINK / 2 + zs + eps, theta, zs))[0]
        assert abs(d + eps / math.sqrt(2)) < 1e-12
        # Beyond the tip face (z < 0) and the nut's top face (z > 0).
        h, off = rng.uniform(1e-5, 1e-3), rng.uniform(0.0, 0.01)
        assert abs(signed_distance_at(bolt, _polar(TIP / 2 - off, theta, -h))[0] - h) < 1e-12
        d = signed_distance_at(bolt, _polar(TIP / 2 + off, theta, -h))[0]
        assert abs(d - math.hypot(h, off)) < 1e-12
        d = signed_distance_at(nut, _polar(SINK / 2 - off, theta, h))[0]
        assert abs(d - math.hypot(h, off)) < 1e-12
        assert abs(signed_distance_at(nut, _polar(SINK / 2 + off, theta, h))[0] - h) < 1e-12
    # A flat tip: beyond it the outline is the thread's section at the tip face, here at
    # a polar angle where that section is mid-flank.
    flat = bolt_body(_spec(BoltPoint("flat"), None))
    theta = -2 * math.pi * u_flank / lead
    outline = _sharp_radius(u_flank, "bolt")
    for off in (-0.003, 0.0, 0.002):
        p = _polar(outline + off, theta, -1e-4)
        assert abs(signed_distance_at(flat, p)[0] - math.hypot(1e-4, max(off, 0.0))) < 1e-12


def test_round_point_normal_is_radial_from_the_sphere_centre():
    radius = 0.35
    spec = _spec(BoltPoint("round", diameter=TIP, radius=radius), None)
    bolt = bolt_body(spec)
    z0 = math.sqrt(radius**2 - (TIP / 2) ** 2)  # the centre: the sphere passes the tip circle
    z = 0.002
    r = math.sqrt(radius**2 - (z - z0) ** 2)
    theta = -1.2
    p = np.array([r * math.cos(theta), r * math.sin(theta), z])
    f = feature_at(bolt, p, TOL)
    assert f.kind == "bevel"
    expected = (p - np.array([0.0, 0.0, z0])) / radius
    np.testing.assert_allclose(f.face_normal, expected, atol=1e-12)
    assert region_at(bolt, p, f) == "round"


def test_countersink_face_normal_region_and_top_rim(chamfered):
    nut = nut_body(chamfered)
    half = math.radians(45.0)  # 90 degrees included
    z = -0.005
    r = SINK / 2 + z * math.tan(half)
    theta = 0.4
    p = np.array([r * math.cos(theta), r * math.sin(theta), z])
    f = feature_at(nut, p, TOL)
    assert f.kind == "bevel"
    # Outward from the nut's material: toward the axis and up.
    expected = np.array([-math.cos(theta), -math.sin(theta), 1.0]) * math.cos(half)
    expected[2] = math.sin(half)
    np.testing.assert_allclose(f.face_normal, expected, atol=1e-12)
    assert region_at(nut, p, f) == "countersink"
    top = np.array([SINK / 2 * math.cos(theta), SINK / 2 * math.sin(theta), 0.0])
    assert feature_at(nut, top, TOL).kind == "rim"
    beyond = np.array([0.15 * math.cos(theta), 0.15 * math.sin(theta), 0.0])
    assert feature_at(nut, beyond, TOL).kind == "cap"


def test_lowest_point_of_a_tilted_chamfered_tip_is_on_its_circle(chamfered):
    """The tip rim of a chamfered bolt is the circle of the tip diameter: tilted by 5
    degrees about X, its lowest point is at angle -90 degrees (closed form)."""
    bolt = bolt_body(chamfered)
    tilt = math.radians(5.0)
    rot = np.array(
        [[1, 0, 0], [0, math.cos(tilt), -math.sin(tilt)], [0, math.sin(tilt), math.cos(tilt)]]
    )
    pose = Pose(rot, np.array([0.0, 0.0, 0.01]))
    guess = pose.to_fixed(np.array([TIP / 2 * math.cos(-1.4), TIP / 2 * math.sin(-1.4), 0.0]))
    low = lowest_on_rim(bolt, pose, guess, 0.02)
    expected = pose.to_fixed(np.array([0.0, -TIP / 2, 0.0]))
    # The height at the minimum is exact to second order in the angle the search leaves.
    assert abs(low[2] - expected[2]) < 1e-9
    on_circle = pose.to_bolt(low)
    assert abs(math.hypot(on_circle[0], on_circle[1]) - TIP / 2) < 1e-12
    assert abs(on_circle[2]) < 1e-12


def test_off_spec_labels(chamfered):
    bolt, nut = bolt_body(chamfered), nut_body(chamfered)
    far_low = np.array([0.3, 0.0, 0.01])  # far off the bolt, near its end
    far_high = np.array([0.3, 0.0, 0.5])
    assert off_spec_region(bolt, far_low) == "point"
    assert off_spec_region(bolt, far_high) == "other"
    assert off_spec_region(nut, np.array([0.0, 0.0, -0.01])) == "countersink"
    assert off_spec_region(nut, np.array([0.0, 0.0, -0.5])) == "other"
    f = Feature("thread", np.zeros(3), None, np.zeros(3))
    assert region_at(bolt, far_low, f, off_spec=1e-4) == "point"


def test_engagement_outline_and_plane_at_the_engagement_radius(chamfered):
    """Closed forms: the 45-degree cone reaches the engagement radius rho (a quarter of
    the way from the nut's minor radius to the bolt's major) at z = rho - TIP/2; the
    90-degree countersink at z = rho - SINK/2."""
    bolt, nut = bolt_body(chamfered), nut_body(chamfered)
    rho = NUT["minor"] / 2 + 0.25 * (BOLT["major"] / 2 - NUT["minor"] / 2)
    outline, plane = engagement_outline(bolt, nut)
    np.testing.assert_allclose(outline[:, 2], rho - TIP / 2, atol=1e-12)
    assert abs(np.hypot(outline[:, 0], outline[:, 1]).max() - rho) < 1e-12
    assert abs(plane - (rho - SINK / 2)) < 1e-12
    # The thesis's flat ends: the tip face's outline and the top face.
    flat = _spec(BoltPoint("flat"), None)
    outline, plane = engagement_outline(bolt_body(flat), nut_body(flat))
    assert plane == 0.0 and np.all(outline[:, 2] == 0.0)
    r = np.hypot(outline[:, 0], outline[:, 1])
    theta = np.arctan2(outline[:, 1], outline[:, 0])
    expected = [_sharp_radius(-PITCH * th / (2 * math.pi), "bolt") for th in theta]
    np.testing.assert_allclose(r, expected, atol=1e-12)


def test_upright_chamfer_rests_on_the_bore_edge_under_the_countersink():
    """A stiffly held, upright chamfered bolt out of phase rests with its cone on the
    nut's crest edge at the countersink's bottom: the cone r = TIP/2 + z_b meets the
    circle r = minor/2 at z = -depth, so the tip sits at -depth - (minor/2 - TIP/2)
    (within the descent's tolerance), the contacts carry the load, and they are on the
    chamfer and the countersink."""
    spec = _spec(BoltPoint("chamfer", angle=45.0, diameter=TIP), Countersink(90.0, SINK))
    mech = Mechanics(spec, Compliance(stiffness=100.0), chord=2e-5)
    depth = SINK / 2 - NUT["minor"] / 2  # 90 degrees included: depth = radial run
    expected = -depth - (NUT["minor"] / 2 - TIP / 2)
    # Half a turn from the phase where its teeth meet the nut's groove (this pair snaps
    # into the thread near phase 0).
    rest = mech.settle(0.0, 0.0, 180.0)
    state = rest.state
    # Held upright on a ring of edge contacts around the axis: the contacts alone carry
    # the load.
    assert state.classification == "stable"
    assert abs(state.origin[2] - expected) < 2e-5 + 1e-4 * abs(expected)
    lifted = sum(c.force * c.normal[2] for c in state.contacts)
    assert abs(lifted - 10.0) < 1e-6 * 10.0
    for c in state.contacts:
        assert c.bolt_region == "chamfer"
        assert c.nut_region == "countersink"


def test_kink_edge_points_lie_on_cone_and_thread_nearest_the_anchor(chamfered):
    """The exact edge where the countersink meets the nut's thread, at several angles: on
    the countersink's cone and on the thread (closed forms), and the crossing nearest the
    anchor's height (the profile's corners once sent a Newton step to another one)."""
    nut = nut_body(chamfered)
    half = math.radians(45.0)
    kink = Feature("kink", None, np.zeros(3), np.zeros(3))

    def gap(z: float, theta: float) -> float:  # thread radius minus cone radius
        return _sharp_radius(z - PITCH * theta / (2 * math.pi), "nut") - (
            SINK / 2 + z * math.tan(half)
        )

    for theta0 in (0.2, 2.5, 5.0):
        zs = np.linspace(-(SINK / 2 - NUT["minor"] / 2), 0.0, 2001)
        g = np.array([gap(z, theta0) for z in zs])
        roots = [
            brentq(gap, zs[i], zs[i + 1], args=(theta0,), xtol=1e-15)
            for i in range(len(zs) - 1)
            if np.signbit(g[i]) != np.signbit(g[i + 1])
        ]
        for z_true in roots:
            anchor = np.array([math.cos(theta0), math.sin(theta0), z_true + 0.002])
            angles = np.array([theta0])
            point = edge_points(_edge_curve(nut, kink, anchor), angles)[0]
            assert abs(point[2] - z_true) < 1e-12
            r = math.hypot(point[0], point[1])
            assert abs(r - (SINK / 2 + point[2] * math.tan(half))) < 1e-12


def _followed(gap, thetas: np.ndarray, z0: float, span: float) -> np.ndarray:
    """Heights where ``gap(z, theta) = 0`` along ``thetas``, each the root nearest the one
    before (the first nearest ``z0``), bracketed on steps of a 400th of a pitch within
    ``span`` of it."""
    out, z = np.empty(len(thetas)), z0
    grid = np.arange(1, int(span / (PITCH / 400)) + 1) * (PITCH / 400)
    for i, theta in enumerate(thetas):
        for d in grid:
            lo, hi = z - d, z - d + PITCH / 400
            if np.signbit(gap(lo, theta)) != np.signbit(gap(hi, theta)):
                break
            lo, hi = z + d - PITCH / 400, z + d
            if np.signbit(gap(lo, theta)) != np.signbit(gap(hi, theta)):
                break
        else:
            raise AssertionError("no root near the edge")
        z = out[i] = brentq(gap, lo, hi, args=(theta,), xtol=1e-15)
    return out


def _edge(kind: str, body: str, sink: bool, thetas: np.ndarray, z0: float) -> np.ndarray:
    """Points of an exact edge at ``thetas`` (its body's frame), from the closed forms:
    the kink where the 45-degree chamfer (bolt) or the 90-degree countersink (nut) meets
    the sharp thread, the tip circle of the chamfer, the outline of a flat end face at
    z = 0, or the helix of the nut's sharp corner at its minor radius through height
    ``z0`` at ``thetas[0]``."""
    lead = PITCH
    if kind == "kink":
        cone = (lambda z: TIP / 2 + z) if body == "bolt" else (lambda z: SINK / 2 + z)

        def gap(z: float, theta: float) -> float:
            return _sharp_radius(z - lead * theta / (2 * math.pi), body) - cone(z)

        z = _followed(gap, thetas, z0, PITCH / 2)
        r = np.array([cone(h) for h in z])
    elif kind == "circle":
        r, z = np.full(len(thetas), TIP / 2), np.zeros(len(thetas))
    elif kind == "rim":
        r = np.array([_sharp_radius(-lead * t / (2 * math.pi), body) for t in thetas])
        z = np.zeros(len(thetas))
    else:  # the nut's corner at its minor radius
        r = np.full(len(thetas), NUT["minor"] / 2)
        z = z0 + lead * (thetas - thetas[0]) / (2 * math.pi)
    return np.column_stack([r * np.cos(thetas), r * np.sin(thetas), z])


@pytest.mark.parametrize(
    ("nut_edge", "bolt_edge", "ends"),
    [
        ("kink", "kink", "chamfered"),
        ("kink", "circle", "chamfered"),
        ("rim", "rim", "flat"),
        ("corner", "rim", "flat"),
    ],
)
def test_two_exact_edges_cross_where_both_pass_over_one_point(nut_edge, bolt_edge, ends):
    """Two exact edges crossing seen along Z (an edge-on-edge contact): the crossing found
    from points of both nearby lies on both edges (the closed forms above) at one x, y,
    and is the crossing a brute-force search of the two sampled edges finds."""
    chamfer = ends == "chamfered"
    spec = _spec(
        BoltPoint("chamfer", angle=45.0, diameter=TIP) if chamfer else BoltPoint("flat"),
        Countersink(90.0, SINK) if chamfer else None,
    )
    nut, bolt = nut_body(spec), bolt_body(spec)
    tilt = math.radians(1.5)
    rotation = np.array(
        [
            [1.0, 0.0, 0.0],
            [0.0, math.cos(tilt), -math.sin(tilt)],
            [0.0, math.sin(tilt), math.cos(tilt)],
        ]
    )
    # Heights on the edges at the first angle: a kink's root nearest the middle of the
    # cone's band; the nut's corner where the thread leaves its minor radius.
    a4 = PITCH / 4 - (NUT["minor"] / 2 - NUT["pitch_diameter"] / 2) / math.sqrt(3)
    # Around angle 0 for the kinks; where the flat ends' outlines run along the flanks
    # (not the crest or root flats) for the rims.
    centre = 0.0 if nut_edge == "kink" else -1.5
    thetas = centre + np.linspace(-1.0, 1.0, 2001)
    z_nut = {"kink": -0.02, "rim": 0.0, "corner": a4 + PITCH * thetas[0] / (2 * math.pi)}
    z_bolt = {"kink": 0.02, "circle": 0.0, "rim": 0.0}
    nut_pts = _edge(nut_edge, "nut", chamfer, thetas, z_nut[nut_edge])
    bolt_b = _edge(bolt_edge, "bolt", chamfer, thetas, z_bolt[bolt_edge])
    # The bolt's axis 0.03 in off the nut's, in the direction that puts a crossing of the
    # edges' outlines (circles of their radii at the centre angle, roughly) there: they
    # cross at an angle, not tangentially.
    r_nut, r_bolt, off = np.hypot(*nut_pts[1000, :2]), np.hypot(*bolt_b[1000, :2]), 0.03
    side = -math.acos((r_nut**2 + off**2 - r_bolt**2) / (2 * r_nut * off))
    side += centre
    pose = Pose(rotation, np.array([off * math.cos(side), off * math.sin(side), 0.05]))
    bolt_f = pose.to_fixed(bolt_b)
    d = np.hypot(nut_pts[:, None, 0] - bolt_f[None, :, 0], nut_pts[:, None, 1] - bolt_f[None, :, 1])
    i, j = np.unravel_index(int(np.argmin(d)), d.shape)
    assert d[i, j] < 3e-4  # the samples' spacing: 1e-3 rad at r ~ 0.1
    q, w = edge_crossing(nut, bolt, pose, nut_pts[i], bolt_f[j], TOL, 0.01)
    assert w is not None
    assert np.hypot(q[0] - w[0], q[1] - w[1]) < 1e-10
    # On both edges: each point where its closed form puts the edge at its own angle.
    for pts, body, edge, z0, theta0 in (
        (q, "nut", nut_edge, nut_pts[i, 2], thetas[i]),
        (pose.to_bolt(w), "bolt", bolt_edge, bolt_b[j, 2], thetas[j]),
    ):
        angle = math.atan2(pts[1], pts[0])
        at = _edge(edge, body, chamfer, np.array([theta0, angle]), z0)[1]
        np.testing.assert_allclose(pts, at, atol=1e-10)
    # And the crossing the sampled edges bracket.
    assert np.linalg.norm(q[:2] - nut_pts[i, :2]) < 3e-4
