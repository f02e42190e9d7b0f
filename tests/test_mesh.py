"""Tessellated bolt and nut: closed, in frame, within the chord of the exact surfaces, and
free of the coplanar-edge degeneracy that makes python-fcl miss triangle pairs.

Every reference value here is computed independently of the mesh generator and of
``threadmate.geometry``'s profile code: the profile (sharp V clamped to the flats, with
circular fillets tangent to flank and flat) is re-derived from conventions.md in
``_meshes.py``, the exact volume integrates it, deviations are measured against a dense
exact polyline of it, and the python-fcl check uses a brute-force triangle-triangle test
written here.
"""

from __future__ import annotations

import math

import fcl
import numpy as np
import pytest
from scipy import integrate
from scipy.spatial import cKDTree

from _fcl import bvh
from _meshes import INSIDE_WEIGHTS, SQ3, ExactProfile, meridian_angles, meridian_gap
from threadmate import InputError
from threadmate.geometry import (
    DEFAULT_CHORD,
    BoltSpec,
    NutSpec,
    Pose,
    TessellatedBody,
    ThreadSpec,
    bolt_mesh,
    mesh_deviation,
    nut_mesh,
    thread_meshes,
)


# -- specs -------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def m6() -> ThreadSpec:
    """M6x1-6g/6H at mean material from the ISO 965-1 limits (root radius 0.125 p)."""
    return ThreadSpec(
        units="mm",
        pitch=1.0,
        bolt=BoltSpec(major=5.884, pitch_diameter=5.268, minor=4.735, root_fillet=0.125),
        nut=NutSpec(major=6.10, pitch_diameter=5.425, minor=5.035),
    )


@pytest.fixture(scope="module")
def sharp_m6(m6: ThreadSpec) -> ThreadSpec:
    d = m6.to_dict()
    d["bolt"]["root_fillet"] = 0.0
    return ThreadSpec.from_dict(d)


@pytest.fixture(scope="module")
def pairs(quarter_20, sharp_quarter_20, m6, sharp_m6):
    """Meshes at the default chord (built once; the cache serves later calls)."""
    return {
        name: (spec, *thread_meshes(spec))
        for name, spec in (
            ("1/4-20", quarter_20),
            ("1/4-20 sharp", sharp_quarter_20),
            ("M6x1", m6),
            ("M6x1 sharp", sharp_m6),
        )
    }


# -- independent references -----------------------------------------------------------
def _exact_volume(spec: ThreadSpec, body: str) -> float:
    """At any height the section sweeps whole pitches of ``t`` as theta turns once, so
    ``V = int int R^2/2 dtheta dz = pi * length * mean(R^2)`` (bolt) and
    ``pi * height * (outer^2 - mean(R^2))`` (nut)."""
    prof = ExactProfile(spec, body)
    radius = prof.radius
    half = spec.pitch / 2
    pts = sorted({c for c in prof.corners if 0 < c < half})
    mean_r2 = (
        2
        * integrate.quad(
            lambda u: radius(u) ** 2, 0, half, points=pts, epsabs=1e-16, epsrel=1e-13, limit=200
        )[0]
        / spec.pitch
    )
    if body == "bolt":
        return math.pi * spec.bolt.length * mean_r2
    return math.pi * spec.nut.height * (spec.nut.outer_radius**2 - mean_r2)


class _AxialDistance:
    """Distance in the axial section from ``(t, r)`` to a dense polyline of the exact
    profile (spacing ~ 1e-5 p: its own sagitta on the fillets is below 1e-9 p)."""

    def __init__(self, spec: ThreadSpec, body: str) -> None:
        prof = ExactProfile(spec, body)
        radius = prof.radius
        p = spec.pitch
        t = np.linspace(-1.5 * p, 1.5 * p, 300_001)
        t = np.union1d(
            t,
            np.concatenate(
                [s * np.asarray(prof.corners) + k * p for s in (-1, 1) for k in (-1, 0, 1)]
            ),
        )
        self.p = p
        self.pts = np.column_stack([t, radius(t - p * np.round(t / p))])
        self.tree = cKDTree(self.pts)

    def __call__(self, t, r):
        q = np.column_stack([t, r])
        _, i = self.tree.query(q)
        best = np.full(len(q), np.inf)
        for j0, j1 in ((i - 1, i), (i, i + 1)):
            j0 = np.clip(j0, 0, len(self.pts) - 1)
            j1 = np.clip(j1, 0, len(self.pts) - 1)
            a, b = self.pts[j0], self.pts[j1]
            d = b - a
            dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
            s = np.clip(np.einsum("ij,ij->i", q - a, d) / dd, 0, 1)
            best = np.minimum(best, np.linalg.norm(q - a - s[:, None] * d, axis=1))
        return best


