"""The exact profile and its regions against closed forms written out here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from threadmate.geometry import Profile, bolt_body, bolt_profile, nut_body, nut_profile

SQ3 = math.sqrt(3.0)


def sharp(t, p, pd, major, minor):
    """conventions.md's sharp profile, written independently."""
    t = (np.asarray(t) + p / 2) % p - p / 2
    return np.clip(pd / 2 + SQ3 * (p / 4 - np.abs(t)), minor / 2, major / 2)


def test_sharp_profile_matches_the_conventions_formula(sharp_quarter_20):
    s = sharp_quarter_20
    t = np.linspace(-0.2, 0.2, 4001)
    for prof, body in ((bolt_profile(s), s.bolt), (nut_profile(s), s.nut)):
        expect = sharp(t, s.pitch, body.pitch_diameter, body.major, body.minor)
        np.testing.assert_allclose(prof.radius(t), expect, atol=1e-15)


def test_regions_follow_conventions(sharp_quarter_20):
    s = sharp_quarter_20
    b, n = bolt_profile(s), nut_profile(s)
    # t = 0: bolt crest centre, nut root centre; t = +-p/2: bolt root, nut crest.
    assert b.region(0.0) == "crest" and n.region(0.0) == "root"
    assert b.region(0.0249) == "root" and n.region(-0.0249) == "crest"
    # Flanks: t < 0 positive side (radius grows with +z), t > 0 negative side.
    assert b.region(-0.012) == "+F" and b.region(0.012) == "-F"
    assert n.region(-0.012) == "+F" and n.region(0.012) == "-F"
    dr = b.radius(-0.012 + 1e-6) - b.radius(-0.012)
    assert dr > 0  # +F: radius grows as t (hence z) grows


def test_region_of_one_number_is_the_arrays(quarter_20, sharp_quarter_20):
    """A region asked for one number (the contact code's path) is the array's, across a
    pitch and beyond it, at the pieces' breakpoints and either side of them."""
    for spec in (quarter_20, sharp_quarter_20):
        for prof in (bolt_profile(spec), nut_profile(spec)):
            edges = np.array(prof.breakpoints)
            t = np.concatenate(
                [
                    np.linspace(-0.06, 0.06, 2401),
                    edges,
                    -edges,
                    np.nextafter(edges, 1.0),
                    np.nextafter(-edges, -1.0),
                    [-prof.pitch / 2, prof.pitch / 2],
                ]
            )
            assert [str(prof.region(float(x))) for x in t] == prof.region(t).tolist()


def _line_distance(u, r, p0, direction):
    d = np.asarray(direction) / np.linalg.norm(direction)
    v = np.array([u - p0[0], r - p0[1]])
    return abs(v[0] * d[1] - v[1] * d[0])


@pytest.mark.parametrize("rho_hi, rho_lo", [(0.004, 0.00625), (0.0, 0.003), (0.002, 0.0)])
def test_fillets_are_tangent_arcs(rho_hi, rho_lo):
    p, pd, major, minor = 0.05, 0.21455, 0.24485, 0.1887
    prof = Profile("bolt", p, pd, major, minor, crest_fillet=rho_hi, root_fillet=rho_lo)
    a1, a2, a3, a4 = prof.breakpoints
    # The profile is continuous with a continuous slope (C1) everywhere.
    t = np.linspace(-p / 2, p / 2, 20001)
    r = prof.radius(t)
    assert np.max(np.abs(np.diff(r))) < SQ3 * (t[1] - t[0]) * 1.0001
    # At a filleted corner the slope is continuous (the arc is tangent to both lines).
    eps = 1e-9
    for rho, ends in ((rho_hi, (a1, a2)), (rho_lo, (a3, a4))):
        if rho > 0:
            for u in ends:
                assert prof.slope(-(u - eps)) == pytest.approx(prof.slope(-(u + eps)), abs=1e-3)
    # Points on each arc are at the radius from a centre found independently as the point
    # at distance rho from both the flat and the flank line.
    flank_p0 = (p / 4, pd / 2)  # the flank passes through (p/4, pd/2) in (u, r)
    flank_dir = (1.0, -SQ3)
    corners = ((rho_hi, a1, a2, major / 2, -1), (rho_lo, a3, a4, minor / 2, 1))
    for rho, lo, hi, r_flat, sgn in corners:
        if rho == 0:
            continue
        u_corner = p / 4 + (pd / 2 - r_flat) / SQ3
        # Centre lies rho from the flat (on the side away from the corner's material edge)
        # and rho from the flank line.
        cr = r_flat + sgn * rho
        cu = u_corner + sgn * rho / SQ3
        assert _line_distance(cu, cr, flank_p0, flank_dir) == pytest.approx(rho, rel=1e-9)
        uu = np.linspace(lo, hi, 50)
        np.testing.assert_allclose(np.hypot(uu - cu, prof.radius(uu) - cr), rho, rtol=1e-9)
    # Away from the fillets the profile is the sharp one.
    away = (np.abs(t) <= a1) | ((np.abs(t) >= a2) & (np.abs(t) <= a3)) | (np.abs(t) >= a4)
    np.testing.assert_allclose(r[away], sharp(t, p, pd, major, minor)[away], atol=1e-15)


