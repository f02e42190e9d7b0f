"""Independent dynamics check of ``threadmate search``: the snap simulated in MuJoCo.

Run:  python docs/scripts/dynamics_check.py [--cases upright,stiff,...] [--ends] [--json FILE]

docs/mechanics.md, "Independent checks worth having": a frictionless, slowly turned,
heavily damped simulation of the same compliance chain, with convex pieces cut from the
exact profile, must reproduce the quasi-static snap phase and click. This script builds
that simulation with nothing from threadmate's contact code but its rest state at the
start (and its search, to compare with):

- **Geometry.** Each body is cut into angular sectors (2 degrees) and, in each sector,
  into one piece per thread tooth the sector holds within the body's slab (the bolt
  ``0 <= z <= length``, the nut ``-height <= z <= 0``). At a fixed angle a tooth's axial
  section is convex (the bolt's: ``root radius <= r <= R_b(t)`` over the tooth; the
  nut's: ``R_n(t) <= r <= root radius``), and so is its intersection with the slab; a
  piece's vertices are those exact section polygons (vertices on the exact profile, the
  tip face and the top face) at every half degree and at every angle where a profile
  breakpoint meets an end face. MuJoCo collides the pieces' convex hulls. Material
  that cannot touch the other body is left out: the bolt's core inside its root radius
  and its root fillets (below the nut's minor radius by more than any tilt here moves
  them), the nut outside its major radius (beyond the bolt's crest); left out material
  is inside the exact body, so it can only make the model miss a contact, and none of
  it is within reach. A chamfered point and a countersink (conventions.md, "Ends"; with
  ``--ends``) are cones about the axis: in the meridian plane each is a half-plane
  (the bolt's material ``r <= r0 + k z``, the nut's ``r >= r0 + k z``) that clips
  every section polygon, which stays convex; the point's core below where the chamfer
  meets the root radius is one more piece (a frustum), its cone the chamfer's. A
  rounded point is not built. The hulls' deviation from the exact bodies is measured:
  outward (hull surface outside the exact body, the dangerous direction) and inward
  (exact thread surface outside every hull; the ends' cones are not sampled).
- **Compliance chain** (SI inside; docs/mechanics.md, "The system"): a slide along Z
  at the compliance centre C (held at x = y = 0), a hinge about the fixed X axis (roll),
  one about the rolled Y axis (pitch), one about the bolt axis (phase), as in the pose
  convention ``R = Rx(roll) Ry(pitch) Rz(phase)``; C at the tip centre. A constant
  axial force F down on the slide; roll and pitch springs ``k_r`` toward the held tilt;
  the spin driven by a stiff position servo turning at a slow constant rate (one turn
  per 80 s by default); heavy joint damping so that the motion is quasi-static;
  frictionless contacts (condim 1, one contact per pair of pieces). Masses are
  arbitrary in the quasi-static limit and chosen for a stable, overdamped integration
  (:class:`Dynamics`); contacts are hard (``solimp`` 0.99, ``solref`` five steps,
  overdamped, a convex-collision tolerance of 1e-13 m) so that the penetration under
  load stays a few tenths of a micrometre. MuJoCo 4.0.0's sparse Cholesky bug (fixed in
  4.0.1) is kept out with the dense Jacobian.
- **Run.** From threadmate's rest state on its search's branch 25 degrees before its
  snap (the ride before is smooth; without a snap, before the jump it located with the
  largest drop), the model settles at that phase, then turns. A jump is a fall of C
  faster than 0.3 of the free fall's speed: the phase where the fall started is its
  phase; the driver then stops, the bolt settles (a landing on one contact creeps for a
  second or more) and the fall of C is its drop. A jump is the snap when the bolt then
  screws in: turned back (clockwise) 180 degrees from the landing, C descends at the
  lead (within 10 %) over the last third, without the driver stalling; otherwise the
  turn goes on from the landing. Falls under 0.002 pitch are slips (a contact passing a
  seam of the pieces), not jumps. The fall a sensor sees (the click) is measured as
  threadmate measures it (``SearchEvent.click``): from the highest the simulated trace
  stands within ``CLICK_SPAN`` (one degree) of turn before the snap's fall started to
  the landing, a cascade of smaller jumps and a steep stretch before it included.
- **Compared** with ``threadmate search`` (frictionless, same compliance): the snap's
  phase and click, the landing (height at the same phase, tilt), and whether each calls
  the landing in phase. The simulated landing and screw-in are
  checked on the exact bodies (:func:`exact_interference`).

Prints a table and, on request, writes the rows as JSON (with threadmate's events and
the simulation's jumps). Progress goes to stderr. Lengths are in the spec's units unless
they say um.

The simulated poses can be checked on the exact bodies (:func:`exact_interference`):
the deepest a sampled point of either body lies inside the other at that pose.
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import os
import sys
import time
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull

from threadmate.contact import CLICK_SPAN, Compliance, Mechanics, search
from threadmate.geometry import ThreadSpec, bolt_body, nut_body, spec_from_designation
from threadmate.geometry._body import ThreadBody

__all__ = [
    "CASES",
    "Case",
    "Piece",
    "SimResult",
    "build_model",
    "closed_form",
    "exact_interference",
    "hull_deviation",
    "pieces",
    "run_case",
    "simulate",
    "thesis_spec",
]

Array = NDArray[np.float64]

#: Metres per spec length unit.
METRES = {"in": 0.0254, "mm": 0.001}
#: Angular width of a piece (degrees).
SECTOR = 2.0
#: Section polygons per piece (the piece's edges included: SUBDIVIDE + 1).
SUBDIVIDE = 4


@dataclass(frozen=True)
class Case:
    """One start to simulate.

    Attributes
    ----------
    name : str
        Short label (the ``--cases`` key).
    roll, pitch, phase : float
        Held tilt and the search's start phase (degrees).
    stiffness : float
        Rotational stiffness ``k_r`` (N m/rad); force 10 N, frictionless.
    lead_in : float
        Start the simulation this many degrees before threadmate's snap (from its rest
        state there), or at the start phase if that is later.
    """

    name: str
    roll: float
    pitch: float
    phase: float
    stiffness: float = 1.0
    lead_in: float = 25.0


CASES: dict[str, Case] = {
    c.name: c
    for c in (
        Case("upright", 0.0, 0.0, 40.0),
        Case("pitch-3", 0.0, -3.0, 30.0),
        Case("tilt+1+1", 1.0, 1.0, 60.0),
        Case("tilt-2+1", -2.0, 1.0, 120.0),
        Case("tilt+2-1.5", 2.0, -1.5, 200.0),
        Case("stiff", 0.0, 0.0, 300.0, stiffness=100.0),
        Case("roll-1", -1.0, 0.0, 30.0),
        Case("pitch-1", 0.0, -1.0, 30.0),
    )
}


def thesis_spec() -> ThreadSpec:
    """The thesis's flat 1/4-20 UNC-2A/2B parts (flat tip, flat nut face, no countersink)."""
    return spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)