def _independent_deviation(spec: ThreadSpec, tb: TessellatedBody) -> tuple[float, float]:
    """(max over vertices, max over points inside the triangles) of the distance to the
    exact surface: thread surface, end faces and (nut) outer cylinder."""
    kind = tb.body.kind
    dist = _AxialDistance(spec, kind)
    lead = spec.pitch * spec.starts
    hand = 1 if spec.hand == "right" else -1
    z0, z1 = (0.0, spec.bolt.length) if kind == "bolt" else (-spec.nut.height, 0.0)
    radius = ExactProfile(spec, kind).radius
    v = np.asarray(tb.mesh.vertices)
    f = np.asarray(tb.mesh.faces)

    def deviation(pts):
        r = np.hypot(pts[:, 0], pts[:, 1])
        theta = np.arctan2(pts[:, 1], pts[:, 0])
        t = pts[:, 2] - hand * lead * theta / (2 * np.pi)
        t = t - spec.pitch * np.round(t / spec.pitch)
        d = dist(t, r)
        on_face = (np.abs(pts[:, 2] - z0) < 1e-12) | (np.abs(pts[:, 2] - z1) < 1e-12)
        R = radius(t)
        if kind == "bolt":
            d = np.where(on_face & (r <= R), 0.0, d)
        else:
            outer = spec.nut.outer_radius
            d = np.where(on_face & (r >= R) & (r <= outer), 0.0, d)
            d = np.minimum(d, np.abs(r - outer))
        return d

    inner = np.einsum("wk,nkd->wnd", INSIDE_WEIGHTS, v[f]).reshape(-1, 3)
    return float(deviation(v).max()), float(deviation(inner).max())


# -- closed volumes in their frames ----------------------------------------------------------
@pytest.mark.parametrize("name", ["1/4-20", "M6x1"])
def test_meshes_are_closed_outward_and_in_frame(pairs, name):
    spec, bolt, nut = pairs[name]
    for tb in (bolt, nut):
        m = tb.mesh
        assert m.vertices.dtype == np.float64
        assert m.is_watertight and m.is_winding_consistent
        assert m.volume > 0  # outward normals
        assert tb.chord == DEFAULT_CHORD[spec.units]
    lo, hi = bolt.mesh.bounds
    assert lo[2] == 0.0 and hi[2] == pytest.approx(spec.bolt.length, abs=1e-15)
    assert np.max(np.hypot(*bolt.mesh.vertices[:, :2].T)) <= spec.bolt.major / 2 + 1e-15
    lo, hi = nut.mesh.bounds
    assert hi[2] == 0.0 and lo[2] == pytest.approx(-spec.nut.height, abs=1e-15)
    r = np.hypot(*nut.mesh.vertices[:, :2].T)
    assert r.max() == pytest.approx(spec.nut.outer_radius, rel=1e-12)
    assert r.min() >= spec.nut.minor / 2 - 1e-15
    # The tip face (base) and nut top (surface) are flat faces at z = 0, facing out.
    n_b = bolt.mesh.face_normals[np.all(bolt.mesh.vertices[bolt.mesh.faces][:, :, 2] == 0, axis=1)]
    n_n = nut.mesh.face_normals[np.all(nut.mesh.vertices[nut.mesh.faces][:, :, 2] == 0, axis=1)]
    assert len(n_b) and np.allclose(n_b, [0, 0, -1])
    assert len(n_n) and np.allclose(n_n, [0, 0, 1])


@pytest.mark.parametrize("name", ["1/4-20", "1/4-20 sharp", "M6x1", "M6x1 sharp"])
def test_volume_matches_the_integrated_profile(pairs, name):
    spec, bolt, nut = pairs[name]
    for tb, kind in ((bolt, "bolt"), (nut, "nut")):
        exact = _exact_volume(spec, kind)
        # Every point of the surface is within the chord: |dV| <= chord x area.
        assert abs(tb.mesh.volume - exact) <= tb.chord * tb.mesh.area, kind
        assert abs(tb.mesh.volume - exact) > 0  # a mesh, not the exact body


def test_fillets_change_the_volume_beyond_the_mesh_error(pairs):
    # The volume check can tell a filleted root from a sharp one at this chord.
    spec, bolt, _ = pairs["1/4-20"]
    sharp_spec, sharp_bolt, _ = pairs["1/4-20 sharp"]
    gap = abs(_exact_volume(spec, "bolt") - _exact_volume(sharp_spec, "bolt"))
    assert gap > 2 * bolt.chord * bolt.mesh.area


