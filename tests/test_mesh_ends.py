"""Meshes of bolts with a point (chamfer, round) and nuts with a countersink: closed, on the
exact trimmed surface, within the chord, of the exact volume, and seen by python-fcl.

Every reference value is computed here from conventions.md and the closed forms of the
envelopes, independently of the mesh generator and of ``threadmate.geometry``'s profile
and body code: the profile (sharp V clamped to the flats, circular fillets tangent to flank
and flat) and its inverse are written out in ``_meshes.py``, the trimmed lateral radius is
``min(R, e)`` (bolt) / ``max(R, e)`` (nut) with ``e`` the cone ``a + z tan(angle)``, the
sphere ``rho^2 = r^2 + (z - z0)^2`` or the countersink ``b + z tan(angle / 2)``, the exact
volume integrates it by Gauss-Legendre quadrature on its smooth pieces, and the python-fcl
poses are placed by a closed-form gap between the chamfer's and the countersink's cones.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import fcl
import numpy as np
import pytest

from _fcl import bvh
from _meshes import GL_W, GL_X, INSIDE_WEIGHTS, ExactProfile, meridian_angles, meridian_gap
from threadmate.geometry import (
    DEFAULT_CHORD,
    BoltPoint,
    BoltSpec,
    Countersink,
    NutSpec,
    TessellatedBody,
    ThreadSpec,
    bolt_mesh,
    mesh_deviation,
    nut_mesh,
)

# The pairs, with every end given explicitly (not from the standards' defaults).
QUARTER = dict(
    units="in",
    pitch=0.05,
    bolt=dict(major=0.24485, pitch_diameter=0.21455, minor=0.1887, root_fillet=0.00625),
    nut=dict(major=0.2500, pitch_diameter=0.21995, minor=0.2015),
    tip=0.18,  # point diameter
    bolt_length=0.09,
    sink=0.265,  # countersink diameter
    nut_height=0.07,
    chord=2e-5,
)
M6 = dict(
    units="mm",
    pitch=1.0,
    bolt=dict(major=5.884, pitch_diameter=5.268, minor=4.735, root_fillet=0.125),
    nut=dict(major=6.10, pitch_diameter=5.425, minor=5.035),
    tip=4.6,
    bolt_length=1.8,
    sink=6.4,
    nut_height=1.4,
    chord=5e-4,
)
PAIRS = {"1/4-20": QUARTER, "M6x1": M6}
CHAMFER_ANGLE = 45.0  # from the axis
ROUND_RADIUS = 1.4  # in major diameters
SINK_ANGLE = 120.0  # included


def _spec(pair: dict, point: str) -> ThreadSpec:
    if point == "chamfer":
        bp = BoltPoint("chamfer", angle=CHAMFER_ANGLE, diameter=pair["tip"])
    else:
        radius = ROUND_RADIUS * pair["bolt"]["major"]
        bp = BoltPoint("round", radius=radius, diameter=pair["tip"])
    return ThreadSpec(
        units=pair["units"],
        pitch=pair["pitch"],
        bolt=BoltSpec(**pair["bolt"], point=bp, length=pair["bolt_length"]),
        nut=NutSpec(
            **pair["nut"],
            countersink=Countersink(SINK_ANGLE, pair["sink"]),
            height=pair["nut_height"],
        ),
    )


# -- the exact trimmed bodies, written out ---------------------------------------------------
@dataclass
class _Envelope:
    """The point's or countersink's meridian curve ``r = e(z)`` over ``[z_lo, z_hi]``,
    its inverse, and which side is material (+1 bolt: ``r <= e``, -1 nut)."""

    side: int
    e: object
    z_of: object
    z_lo: float
    z_hi: float


def _envelope(spec: ThreadSpec, body: str) -> _Envelope:
    if body == "nut":
        sink = spec.nut.countersink
        b, k = sink.diameter / 2, math.tan(math.radians(sink.angle / 2))
        return _Envelope(
            -1, lambda z: b + k * z, lambda r: (r - b) / k, (spec.nut.minor / 2 - b) / k, 0.0
        )
    point = spec.bolt.point
    a, r_major = point.diameter / 2, spec.bolt.major / 2
    if point.form == "chamfer":
        k = math.tan(math.radians(point.angle))
        return _Envelope(1, lambda z: a + k * z, lambda r: (r - a) / k, 0.0, (r_major - a) / k)
    rho = point.radius
    z0 = math.sqrt(rho**2 - a**2)  # the sphere's centre on the axis: r = a at z = 0
    return _Envelope(
        1,
        lambda z: np.sqrt(rho**2 - (z - z0) ** 2),
        lambda r: z0 - np.sqrt(rho**2 - r**2),
        0.0,
        z0 - math.sqrt(rho**2 - r_major**2),
    )


def _lateral(spec: ThreadSpec, body: str, theta, z):
    """Radius of the exact trimmed lateral surface at angle ``theta``, height ``z``."""
    prof, env = ExactProfile(spec, body), _envelope(spec, body)
    z = np.asarray(z, dtype=float)
    hand = 1 if spec.hand == "right" else -1
    R = prof.of_t(z - hand * spec.pitch * spec.starts * np.asarray(theta) / (2 * np.pi))
    inside = (z >= env.z_lo) & (z <= env.z_hi)
    e = np.where(inside, env.e(np.clip(z, env.z_lo, env.z_hi)), np.inf * env.side)
    return np.minimum(R, e) if env.side > 0 else np.maximum(R, e)


def _exact_volume(spec: ThreadSpec, body: str, trimmed: bool = True) -> float:
    """At height z the section sweeps whole pitches of t as theta turns once, so its area
    is ``(2 pi / p) int_0^{p/2} min(R, e)^2 du`` (bolt) and ``pi outer^2 - (2 pi / p)
    int_0^{p/2} max(R, e)^2 du`` (nut); ``R`` is monotone in ``u``, so with ``R(u_e) = e``
    the integrals are ``e^2 u_e + G(p/2) - G(u_e)`` and ``G(u_e) + e^2 (p/2 - u_e)``.
    Integrated over z on the pieces between the heights where ``e`` meets a corner radius
    of the profile (smooth there)."""
    prof, env = ExactProfile(spec, body), _envelope(spec, body)
    half = spec.pitch / 2
    g_half = float(prof.square_integral(half)[0])
    outer2 = spec.nut.outer_radius**2 if body == "nut" else 0.0

    def area(z):
        e = env.e(z)
        u_e = np.where(e >= prof.r_hi, 0.0, np.where(e <= prof.r_lo, half, prof.inverse(e)))
        g = prof.square_integral(u_e)
        if body == "bolt":
            return 2 * np.pi / spec.pitch * (e**2 * u_e + g_half - g)
        return np.pi * outer2 - 2 * np.pi / spec.pitch * (g + e**2 * (half - u_e))

    length = spec.bolt.length if body == "bolt" else spec.nut.height
    plain = 2 * np.pi / spec.pitch * g_half
    plain = plain if body == "bolt" else np.pi * outer2 - plain
    if not trimmed:
        return float(plain * length)
    cuts = [float(env.z_of(r)) for r in prof.radii]
    knots = sorted({env.z_lo, env.z_hi, *(c for c in cuts if env.z_lo < c < env.z_hi)})
    volume = plain * (length - (env.z_hi - env.z_lo))
    for lo, hi in zip(knots[:-1], knots[1:], strict=True):
        z = lo + (hi - lo) / 2 * (GL_X + 1)
        volume += (hi - lo) / 2 * float(area(z) @ GL_W)
    return float(volume)


# -- meshes (built once) -----------------------------------------------------------------------
CASES = [
    (pair, form) for pair in ("1/4-20", "M6x1") for form in ("chamfer", "round", "countersink")
]


@pytest.fixture(scope="module")
def built():
    cache: dict[tuple[str, str], tuple[ThreadSpec, str, TessellatedBody]] = {}

    def get(pair: str, form: str):
        if (pair, form) not in cache:
            spec = _spec(PAIRS[pair], "round" if form == "round" else "chamfer")
            body = "nut" if form == "countersink" else "bolt"
            make = nut_mesh if body == "nut" else bolt_mesh
            cache[pair, form] = (spec, body, make(spec, PAIRS[pair]["chord"]))
        return cache[pair, form]

    return get


def _polar(v):
    return np.hypot(v[:, 0], v[:, 1]), np.arctan2(v[:, 1], v[:, 0])


# -- closed, and on the exact trimmed surface ----------------------------------------------------
@pytest.mark.parametrize(("pair", "form"), CASES)
def test_closed_outward_and_within_the_chord(built, pair, form):
    spec, body, tb = built(pair, form)
    m = tb.mesh
    assert m.is_watertight and m.is_winding_consistent
    assert m.volume > 0  # outward normals
    assert tb.chord == PAIRS[pair]["chord"]
    assert tb.max_deviation <= tb.chord
    assert mesh_deviation(m, tb.body) <= tb.chord


@pytest.mark.parametrize(("pair", "form"), CASES)
def test_vertices_lie_on_the_trimmed_surface_and_the_envelope(built, pair, form):
    spec, body, tb = built(pair, form)
    v = np.asarray(tb.mesh.vertices)
    r, theta = _polar(v)
    env = _envelope(spec, body)
    lateral = ~np.isclose(r, 0.0, atol=1e-15)
    if body == "nut":
        lateral &= r < spec.nut.outer_radius * (1 - 1e-12)
    exact = _lateral(spec, body, theta[lateral], v[lateral, 2])
    assert np.max(np.abs(r[lateral] - exact)) <= 1e-9 * spec.pitch
    # Where the envelope bounds the material (the thread lies beyond it), the vertex is on
    # the closed-form cone or sphere.
    prof = ExactProfile(spec, body)
    hand = 1 if spec.hand == "right" else -1
    z = v[lateral, 2]
    R = prof.of_t(z - hand * spec.lead * theta[lateral] / (2 * np.pi))
    span = (z >= env.z_lo) & (z <= env.z_hi)
    tol = 1e-12 * spec.pitch
    on_env = span & (env.side * (R - env.e(np.clip(z, env.z_lo, env.z_hi))) >= -tol)
    rr, zz = r[lateral][on_env], z[on_env]
    if form == "chamfer":
        a, k = spec.bolt.point.diameter / 2, math.tan(math.radians(spec.bolt.point.angle))
        residual = rr - (a + zz * k)
    elif form == "round":
        rho, a = spec.bolt.point.radius, spec.bolt.point.diameter / 2
        residual = np.hypot(rr, zz - math.sqrt(rho**2 - a**2)) - rho
    else:
        sink = spec.nut.countersink
        residual = rr - (sink.diameter / 2 + zz * math.tan(math.radians(sink.angle / 2)))
    # One end vertex per meridian on the envelope's face (the bolt's centre and the nut's
    # outer ring are not lateral).
    n_meridians = int(np.sum(lateral & (v[:, 2] == 0.0)))
    assert len(rr) > 1.5 * n_meridians  # the end circle and the kinks
    assert np.max(np.abs(residual)) <= tol
    # Nothing pokes through the envelope anywhere.
    e = env.e(np.clip(z, env.z_lo, env.z_hi))
    assert np.all(env.side * (r[lateral][span] - e[span]) <= tol)


@pytest.mark.parametrize(("pair", "form"), CASES)
def test_end_face_is_the_envelopes_circle(built, pair, form):
    spec, body, tb = built(pair, form)
    m = tb.mesh
    v = np.asarray(m.vertices)
    r, _ = _polar(v)
    at_face = v[:, 2] == 0.0
    on_face = np.all(at_face[m.faces], axis=1)
    normal = [0, 0, -1] if body == "bolt" else [0, 0, 1]
    assert on_face.sum() > 100 and np.allclose(m.face_normals[on_face], normal)
    if body == "bolt":
        # A disc of the point's diameter: a fan from the axis to one circle.
        ring = r[at_face & (r > 0)]
        assert np.sum(at_face & (r == 0)) == 1
        assert len(ring) > 100
        assert (
            np.max(np.abs(ring - spec.bolt.point.diameter / 2)) <= 1e-14 * spec.bolt.point.diameter
        )
        # Its area is that of the inscribed polygon: within the chord of the circle.
        area = m.area_faces[on_face].sum()
        assert math.pi * (spec.bolt.point.diameter / 2) ** 2 - area > 0
        assert math.pi * (spec.bolt.point.diameter / 2) ** 2 - area <= (
            math.pi * spec.bolt.point.diameter * tb.chord
        )
    else:
        ring = r[at_face]
        inner = ring[ring < spec.nut.outer_radius * 0.99]
        assert len(inner) > 100
        assert np.max(np.abs(inner - spec.nut.countersink.diameter / 2)) <= (
            1e-14 * spec.nut.countersink.diameter
        )


def _axial_deviation(spec: ThreadSpec, body: str, points, chord: float, window: int = 121):
    """Upper bound on each point's distance to the exact trimmed surface: the distance in
    its meridian half-plane to the curve ``r = lateral(theta, z')`` (which lies on the
    surface), over ``z'`` within 1.2 chords, sampled every 0.02 chord, or to the end face
    it lies over."""
    r, theta = _polar(points)
    z = points[:, 2]
    z_lo, z_hi = (0.0, spec.bolt.length) if body == "bolt" else (-spec.nut.height, 0.0)
    best = np.full(len(points), np.inf)
    for off in np.linspace(-1.2 * chord, 1.2 * chord, window):
        zz = np.clip(z + off, z_lo, z_hi)
        best = np.minimum(best, np.hypot(zz - z, _lateral(spec, body, theta, zz) - r))
    for z_end in (z_lo, z_hi):
        outline = _lateral(spec, body, theta, np.full_like(z, z_end))
        over = r <= outline if body == "bolt" else r >= outline
        best = np.where(over, np.minimum(best, np.abs(z - z_end)), best)
    return best


@pytest.mark.parametrize(("pair", "form"), CASES)
def test_triangles_at_the_envelope_within_the_chord_by_an_independent_measure(built, pair, form):
    spec, body, tb = built(pair, form)
    v, f = np.asarray(tb.mesh.vertices), np.asarray(tb.mesh.faces)
    env = _envelope(spec, body)
    r, _ = _polar(v)
    near = (v[:, 2] >= env.z_lo - spec.pitch / 4) & (v[:, 2] <= env.z_hi + spec.pitch / 4)
    if body == "nut":
        near &= r < spec.nut.outer_radius * (1 - 1e-12)
    tri = f[np.all(near[f], axis=1)]
    points = np.einsum("wk,nkd->wnd", INSIDE_WEIGHTS, v[tri]).reshape(-1, 3)
    d = _axial_deviation(spec, body, points, tb.chord)
    assert len(tri) > 1000
    assert d.max() <= tb.chord
    assert d.max() >= 0.3 * tb.chord  # the envelope's triangles use the tolerance too


@pytest.mark.parametrize(("pair", "form"), CASES)
def test_volume_matches_the_integrated_trimmed_profile(built, pair, form):
    spec, body, tb = built(pair, form)
    exact = _exact_volume(spec, body)
    # Every point of the surface is within the chord of the exact one: |dV| <= chord x area.
    tolerance = tb.chord * tb.mesh.area
    assert abs(tb.mesh.volume - exact) <= tolerance
    assert abs(tb.mesh.volume - exact) > 0  # a mesh, not the exact body
    # And the check tells the trimmed body from the untrimmed one by far.
    assert _exact_volume(spec, body, trimmed=False) - exact > 5 * tolerance


# -- the default chord -----------------------------------------------------------------------------
def test_quarter_20_chamfer_and_countersink_at_the_default_chord():
    spec = _spec(QUARTER, "chamfer")
    chord = DEFAULT_CHORD["in"]
    for tb, body in ((bolt_mesh(spec), "bolt"), (nut_mesh(spec), "nut")):
        m = tb.mesh
        assert tb.chord == chord == 5e-6
        assert m.is_watertight and m.is_winding_consistent and m.volume > 0
        assert tb.max_deviation <= chord
        v = np.asarray(m.vertices)
        r, theta = _polar(v)
        lateral = r > 0
        if body == "nut":
            lateral &= r < spec.nut.outer_radius * (1 - 1e-12)
        exact = _lateral(spec, body, theta[lateral], v[lateral, 2])
        assert np.max(np.abs(r[lateral] - exact)) <= 1e-9 * spec.pitch
        assert abs(m.volume - _exact_volume(spec, body)) <= chord * m.area


# -- no shared meridian planes -------------------------------------------------------------------
@pytest.mark.parametrize("pair", ["1/4-20", "M6x1"])
def test_pointed_bolt_and_countersunk_nut_share_no_meridian_plane(built, pair):
    _, _, bolt = built(pair, "chamfer")
    _, _, nut = built(pair, "countersink")
    mb, mn = meridian_angles(bolt), meridian_angles(nut)
    assert len(mb) > 150 and len(mn) > 150
    for phase in range(0, 360, 5):
        assert meridian_gap(mb, mn, phase) > 1e-9, phase


# -- python-fcl on the chamfer in the countersink ---------------------------------------------
@pytest.mark.parametrize("pair", ["1/4-20", "M6x1"])
@pytest.mark.parametrize("phase", [0.0, 37.0])
@pytest.mark.parametrize("direction", [0.0, 113.0])
def test_fcl_sees_the_chamfer_meet_the_countersink(built, pair, phase, direction):
    """The bolt, axis vertical and offset sideways by ``x``, dips its tip to ``h`` just
    below the nut's face. Near the tip the bolt is all chamfer (``r <= a + k_b (z - h)``,
    up to ``k_b z = r_lo_b - a``), near the face the nut is all countersink (``r >= b +
    k_n z``, down to ``k_n z = r_hi_n - b``); ``h`` is within both. In the (radius from the
    nut axis, z) half-plane, a projection that shortens distances, the bolt lies in the
    wedge ``z >= h, r <= x + a + k_b (z - h)`` and the nut there in ``r >= b + k_n z``
    (below the countersink-only band, far from the bolt). With ``k_b < k_n`` the wedge's
    corner ``(x + a, h)`` is the nearest point: the bodies are apart by at least
    ``(x* - x) / sqrt(1 + k_n^2)``, ``x* = b + k_n h - a``, and for ``x > x*`` the corner's
    neighbourhood (bolt material) lies inside the nut by ``(x - x*) / sqrt(1 + k_n^2)``."""
    spec, _, bolt = built(pair, "chamfer")
    _, _, nut = built(pair, "countersink")
    chord = bolt.chord
    a = spec.bolt.point.diameter / 2
    k_b = math.tan(math.radians(spec.bolt.point.angle))
    b = spec.nut.countersink.diameter / 2
    k_n = math.tan(math.radians(spec.nut.countersink.angle / 2))
    bolt_band = (ExactProfile(spec, "bolt").r_lo - a) / k_b
    nut_band = (b - ExactProfile(spec, "nut").r_hi) / k_n
    h = -0.4 * min(bolt_band, nut_band)
    assert k_b < k_n and h - (-nut_band) > 20 * chord  # the band below is far
    x_star = b + k_n * h - a
    assert x_star > 0
    norm = math.hypot(1.0, k_n)
    nut_o = fcl.CollisionObject(bvh(nut.mesh))
    bolt_o = fcl.CollisionObject(bvh(bolt.mesh))
    c, s = math.cos(math.radians(phase)), math.sin(math.radians(phase))
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    for gap_chords, expected in ((10.0, False), (-10.0, True), (3.0, False), (-3.0, True)):
        x = x_star - gap_chords * chord * norm
        d = math.radians(direction)
        bolt_o.setTransform(
            fcl.Transform(rotation, np.array([x * math.cos(d), x * math.sin(d), h]))
        )
        result = fcl.CollisionResult()
        hit = fcl.collide(bolt_o, nut_o, fcl.CollisionRequest(), result) > 0
        assert hit == expected, (gap_chords, x)