def _flat(spec: ThreadSpec) -> bool:
    """Whether both bodies end flat (the closed form's parts)."""
    return bolt_body(spec).envelope is None and nut_body(spec).envelope is None


def closed_form(spec: ThreadSpec) -> tuple[float, float]:
    """Snap phase (degrees) and drop (spec units) of an upright, stiffly held bolt.

    The bolt fits the nut where its thread lies within the axial flank clearance
    ``c = (nut pd - bolt pd) / sqrt(3)`` of the nut's; resting on the top face, it falls
    at the phase where that window opens (``360 (1 - c / (2 lead))`` for a right-hand
    thread), by ``c``.
    """
    c = (spec.nut.pitch_diameter - spec.bolt.pitch_diameter) / math.sqrt(3.0)
    return 360.0 * (1.0 - c / (2.0 * spec.lead)), c


# -- geometry -----------------------------------------------------------------------------


@dataclass(frozen=True)
class Piece:
    """One convex piece of a body, in the body's frame (spec units).

    Attributes
    ----------
    sector : int
        Index of its angular sector (``sector`` times the pieces' width, in degrees,
        onward); -1 for the bolt point's core, all round.
    tooth : int
        Which tooth (profile period) of the helix it holds.
    vertices : (n, 3) array
        Points on the exact body whose hull the simulation collides.
    """

    sector: int
    tooth: int
    vertices: Array = field(repr=False)


def _tooth(body: ThreadBody) -> tuple[float, float, Array, float]:
    """A tooth's profile range ``[lo, hi]`` in ``t``, its breakpoints inside, and the
    radius that closes its section (the bolt's root, the nut's major radius).

    The bolt's tooth runs between the ends of its flanks (its root fillets, concave, are
    left out); the nut's between the ends of its flanks at the root (its root fillets are
    left out), over its crest.
    """
    prof = body.profile
    p = prof.pitch
    a1, a2, a3, a4 = prof.breakpoints
    if body.kind == "bolt":
        arcs = prof._arc_stations(1e-4 * p) if prof.fillet_hi > 0 else np.empty(0)
        arcs = arcs[(arcs > a1) & (arcs < a2)]
        bps = np.unique(np.concatenate([[-a2, -a1, a1, a2], arcs, -arcs]))
        return -a3, a3, bps, prof.r_lo
    arcs = prof._arc_stations(1e-4 * p) if prof.fillet_lo > 0 else np.empty(0)
    arcs = arcs[(arcs > a3) & (arcs < a4)]
    bps = np.unique(np.concatenate([[a3, a4, p - a4, p - a3], arcs, p - arcs]))
    return a2, p - a2, bps, prof.r_hi


def _helix_rate(body: ThreadBody) -> float:
    """``dz/dtheta`` along the thread (spec units per radian)."""
    return body.hand * body.lead / (2.0 * math.pi)


def _sections(
    body: ThreadBody, tooth: int, angles: Array
) -> list[tuple[float, float, float, Array, Array]]:
    """At each angle, the tooth's section clipped to the slab: ``(theta, t_a, t_b, t, R)``
    with the section's profile stations ``t`` and radii ``R`` (empty angles left out)."""
    prof = body.profile
    s = _helix_rate(body)
    lo, hi, bps, _ = _tooth(body)
    shift = tooth * prof.pitch
    out = []
    for th in angles:
        ta = max(lo + shift, body.z_min - s * th)
        tb = min(hi + shift, body.z_max - s * th)
        if tb < ta:
            continue
        inner = bps + shift
        ts = np.unique(np.concatenate([[ta, tb], inner[(inner > ta) & (inner < tb)]]))
        out.append((float(th), ta, tb, ts, np.asarray(prof.radius(ts), dtype=float)))
    return out


def _clip(poly: Array, body: ThreadBody) -> Array:
    """The section polygon ``poly`` (``(r, z)`` vertices in order) within the material
    side of the body's conical end (Sutherland-Hodgman against one half-plane); as given
    for flat ends."""
    env = body.envelope
    if env is None:
        return poly
    # The cone's signed distance is the unbounded cone's: beyond its span the half-plane
    # holds wherever the thread is (the bolt's cone passes its major radius at the span's
    # top, the nut's its minor radius at the bottom).
    inside = -env.signed_distance(poly[:, 0], poly[:, 1])
    out = []
    for i in range(len(poly)):
        j = (i + 1) % len(poly)
        if inside[i] >= 0:
            out.append(poly[i])
        if (inside[i] >= 0) != (inside[j] >= 0):
            out.append(poly[i] + inside[i] / (inside[i] - inside[j]) * (poly[j] - poly[i]))
    return np.array(out) if out else np.empty((0, 2))


def _point_core(body: ThreadBody, n: int = 180) -> list[Piece]:
    """The bolt point's core: the frustum inside the root radius from the tip face up to
    a pitch above where the chamfer meets that radius (sector -1: no thread's)."""
    env = body.envelope
    if body.kind != "bolt" or env is None:
        return []
    r_root, pitch = body.profile.r_lo, body.profile.pitch
    z_root = (r_root - env.r0) / env.slope_rz
    if z_root <= 0:
        return []
    th = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    rings = ((env.r0, 0.0), (r_root, z_root), (r_root, z_root + pitch))
    v = np.concatenate(
        [np.column_stack([r * np.cos(th), r * np.sin(th), np.full(n, z)]) for r, z in rings]
    )
    return [Piece(-1, -1, v)]


def pieces(body: ThreadBody, sector: float = SECTOR, subdivide: int = SUBDIVIDE) -> list[Piece]:
    """The convex pieces of ``body`` (see the module docstring).

    Parameters
    ----------
    body : ThreadBody
        The exact bolt or nut: flat ends, a chamfered point, a countersink.
    sector : float
        Angular width of a piece (degrees).
    subdivide : int
        Section polygons per piece, besides the breakpoint angles, minus one.

    Returns
    -------
    list of Piece
    """
    if body.envelope is not None and body.envelope.kind != "cone":
        raise ValueError("dynamics_check builds flat and conical ends, not a rounded point")
    prof = body.profile
    s = _helix_rate(body)
    lo, hi, bps, close = _tooth(body)
    n = round(360.0 / sector)
    span = (body.z_max - body.z_min) / prof.pitch
    teeth = range(-math.ceil(span) - 2, math.ceil(span) + 3)
    out: list[Piece] = []
    for i in range(n):
        th0, th1 = math.radians(i * sector), math.radians((i + 1) * sector)
        for k in teeth:
            shift = k * prof.pitch
            special = [
                (zc - t) / s
                for t in (lo + shift, hi + shift, *(bps + shift))
                for zc in (body.z_min, body.z_max)
            ]
            angles = np.unique(
                np.concatenate(
                    [np.linspace(th0, th1, subdivide + 1), [a for a in special if th0 < a < th1]]
                )
            )
            secs = _sections(body, k, angles)
            if not secs:
                continue
            pts = []
            for th, _, _, ts, R in secs:
                z = ts + s * th
                # the section: the profile up, the closing radius down
                poly = _clip(
                    np.concatenate(
                        [np.column_stack([R, z]), np.column_stack([0 * R + close, z])[::-1]]
                    ),
                    body,
                )
                if len(poly):
                    pts.append(
                        np.column_stack(
                            [poly[:, 0] * math.cos(th), poly[:, 0] * math.sin(th), poly[:, 1]]
                        )
                    )
            if not pts:
                continue
            v = np.unique(np.concatenate(pts), axis=0)
            if len(v) < 4 or np.linalg.matrix_rank(v[1:] - v[0], tol=1e-9 * prof.pitch) < 3:
                continue
            out.append(Piece(i, k, v))
    return out + _point_core(body)