# -- deviation from the exact surface ------------------------------------------------------
@pytest.mark.parametrize("name", ["1/4-20", "1/4-20 sharp", "M6x1", "M6x1 sharp"])
def test_deviation_within_chord_by_an_independent_measure(pairs, name):
    spec, bolt, nut = pairs[name]
    for tb in (bolt, nut):
        at_vertices, inside = _independent_deviation(spec, tb)
        assert at_vertices <= 1e-9 * spec.pitch  # vertices lie on the exact surface
        assert inside <= tb.chord
        # Not wastefully fine either: the meshes use most of the tolerance.
        assert inside >= 0.5 * tb.chord
        assert tb.max_deviation <= tb.chord
        assert tb.max_deviation == pytest.approx(inside, rel=0.15)


def test_quarter_20_pair_within_5e6_inch(pairs):
    _, bolt, nut = pairs["1/4-20"]
    assert DEFAULT_CHORD["in"] == 5e-6
    assert DEFAULT_CHORD["mm"] == pytest.approx(5e-6 * 25.4)
    assert bolt.max_deviation <= 5e-6 and nut.max_deviation <= 5e-6


def test_mesh_deviation_sees_a_displaced_mesh(pairs):
    _, bolt, _ = pairs["1/4-20"]
    moved = bolt.mesh.copy()
    moved.apply_translation([0, 0, 1e-4])
    # Moving the mesh 1e-4 along the axis shifts the flanks by 1e-4 * sin 60 deg normal
    # to themselves (and more on the flats' ends).
    assert mesh_deviation(moved, bolt.body) >= 1e-4 * SQ3 / 2 - bolt.chord


@pytest.mark.parametrize("chord", [1e-4, 2e-5])
def test_coarser_chords_hold_and_shrink_the_mesh(quarter_20, chord):
    bolt, nut = bolt_mesh(quarter_20, chord), nut_mesh(quarter_20, chord)
    default_bolt, default_nut = thread_meshes(quarter_20)
    for tb, ref in ((bolt, default_bolt), (nut, default_nut)):
        assert tb.mesh.is_watertight and tb.mesh.is_winding_consistent
        assert tb.max_deviation <= chord
        assert _independent_deviation(quarter_20, tb)[1] <= chord
        assert tb.triangles < ref.triangles


def test_left_hand_two_start_filleted_pair(quarter_20):
    d = quarter_20.to_dict()
    d.update(hand="left", starts=2)
    d["bolt"].update(crest_fillet=0.003, length=0.13)
    d["nut"].update(root_fillet=0.003, crest_fillet=0.002, height=0.07)
    spec = ThreadSpec.from_dict(d)
    chord = 2e-5
    for tb, kind in ((bolt_mesh(spec, chord), "bolt"), (nut_mesh(spec, chord), "nut")):
        assert tb.mesh.is_watertight and tb.mesh.is_winding_consistent and tb.mesh.volume > 0
        assert _independent_deviation(spec, tb)[1] <= chord
        assert abs(tb.mesh.volume - _exact_volume(spec, kind)) <= chord * tb.mesh.area


def test_thread_meshes_is_cached_and_checks_its_input(quarter_20):
    first = thread_meshes(quarter_20)
    assert thread_meshes(quarter_20) is first
    assert thread_meshes(quarter_20, DEFAULT_CHORD["in"]) is first
    for bad in (0.0, -1e-5, float("nan"), float("inf"), 1.0, 1e-12, "5e-6"):
        with pytest.raises(InputError, match="chord"):
            thread_meshes(quarter_20, bad)  # type: ignore[arg-type]
    with pytest.raises(InputError):
        bolt_mesh("1/4-20 UNC")  # type: ignore[arg-type]


# -- no shared meridian planes ---------------------------------------------------------------
@pytest.mark.parametrize("name", ["1/4-20", "M6x1"])
def test_bolt_and_nut_share_no_meridian_plane_at_round_phases(pairs, name):
    _, bolt, nut = pairs[name]
    mb, mn = meridian_angles(bolt), meridian_angles(nut)
    assert len(mb) > 300 and len(mn) > 300
    for phase in range(0, 360, 5):
        assert meridian_gap(mb, mn, phase) > 1e-9, (name, phase)


