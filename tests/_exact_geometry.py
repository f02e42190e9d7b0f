"""Exact-geometry references for the contact and mechanics tests (no mesh involved).

The nut is the sharp profile of conventions.md written out here; the bolt's profile (with
its fillets) is taken from :func:`threadmate.geometry.bolt_body`, whose radius function is
tested against the published profile in ``test_profile.py``. Neither python-fcl nor any
mesh enters. The height at which the exact bolt, at a given rotation, first touches the
exact nut when lowered along -Z is the larger of two searches:

- over the bolt's surface (tip face and thread): the highest point of nut material under
  each bolt point, a dense parametric grid refined locally;
- over the nut's convex edges (the top face's inner boundary, the crest's corners): the
  lowest bolt material over each edge point, found along the vertical line through it.
  Over an edge the nut's height jumps, and the bolt points just over it form a band too
  thin for the first grid; from the edge's side the search is a smooth one-dimensional one.
"""

from __future__ import annotations

import math

import numpy as np

from threadmate.geometry import bolt_body


def rot(roll, pitch, phase):
    """Rx(roll) Ry(pitch) Rz(phase), written out here (conventions.md)."""
    a, b, c = np.radians([roll, pitch, phase])
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rx @ ry @ rz


def nut_top(spec, x, y):
    """Highest z <= 0 of the (sharp) nut's material on the vertical line through (x, y).

    Material where R_n(t) <= r with t = z - hand lead theta / 2 pi: |t| >= u_r, the flank
    solution of R_n(u_r) = r. Coming down from z = 0, t falls from t0 and first reaches
    -u_r at z = -(t0 + u_r).
    """
    n, p = spec.nut, spec.pitch
    r, th = np.hypot(x, y), np.arctan2(y, x)
    t0 = -spec.handedness * spec.lead * th / (2 * math.pi)
    t0 = t0 - p * np.floor(t0 / p + 0.5)
    u_r = np.clip(p / 4 + (n.pitch_diameter / 2 - r) / math.sqrt(3), 0, p / 2)
    z = np.where(np.abs(t0) >= u_r, 0.0, -(t0 + u_r))
    return np.where((r < n.minor / 2) | (r > n.outer_radius), -np.inf, z)


def exact_centre_height(
    spec, rotation, compliance_z=0.0, n_theta=1200, n_v=48, sectors=48, refined=16
):
    """Height of the compliance centre C (held at x = y = 0) at which the exact bolt, at
    ``rotation``, first touches the exact nut when lowered along -Z.

    A bolt point x_B sits at R (x_B - compliance_z e_z) + (0, 0, z_C); it touches when that
    height equals ``nut_top`` below it. So z_C = max over bolt points of
    nut_top(q_x, q_y) - q_z with q = R (x_B - compliance_z e_z): a dense grid over the tip
    face and the thread surface, then a shrinking local grid around the best point of each
    of the ``refined`` best angular sectors (``sectors`` of them; ``n_theta`` a multiple).
    With compliance_z = 0 it is the origin's height (the tip centre's).

    ``nut_top`` jumps at the nut's convex edges (the top face's inner boundary, the crest's
    corners), where a grid over the bolt cannot resolve the thin band of bolt points just
    over the edge; those contacts are found from the other side (:func:`_over_edges`).
    """
    assert spec.nut.crest_fillet == 0 and spec.nut.root_fillet == 0, "a sharp nut only"
    bolt = bolt_body(spec)  # R_b(t) with its fillets, from the profile
    R = np.asarray(rotation, dtype=float)
    length = spec.bolt.length

    def lowest(q):
        return nut_top(spec, q[..., 0], q[..., 1]) - q[..., 2]

    def lateral(th, zb):
        r = bolt.section_radius(th, zb)
        return lowest(np.stack([r * np.cos(th), r * np.sin(th), zb - compliance_z], -1) @ R.T)

    def tip(th, s):
        r = s * bolt.section_radius(th, 0.0)
        return lowest(np.stack([r * np.cos(th), r * np.sin(th), 0 * r - compliance_z], -1) @ R.T)

    best = -np.inf
    for f, top in ((lateral, length), (tip, 1.0)):
        th = np.linspace(-np.pi, np.pi, n_theta, endpoint=False)
        v = np.linspace(0, top, n_v)
        grid = f(*np.meshgrid(th, v, indexing="ij"))
        # Candidates: the best grid point of each of ``sectors`` angular sectors (a narrow
        # contact elsewhere is not crowded out by a broad one), the best of them refined.
        per = grid.reshape(sectors, -1)
        local_best = per.argmax(axis=1)
        order = np.argsort(per[np.arange(sectors), local_best])[::-1][:refined]
        for sector in order:
            k = sector * per.shape[1] + local_best[sector]
            i, j = np.unravel_index(k, grid.shape)
            t0, v0, h = th[i], v[j], grid[i, j]
            if not np.isfinite(h):
                continue
            wt, wv = 2 * np.pi / n_theta, top / n_v
            for _ in range(12):
                tt = t0 + np.linspace(-wt, wt, 21)
                vv = np.clip(v0 + np.linspace(-wv, wv, 21), 0, top)
                local = f(*np.meshgrid(tt, vv, indexing="ij"))
                a, b = np.unravel_index(local.argmax(), local.shape)
                if local[a, b] >= h:
                    h, t0, v0 = local[a, b], tt[a], vv[b]
                wt, wv = wt / 4, wv / 4
            best = max(best, h)
    return float(max(best, _over_edges(spec, bolt, R, compliance_z)))