def _hull(v: Array) -> ConvexHull:
    return ConvexHull(v, qhull_options="Qt")


def hull_deviation(
    body: ThreadBody, parts: list[Piece], sector: float = SECTOR
) -> tuple[float, float]:
    """How far the pieces' hulls stray from the exact body (spec units).

    ``sector`` is the pieces' angular width (degrees, as given to :func:`pieces`).

    Returns
    -------
    outward : float
        The largest distance of a hull surface point (vertices, edge midpoints and seven
        interior points of every facet) outside the exact body (``surface_distance``:
        an upper bound).
    inward : float
        The largest distance of an exact surface point (the flanks, crest and end face of
        every piece's teeth, 20 angles x 40 profile stations per piece, and 9 points across
        each end section) outside every hull of its own and the neighbouring sectors
        (the largest facet-plane excess: a lower bound of the distance, tight near a facet).
    """
    prof = body.profile
    hulls = [_hull(pc.vertices) for pc in parts]
    weights = np.array(
        [
            [1, 0, 0],
            [1 / 3, 1 / 3, 1 / 3],
            [0.5, 0.5, 0],
            [0, 0.5, 0.5],
            [0.5, 0, 0.5],
            [2 / 3, 1 / 6, 1 / 6],
            [1 / 6, 2 / 3, 1 / 6],
            [1 / 6, 1 / 6, 2 / 3],
            [0.45, 0.45, 0.1],
            [0.1, 0.45, 0.45],
        ]
    )
    outward = 0.0
    for pc, h in zip(parts, hulls, strict=True):
        pts = np.einsum("wj,njk->nwk", weights, pc.vertices[h.simplices]).reshape(-1, 3)
        d = np.where(body.contains(pts), 0.0, body.surface_distance(pts))
        outward = max(outward, float(d.max()))
    n = round(360.0 / sector)
    by_sector: dict[int, list[int]] = {}
    for j, pc in enumerate(parts):
        by_sector.setdefault(pc.sector, []).append(j)
    _, _, _, close = _tooth(body)
    inward = 0.0
    for pc in parts:
        if pc.sector < 0:
            continue  # the point's core: its surface is the chamfer's cone, not sampled
        th0 = math.radians(pc.sector * sector)
        secs = _sections(body, pc.tooth, np.linspace(th0, th0 + math.radians(sector), 20))
        samples = []
        s = _helix_rate(body)
        for th, ta, tb, _, _ in secs:
            ts = np.linspace(ta, tb, 40)
            R = np.asarray(prof.radius(ts), dtype=float)
            samples.append(np.column_stack([R * math.cos(th), R * math.sin(th), ts + s * th]))
            for tc in (ta, tb):
                rc = float(prof.radius(tc))
                rr = np.linspace(min(rc, close), max(rc, close), 9)
                z = np.full(9, tc + s * th)
                samples.append(np.column_stack([rr * math.cos(th), rr * math.sin(th), z]))
        if not samples:
            continue
        pts = np.concatenate(samples)
        if body.envelope is not None:
            # thread surface the end trims away is no surface of the body
            r = np.hypot(pts[:, 0], pts[:, 1])
            pts = pts[body.envelope.side * (body.envelope.radius(pts[:, 2]) - r) >= 0]
        if not len(pts):
            continue
        best = np.full(len(pts), np.inf)
        for ii in (pc.sector - 1, pc.sector, pc.sector + 1):
            # (the point's core, sector -1, borders every sector)
            for jj in by_sector.get(ii % n, []) + by_sector.get(-1, []):
                eq = hulls[jj].equations
                excess = (pts @ eq[:, :3].T + eq[:, 3]).max(axis=1)
                best = np.minimum(best, np.maximum(excess, 0.0))
        inward = max(inward, float(best.max()))
    return outward, inward


# -- the model ----------------------------------------------------------------------------


@dataclass(frozen=True)
class Dynamics:
    """Integration and damping settings (SI).

    The quasi-static result does not depend on them; they set how fast and how cleanly
    the model gets there. Defaults: one turn per 80 s; the tilt relaxes toward its rest
    in ``damping_tilt / k_r`` (20 ms at 1 N m/rad: 0.09 degree of turn), C falls at most
    at ``F / damping_z`` (1 mm/s), and the heavy bolt (1 kg, 1e-5 kg m^2) makes the
    contacts' effective mass large, so that hard contacts (``impedance`` 0.99, a time
    constant of ``timeconst`` steps, overdamped by ``dampratio``) hold penetration
    under load to a few tenths of a micrometre. Lighter or less damped settings (0.01 kg,
    critically damped contacts of two steps) made a bolt resting tilted on the edge of
    the top face rock, with 1 to 5 um penetration.
    """

    timestep: float = 1e-4
    turn_period: float = 80.0
    mass: float = 1.0
    inertia: float = 1e-5
    damping_z: float = 1e4
    damping_tilt: float = 2e-2
    spin_kp: float = 100.0
    spin_armature: float = 1e-4
    impedance: float = 0.99
    timeconst: float = 5.0
    dampratio: float = 3.0
    ccd_tolerance: float = 1e-13
    multiccd: bool = False

    def tilt_damping(self, stiffness: float) -> float:
        """Roll and pitch damping (N m s/rad): at least 1.5 times critical."""
        return max(self.damping_tilt, 3.0 * math.sqrt(stiffness * self.inertia))


def _mesh(name: str, v: Array) -> str:
    coords = " ".join(f"{x:.15g}" for x in v.ravel())
    return f'<mesh name="{name}" inertia="shell" vertex="{coords}"/>'