def test_distance_is_zero_on_the_profile_and_exact_off_it(quarter_20):
    prof = bolt_profile(quarter_20)
    t = np.random.default_rng(0).uniform(-0.025, 0.025, 500)
    assert np.max(prof.distance(t, prof.radius(t))) < 1e-15
    # On a flank the axial-section distance to the line is |dr| / 2 (slope sqrt 3).
    t_flank = np.full(5, -0.012)
    d = prof.distance(t_flank, prof.radius(t_flank) + 1e-4)
    np.testing.assert_allclose(d, 1e-4 / 2, rtol=1e-9)


def test_section_radius_is_the_helix(quarter_20):
    b, n = bolt_body(quarter_20), nut_body(quarter_20)
    theta = np.linspace(0, 2 * np.pi, 97)
    # One turn up along a right-hand helix returns to the same profile point.
    np.testing.assert_allclose(
        b.section_radius(theta, 0.0), b.section_radius(theta + 2 * np.pi, 0.0), atol=1e-15
    )
    np.testing.assert_allclose(
        b.section_radius(theta, 0.0),
        b.section_radius(theta + 0.3, 0.05 * 0.3 / (2 * np.pi)),
        atol=1e-12,
    )
    # At theta = 0, z = 0 the bolt's crest centre meets the nut's groove centre (in phase).
    assert b.helical_region(0.0, 0.0) == "crest" and n.helical_region(0.0, 0.0) == "root"


def test_region_of_points_on_end_faces(quarter_20):
    b, n = bolt_body(quarter_20), nut_body(quarter_20)
    assert b.region_of([[0.05, 0.0, 0.0]])[0] == "base"
    assert n.region_of([[0.18, 0.0, 0.0]])[0] == "surface"
    # A point on the bolt's flank above the base is in a thread region.
    theta = 0.4
    t_target = -0.012  # +F
    z = t_target + 0.05 * theta / (2 * np.pi)
    r = float(bolt_profile(quarter_20).radius(t_target))
    assert b.region_of([[r * np.cos(theta), r * np.sin(theta), z]])[0] == "+F"


@pytest.mark.parametrize("which", ["bolt", "nut"])
def test_distance_matches_brute_force_near_and_far(quarter_20, which):
    """The axial-section distance to the profile against the nearest of the profile's own
    points sampled every 0.5 micro-inch over three pitches, for points inside and outside
    the body, near the fillet arcs and far below them (where the arcs' whole circles, not
    the arcs, pass close by)."""
    prof = bolt_profile(quarter_20) if which == "bolt" else nut_profile(quarter_20)
    p = quarter_20.pitch
    spacing = 5e-7
    ts = np.arange(-1.5 * p, 1.5 * p, spacing)
    curve = np.column_stack([ts, prof.radius(ts)])
    rng = np.random.default_rng(3)
    a1, a2, a3, a4 = prof.breakpoints
    t = np.concatenate(
        [
            rng.uniform(-p / 2, p / 2, 200),
            rng.uniform(a1, a2, 100) * rng.choice([-1, 1], 100),
            rng.uniform(a3, a4, 100) * rng.choice([-1, 1], 100),
        ]
    )
    r = rng.uniform(prof.r_lo - 0.3 * p, prof.r_hi + 0.3 * p, t.size)
    got = prof.distance(t, r)
    for k in range(t.size):
        brute = np.hypot(curve[:, 0] - t[k], curve[:, 1] - r[k]).min()
        assert brute - spacing <= got[k] <= brute + 1e-12, (t[k], r[k], got[k], brute)