def exact_first_height(spec, roll, pitch, phase, n_theta=2400, n_v=80):
    """Origin (tip-centre) height at which the exact bolt at (roll, pitch, phase), its
    origin over x = y = 0, first touches the exact nut."""
    return exact_centre_height(spec, rot(roll, pitch, phase), 0.0, n_theta, n_v)


def _material(bolt, a, d, s):
    """Whether the bolt-frame points a + s d are bolt material (tip face and thread)."""
    q = a + s[..., None] * d
    r = np.hypot(q[..., 0], q[..., 1])
    return r <= bolt.section_radius(np.arctan2(q[..., 1], q[..., 0]), q[..., 2])


def _bolt_bottom(spec, bolt, R, compliance_z, x, y, n_s=120):
    """Lowest height of the bolt's material over the points (x, y) of F with C at the
    origin (+inf where there is none): each vertical line, in the bolt frame, sampled along
    the bolt's length, its first material sample closed in on by bisection."""
    a = np.stack([x, y, np.zeros_like(x)], -1) @ R  # R^T (x, y, 0)
    a[..., 2] += compliance_z
    d = R[2, :]  # R^T e_z: the vertical's direction in the bolt frame
    s0 = -a[..., 2] / d[2]  # where the line crosses the tip face's plane
    s1 = (spec.bolt.length - a[..., 2]) / d[2]
    S = s0[:, None] + (s1 - s0)[:, None] * np.linspace(0.0, 1.0, n_s)
    inside = _material(bolt, a[:, None, :], d, S)
    first = np.argmax(inside, axis=1)
    rows = np.arange(len(S))
    lo, hi = S[rows, np.maximum(first - 1, 0)], S[rows, first]
    for _ in range(32):
        mid = 0.5 * (lo + hi)
        m = _material(bolt, a, d, mid)
        lo, hi = np.where(m, lo, mid), np.where(m, mid, hi)
    out = np.where(first > 0, hi, s0)  # first == 0: on the tip face itself
    return np.where(inside.any(axis=1), out, np.inf)


def _nut_edges(spec, edge, theta):
    """Points (r, z) of the nut's convex edges at the angles ``theta`` (radians): edge 0 is
    the top face's inner boundary (z = 0), the others the corners of the crest
    (r = minor / 2) with a flank, one per turn within the nut's height (z NaN where that
    turn is outside the nut)."""
    n, p = spec.nut, spec.pitch
    t0 = -spec.handedness * spec.lead * theta / (2 * math.pi)
    t0 = t0 - p * np.floor(t0 / p + 0.5)
    r_top = np.clip(
        n.pitch_diameter / 2 + math.sqrt(3) * (p / 4 - np.abs(t0)), n.minor / 2, n.major / 2
    )
    u_c = float(np.clip(p / 4 + (n.pitch_diameter - n.minor) / 2 / math.sqrt(3), 0, p / 2))
    # Corner edges: t = +-u_c on the crest's corners, t = z + t0 (mod p): z = t - t0 + k p.
    k = np.where(edge % 2 == 1, 1, -1) * u_c - t0 + ((edge - 1) // 2 - _TURNS) * p
    z = np.where(edge == 0, 0.0, np.where((k <= 0) & (k >= -n.height), k, np.nan))
    r = np.where(edge == 0, r_top, n.minor / 2)
    return r, z


_TURNS = 3  # corner edges are tried over this many turns either side of the top


def _over_edges(spec, bolt, R, compliance_z, n_theta=720, refined=12):
    """Highest compliance-centre height at which the bolt touches one of the nut's convex
    edges: max over edge points E of E_z - (lowest bolt material over E), a grid over the
    edges' angle, the best ``refined`` grid points of all edges refined together by
    shrinking local grids."""

    def height(edge, theta, n_s):
        r, z = _nut_edges(spec, edge, theta)
        out = np.full(theta.shape, -np.inf)
        ok = np.isfinite(z)
        if ok.any():
            th = theta[ok]
            out[ok] = z[ok] - _bolt_bottom(
                spec, bolt, R, compliance_z, r[ok] * np.cos(th), r[ok] * np.sin(th), n_s
            )
        return out

    n_edges = 1 + 2 * (2 * _TURNS + 1)
    theta = np.linspace(-np.pi, np.pi, n_theta, endpoint=False)
    edge = np.repeat(np.arange(n_edges), n_theta)
    grid_theta = np.tile(theta, n_edges)
    values = height(edge, grid_theta, 60)
    if not np.isfinite(values).any():
        return -np.inf
    top = np.argsort(values)[::-1][:refined]
    top = top[np.isfinite(values[top])]
    e, t0, h = edge[top], grid_theta[top], values[top]
    w = 2 * np.pi / n_theta
    for _ in range(9):
        tt = t0[:, None] + np.linspace(-w, w, 21)
        local = height(np.repeat(e, 21), tt.ravel(), 120).reshape(tt.shape)
        j = np.argmax(local, axis=1)
        better = local[np.arange(len(j)), j] >= h
        h = np.where(better, local[np.arange(len(j)), j], h)
        t0 = np.where(better, tt[np.arange(len(j)), j], t0)
        w /= 4
    return float(h.max())