def build_model(
    spec: ThreadSpec,
    held: tuple[float, float],
    stiffness: float,
    dyn: Dynamics,
    parts: tuple[list[Piece], list[Piece]] | None = None,
) -> Any:
    """The MuJoCo model of the held bolt on its nut.

    Parameters
    ----------
    spec : ThreadSpec
        The thread pair (flat or conical ends).
    held : (roll0, pitch0)
        Held tilt (degrees): the springs' rest angles.
    stiffness : float
        ``k_r`` (N m/rad).
    dyn : Dynamics
    parts : (bolt pieces, nut pieces), optional
        Precomputed :func:`pieces`.

    Returns
    -------
    mujoco.MjModel
        Joints ``z`` (height of C, m), ``roll``, ``pitch``, ``spin`` (rad); actuator
        ``drive`` (position servo of the spin).
    """
    import mujoco

    scale = METRES[spec.units]
    bolt_parts, nut_parts = parts or (pieces(bolt_body(spec)), pieces(nut_body(spec)))
    assets, bolt_geoms, nut_geoms = [], [], []
    for j, pc in enumerate(bolt_parts):
        assets.append(_mesh(f"b{j}", pc.vertices * scale))
        bolt_geoms.append(f'<geom type="mesh" mesh="b{j}" contype="1" conaffinity="0"/>')
    for j, pc in enumerate(nut_parts):
        assets.append(_mesh(f"n{j}", pc.vertices * scale))
        nut_geoms.append(f'<geom type="mesh" mesh="n{j}" contype="0" conaffinity="1"/>')
    dt = dyn.timestep
    c_tilt = dyn.tilt_damping(stiffness)
    roll0, pitch0 = (math.radians(a) for a in held)
    tiny = 'mass="1e-6" diaginertia="1e-13 1e-13 1e-13"'
    i3 = f"{dyn.inertia:g} {dyn.inertia:g} {dyn.inertia:g}"
    xml = f"""
<mujoco model="threadmate-dynamics-check">
 <compiler angle="radian" inertiafromgeom="false"/>
 <option timestep="{dt:g}" integrator="implicitfast" solver="Newton" iterations="100"
   tolerance="1e-12" jacobian="dense" gravity="0 0 0" ccd_tolerance="{dyn.ccd_tolerance:g}"
   ccd_iterations="200"/>
 <default>
  <geom condim="1" margin="0" solref="{dyn.timeconst * dt:g} {dyn.dampratio:g}"
    solimp="{dyn.impedance:g} {dyn.impedance:g} 1e-6 0.5 2"/>
 </default>
 <asset>{"".join(assets)}</asset>
 <worldbody>
  {"".join(nut_geoms)}
  <body name="slide">
   <joint name="z" type="slide" axis="0 0 1" damping="{dyn.damping_z:g}"/>
   <inertial pos="0 0 0" {tiny}/>
   <body name="roll">
    <joint name="roll" type="hinge" axis="1 0 0" stiffness="{stiffness:g}"
      springref="{roll0:.17g}" damping="{c_tilt:g}"/>
    <inertial pos="0 0 0" {tiny}/>
    <body name="pitch">
     <joint name="pitch" type="hinge" axis="0 1 0" stiffness="{stiffness:g}"
       springref="{pitch0:.17g}" damping="{c_tilt:g}"/>
     <inertial pos="0 0 0" {tiny}/>
     <body name="bolt">
      <joint name="spin" type="hinge" axis="0 0 1" armature="{dyn.spin_armature:g}"/>
      <inertial pos="0 0 0" mass="{dyn.mass:g}" diaginertia="{i3}"/>
      {"".join(bolt_geoms)}
     </body>
    </body>
   </body>
  </body>
 </worldbody>
 <actuator>
  <position name="drive" joint="spin" kp="{dyn.spin_kp:g}"
    kv="{2 * math.sqrt(dyn.spin_kp * dyn.spin_armature):g}"/>
 </actuator>
</mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    if not dyn.multiccd:
        # MuJoCo's several-contact convex collision reports, between nearly conformal thin
        # pieces (a bolt flank on the nut's crest edge during the screw-in), contacts tens
        # of micrometres deep with a normal in a piece's radial side face where the hulls
        # overlap by 0.01 um (mj_geomDistance); one contact per pair has none of them
        model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_MULTICCD)
    return model


# -- the run ------------------------------------------------------------------------------


@dataclass
class Jump:
    """A jump the simulation saw: phase where the fall started (degrees), drop of C
    (spec units), whether the bolt then screwed in, its descent per degree turned back
    (spec units; the lead / 360 when in phase), the tilts before and after (degrees),
    whether the turn back jammed, the poses ``(z_C, roll, pitch, phase)`` every 15
    degrees of the turn back, and the heights of C where the fall started and after the
    landing (spec units)."""

    phase: float
    drop: float
    in_phase: bool
    descent_per_degree: float
    tilt_before: tuple[float, float]
    tilt_after: tuple[float, float]
    jammed: bool = False
    proof_poses: list[tuple[float, float, float, float]] = field(default_factory=list, repr=False)
    z_before: float = math.nan
    z_after: float = math.nan


@dataclass
class SimResult:
    """What one simulated turn found.

    Attributes
    ----------
    start_phase : float
        Phase the turn started from (degrees).
    snap : Jump or None
    jumps : list of Jump
        Every jump, the snap included (last).
    penetration_quasi_static, penetration_max : float
        Largest contact penetration of the hulls (m) while the bolt moved slowly (every
        joint speed under a tenth of a jump's), and over the whole run (falls included).
    steps : int
    seconds : float
        Wall-clock time of the run.
    final_pose : (z, roll, pitch, phase)
        Height of C (spec units) and angles (degrees) at the end.
    snap_pose_before : (z, roll, pitch, phase) or None
        The pose where the snap's fall started.
    penetration_where, penetration_by_stage
        Where the slow-motion maximum came, and the maximum in each stage of the run
        (``ride``, ``fall``, ``landing``, ``screw-in proof``; m).
    slips : list of (drop, phase)
        Falls too small to be jumps (spec units, degrees).
    trace : list of (z, roll, pitch, phase)
        The pose every 0.005 degree of the counter-clockwise turn.
    screwed_back : (descent per degree, jammed) or None
        With ``screw_back`` and no jump: the turn back from the end (spec units per
        degree).
    """

    start_phase: float
    snap: Jump | None
    jumps: list[Jump]
    penetration_quasi_static: float
    penetration_max: float
    steps: int
    seconds: float
    final_pose: tuple[float, float, float, float]
    snap_pose_before: tuple[float, float, float, float] | None = None
    penetration_where: str = ""
    penetration_by_stage: dict[str, float] = field(default_factory=dict)
    slips: list[tuple[float, float]] = field(default_factory=list)
    trace: list[tuple[float, float, float, float]] = field(default_factory=list, repr=False)
    screwed_back: tuple[float, bool] | None = None


def _penetration(d: Any) -> float:
    return float(-d.contact.dist[: d.ncon].min()) if d.ncon else 0.0


def _pose(d: Any, scale: float) -> tuple[float, float, float, float]:
    z, roll, pitch, spin = (float(x) for x in d.qpos[:4])
    return (z / scale, math.degrees(roll), math.degrees(pitch), math.degrees(spin))


def simulate(
    spec: ThreadSpec,
    held: tuple[float, float],
    stiffness: float,
    start: tuple[float, float, float, float],
    *,
    until: float,
    force: float = 10.0,
    dyn: Dynamics | None = None,
    jump_speed: float | None = None,
    min_drop: float = 2e-3,
    settle_speed: float = 2e-8,
    proof: float = 180.0,
    proof_period: float = 20.0,
    stop_at_snap: bool = True,
    screw_back: bool = False,
    model: Any = None,
    log: bool = True,
) -> SimResult:
    """Turn the simulated bolt counter-clockwise from ``start`` to phase ``until``.

    Parameters
    ----------
    spec : ThreadSpec
    held : (roll0, pitch0)
        Held tilt (degrees).
    stiffness : float
        ``k_r`` (N m/rad).
    start : (z_C, roll, pitch, phase)
        Start pose (spec units, degrees): a rest state to settle from.
    until : float
        Phase (degrees) at which to stop if no snap came.
    force : float
        Axial force (N).
    dyn : Dynamics, optional
    jump_speed : float, optional
        A fall of C faster than this (m/s) is a jump; default five times the speed of
        the ride along the helix (the lead per turn: 1.6e-5 m/s at one turn per 80 s on
        a 1/4-20). A jump starts where C last fell slower than twice that speed.
    settle_speed : float
        A landing has settled when C and the contact points move slower than this
        (m/s; 2e-8: under 0.01 um over the valley's relaxation time of a few 0.1 s).
    min_drop : float
        A fall that settles less than this many pitches lower is a slip, not a jump
        (pieces' seams and re-seats of a contact: a few tenths of a micrometre).
    proof : float
        Turn back (degrees, clockwise, from the settled landing) that decides whether a
        jump landed in phase: it did when C descends at the lead (within 10 %) over the
        last third of it, the driver never lagging by a degree (a jam).
    proof_period : float
        Seconds per turn of the turn back.
    stop_at_snap : bool
        End the run at the snap.
    screw_back : bool
        Without a jump by ``until``, turn back from there as from a landing
        (:attr:`SimResult.screwed_back`): whether the bolt passed into phase without
        falling.
    model : mujoco.MjModel, optional
        A model from :func:`build_model` for the same spec, held tilt and stiffness.
    log : bool
        Progress on stderr.

    Returns
    -------
    SimResult
    """
    import mujoco

    dyn = dyn or Dynamics()
    scale = METRES[spec.units]
    m = model if model is not None else build_model(spec, held, stiffness, dyn)
    d = mujoco.MjData(m)
    t0 = time.time()
    z0, roll0, pitch0, phase0 = start
    d.qpos[:4] = [z0 * scale, math.radians(roll0), math.radians(pitch0), math.radians(phase0)]
    d.qfrc_applied[0] = -force
    omega = 2.0 * math.pi / dyn.turn_period
    dt = m.opt.timestep
    pen_qs = 0.0
    pen_where = ""
    stage = "ride"
    by_stage: dict[str, float] = {}
    slips: list[tuple[float, float]] = []
    trace: list[tuple[float, float, float, float]] = []
    trace_step = 0.005  # degrees
    pen_max = 0.0
    steps = 0
    # the ride along the helix rises or falls at the lead per turn: a jump falls faster
    lead_speed = spec.lead * scale / dyn.turn_period
    if jump_speed is None:
        jump_speed = 5.0 * lead_speed
    slow = 2.0 * lead_speed

    def step(target: float) -> None:
        nonlocal steps, pen_qs, pen_max, pen_where
        d.ctrl[0] = target
        mujoco.mj_step(m, d)
        steps += 1
        pen = _penetration(d)
        pen_max = max(pen_max, pen)
        by_stage[stage] = max(by_stage.get(stage, 0.0), pen)
        # "slow": C and every contact point (within 4 mm of C) move under a tenth of a
        # jump's speed
        if abs(d.qvel[0]) < slow and 4e-3 * float(np.abs(d.qvel[1:3]).max()) < slow:
            if pen > pen_qs:
                pen_qs = pen
                pen_where = f"{stage} at {math.degrees(d.qpos[3]):.2f} deg"

    def settle(target: float, hold: float = 0.02, limit: float = 4.0) -> None:
        """Hold the driver at ``target`` until C and every contact point (within 4 mm of
        C) move slower than ``settle_speed`` for ``hold`` s. A landing on one contact
        rolls down a shallow valley of the potential and creeps for a second or more: a
        looser test stopped it micrometres short."""
        quiet, t = 0.0, 0.0
        while t < limit:
            step(target)
            t += dt
            still = (
                abs(d.qvel[0]) < settle_speed
                and 4e-3 * float(np.abs(d.qvel[1:3]).max()) < settle_speed
            )
            quiet = quiet + dt if still else 0.0
            if quiet >= hold:
                return

    def turn_back() -> tuple[float, bool, list[tuple[float, float, float, float]]]:
        """Screw in from where the driver stands: turn back ``proof`` degrees (at the
        proof's rate) on a copy of the state; C descends at the lead when in phase (its
        rate measured over the last third of the turn back, once a tilt left by the
        landing has relaxed). The descent per degree, whether the driver lagged by a
        degree (a jam), and the poses every 15 degrees."""
        nonlocal d, stage
        saved = d
        d = copy.copy(d)
        stage = "screw-in proof"
        back = target
        z_mark = None
        lag = 0.0
        rate = 2.0 * math.pi / proof_period
        poses = []
        next_pose = target
        while back > target - math.radians(proof):
            back -= rate * dt
            step(back)
            lag = max(lag, abs(float(d.qpos[3]) - back))
            if back <= next_pose:
                poses.append(_pose(d, scale))
                next_pose -= math.radians(15.0)
            if z_mark is None and back <= target - math.radians(2 * proof / 3):
                z_mark = float(d.qpos[0])
            if lag > math.radians(1.0):
                break
        settle(back)
        poses.append(_pose(d, scale))
        jammed = lag > math.radians(1.0)
        descent = math.nan
        if z_mark is not None and not jammed:
            descent = (z_mark - float(d.qpos[0])) / scale / (proof / 3)
        d = saved
        stage = "ride"
        return descent, jammed, poses

    target = math.radians(phase0)
    d.ctrl[0] = target
    mujoco.mj_forward(m, d)
    settle(target, hold=0.005)
    jumps: list[Jump] = []
    snap: Jump | None = None
    before_pose = None
    history: list[tuple[float, float, float, float, float]] = []  # phase, z, vz, roll, pitch
    last_report = time.time()
    while math.degrees(target) < until:
        target += omega * dt
        step(target)
        z, vz = float(d.qpos[0]), float(d.qvel[0])
        history.append((float(d.qpos[3]), z, vz, float(d.qpos[1]), float(d.qpos[2])))
        if not trace or math.degrees(d.qpos[3]) - trace[-1][3] >= trace_step:
            trace.append(_pose(d, scale))
        if len(history) > 20000:
            del history[:10000]
        if log and time.time() - last_report > 10:
            last_report = time.time()
            print(
                f"    phase {math.degrees(d.qpos[3]):8.3f}  z_C {z / scale:+.6f} {spec.units}",
                file=sys.stderr,
                flush=True,
            )
        if vz > -jump_speed:
            continue
        # a jump: where it started (the last step whose fall was slower than the ride)
        k = len(history) - 1
        while k > 0 and history[k][2] < -slow:
            k -= 1
        ph_on, z_on, _, r_on, p_on = history[k]
        stage = "fall"
        before_pose = (z_on / scale, math.degrees(r_on), math.degrees(p_on), math.degrees(ph_on))
        stage = "landing"
        settle(target)
        z_after = float(d.qpos[0])
        if (z_on - z_after) / scale < min_drop * spec.pitch:
            # a slip (a contact passing a seam of the pieces, or a re-seat): no jump
            slips.append(((z_on - z_after) / scale, math.degrees(ph_on)))
            stage = "ride"
            history.clear()
            continue
        descent, jammed, poses = turn_back()
        lead_rate = spec.lead / 360.0
        jump = Jump(
            phase=math.degrees(ph_on),
            drop=(z_on - z_after) / scale,
            in_phase=abs(descent - lead_rate) <= 0.1 * lead_rate,
            descent_per_degree=descent,
            tilt_before=(math.degrees(r_on), math.degrees(p_on)),
            tilt_after=(math.degrees(d.qpos[1]), math.degrees(d.qpos[2])),
            jammed=jammed,
            proof_poses=poses,
            z_before=z_on / scale,
            z_after=z_after / scale,
        )
        jumps.append(jump)
        if log:
            print(
                f"    jump at {jump.phase:.3f} deg: drop {jump.drop:.6f} {spec.units}, "
                f"{'in phase' if jump.in_phase else 'not in phase'} "
                f"(descent {descent:.3e} {spec.units}/deg turned back)",
                file=sys.stderr,
                flush=True,
            )
        history.clear()
        if jump.in_phase:
            snap = jump
            if stop_at_snap:
                break
    screwed_back = None
    if screw_back and not jumps:
        settle(target)
        descent, jammed, _ = turn_back()
        screwed_back = (descent, jammed)
        if log:
            print(
                f"    no jump by {math.degrees(target):.3f} deg; turned back: descent "
                f"{descent:.3e} {spec.units}/deg{' (jammed)' if jammed else ''}",
                file=sys.stderr,
                flush=True,
            )
    return SimResult(
        start_phase=phase0,
        snap=snap,
        jumps=jumps,
        penetration_quasi_static=pen_qs,
        penetration_max=pen_max,
        steps=steps,
        seconds=time.time() - t0,
        final_pose=_pose(d, scale),
        snap_pose_before=before_pose if snap is not None else None,
        penetration_where=pen_where,
        penetration_by_stage=by_stage,
        slips=slips,
        trace=trace,
        screwed_back=screwed_back,
    )


# -- exact-body check ---------------------------------------------------------------------


def _rotation(roll: float, pitch: float, phase: float) -> Array:
    r, p, f = (math.radians(a) for a in (roll, pitch, phase))
    rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
    ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    rz = np.array([[math.cos(f), -math.sin(f), 0], [math.sin(f), math.cos(f), 0], [0, 0, 1]])
    return rx @ ry @ rz


def _surface_points(body: ThreadBody, n_theta: int = 3600, n_t: int = 48) -> Array:
    """Points on the exact lateral surface (the thread trimmed by the end) within the
    body's slab and on the edge where it meets the end face at ``z = 0`` (spec units,
    body frame)."""
    theta = np.linspace(0.0, 2 * math.pi, n_theta, endpoint=False)
    pts = []
    # the edge of the end face at z = 0 (tip rim, top-face edge): dense
    th_edge = np.linspace(0.0, 2 * math.pi, 8 * n_theta, endpoint=False)
    r_edge = body.lateral_radius(th_edge, 0.0)
    pts.append(np.column_stack([r_edge * np.cos(th_edge), r_edge * np.sin(th_edge), 0 * th_edge]))
    # the lateral surface over the slab
    z = np.linspace(body.z_min, body.z_max, n_t)
    tt, zz = np.meshgrid(theta, z)
    rr = np.asarray(body.lateral_radius(tt, zz), dtype=float)
    pts.append(np.column_stack([(rr * np.cos(tt)).ravel(), (rr * np.sin(tt)).ravel(), zz.ravel()]))
    return np.concatenate(pts)


def exact_interference(spec: ThreadSpec, pose: tuple[float, float, float, float]) -> float:
    """Deepest interference of the exact bodies at a pose (spec units; 0: none found).

    Parameters
    ----------
    spec : ThreadSpec
    pose : (z_C, roll, pitch, phase)
        Height of the tip centre (C, held at x = y = 0) and the bolt's angles (degrees).

    Returns
    -------
    float
        The largest depth (``ThreadBody.depth``, an upper bound of the distance to the
        surface) of a sampled surface point of either body inside the other: dense
        samples of each body's end-face edge at z = 0 and of its thread surface.
    """
    bolt, nut = bolt_body(spec), nut_body(spec)
    rot = _rotation(*pose[1:])
    origin = np.array([0.0, 0.0, pose[0]])
    bolt_pts = _surface_points(bolt) @ rot.T + origin
    near = bolt_pts[:, 2] <= spec.pitch * 0.3
    d1 = nut.depth(bolt_pts[near])
    nut_pts = _surface_points(nut)
    nut_pts = nut_pts[nut_pts[:, 2] >= pose[0] - spec.pitch * 0.3]
    d2 = bolt.depth((nut_pts - origin) @ rot)
    return float(max(d1.max(initial=0.0), d2.max(initial=0.0)))


# -- a case -------------------------------------------------------------------------------


def run_case(
    case: Case,
    spec: ThreadSpec | None = None,
    *,
    dyn: Dynamics | None = None,
    after: float = 20.0,
    deviation: tuple[float, float] | None = None,
    parts: tuple[list[Piece], list[Piece]] | None = None,
    proof: float = 180.0,
    log: bool = True,
) -> dict[str, Any]:
    """Threadmate's search and the simulation of one case, side by side.

    Parameters
    ----------
    case : Case
    spec : ThreadSpec, optional
        Default :func:`thesis_spec`.
    dyn : Dynamics, optional
    after : float
        How far past threadmate's snap (degrees) the simulation turns before giving up.
    deviation : (outward, inward), optional
        The hulls' deviation (spec units), printed with the row.
    parts : optional
        Precomputed pieces of the bolt and the nut.
    proof : float
        The simulated turn back from a landing that decides whether it is in phase
        (degrees, :func:`simulate`).
    log : bool

    Returns
    -------
    dict
        One row of the table (phases in degrees, lengths in the spec's units, penetration
        and deviation in um, seconds).
    """
    spec = spec or thesis_spec()
    dyn = dyn or Dynamics()
    comp = Compliance(force=10.0, stiffness=case.stiffness, friction=0.0)
    t0 = time.time()
    mech = Mechanics(spec, comp)
    run = search(mech, case.roll, case.pitch, case.phase, turns=1)
    t_tm = time.time() - t0
    tm_phase = run.snap.phase if run.snap else None
    tm_click = run.snap.click if run.snap else None
    # without a snap, the jump threadmate located with the largest drop (the one it
    # refused as a snap, with its reason) is the one to compare
    tm_jumps = [e for e in run.events if e.kind in ("jump", "snap")]
    tm_jump = run.snap or max(tm_jumps, key=lambda e: e.drop, default=None)
    aim = tm_jump.phase if tm_jump is not None else case.phase + 360.0
    # the landing
    at = [s for s in run.states if abs(s.phase - aim) < 1e-9]
    land = min(at, key=lambda s: s.centre[2]) if at else None
    tm_landing = None if land is None else (land.centre[2], land.roll, land.pitch, land.phase)
    start_phase = max(case.phase, aim - case.lead_in)
    before = [s for s in run.states if s.phase <= start_phase + 1e-9]
    state = before[-1] if before else run.states[0]
    if log:
        print(
            f"[{case.name}] held ({case.roll:g}, {case.pitch:g}) k_r {case.stiffness:g} from "
            f"{case.phase:g} deg: threadmate snap {tm_phase} click {tm_click} "
            f"(largest jump {None if tm_jump is None else (tm_jump.phase, tm_jump.drop)}; "
            f"{t_tm:.1f} s); "
            f"simulating from its rest state at {state.phase:.2f} deg",
            file=sys.stderr,
            flush=True,
        )
    start = (state.centre[2], state.roll, state.pitch, state.phase)
    t1 = time.time()
    model = build_model(spec, (case.roll, case.pitch), case.stiffness, dyn, parts)
    sim = simulate(
        spec,
        (case.roll, case.pitch),
        case.stiffness,
        start,
        until=aim + after,
        dyn=dyn,
        proof=proof,
        model=model,
        log=log,
    )
    t_sim = time.time() - t1
    um = METRES[spec.units] * 1e6
    row: dict[str, Any] = {
        "case": case.name,
        "held_roll": case.roll,
        "held_pitch": case.pitch,
        "start_phase": case.phase,
        "stiffness": case.stiffness,
        "sim_start_phase": state.phase,
        "threadmate_snap_phase": tm_phase,
        "threadmate_click": None if tm_jump is None else tm_jump.click,
        "threadmate_jump_phase": None if tm_jump is None else tm_jump.phase,
        "threadmate_jump_drop": None if tm_jump is None else tm_jump.drop,
        "threadmate_jump_note": None if tm_jump is None else tm_jump.note,
        "threadmate_landing": tm_landing,
        "threadmate_events": [
            (e.phase, e.kind, e.before, e.after, e.drop, e.note) for e in run.events
        ],
        "threadmate_commit": _commit(),
        "sim_snap_phase": sim.snap.phase if sim.snap else None,
        "sim_jumps": [
            {k: v for k, v in asdict(j).items() if k != "proof_poses"} for j in sim.jumps
        ],
        "sim_slips": len(sim.slips),
        "sim_largest_slip": max((x for x, _ in sim.slips), default=0.0),
        "penetration_quasi_static_um": sim.penetration_quasi_static * 1e6,
        "penetration_max_um": sim.penetration_max * 1e6,
        "penetration_where": sim.penetration_where,
        "penetration_by_stage_um": {k: v * 1e6 for k, v in sim.penetration_by_stage.items()},
        "hull_outward_um": None if deviation is None else deviation[0] * um,
        "hull_inward_um": None if deviation is None else deviation[1] * um,
        "threadmate_seconds": t_tm,
        "sim_seconds": t_sim,
        "sim_steps": sim.steps,
        "units": spec.units,
    }
    sim_jump = sim.snap or max(sim.jumps, key=lambda j: j.drop, default=None)
    row["sim_jump_phase"] = None if sim_jump is None else sim_jump.phase
    row["sim_jump_drop"] = None if sim_jump is None else sim_jump.drop
    row["sim_jump_in_phase"] = None if sim_jump is None else sim_jump.in_phase
    if sim_jump is not None:
        # the fall a sensor sees, as threadmate measures it: from the highest the trace
        # stands within CLICK_SPAN before the fall started (a cascade of smaller jumps and
        # a steep stretch before it included) to the landing
        at = sim_jump.phase - CLICK_SPAN
        span = [(q[3], q[0]) for q in sim.trace if at <= q[3] < sim_jump.phase]
        top = max([*span, (sim_jump.phase, sim_jump.z_before)], key=lambda q: q[1])
        row["sim_fall_start"] = top[0]
        row["sim_click"] = top[1] - sim_jump.z_after
        row["sim_landing"] = sim.final_pose if sim.snap is not None else None
    if row.get("sim_landing") and tm_landing:
        # the landings compared at the same phase: the in-phase bolt rises at the lead
        rise = spec.lead / 360.0 * (row["sim_landing"][3] - tm_landing[3])
        row["landing_height_difference"] = row["sim_landing"][0] - rise - tm_landing[0]
        row["landing_tilt_difference"] = (
            row["sim_landing"][1] - tm_landing[1],
            row["sim_landing"][2] - tm_landing[2],
        )
    row["threadmate_jump_is_snap"] = run.snap is not None
    if sim_jump is not None and tm_jump is not None and tm_jump.click:
        row["phase_difference"] = sim_jump.phase - tm_jump.phase
        row["click_difference_pct"] = 100.0 * (row["sim_click"] - tm_jump.click) / tm_jump.click
    # agreement: both snap (or neither), the snap within 0.5 degree, the click within 5 %
    click_ok = abs(row.get("click_difference_pct", math.inf)) <= 5.0
    row["agree"] = (
        sim_jump is not None
        and tm_jump is not None
        and sim_jump.in_phase == (run.snap is not None)
        and abs(row["phase_difference"]) <= 0.5
        and click_ok
    )
    if sim.snap_pose_before is not None:
        row["sim_pose_before_snap"] = sim.snap_pose_before
        row["exact_interference_before_snap_um"] = (
            exact_interference(spec, sim.snap_pose_before) * um
        )
    if sim_jump is not None:
        # the simulated screw-in from the landing, on the exact bodies
        row["exact_interference_screw_in_um"] = max(
            (exact_interference(spec, q) * um for q in sim_jump.proof_poses), default=None
        )
    if case.roll == 0 and case.pitch == 0 and _flat(spec):
        row["closed_form_phase"], row["closed_form_click"] = closed_form(spec)
    return row


def _commit() -> str:
    """The threadmate checkout's commit, with ``+dirty`` when its sources are modified."""
    import subprocess

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    try:
        head = subprocess.run(
            ["git", "-C", root, "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "-C", root, "status", "--porcelain", "--", "src"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return head + ("+dirty" if dirty else "")


def _fmt(x: Any, spec: str) -> str:
    return "-" if x is None else format(x, spec)


def format_table(rows: list[dict[str, Any]]) -> str:
    """The Markdown table of the rows.

    "threadmate" is its snap, or (marked ``no snap``) the jump it located with the
    largest drop; "simulated" is the simulation's snap, or its largest jump (marked
    ``not in phase``). Each click is the fall a sensor sees, measured the same way in
    both (threadmate's ``SearchEvent.click``: from the highest within ``CLICK_SPAN``
    before the fall to the landing); "drop" is the last jump's own drop;
    "landing dz" is the simulated landing's height less threadmate's at the same phase.
    """
    head = (
        "| case | held (roll, pitch) | k_r | threadmate snap / click (drop) | "
        "simulated snap / click (drop) | d phase | d click | landing dz (um) | "
        "agree | pen. ride / max (um) | sim s |"
    )
    lines = [head, "|" + "---|" * 11]
    um = {"in": 25400.0, "mm": 1000.0}
    for r in rows:
        tm = "" if r["threadmate_jump_is_snap"] else " no snap"
        sim = "" if r["sim_jump_in_phase"] in (True, None) else " not in phase"
        ride = r["penetration_by_stage_um"].get("ride", 0.0)
        dz = r.get("landing_height_difference")
        lines.append(
            f"| {r['case']} | ({r['held_roll']:g}, {r['held_pitch']:g}) | {r['stiffness']:g} "
            f"| {_fmt(r['threadmate_jump_phase'], '.2f')} / "
            f"{_fmt(r.get('threadmate_click'), '.5f')} ({_fmt(r['threadmate_jump_drop'], '.5f')})"
            f"{tm} "
            f"| {_fmt(r['sim_jump_phase'], '.2f')} / {_fmt(r.get('sim_click'), '.5f')} "
            f"({_fmt(r['sim_jump_drop'], '.5f')}){sim} "
            f"| {_fmt(r.get('phase_difference'), '+.2f')} "
            f"| {_fmt(r.get('click_difference_pct'), '+.1f')} % "
            f"| {_fmt(None if dz is None else dz * um[r['units']], '+.2f')} "
            f"| {'yes' if r['agree'] else 'NO'} "
            f"| {ride:.3f} / {r['penetration_max_um']:.2f} "
            f"| {r['sim_seconds']:.0f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """The command line (see the module docstring)."""
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument(
        "--cases",
        default=",".join(CASES),
        help=f"comma-separated, of {', '.join(CASES)} (default all)",
    )
    parser.add_argument(
        "--spec",
        default=None,
        help="a designation, simulated with flat ends unless --ends (default: the thesis's "
        "1/4-20 pair)",
    )
    parser.add_argument(
        "--ends",
        action="store_true",
        help="keep the designation's standard ends (chamfered point, countersunk nut; "
        "default designation 1/4-20 UNC-2A/2B): the default parts of threadmate run",
    )
    parser.add_argument(
        "--start",
        action="append",
        default=[],
        metavar="ROLL,PITCH,PHASE[,K]",
        help="a start of your own (held tilt and start phase in degrees, stiffness in "
        "N m/rad, default 1); repeatable; given alone, only these are run",
    )
    parser.add_argument("--json", metavar="FILE", help="write the rows as JSON")
    parser.add_argument(
        "--turn-period", type=float, default=80.0, help="seconds per simulated turn (80)"
    )
    parser.add_argument("--timestep", type=float, default=1e-4, help="s (1e-4)")
    parser.add_argument(
        "--sector", type=float, default=SECTOR, help=f"pieces' angular width, deg ({SECTOR:g})"
    )
    parser.add_argument(
        "--lead-in", type=float, default=None, help="degrees before threadmate's snap to start"
    )
    parser.add_argument(
        "--proof",
        type=float,
        default=180.0,
        help="degrees a landing is turned back to tell whether it screws in (180)",
    )
    args = parser.parse_args(argv)
    names = [c.strip() for c in args.cases.split(",") if c.strip()]
    unknown = [n for n in names if n not in CASES]
    if unknown:
        parser.error(f"unknown case(s) {', '.join(unknown)}: choose from {', '.join(CASES)}")
    cases = {n: CASES[n] for n in names}
    if args.start:
        given = "--cases" in " ".join(argv if argv is not None else sys.argv)
        cases = cases if given else {}
        for text in args.start:
            try:
                values = [float(v) for v in text.split(",")]
            except ValueError:
                values = []
            if len(values) not in (3, 4):
                parser.error(f"--start takes ROLL,PITCH,PHASE[,K], got {text!r}")
            roll, pitch, phase = values[:3]
            stiffness = values[3] if len(values) == 4 else 1.0
            name = f"({roll:g},{pitch:g}) from {phase:g}" + (
                f" k{stiffness:g}" if stiffness != 1.0 else ""
            )
            cases[name] = Case(name, roll, pitch, phase, stiffness)
    if args.ends:
        spec = spec_from_designation(args.spec or "1/4-20 UNC-2A/2B")
    elif args.spec:
        spec = spec_from_designation(args.spec, point="flat", countersink=False)
    else:
        spec = thesis_spec()
    dyn = Dynamics(timestep=args.timestep, turn_period=args.turn_period)
    t0 = time.time()
    bolt, nut = bolt_body(spec), nut_body(spec)
    parts = (pieces(bolt, args.sector), pieces(nut, args.sector))
    dev_b = hull_deviation(bolt, parts[0], args.sector)
    dev_n = hull_deviation(nut, parts[1], args.sector)
    deviation = (max(dev_b[0], dev_n[0]), max(dev_b[1], dev_n[1]))
    um = METRES[spec.units] * 1e6
    print(
        f"pieces: bolt {len(parts[0])}, nut {len(parts[1])}; hull deviation outward "
        f"bolt {dev_b[0] * um:.3f} um, nut {dev_n[0] * um:.3f} um; inward bolt "
        f"{dev_b[1] * um:.3f} um, nut {dev_n[1] * um:.3f} um ({time.time() - t0:.1f} s)",
        file=sys.stderr,
        flush=True,
    )
    rows = []
    for case in cases.values():
        if args.lead_in is not None:
            case = Case(**{**asdict(case), "lead_in": args.lead_in})
        rows.append(
            run_case(case, spec, dyn=dyn, deviation=deviation, parts=parts, proof=args.proof)
        )
        print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    print(format_table(rows))
    closed = ""
    if _flat(spec):
        cf_phase, cf_drop = closed_form(spec)
        closed = (
            f"; closed form (upright, stiff): snap {cf_phase:.2f} deg, click {cf_drop:.5f} "
            f"{spec.units}"
        )
    print(
        f"\nhulls: deviation outward {deviation[0] * um:.3f} um, inward {deviation[1] * um:.3f} "
        f"um ({len(parts[0])} bolt and {len(parts[1])} nut pieces of {args.sector:g} deg)"
        f"{closed}; threadmate {_commit()}; load average {os.getloadavg()[0]:.2f}"
    )
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(rows, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
