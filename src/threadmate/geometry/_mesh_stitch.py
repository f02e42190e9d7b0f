"""Stitching a body's mesh: the meridians' vertex chains, the lateral strips between
neighbouring meridians, the end caps, into one watertight mesh.

The vertex list of a meridian runs from the lower end plane to the upper one (in ``z``
order, which is the order of ``tau = z - s``, the helix each vertex lies on). Neighbouring
meridians are stitched by a zipper that merges their vertices in ``tau`` order, so every
lateral triangle runs along the helices; on a trimmed body piecewise between the kinks of
the ridge (:mod:`._mesh_trim`). The bolt's end faces are fans from the axis; the nut's end
faces are annuli zipped to the outer circle, a regular polygon of its own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import NDArray

from .._angles import TWO_PI, wrap_phase
from ._body import ThreadBody
from ._mesh_plan import NUT_GRID_TURN, SAGITTA_SHARE, meridians, prime
from ._mesh_trim import KINK_TOL, Trim, meridian_kinks, trimmed_chain

__all__ = ["assemble"]


@dataclass
class _Chain:
    """A meridian's vertices from the lower end plane to the upper one: indices, helix
    coordinates, heights, kink labels (label -> position), latitude-station flags."""

    idx: NDArray[np.int64]
    tau: NDArray[np.float64]
    z: NDArray[np.float64]
    marks: dict[int, int]
    lat: NDArray[np.bool_] | None = None


def assemble(
    body: ThreadBody,
    stations: NDArray[np.float64],
    crossings: NDArray[np.float64],
    count: int,
    turn: float,
    chord: float,
    trim: Trim | None = None,
) -> trimesh.Trimesh:
    """The watertight mesh of ``body`` on the meridians of a regular grid of ``count``
    (turned by ``turn`` of its spacing) and the ``crossings``, through ``stations``: one
    chain per meridian, the lateral strips between them, the end caps (a nut's with its
    outer cylinder, a polygon within ``chord``); trimmed by ``trim`` when the body has an
    envelope."""
    profile = body.profile
    p, lead, hand = profile.pitch, body.lead, body.hand
    z_lo, z_hi = body.z_min, body.z_max
    theta = meridians(crossings, count, turn)
    n_mer = len(theta)
    tol = 1e-9 * p
    kinks = meridian_kinks(body, trim, theta) if trim is not None else None

    vertices: list[NDArray[np.float64]] = []
    chains: list[_Chain] = []
    n_vert = 0
    for j, th in enumerate(theta):
        s = hand * lead * th / TWO_PI
        lo, hi = z_lo - s, z_hi - s
        k = np.arange(math.floor((lo - stations[-1]) / p), math.ceil((hi - stations[0]) / p) + 1)
        tau = (stations[None, :] + p * k[:, None]).ravel()
        tau = np.sort(tau[(tau > lo + tol) & (tau < hi - tol)])
        # End vertices lie exactly on the end planes; on an inserted meridian they take the
        # crossing station's radius (the same helix, within the rounding of the angle).
        ends = np.array([lo, hi])
        near = [_station_at(e, stations, p, tol) for e in ends]
        if trim is None or kinks is None:
            r_ends = np.array(
                [
                    profile.radius(n if n is not None else e).item()
                    for e, n in zip(ends, near, strict=True)
                ]
            )
            r = np.concatenate([[r_ends[0]], profile.radius(tau), [r_ends[1]]])
            z = np.concatenate([[z_lo], tau + s, [z_hi]])
            key = np.concatenate([[lo], tau, [hi]])
            chain = _Chain(n_vert + np.arange(len(z)), key, z, {})
        else:
            t_ends = (lo if near[0] is None else near[0], hi if near[1] is None else near[1])
            key, z, r, marks, lat = trimmed_chain(
                trim, s, (lo, hi), (z_lo, z_hi), t_ends, tau, kinks[j], KINK_TOL * p
            )
            chain = _Chain(n_vert + np.arange(len(z)), key, z, marks, lat)
        vertices.append(np.column_stack([r * math.cos(th), r * math.sin(th), z]))
        chains.append(chain)
        n_vert += len(z)

    faces: list[NDArray[np.int64]] = []
    # Lateral strips; the last one joins the last meridian to the first one turned by a
    # full revolution, whose helix labels are shifted by one lead.
    starts = round(lead / p)
    n_grid = len(trim.grid) if trim is not None else 0
    for j in range(n_mer):
        last = j + 1 == n_mer
        faces.append(
            _strip(
                chains[j],
                chains[(j + 1) % n_mer],
                hand * lead if last else 0.0,
                hand * starts * n_grid if last else 0,
            )
        )
    lateral = np.concatenate(faces)
    if body.kind == "nut":
        lateral = lateral[:, ::-1]  # the nut's material lies outside the thread surface

    bottom = np.array([c.idx[0] for c in chains])
    top = np.array([c.idx[-1] for c in chains])
    caps: list[NDArray[np.int64]] = []
    if body.kind == "bolt":
        centres = np.array([[0.0, 0.0, z_lo], [0.0, 0.0, z_hi]])
        c_lo, c_hi = n_vert, n_vert + 1
        vertices.append(centres)
        nxt = np.roll(np.arange(n_mer), -1)
        caps.append(np.column_stack([np.full(n_mer, c_lo), bottom[nxt], bottom]))
        caps.append(np.column_stack([np.full(n_mer, c_hi), top, top[nxt]]))
    else:
        assert body.outer_radius is not None  # a nut body has its outer cylinder
        r_out = float(body.outer_radius)
        sag = 2.0 * math.acos(max(-1.0, 1.0 - SAGITTA_SHARE * chord / r_out))
        n_out = prime(math.ceil(TWO_PI / sag), 3)
        phi = TWO_PI / n_out * (np.arange(n_out, dtype=np.float64) + NUT_GRID_TURN)
        ring = np.column_stack([r_out * np.cos(phi), r_out * np.sin(phi)])
        o_lo = n_vert + np.arange(n_out)
        o_hi = o_lo + n_out
        vertices.append(np.column_stack([ring, np.full(n_out, z_lo)]))
        vertices.append(np.column_stack([ring, np.full(n_out, z_hi)]))
        top_faces = _annulus(top, theta, o_hi, phi)
        caps.append(top_faces)
        caps.append(_annulus(bottom, theta, o_lo, phi)[:, ::-1])
        nxt = np.roll(np.arange(n_out), -1)
        caps.append(np.column_stack([o_lo, o_lo[nxt], o_hi]))
        caps.append(np.column_stack([o_lo[nxt], o_hi[nxt], o_hi]))
    mesh = trimesh.Trimesh(
        np.concatenate(vertices), np.concatenate([lateral, *caps]), process=False
    )
    return mesh


def _strip(a: _Chain, b: _Chain, shift: float, label_shift: int) -> NDArray[np.int64]:
    """Triangles between neighbouring meridians' chains (``b`` turned by ``shift`` of
    helix coordinate and ``label_shift`` of kink labels when it closes the revolution).

    Without kinks, one zipper in ``tau`` order. With them, the kinks of one branch on both
    chains are joined by an edge (so no triangle cuts across the ridge where thread and
    envelope meet), and the pieces between are zipped in ``tau`` order on the thread, in
    height order on a sphere (along its latitudes).
    """
    b_tau = b.tau - shift
    if not a.marks or not b.marks:
        return _zipper(a.idx, a.tau, b.idx, b_tau)
    pairs = sorted(
        {
            (pa, b.marks[lab + label_shift])
            for lab, pa in a.marks.items()
            if lab + label_shift in b.marks
        }
    )
    path = [(0, 0)]
    for pa, pb in pairs:
        if pa >= path[-1][0] and pb >= path[-1][1] and (pa, pb) != path[-1]:
            path.append((pa, pb))
    end = (len(a.idx) - 1, len(b.idx) - 1)
    if path[-1] != end:
        path.append(end)
    faces = []
    for (a0, b0), (a1, b1) in zip(path[:-1], path[1:], strict=True):
        sa, sb = slice(a0, a1 + 1), slice(b0, b1 + 1)
        inner = (
            np.concatenate([a.lat[a0 + 1 : a1], b.lat[b0 + 1 : b1]])
            if a.lat is not None and b.lat is not None
            else np.empty(0, bool)
        )
        if len(inner) and inner.all():
            faces.append(_zipper(a.idx[sa], a.z[sa], b.idx[sb], b.z[sb]))
        else:
            faces.append(_zipper(a.idx[sa], a.tau[sa], b.idx[sb], b_tau[sb]))
    return np.concatenate(faces)


def _station_at(tau: float, stations: NDArray[np.float64], p: float, tol: float) -> float | None:
    """The station (as a ``tau`` on the same helix) within ``tol`` of ``tau``, if any."""
    k = np.round((tau - stations) / p)
    cand = stations + k * p
    i = int(np.argmin(np.abs(cand - tau)))
    return float(cand[i]) if abs(cand[i] - tau) <= tol else None


def _zipper(
    a_idx: NDArray[np.int64],
    a_key: NDArray[np.float64],
    b_idx: NDArray[np.int64],
    b_key: NDArray[np.float64],
) -> NDArray[np.int64]:
    """Triangles stitching two vertex chains merged in ``key`` order.

    Each step advances the chain whose next vertex has the smaller key and makes the
    triangle ``(a, b, new)``; for chains on meridians ``theta_a < theta_b`` ordered upward
    this winds counter-clockwise seen from outside (+r).
    """
    keys = np.concatenate([a_key[1:], b_key[1:]])
    from_a = np.concatenate([np.ones(len(a_key) - 1, bool), np.zeros(len(b_key) - 1, bool)])
    from_a = from_a[np.argsort(keys, kind="stable")]
    ia = np.cumsum(from_a)
    ib = np.cumsum(~from_a)
    a_prev = a_idx[ia - from_a]
    b_prev = b_idx[ib - ~from_a]
    new = np.where(from_a, a_idx[ia], b_idx[ib])
    return np.column_stack([a_prev, b_prev, new])


def _annulus(
    inner: NDArray[np.int64],
    inner_angle: NDArray[np.float64],
    outer: NDArray[np.int64],
    outer_angle: NDArray[np.float64],
) -> NDArray[np.int64]:
    """Triangles of a flat ring between two closed chains, wound to face +z."""
    start = inner_angle[0]
    o_ang = start + wrap_phase(outer_angle - start, TWO_PI)
    order = np.argsort(o_ang)
    o_idx, o_ang = outer[order], o_ang[order]
    # Close both chains by repeating their first vertex one revolution on.
    i_idx = np.concatenate([inner, inner[:1]])
    i_ang = np.concatenate([inner_angle, [start + TWO_PI]])
    o_idx = np.concatenate([o_idx, o_idx[:1]])
    o_ang = np.concatenate([o_ang, o_ang[:1] + TWO_PI])
    # (inner, outer, new) turns from the radial direction to the circumferential: +z.
    return _zipper(i_idx, i_ang, o_idx, o_ang)