# -- python-fcl finds every intersecting pair ------------------------------------------------
def _brute_force_pairs(A: np.ndarray, B: np.ndarray, eps: float) -> set[tuple[int, int]]:
    """Every (i, j) with triangle A[i] crossing B[j] by more than ``eps`` (Moller 1997:
    each triangle must straddle the other's plane, and their segments on the planes'
    common line must overlap)."""
    a_lo, a_hi = A.min(axis=1), A.max(axis=1)
    b_lo, b_hi = B.min(axis=1), B.max(axis=1)
    cand = []
    for start in range(0, len(A), 512):
        sl = slice(start, start + 512)
        ok = np.all((a_lo[sl, None, :] <= b_hi[None]) & (b_lo[None] <= a_hi[sl, None, :]), axis=2)
        i, j = np.nonzero(ok)
        cand.append(np.column_stack([i + start, j]))
    ij = np.concatenate(cand)
    T1, T2 = A[ij[:, 0]], B[ij[:, 1]]

    def plane(T):
        n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        return n, -np.einsum("ij,ij->i", n, T[:, 0])

    n1, c1 = plane(T1)
    n2, c2 = plane(T2)
    d2 = np.einsum("nj,nkj->nk", n1, T2) + c1[:, None]
    d1 = np.einsum("nj,nkj->nk", n2, T1) + c2[:, None]
    straddle = (d1.max(1) > eps) & (d1.min(1) < -eps) & (d2.max(1) > eps) & (d2.min(1) < -eps)
    D = np.cross(n1, n2)
    D /= np.maximum(np.linalg.norm(D, axis=1, keepdims=True), 1e-300)

    def interval(T, d):
        lo = np.full(len(T), np.inf)
        hi = np.full(len(T), -np.inf)
        for i, j in ((0, 1), (1, 2), (2, 0)):
            cross = d[:, i] * d[:, j] < 0
            s = d[:, i] / np.where(cross, d[:, i] - d[:, j], 1.0)
            x = T[:, i] + s[:, None] * (T[:, j] - T[:, i])
            proj = np.einsum("nj,nj->n", D, x)
            lo = np.where(cross, np.minimum(lo, proj), lo)
            hi = np.where(cross, np.maximum(hi, proj), hi)
        return lo, hi

    lo1, hi1 = interval(T1, d1)
    lo2, hi2 = interval(T2, d2)
    overlap = np.minimum(hi1, hi2) - np.maximum(lo1, lo2) > eps
    hit = ij[straddle & overlap]
    return {(int(i), int(j)) for i, j in hit}


POSES = [  # (roll, pitch, phase, h): bolt partly into the nut, out of phase
    (0.0, 0.0, 5.0, -0.003),  # round phases, axes aligned: the meridian-plane danger
    (0.0, 0.0, 10.0, -0.002),
    (0.0, 0.0, 90.0, -0.001),
    (0.0, 0.0, 180.0, -0.0005),
    (2.0, 0.0, 180.0, 0.002),
    (4.0, 3.0, 200.0, 0.004),
    (0.0, -3.0, 45.0, 0.003),
    (5.0, 0.0, 300.0, 0.006),
    (0.0, 6.0, 30.0, 0.008),
    (-1.5, 2.5, 275.0, 0.001),
]


@pytest.fixture(scope="module")
def coarse_fcl(quarter_20):
    chord = 1e-4  # the anti-degeneracy measures are the same at every chord
    bolt, nut = bolt_mesh(quarter_20, chord), nut_mesh(quarter_20, chord)
    return (
        bolt.mesh,
        nut.mesh,
        fcl.CollisionObject(bvh(bolt.mesh)),
        fcl.CollisionObject(bvh(nut.mesh)),
    )


@pytest.mark.parametrize("pose", POSES)
def test_fcl_finds_every_intersecting_triangle_pair(coarse_fcl, pose):
    bolt_m, nut_m, bolt_o, nut_o = coarse_fcl
    roll, pitch, phase, h = pose
    p = Pose.from_angles(roll, pitch, phase, h)
    bolt_o.setTransform(fcl.Transform(p.rotation, p.origin))
    request = fcl.CollisionRequest(num_max_contacts=10**6, enable_contact=True)
    result = fcl.CollisionResult()
    fcl.collide(bolt_o, nut_o, request, result)
    found = {(c.b1, c.b2) for c in result.contacts}

    A = p.to_fixed(bolt_m.vertices)[bolt_m.faces]
    B = np.asarray(nut_m.vertices)[nut_m.faces]
    brute = _brute_force_pairs(A, B, eps=1e-12)
    assert len(brute) >= 4, "the pose must be in collision"
    missed = brute - found
    assert not missed, f"python-fcl missed {len(missed)} of {len(brute)} pairs"
    # And fcl reports nothing far from a crossing (a check that the ids mean what we think).
    loose = _brute_force_pairs(A, B, eps=-1e-9)
    assert found <= loose
