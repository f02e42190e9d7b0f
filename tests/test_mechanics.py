"""The mechanics of the compliance-held bolt against facts computed without it.

docs/mechanics.md, "Independent checks worth having". Nothing here compares the code
with its own earlier output:

- KKT at rest states: python-fcl BVHs built here from the meshes (no collision at the pose,
  a collision near each loaded contact after a tiny motion into the nut along its normal);
  the forces' signs; the balance of load and spring recomputed from the reported contact
  points and normals with the generalised forces of R = Rx(roll) Ry(pitch) Rz(phase);
- perturbation: the potential re-evaluated with the exact bodies (``_exact_geometry``: the
  profile formula, no mesh) at tilts around the rest tilt, each re-lowered to first touch;
- closed forms: the planar analysis of an upright, stiffly held bolt (flat rest, the in-phase
  window, the snap at its edge with a drop of the axial clearance), the infinitely stiff
  compliance (the held tilt), the frictionless driver's work (the change of the potential);
- symmetry: a left-hand thread gives the mirror image of a right-hand one;
- the classes from the forces: cone membership by non-negative least squares, and for
  quasi-stable states a descent direction of the load alone checked on the exact bodies.

Units: the potential is U = F z_C + k_roll/2 (roll - roll0)^2 + k_pitch/2 (pitch - pitch0)^2
with z_C in metres and angles in radians (J); states report it in mJ.
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.optimize import nnls

from _exact_geometry import exact_centre_height, rot
from _fcl import collider
from _poses import axis_angle, leaves_branch
from threadmate.contact import (
    BALANCE,
    MAX_STEPS,
    Compliance,
    Continuation,
    Mechanics,
    search,
    sensor_click,
)
from threadmate.contact.mechanics._search import FLICKER  # internal: no public form
from threadmate.geometry import (
    BoltSpec,
    NutSpec,
    ThreadSpec,
    spec_from_designation,
    thread_meshes,
)

#: Metres per length unit, written here (not taken from the package).
METRES = {"in": 0.0254, "mm": 0.001}


def inch(spec):
    """One inch in the spec's length units."""
    return 0.0254 / METRES[spec.units]


# -- thread pairs and compliances ---------------------------------------------------------


@pytest.fixture(scope="module")
def m6():
    """M6x1-6g/6H at mean material, from the ISO 965-1/-2 limits for P = 1, d = 6.

    Bolt (6g, es = -0.026): d 5.794-5.974, d2 5.212-5.324, d3 below 4.747 (root radius
    0.125 P). Nut (6H): D1 4.917-5.153, D2 5.350-5.500, D min 6.000 (sharp corners).
    """
    return ThreadSpec(
        units="mm",
        pitch=1.0,
        bolt=BoltSpec(major=5.884, pitch_diameter=5.268, minor=4.74, root_fillet=0.125),
        nut=NutSpec(major=6.0, pitch_diameter=5.425, minor=5.035),
    )


def left_hand(spec):
    """The same pair with a left-hand thread."""
    return ThreadSpec(units=spec.units, pitch=spec.pitch, bolt=spec.bolt, nut=spec.nut, hand="left")


DEFAULT = Compliance()
#: Anisotropic, heavier, with the compliance centre 2 mm above the tip (an RCC projecting it).
M6_COMPLIANCE = Compliance(force=20.0, stiffness=(0.5, 2.0), compliance_z=2.0)
SOFT = Compliance(stiffness=0.01)
STIFF = Compliance(stiffness=1e4)
RIGID = Compliance(stiffness=1e6)
FRICTIONLESS = Compliance(friction=0.0)


@pytest.fixture(scope="module")
def mech(quarter_20):
    return Mechanics(quarter_20, DEFAULT)


@pytest.fixture(scope="module")
def mech_m6(m6):
    return Mechanics(m6, M6_COMPLIANCE)


@pytest.fixture(scope="module")
def mech_soft(quarter_20):
    return Mechanics(quarter_20, SOFT)


@pytest.fixture(scope="module")
def mech_stiff(quarter_20):
    return Mechanics(quarter_20, STIFF)


# Varied held tilts and phases, |roll|, |pitch| <= 4; the last two settle in-phase (the
# bolt comes to rest in the thread: the same conditions hold there).
Q20_CONFIGS = [
    (4, 0, 185),
    (4, 4, 235),
    (-4, 0, 131),
    (2, -3, 40),
    (-3, 2, 300),
    (1, 0.5, 10),
    (0, 0, 90),
    (3, 3, 70),
    (-2, -4, 160),
    (0, 4, 250),
    (-1, 2, 330),
    (3, 0, -10),
    (0, 0, 5),
    (1, 0, -5),
    (-1, 0, 115),  # tips onto its tip face: seated upright (test_tip_face_seats_flat)
]
M6_CONFIGS = [
    (-2, 3, 110),
    (1, 1, 200),
    (-4, -2, 290),
    (0, 2.5, 160),
    (2, 0, 70),
    (-1, -3, 330),
    (3, -1, 20),
]
# Starts at which a soft compliance lets the bolt settle on three points.
SOFT_CANDIDATES = [(-3, 2, 300), (1, 0.5, 10), (0, 0, 200), (4, 4, 235)]


@pytest.fixture(scope="module")
def q20_rests(mech):
    return {cfg: mech.settle(*cfg) for cfg in Q20_CONFIGS}


@pytest.fixture(scope="module")
def m6_rests(mech_m6):
    return {cfg: mech_m6.settle(*cfg) for cfg in M6_CONFIGS}


@pytest.fixture(scope="module")
def soft_rests(mech_soft):
    return {cfg: mech_soft.settle(*cfg) for cfg in SOFT_CANDIDATES}


# -- independent collision checks -----------------------------------------------------------


# -- the mechanics recomputed from a state ----------------------------------------------------


def generalised_rows(spec, state):
    """Rows (n_z, X . (r x n), Y' . (r x n)) of the touching contacts, r = p - C in metres,
    X the roll axis, Y' = Rx(roll) Y the pitch axis; and their forces (N)."""
    m = METRES[spec.units]
    centre = np.array(state.centre)
    x_axis = np.array([1.0, 0.0, 0.0])
    pitch_axis = rot(state.roll, 0.0, 0.0)[:, 1]
    rows, forces = [], []
    for c in state.touching:
        n = np.array(c.normal)
        moment = np.cross((np.array(c.point) - centre) * m, n)
        rows.append([n[2], x_axis @ moment, pitch_axis @ moment])
        forces.append(c.force)
    return np.array(rows, dtype=float).reshape(-1, 3), np.array(forces, dtype=float)


def spring(comp, rest):
    """Generalised force of the load and the spring: (F, k_r (roll - roll0), k_p ...)."""
    s = rest.state
    return np.array(
        [
            comp.force,
            comp.roll_stiffness * math.radians(s.roll - rest.held_roll),
            comp.pitch_stiffness * math.radians(s.pitch - rest.held_pitch),
        ]
    )


def radius_m(spec):
    return 0.5 * spec.bolt.major * METRES[spec.units]


def tip_face_top(spec, state):
    """Height in F of the highest point of the tip face (its rim taken at the major).

    It is above the nut's bottom face in every state: at a fixed phase the bolt cannot get
    past the nut's thread. On a cylinder r = r0 between the nut's minor and the bolt's
    major radius the nut (one pitch tall or more) has material at every angle in a band of
    heights within [-height, 0], and the bolt, one pitch long, a band of its own; moving
    without turning, the bolt's band at an angle can pass the nut's only by overlapping it.
    A tip face wholly below the nut: the lowering tunnelled through the nut's thread.
    """
    R = np.array(state.rotation)
    th = np.linspace(0, 2 * np.pi, 721)
    rim = 0.5 * spec.bolt.major * np.stack([np.cos(th), np.sin(th), 0 * th], -1)
    return float((rim @ R.T)[:, 2].max() + state.origin[2])


def check_kkt(spec, comp, rest):
    """docs/mechanics.md's KKT conditions at a rest state, each recomputed here."""
    s = rest.state
    label = (rest.held_roll, rest.held_pitch, rest.phase, s.classification)
    assert s.classification in ("stable", "quasi-stable", "in-phase"), label
    R, origin = np.array(s.rotation), np.array(s.origin)
    np.testing.assert_allclose(R, rot(s.roll, s.pitch, rest.phase), atol=1e-12)
    # The compliance centre is on the bolt axis at compliance_z, held at x = y = 0.
    np.testing.assert_allclose(s.centre, origin + R[:, 2] * comp.compliance_z, atol=1e-12)
    np.testing.assert_allclose(s.centre[:2], (0.0, 0.0), atol=1e-12)
    # Whatever the state, the bolt has not passed the nut without turning (tip_face_top).
    assert tip_face_top(spec, s) > -spec.nut.height, label
    col = collider(spec)
    up = np.array([0.0, 0.0, 1.0])
    # (a) No interpenetration: fcl reports the exact touch itself as a collision, so the
    # pose is raised by 1e-8 in (a hundredth of the descent's length tolerance); and the
    # bolt does rest on the nut: 1e-6 in lower it collides.
    assert len(col.contacts(R, origin + 1e-8 * inch(spec) * up)) == 0, label
    assert len(col.contacts(R, origin - 1e-6 * inch(spec) * up)) > 0, label
    # (c) Forces: finite, non-negative, zero where a contact is not touching.
    touching = s.touching
    assert touching, label
    for c in s.contacts:
        assert math.isfinite(c.force) and c.force >= 0.0, (label, c)
        if c.gap > 0:
            assert c.force == 0.0, (label, c)
        assert np.linalg.norm(c.normal) == pytest.approx(1.0, abs=1e-9)
    # (b) Every loaded contact is real: 2e-5 in into the nut along -normal collides there.
    for c in touching:
        if c.force <= 0:
            continue
        hits = col.contacts(R, origin - 2e-5 * inch(spec) * np.array(c.normal))
        assert len(hits) > 0, (label, c)
        nearest = float(np.linalg.norm(hits - np.array(c.point), axis=1).min())
        assert nearest <= spec.pitch / 20, (label, c.regions, nearest)
    # (d) Balance of the load and the spring, recomputed from points and normals.
    rows, forces = generalised_rows(spec, s)
    if s.near_singular:
        # The rigid balance asks for more than the model reports (its forces are bounded,
        # mechanics.md): a balancing set of non-negative forces exists all the same.
        # Bounded by three times what the load and the spring press a contact with.
        pressing = comp.force + np.abs(spring(comp, rest)[1:]).max() / radius_m(spec)
        assert forces.max() <= 3.0 * pressing * (1 + 1e-9), (label, forces)
        scale = np.array([1.0, 1.0 / radius_m(spec), 1.0 / radius_m(spec)])
        forces, _ = nnls((rows * scale).T, spring(comp, rest) * scale)
    resid = rows.T @ forces - spring(comp, rest)
    f = comp.force
    assert abs(resid[0]) <= 1e-6 * f, (label, resid)
    assert np.abs(resid[1:]).max() <= 1e-6 * f * radius_m(spec), (label, resid)


@pytest.mark.parametrize("cfg", Q20_CONFIGS)
def test_kkt_at_rest_states(q20_rests, quarter_20, cfg):
    """KKT at rest states of 1/4-20 held by the default compliance: no collision at the pose
    (own fcl BVHs), a collision near each loaded contact after 2e-5 in along -normal, every
    force >= 0, and sum F_i n_iz = F, sum F_i a.(r_i x n_i) = k (angle - held) about the
    roll axis X and the pitch axis Rx(roll) Y to 1e-6 of F (and of F times the radius)."""
    check_kkt(quarter_20, DEFAULT, q20_rests[cfg])


@pytest.mark.parametrize("cfg", M6_CONFIGS)
def test_kkt_at_rest_states_metric_offset_centre(m6_rests, m6, cfg):
    """The same KKT conditions on an M6x1 pair (mm) with an anisotropic compliance of 20 N
    whose centre is 2 mm above the tip (so the tip is not at x = y = 0 when tilted)."""
    check_kkt(m6, M6_COMPLIANCE, m6_rests[cfg])


@pytest.mark.parametrize("cfg", SOFT_CANDIDATES)
def test_kkt_at_rest_states_soft_compliance(soft_rests, quarter_20, cfg):
    """The same KKT conditions with a soft compliance (0.01 N m/rad), where the contacts
    carry nearly all of the load's moment."""
    check_kkt(quarter_20, SOFT, soft_rests[cfg])


@pytest.mark.parametrize("cfg", [(-4, 0, 131), (3, 3, 70), (-2, -4, 160)])
def test_settle_reaches_a_rest_state_soft_compliance(mech_soft, quarter_20, cfg):
    """settle returns a rest (or in-phase) state satisfying the KKT conditions at these
    soft-compliance starts too (U is bounded below over the free poses near the nut top,
    so a local minimiser is there to be found)."""
    check_kkt(quarter_20, SOFT, mech_soft.settle(*cfg))


@pytest.mark.parametrize("phase", [20.0, 280.0])
def test_kkt_with_the_point_seated_round_the_countersink(phase):
    """The standard 1/4-20 parts (chamfered point, countersunk nut) held at pitch 1.5
    degrees: the point comes to rest in the countersink within a few hundredths of a degree
    of upright, cone in cone, on contacts round the ring. The descent reaches a rest state
    there, and docs/mechanics.md's KKT conditions hold, each recomputed from the state."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    rest = Mechanics(spec, DEFAULT).settle(0.0, 1.5, phase)
    assert {c.regions for c in rest.state.touching} == {"chamfer/countersink"}
    check_kkt(spec, DEFAULT, rest)


def test_kkt_where_the_countersinks_kink_lies_along_the_points_cone():
    """The standard 1/4-20 parts held (-1, -2) from phase 280 degrees (a start of the
    default run): the nut's edge where its countersink meets its thread lies along the
    bolt's chamfer cone, a few 1e-7 in off it, and touches where it crosses the bolt's
    own kink. The mesh's pairs within the length tolerance of touching run along the cone
    from one pose and not from the next, so the group was its hull's corners on the cone
    at one step and the kinks' crossing at the other, and the descent alternated between
    them for all 60 steps, unbalanced. With both kept, settle returns a rest state
    satisfying the KKT conditions, each recomputed from the state, and the crossing
    carries load. And it is a minimum on the whole meshes: tilted 0.05 and 0.2 degree in
    eight directions and lowered to first touch by python-fcl's yes/no query bisected, U
    does not fall by more than F x 5e-6 in (the exact reference of the perturbation tests
    below knows no chamfer nor countersink)."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    rest = Mechanics(spec, DEFAULT).settle(-1.0, -2.0, 280.0)
    check_kkt(spec, DEFAULT, rest)
    s = rest.state
    loaded = [c for c in s.touching if c.force > 0]
    assert any((c.bolt_feature, c.nut_feature) == ("kink", "kink") for c in loaded), loaded
    col = collider(spec)

    def potential(roll, pitch):
        held = (rest.held_roll, rest.held_pitch)
        args = (s.origin[2], spec.pitch / 20, METRES[spec.units])
        return col.potential(DEFAULT, held, rest.phase, roll, pitch, *args)

    u0 = potential(s.roll, s.pitch)
    # (The state's potential is in mJ.)
    assert 1e3 * u0 == pytest.approx(s.potential, abs=1e3 * u_tolerance(spec, DEFAULT))
    for d in PERTURBATIONS:
        assert potential(s.roll + d[0], s.pitch + d[1]) - u0 >= -u_tolerance(spec, DEFAULT), d


@pytest.mark.parametrize("cfg", [(1, 4, 348.0), (2, 4, 347.5)])
def test_kkt_where_the_thread_starts_meet_edge_to_edge(mech, quarter_20, cfg):
    """The bolt's thread start (a thin wedge on its tip face) lowered onto the nut's (one on
    its top face) rests edge on edge, with the nut's tooth a hair above the bolt's flank:
    settle returns a rest state satisfying the KKT conditions there.

    Two faults once hung the bolt there, unbalanced (force residual 1), for all 60 descent
    steps. The contact refined along the nut's rim slid onto the nut's tooth over the
    bolt's flank, a normal pointing down that no lowering can give; and the pairs crossing
    at the touch were dropped for those crossing a little lower, where the bolt's wedge
    lies wholly inside the nut, so the touch had no contact."""
    rest = mech.settle(*cfg)
    check_kkt(quarter_20, DEFAULT, rest)
    loaded = [c for c in rest.state.touching if c.force > 0]
    assert any((c.bolt_feature, c.nut_feature) == ("rim", "rim") for c in loaded), loaded


def test_embedded_vertices_as_every_vertex_tested_finds_them(mech, q20_rests):
    """The lowering's test for a mesh vertex sunk deep into the other exact body tests
    only the points that can lie there (by height, and the bolt's by their distance from
    the axis once turned); tested here at every vertex of the bolt's tip and the nut's
    top, about the heights where the first vertex sinks deep, at rest poses and shifted
    sideways: the same verdicts either side."""
    an = mech.scene
    depth = 2 * an.deviation + mech.tolerance

    def every_vertex(rotation, xy, zc):
        pose = mech._pose(rotation, xy, zc)
        for body, points in (
            (an.bolt, pose.to_bolt(mech._nut_top)),
            (an.nut, pose.to_fixed(mech._bolt_tip)),
        ):
            points = points[(points[:, 2] >= body.z_min) & (points[:, 2] <= body.z_max)]
            inside = points[body.contains(points)]
            if np.any(body.surface_distance(inside) > depth):
                return True
        return False

    rng = np.random.default_rng(11)
    for rest in q20_rests.values():
        s = rest.state
        rotation = mech._rotation(np.radians([s.roll, s.pitch]), s.phase)
        angle = rng.uniform(0.0, 2 * math.pi)
        aside = 0.015 * np.array([math.cos(angle), math.sin(angle)])
        for shift in (np.zeros(2), rng.uniform(-3e-3, 3e-3, 2), aside):
            xy = np.asarray(s.centre[:2], dtype=float) + shift
            # The sink at which the first vertex lies deep, by bisection on every vertex:
            # there the one vertex (or few) that decides must be among those tested.
            free, sunk = s.centre[2] + 0.3, s.centre[2] - 0.01
            assert not every_vertex(rotation, xy, free) and every_vertex(rotation, xy, sunk)
            while free - sunk > 1e-7:
                mid = 0.5 * (free + sunk)
                free, sunk = (free, mid) if every_vertex(rotation, xy, mid) else (mid, sunk)
            assert not mech._embedded(rotation, xy, free), (s.roll, s.pitch, s.phase, shift)
            assert mech._embedded(rotation, xy, sunk), (s.roll, s.pitch, s.phase, shift)


@pytest.mark.parametrize(
    "which, cfg", [("q20", c) for c in Q20_CONFIGS] + [("m6", c) for c in M6_CONFIGS]
)
def test_first_contact_is_the_exact_first_touch(
    which, cfg, q20_rests, m6_rests, mech_m6, quarter_20, m6
):
    """settle starts where the bolt, at the held tilt with its compliance centre over
    x = y = 0, first touches the nut lowered from above: its first state's z_C is the exact
    reference's within 5e-6 in (the meshes' first-contact accuracy)."""
    if which == "q20":
        spec, comp, rest = quarter_20, DEFAULT, q20_rests[cfg]
    else:
        spec, comp = m6, M6_COMPLIANCE
        rest = m6_rests[cfg] if cfg in m6_rests else mech_m6.settle(*cfg)
    first = rest.path[0] if rest.path else rest.state  # no path: the descent did not move
    assert not rest.path or first.kind == "first-contact"
    assert first.roll == pytest.approx(cfg[0], abs=1e-9)
    assert first.pitch == pytest.approx(cfg[1], abs=1e-9)
    h = exact_height(spec, float(cfg[0]), float(cfg[1]), float(cfg[2]), comp.compliance_z)
    assert first.centre[2] == pytest.approx(h, abs=5e-6 * inch(spec))


@pytest.mark.parametrize("point", ["chamfer", "flat"])
def test_a_lowering_from_above_asks_its_free_steps_in_one_walk_and_lands_as_stepping(
    point, monkeypatch
):
    """A lowering from above the nut asks the bracket's first steps, those the bolt's fall
    into the bore lets it take, in one walk (``_Lowering._free_steps``); it then lands
    where stepping through each of them lands, to the last bit and with the same pairs,
    from any tilt, phase and shift. The bore it guesses the fall from holds no point of
    the nut's faces farther in than the meshes' deviation (random points on every face)."""
    from threadmate.contact.mechanics import _lowering

    if point == "flat":
        spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    else:
        spec = spec_from_designation("1/4-20 UNC-2A/2B")
    mech = Mechanics(spec, DEFAULT)
    eng = mech.engine
    edges, bore = eng._bore_by_height()
    rng = np.random.default_rng(5)
    tri = eng.nut_vertices[eng.nut_faces]
    weights = rng.dirichlet(np.ones(3), size=len(tri))
    points = np.einsum("fk,fkc->fc", weights, tri)
    band = np.clip(np.searchsorted(edges, points[:, 2], side="right") - 1, 0, len(bore) - 1)
    assert (np.hypot(points[:, 0], points[:, 1]) >= bore[band] - 5e-6).all()
    skipped = 0
    for _ in range(40):
        size, direction = rng.uniform(0, 5), rng.uniform(0, 2 * np.pi)
        tilt = np.radians(size) * np.array([np.cos(direction), np.sin(direction)])
        rotation = mech._rotation(tilt, rng.uniform(0, 360))
        xy = rng.uniform(-1, 1, 2) * 0.003
        monkeypatch.setattr(_lowering, "FREE_FALL_SHARE", 0.0)
        before = eng.queries
        stepped, asked = mech.drop(rotation, xy, None), eng.queries
        monkeypatch.undo()
        jumped = mech.drop(rotation, xy, None)
        skipped += int(eng.queries - asked < asked - before)
        assert stepped is not None and jumped is not None
        for name in ("zc", "top", "start", "span"):
            assert getattr(jumped, name) == getattr(stepped, name), name
        np.testing.assert_array_equal(jumped.pairs, stepped.pairs)
        np.testing.assert_array_equal(jumped.drops, stepped.drops)
        np.testing.assert_array_equal(jumped.gaps, stepped.gaps)
    # From the countersink the fall is long; onto a flat nut's face, mostly none.
    assert skipped >= (30 if point == "chamfer" else 1)


def test_a_lowering_verified_by_a_walk_of_its_own_lands_as_by_its_brackets(mech):
    """The verification asks the walk its bracket swept down to the touch; where that walk
    is not at hand (``_Lowering._covering``), it walks between the free top and the touch
    itself, and lands where the bracket's walk does, to the last bit and with the same
    pairs: first touches from above, some of them raised above the bracket's touch."""
    rng = np.random.default_rng(3)
    raised = 0
    for _ in range(60):
        tilt = np.radians(rng.uniform(-4, 4, 2))
        rotation = mech._rotation(tilt, rng.uniform(0, 360))
        found = mech.drop(rotation, rng.uniform(-1, 1, 2) * 0.002, None, verify=False)
        assert found is not None and found.sweep is not None
        by_bracket = mech.verified(found)
        by_itself = mech.verified(replace(found, sweep=None))
        assert by_itself.zc == by_bracket.zc
        np.testing.assert_array_equal(by_itself.pairs, by_bracket.pairs)
        np.testing.assert_array_equal(by_itself.gaps, by_bracket.gaps)
        raised += int(by_bracket.zc > found.zc)
    assert raised >= 2


def test_rest_heights_are_the_exact_first_touch(q20_rests, m6_rests, soft_rests, quarter_20, m6):
    """A rest state that has not dropped into the thread rests on the nut as the bolt,
    lowered from above at the rest tilt, would first touch it: z_C is the exact reference's
    height at the rest tilt within 5e-6 in."""
    checked = 0
    for spec, comp, rest in all_rests(q20_rests, m6_rests, soft_rests, quarter_20, m6):
        s = rest.state
        if s.classification not in ("stable", "quasi-stable"):
            continue
        h = exact_height(spec, s.roll, s.pitch, rest.phase, comp.compliance_z)
        assert s.centre[2] == pytest.approx(h, abs=5e-6 * inch(spec)), (
            spec.units,
            rest.held_roll,
            rest.held_pitch,
            rest.phase,
            (s.centre[2] - h),
        )
        checked += 1
    assert checked >= 15


# -- perturbation with the exact bodies -------------------------------------------------------


@functools.lru_cache(maxsize=4096)
def exact_height(spec, roll, pitch, phase, compliance_z):
    """Exact height of the compliance centre lowered onto the nut at this tilt (cached)."""
    return exact_centre_height(spec, rot(roll, pitch, phase), compliance_z)


def exact_potential(spec, comp, rest, roll, pitch, stiffness=None):
    """U (J) with the exact lowering height at (roll, pitch) and the rest state's phase."""
    kr, kp = (comp.roll_stiffness, comp.pitch_stiffness) if stiffness is None else stiffness
    h = exact_height(spec, float(roll), float(pitch), float(rest.phase), comp.compliance_z)
    return (
        comp.force * h * METRES[spec.units]
        + 0.5 * kr * math.radians(roll - rest.held_roll) ** 2
        + 0.5 * kp * math.radians(pitch - rest.held_pitch) ** 2
    )


PERTURBATIONS = [
    (d * math.cos(math.radians(a)), d * math.sin(math.radians(a)))
    for d in (0.05, 0.2)
    for a in range(0, 360, 45)
]


def perturbation_drops(spec, comp, rest, stiffness=None):
    """U(perturbed) - U(rest) (J) over the tilts of :data:`PERTURBATIONS`, exact bodies."""
    s = rest.state
    u0 = exact_potential(spec, comp, rest, s.roll, s.pitch, stiffness)
    return {
        d: exact_potential(spec, comp, rest, s.roll + d[0], s.pitch + d[1], stiffness) - u0
        for d in PERTURBATIONS
    }


def u_tolerance(spec, comp):
    """F x 5e-6 in, in J: the first-contact accuracy of the meshes."""
    return comp.force * 5e-6 * 0.0254


PERTURBED_Q20 = [(4, 0, 185), (1, 0.5, 10), (0, 0, 90), (3, 3, 70), (-3, 2, 300), (-1, 0, 115)]
PERTURBED_M6 = [(-2, 3, 110), (-4, -2, 290)]


@pytest.mark.parametrize(
    "which, cfg", [("q20", c) for c in PERTURBED_Q20] + [("m6", c) for c in PERTURBED_M6]
)
def test_exact_perturbation_never_lowers_the_potential(
    which, cfg, q20_rests, m6_rests, quarter_20, m6
):
    """The rest state is a local minimum of U on the EXACT bodies: at tilts 0.05 and 0.2
    degrees away (rolls, pitches and diagonals), each re-lowered to first touch by the exact
    reference, U does not fall by more than F x 5e-6 in; and the reported height of the
    compliance centre is the exact one at the rest tilt within 5e-6 in."""
    spec, comp, rest = (
        (quarter_20, DEFAULT, q20_rests[cfg])
        if which == "q20"
        else (m6, M6_COMPLIANCE, m6_rests[cfg])
    )
    s = rest.state
    # In-phase rest states are minima too: the thread holds them as the end faces hold others.
    h = exact_height(spec, s.roll, s.pitch, rest.phase, comp.compliance_z)
    assert s.centre[2] == pytest.approx(h, abs=5e-6 * inch(spec))
    tol = u_tolerance(spec, comp)
    drops = perturbation_drops(spec, comp, rest)
    worst = min(drops, key=drops.get)
    assert drops[worst] >= -tol, (cfg, worst, drops[worst] / tol)


def test_tip_face_seats_flat(q20_rests, quarter_20):
    """Held 1 degree off upright where the tip face overlaps the nut's top face, the load
    tips the bolt onto its tip face (the spring's 1 N m/rad x 1 degree, 0.017 N m, is less
    than the load's 10 N times the face's lever of about 0.1 in): the rest is exactly
    upright with the tip face on the top face's plane (the exact reference's height), held
    by tip-face contacts alone. (KKT and exact perturbation: the tests above.)"""
    rest = q20_rests[(-1, 0, 115)]
    s = rest.state
    assert s.roll == pytest.approx(0.0, abs=1e-9) and s.pitch == pytest.approx(0.0, abs=1e-9)
    assert s.centre[2] == pytest.approx(0.0, abs=5e-6)
    assert exact_height(quarter_20, 0.0, 0.0, 115.0, 0.0) == pytest.approx(0.0, abs=5e-6)
    loaded = [c for c in s.touching if c.force > 0]
    assert len(loaded) >= 3
    assert {c.regions for c in s.touching} == {"base/surface"}


@pytest.fixture(scope="module")
def stable_states(soft_rests, q20_rests):
    """Stable states found among a few starts (soft compliance; and the default one)."""
    found = [(SOFT, r) for r in soft_rests.values() if r.classification == "stable"]
    found += [(DEFAULT, r) for r in q20_rests.values() if r.classification == "stable"]
    return found


def test_stable_states_exist(stable_states):
    """Three-point states that the contacts hold by themselves are found at all."""
    assert len(stable_states) >= 2


def test_stable_states_hold_without_the_compliance(stable_states, quarter_20):
    """A stable state is a minimum of U with k = 0 (U = F z_C alone): at the exact bodies'
    perturbed tilts the compliance centre does not come lower than F x 5e-6 in allows."""
    tol = u_tolerance(quarter_20, DEFAULT)
    assert stable_states
    for comp, rest in stable_states:
        drops = perturbation_drops(quarter_20, comp, rest, stiffness=(0.0, 0.0))
        worst = min(drops, key=drops.get)
        assert drops[worst] >= -comp.force / DEFAULT.force * tol, (
            rest.held_roll,
            rest.held_pitch,
            rest.phase,
            worst,
            drops[worst],
        )


# -- classes from the forces ------------------------------------------------------------------


def held_by_contacts(spec, comp, state, margin):
    """Whether non-negative contact forces alone balance (F, 0, 0) and every target pushed
    by ``margin`` (F/100 in force, F x margin in moment, margin a length in metres)."""
    rows, _ = generalised_rows(spec, state)
    if len(rows) == 0:
        return False
    scale = np.array([1.0, 1.0 / radius_m(spec), 1.0 / radius_m(spec)])
    A = (rows * scale).T
    f = comp.force
    target = np.array([f, 0.0, 0.0])
    push = np.array([f / 100, f * margin / radius_m(spec), f * margin / radius_m(spec)])
    for j in range(3):
        for sign in (1.0, -1.0):
            t = target.copy()
            t[j] += sign * push[j]
            if nnls(A, t)[1] > 1e-9 * f:
                return False
    return True


def all_rests(q20_rests, m6_rests, soft_rests, quarter_20, m6):
    out = [(quarter_20, DEFAULT, r) for r in q20_rests.values()]
    out += [(m6, M6_COMPLIANCE, r) for r in m6_rests.values()]
    out += [(quarter_20, SOFT, r) for r in soft_rests.values()]
    return out


def test_classes_follow_from_the_forces(q20_rests, m6_rests, soft_rests, quarter_20, m6):
    """stable => the touching contacts alone balance (F, 0, 0) with non-negative forces
    (nnls residual <= 1e-6 F), strictly: still so with the target pushed by F x pitch/1000
    in moment; quasi-stable => they do not, robustly: pushed by F x pitch/20 some target
    fails (the load needs the spring, or its line lies on or outside the support)."""
    checked = {"stable": 0, "quasi-stable": 0}
    for spec, comp, rest in all_rests(q20_rests, m6_rests, soft_rests, quarter_20, m6):
        s = rest.state
        label = (spec.units, rest.held_roll, rest.held_pitch, rest.phase, s.classification)
        m = METRES[spec.units]
        if s.classification == "stable":
            rows, _ = generalised_rows(spec, s)
            scale = np.array([1.0, 1.0 / radius_m(spec), 1.0 / radius_m(spec)])
            lam, resid = nnls((rows * scale).T, np.array([comp.force, 0.0, 0.0]))
            assert resid <= 1e-6 * comp.force, label
            assert held_by_contacts(spec, comp, s, spec.pitch / 1000 * m), label
        elif s.classification == "quasi-stable":
            assert not held_by_contacts(spec, comp, s, spec.pitch / 20 * m), label
        else:
            continue
        checked[s.classification] += 1
    assert checked["stable"] >= 1 and checked["quasi-stable"] >= 5, checked


@pytest.mark.parametrize("cfg", [(4, 0, 185), (2, -3, 40), (0, 0, 90), (3, 3, 70)])
def test_quasi_stable_states_need_the_compliance(q20_rests, quarter_20, cfg):
    """Without the spring a quasi-stable state is not a minimum: the Farkas direction of the
    contacts' cone (the nnls residual w: every contact opens or stays along -w while the
    load's work falls) tilts the EXACT bolt, re-lowered, to a lower compliance centre."""
    rest = q20_rests[cfg]
    s = rest.state
    assert s.classification == "quasi-stable"
    spec, comp = quarter_20, DEFAULT
    rows, _ = generalised_rows(spec, s)
    rho = radius_m(spec)
    scale = np.array([1.0, 1.0 / rho, 1.0 / rho])
    A = (rows * scale).T
    b = np.array([comp.force, 0.0, 0.0])
    lam, _ = nnls(A, b)
    w = b - A @ lam
    assert w[0] > 1e-3 * comp.force, "the contacts alone hold the load"
    assert np.all((rows * scale) @ w <= 1e-9 * comp.force)  # -w opens every contact
    # Tilt by 0.1 degree along -w (its moment part, scaled by 1/rho, is rho times the angle).
    tilt = 0.1 * -w[1:] / np.linalg.norm(w[1:])
    before = exact_height(spec, s.roll, s.pitch, rest.phase, 0.0)
    after = exact_height(spec, s.roll + tilt[0], s.pitch + tilt[1], rest.phase, 0.0)
    assert comp.force * (after - before) * METRES[spec.units] < -u_tolerance(spec, comp), (
        before,
        after,
    )


# -- closed forms -----------------------------------------------------------------------------


def window_shift(spec, phase):
    """s = lead * phase / 360 wrapped into [-lead/2, lead/2)."""
    return spec.lead * (((phase + 180.0) % 360.0) - 180.0) / 360.0


# 1/4-20's in-phase window is |phase| <= 180 c / lead = 11.22 degrees (asserted below).
UPRIGHT_IN = [0.0, 6.0, -8.0, 10.5, -10.5]
UPRIGHT_OUT = [11.5, -11.5, 15.0, 45.0, 90.0, 135.0, 200.0, 270.0, 330.0]
UPRIGHT_PHASES = UPRIGHT_IN + UPRIGHT_OUT


@pytest.fixture(scope="module")
def upright_rests(mech_stiff):
    return {phase: mech_stiff.settle(0, 0, phase) for phase in UPRIGHT_PHASES}


@pytest.mark.parametrize("phase", UPRIGHT_PHASES)
def test_upright_stiff_bolt_follows_the_planar_analysis(upright_rests, quarter_20, phase):
    """Upright, stiffly held (1e4 N m/rad): in the in-phase window |s| <= c/2 (s = lead
    phase / 360 wrapped, c the axial clearance) the bolt drops to flank on flank,
    z_C = -(c/2 - s); outside it the tip face lies flat on the nut's top face, z_C = 0;
    either way the tilt stays within 0.01 degree of upright (5e-6 in in height)."""
    c = quarter_20.axial_clearance
    s_ = window_shift(quarter_20, phase)
    assert (abs(s_) <= c / 2) == (phase in UPRIGHT_IN)
    s = upright_rests[phase].state
    assert abs(s.roll) <= 0.01 and abs(s.pitch) <= 0.01, (s.roll, s.pitch)
    if abs(s_) <= c / 2:
        assert s.centre[2] == pytest.approx(-(c / 2 - s_), abs=5e-6)
        assert s.classification == "in-phase"
    else:
        assert s.centre[2] == pytest.approx(0.0, abs=5e-6)
        assert s.touching
        assert all(c.regions == "base/surface" for c in s.touching), s.region_combination


@pytest.mark.parametrize("phase", UPRIGHT_OUT)
def test_upright_stiff_bolt_rests_flat_outside_the_window(upright_rests, quarter_20, phase):
    """Outside the window the flat bolt is a rest state (on the top face, the spring holding
    what tilt the load's offset from the support would give): settle classifies it stable
    or quasi-stable, not unstable, and its contact forces balance the load."""
    rest = upright_rests[phase]
    assert rest.state.classification in ("stable", "quasi-stable"), (
        rest.state.classification,
        rest.balance,
    )
    check_kkt(quarter_20, STIFF, rest)


def test_search_snaps_at_the_window_edge_by_the_axial_clearance(sharp_quarter_20):
    """Upright and stiff, sharp flanks: turning counter-clockwise from a flat start the bolt
    stays flat and snaps where it enters the window, s = -c/2 (phase -180 c / lead mod 360),
    within the phase tolerance plus the meshes' height error as phase; the click (drop of
    the compliance centre) is the axial clearance c = (nut PD - bolt PD) / sqrt(3)."""
    spec = sharp_quarter_20
    c = (spec.nut.pitch_diameter - spec.bolt.pitch_diameter) / math.sqrt(3)
    edge = (-180.0 * c / spec.lead) % 360.0
    bolt, nut = thread_meshes(spec)
    # A flank's vertical error is the surfaces' error over its normal's z (sqrt(3)/2).
    height_error = (bolt.max_deviation + nut.max_deviation) / (math.sqrt(3) / 2)
    phase_error = 360.0 * height_error / spec.lead
    start = 340.0
    run = search(
        Mechanics(spec, STIFF), 0, 0, start, turns=15 / 360, step=2.0, phase_tolerance=0.01
    )
    assert run.snap is not None
    assert run.snap.phase == pytest.approx(edge, abs=0.01 + phase_error)
    assert run.snap_turn == pytest.approx(edge - start, abs=0.01 + phase_error)
    assert run.snap.drop == pytest.approx(c, abs=1e-5)
    assert run.states[-1].classification == "in-phase"
    for s in run.states[:-1]:
        assert s.classification != "in-phase"
        assert abs(s.roll) <= 0.01 and abs(s.pitch) <= 0.01
        assert s.centre[2] == pytest.approx(0.0, abs=5e-6)


def test_the_standard_flat_pair_upright_and_stiff_drops_by_the_axial_clearance():
    """The same closed form on the standard flat pair (its profile's fillets and all),
    held stiffly (100 N m/rad) from 40 degrees as docs/validation.md's "Closed forms"
    does: the bolt rides the nut's top face up to the end of the thin tooth where the
    nut's thread starts and snaps off it where the window opens, by the axial clearance
    c, within the meshes' height error as phase."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    c = (spec.nut.pitch_diameter - spec.bolt.pitch_diameter) / math.sqrt(3)
    edge = 360.0 * (1.0 - c / (2.0 * spec.lead))
    bolt, nut = thread_meshes(spec)
    height_error = (bolt.max_deviation + nut.max_deviation) / (math.sqrt(3) / 2)
    phase_error = 360.0 * height_error / spec.lead
    stiff = Compliance(stiffness=100.0, friction=0.0)
    run = search(Mechanics(spec, stiff), 0, 0, 40.0)
    assert run.snap is not None and run.states[-1].classification == "in-phase"
    assert run.snap.drop == pytest.approx(c, abs=1e-5)
    assert run.snap.click == pytest.approx(c, abs=1e-5)
    assert run.snap.phase == pytest.approx(edge, abs=0.05 + phase_error)


@pytest.mark.parametrize("cfg", [(4, 0, 170), (-1, 2, 330)])
def test_rest_state_is_a_consequence_of_load_and_spring_not_of_the_search(quarter_20, cfg):
    """A rest state with a finite stiffness is where load and spring balance: halving the
    descent's tolerance moves no bolt point by more than the tolerance (the farthest bolt
    point lies within the bolt's radius plus its length of the compliance centre)."""
    tolerance = 1e-7
    coarse = Mechanics(quarter_20, DEFAULT, tolerance=tolerance)
    fine = Mechanics(quarter_20, DEFAULT, tolerance=tolerance / 2, scene=coarse.scene)
    a, b = coarse.settle(*cfg).state, fine.settle(*cfg).state
    assert a.classification == b.classification != "unstable"
    reach = quarter_20.bolt.major / 2 + quarter_20.bolt.length
    turned = math.radians(max(abs(a.roll - b.roll), abs(a.pitch - b.pitch)))
    assert turned * reach + abs(a.centre[2] - b.centre[2]) <= tolerance


def test_a_continuation_step_depends_on_the_state_it_leaves_alone(mech, q20_rests):
    """The step from a rest state to the next phase is the same whatever was settled in
    between (the library's sweep and the search settle different states between two
    steps, and must follow one branch)."""
    start = q20_rests[(2, -3, 40)].state
    first = mech.settle(2, -3, 45, start=start).state
    for cfg in ((4, 0, 185), (-3, 2, 300)):  # other descents, with other curvatures
        mech.settle(*cfg)
    mech.settle(2, -3, 42.5, start=start)
    again = mech.settle(2, -3, 45, start=start).state
    assert again.origin == first.origin and again.rotation == first.rotation
    assert [c.force for c in again.contacts] == [c.force for c in first.contacts]


def _settles_of_a_continuation(mech, monkeypatch, held, phase, turn):
    """Every settle (arguments and result) of the continuation from the start at
    ``phase`` over ``turn`` degrees (the library's: folds only)."""
    settled = []
    settle = mech.settle

    def recording(*args, **kwargs):
        rest = settle(*args, **kwargs)
        settled.append((args, kwargs, rest))
        return rest

    start = mech.settle(*held, phase).state
    monkeypatch.setattr(mech, "settle", recording)
    Continuation(mech, *held, contact_changes=False).advance(start, phase, turn)
    monkeypatch.undo()
    return settled


@pytest.mark.parametrize("held", [(4, 4), (4, -4)])
def test_every_jump_of_the_continuation_leaves_the_branch(mech, quarter_20, held):
    """Where the thread starts meet (345 to 350 degrees), a probe of the bisection can
    leave the branch while the descent carried to its end comes back to it (before this was
    checked, two of the four jumps reported at each of these held tilts joined states a
    hair apart). Every jump or snap the continuation reports is one by its own
    thresholds, recomputed here from the states' poses: in phase, or the compliance centre
    fallen more than pitch / 40, or the bolt axis turned more than 0.5 degree."""
    start = mech.settle(*held, 345.0).state
    walk = Continuation(mech, *held, contact_changes=False)
    legs, _, _ = walk.advance(start, 345.0, 5.0)
    jumps = [leg for leg in legs if leg.kind in ("jump", "snap")]
    assert jumps
    for leg in jumps:
        fall = leg.before.centre[2] - leg.after.centre[2]
        turned = axis_angle(leg.before.rotation, leg.after.rotation)
        in_phase = leg.after.classification == "in-phase"
        assert leaves_branch(fall, turned, in_phase, quarter_20.pitch), (leg.before.phase, fall)


def test_a_click_is_the_fall_from_the_rest_states_before_the_jump(q20_rests):
    """``sensor_click``: the fall from the branch's rest states within the span before the
    jump to the landing (a landing 1e-3 below the one rest state: 1e-3), and unknown (NaN)
    where the turn passed no rest state (a first contact only): no height to fall from."""
    rest = q20_rests[(0, 0, 90)]
    x, y, z = rest.state.centre
    landing = replace(rest.state, centre=(x, y, z - 1e-3))
    at = rest.state.phase - 1.0
    assert sensor_click([rest.state], landing, at) == pytest.approx(1e-3, abs=1e-12)
    first = rest.path[0]
    assert first.classification == "unstable"
    assert math.isnan(sensor_click([first], landing, at))


def test_every_change_of_the_load_carrying_contacts_is_reported(mech):
    """The search's walk (contact changes located) from held (1, 4) over the thread starts'
    folds (340 to 350 degrees). Between any two rest states it returns, one after the
    other on a branch (no jump or snap between them), whose load-carrying contacts
    differ, a contact change is reported, unless a later one within ``FLICKER`` undoes
    it. Those contacts are recomputed here from the states: the touching contacts
    carrying more than 1e-4 of the load. The changes on a step that a probe left and came
    back to, and those on the way to a jump within a step, are among them."""
    floor = 1e-4 * DEFAULT.force

    def carrying(s):
        return sorted(c.regions for c in s.touching if c.force > floor)

    start = mech.settle(1, 4, 340.0).state
    _, events, states = Continuation(mech, 1, 4).advance(start, 340.0, 10.0)
    tol = 0.01  # the events' phase tolerance
    states = [start, *states]
    changes = 0
    for i, (a, b) in enumerate(zip(states, states[1:], strict=False)):
        lo, hi = a.phase - tol, b.phase + tol
        between = [e for e in events if lo <= e.phase <= hi]
        if any(e.kind in ("jump", "snap") for e in between) or carrying(a) == carrying(b):
            continue
        if "unstable" in (a.classification, b.classification):
            continue  # a descent that stopped short of the balance: its contacts carry no load
        changes += 1
        # A change that a later one within FLICKER undoes (a contact point flickering
        # across the border of two regions) is not told, by design.
        flicker = any(
            carrying(c) == carrying(a) and c.phase - b.phase < FLICKER for c in states[i + 2 :]
        )
        assert flicker or any(e.kind == "contact-change" for e in between), (a.phase, b.phase)
    # the walk passes contact changes on its branches
    assert changes or any(e.kind == "contact-change" for e in events)


def test_a_probe_stops_once_departed_where_its_full_descent_leaves_the_branch(
    mech, quarter_20, monkeypatch
):
    """A probe of the continuation (held (1, 4), past three folds between 345 and 350
    degrees) stops once the bolt has gone twice the jump's fall or tilt from the state it
    leaves. The descent carried on to its end (no probe) from the same state ends off the
    branch too: in phase, fallen more than pitch / 40, or turned more than 0.5 degree,
    recomputed here from the poses."""
    settled = _settles_of_a_continuation(mech, monkeypatch, (1, 4), 345.0, 5.0)
    departed = [(a, k) for a, k, rest in settled if rest.state.kind == "departed"]
    assert len(departed) >= 3, [rest.state.kind for _, _, rest in settled]
    for args, kwargs in departed:
        before = kwargs["start"]
        full = mech.settle(*args, start=before).state
        fall = before.centre[2] - full.centre[2]
        turned = axis_angle(before.rotation, full.rotation)
        assert leaves_branch(fall, turned, full.classification == "in-phase", quarter_20.pitch)


def test_a_probe_whose_lowering_climbs_past_its_fall_has_departed(mech, quarter_20):
    """A probe asks only whether the bolt stays near the state it leaves. Started from a
    pose sunk into the nut (a rest state lowered by 0.3 pitch), the lowering meets material
    at every height up to past twice the jump's fall above it: the probe has departed
    there, with no descent step and at less cost than the lowering alone. The pose it
    departed at collides (python-fcl on the whole meshes), so the first touch from above
    lies there or higher; lowered from the same pose with no ceiling, it does."""
    rest = mech.settle(1, -1, 120.0).state
    x, y, z = rest.centre
    sunk = replace(rest, centre=(x, y, z - 0.3 * quarter_20.pitch))
    fall = quarter_20.pitch / 20  # twice the continuation's jump threshold, pitch / 40
    probe = mech.settle(1, -1, 120.0, start=sunk, leave=(fall, 1.0))
    assert probe.state.kind == "departed" and probe.iterations == 0
    assert probe.state.centre[2] > sunk.centre[2] + fall
    assert collider(quarter_20).collides(probe.state.rotation, probe.state.origin)
    queries = mech.engine.queries
    full = mech.drop(np.array(sunk.rotation), np.array([x, y]), sunk.centre[2])
    assert full is not None and full.zc > sunk.centre[2] + fall
    assert probe.queries < mech.engine.queries - queries


@pytest.mark.parametrize("held, phase", [((2, -3), 40.0), ((-2, 2), 100.0), ((-3, -2), 50.0)])
def test_a_continuation_that_arrives_at_a_known_state_would_have_ended_there(
    mech, quarter_20, held, phase
):
    """The library's continuation stops its descent to a grid phase once a pose reaches a
    rest state already there (the next start's): same load-carrying contacts, compliance
    centre within pitch / 1000, axis within 0.05 degree. Carried on to its end without
    that, the descent ends at a state those tolerances join to the same one. The leg's
    friction work is the trapezoid rule over the 5 degrees turned."""
    floor = 1e-4 * DEFAULT.force

    def joins(a, b):
        carrying = [sorted(c.regions for c in s.touching if c.force > floor) for s in (a, b)]
        return (
            carrying[0] == carrying[1]
            and math.dist(a.centre, b.centre) <= quarter_20.pitch / 1000
            and axis_angle(a.rotation, b.rotation) <= 0.05
        )

    start = mech.settle(*held, phase).state
    known = mech.settle(*held, (phase + 5.0) % 360.0).state
    walk = Continuation(mech, *held, contact_changes=False)
    legs, _, _ = walk.advance(
        start, phase, 5.0, arrive=lambda s: known if joins(known, s) else None
    )
    # It arrived: the known state, at the phase turned to.
    assert legs[-1].after.centre == known.centre and legs[-1].after.phase == phase + 5.0
    trapezoid = 0.5 * (start.friction_torque + known.friction_torque) * math.radians(5.0)
    assert legs[-1].work_friction == pytest.approx(1e3 * trapezoid, rel=1e-12)
    full_legs, _, _ = walk.advance(start, phase, 5.0)
    assert joins(known, full_legs[-1].after)
    assert full_legs[-1].after.classification == known.classification


def test_a_stalled_descent_ends_near_where_the_longer_one_ends(mech, quarter_20, monkeypatch):
    """Where the thread starts meet edge to edge (held (1, 4), 348.5 to 348.8 degrees) some
    descents of the continuation stall: they stop after ``stall_steps`` without progress,
    their potential moving by about the meshes' noise. Carried on to the step limit, each
    ends within half the thresholds the continuation tells a jump by (a fall of pitch /
    40, a tilt of 0.5 degree) of where it stalled: the continuation's decisions stand.
    Some stay unbalanced, others balance in the end, there (which do rests on the
    arithmetic's last bits: their contacts flicker at the touching threshold)."""
    settled = _settles_of_a_continuation(mech, monkeypatch, (1, 4), 345.0, 5.0)
    stalled = [
        (a, k, rest)
        for a, k, rest in settled
        if rest.state.kind == "rest"
        and not rest.balance["converged"]
        and rest.iterations < MAX_STEPS
    ]
    assert stalled, [(rest.state.kind, rest.iterations) for _, _, rest in settled]
    monkeypatch.setattr(mech, "stall_steps", MAX_STEPS + 1)
    compared = 0
    for args, kwargs, rest in stalled:
        longer = mech.settle(*args, **kwargs)
        if longer.iterations == rest.iterations:
            continue  # stopped by another rule than the stall (a degenerate step)
        compared += 1
        assert longer.iterations > rest.iterations
        a, b = rest.state, longer.state
        assert math.dist(a.centre, b.centre) <= quarter_20.pitch / 80
        assert axis_angle(a.rotation, b.rotation) <= 0.25
        if max(longer.balance["force"], longer.balance["moment"]) > BALANCE:
            assert longer.classification == rest.classification
    assert compared


def _recording_lowerings(spec):
    """A default mechanics of ``spec`` that records every lowering it keeps (verified),
    and the list it records them in."""
    kept = []

    class Recording(Mechanics):
        def verified(self, d):
            found = super().verified(d)
            kept.append(found)
            return found

    return Recording(spec, DEFAULT), kept


def _whole_meshes_collide(spec, found):
    """Whether the bolt at ``found``'s tilt and lateral place, its compliance centre at a
    height, meets the nut: python-fcl's query of the two whole meshes (not the engine's)."""
    reference, reach, rotation = collider(spec), DEFAULT.compliance_z, found.rotation

    def collides(zc):
        return reference.collides(
            rotation, np.array([found.xy[0], found.xy[1], zc]) - rotation[:, 2] * reach
        )

    return collides


@pytest.mark.parametrize(
    "designation, parts, held, phases",
    [
        ("1/4-20 UNC-2A/2B", {}, (2, 1), (120, 125)),
        ("1/4-20 UNC-2A/2B", {"point": "flat", "countersink": False}, (4, 4), (347.5, 347.6)),
    ],
)
def test_every_lowering_a_descent_keeps_is_at_the_first_touch_from_above(
    designation, parts, held, phases
):
    """Every lowering a descent keeps must lie at the first touch below its free top, as a
    python-fcl sweep of the two whole meshes down from above it in steps of 1e-6 in finds
    it (brute force), not at a touch below material it passed. Two ways to miss it, each
    seen here before the lowering checked the pairs above its touch:

    - chamfered point, countersunk nut, held (2, 1), continued from phase 120 to 125: a
      step that starts in collision climbs out in doubling steps, and its long bracket
      passed 1.7e-4 in of an overhang of the nut whole; from there the bolt "snapped" at
      122.5 degrees into a thread it could not reach;
    - flat ends, held (4, 4), continued from 347.5 to 347.6 (past a fold): a bolt triangle
      meeting a nut flank nearly parallel to it sank whole into the nut within the
      bracket and crossed no nut triangle at its foot, 1.6e-5 in too low; and a long step
      passed a 4e-4 in tooth at the nut's face whole.
    """
    spec = spec_from_designation(designation, **parts)
    mech, kept = _recording_lowerings(spec)
    start = mech.settle(*held, phases[0]).state
    kept.clear()
    mech.settle(*held, phases[1], start=start)
    assert kept
    for found in kept[:6]:
        collides = _whole_meshes_collide(spec, found)
        # From the free height the lowering measured its touch from (it can lie under an
        # overhang of the nut: the bolt's tooth in the nut's groove).
        assert not collides(found.top)
        z = found.top
        while not collides(z):
            z -= 1e-6
        assert found.zc - 1e-6 <= z <= found.zc + 1e-9


@pytest.mark.parametrize(
    "parts, cfg",
    [
        ({}, (4, -1, 107.45681162908438)),
        ({"point": "flat", "countersink": False}, (4, 4, 346.6147182500939)),
        ({"point": "flat", "countersink": False}, (4, 2, 347.99846233962177)),
    ],
)
def test_a_descent_from_first_contact_keeps_no_lowering_below_a_touch_elsewhere(parts, cfg):
    """Every lowering a descent from first contact keeps lies at the first touch below its
    free top, wherever round the nut the bolt meets it: no height between the top and the
    touch collides (python-fcl's query of the two whole meshes, scanned down in steps of
    2e-6 in from the top) and the bolt collides just below the touch. Here, before the
    verification tested the motion down from the top exactly, a descent kept poses 1e-5
    to 5e-5 in below such a touch: the pairs crossing just above the touch were asked of
    the nut's sectors round the touch only, and the bracket was shorter than one step of
    its yes/no probes."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B", **parts)
    mech, kept = _recording_lowerings(spec)
    mech.settle(*cfg)
    assert kept
    for found in kept:
        collides = _whole_meshes_collide(spec, found)
        heights = np.arange(found.top, found.zc + 1e-6, -2e-6)
        assert not any(collides(z) for z in heights), (found.zc, found.top)
        assert collides(found.zc - 1e-8)


@pytest.mark.parametrize("cfg", [(-3.15, 1.07, 136.95), (-2.25, -1.19, 138.33)])
def test_a_lowering_from_above_stops_on_a_tooth_at_the_nuts_face(cfg):
    """mechanics.md's h is the height at which the bolt, lowered along -Z, first touches.
    Where the nut's thread runs out into its countersink, a tooth of it (here about 2e-3
    in thick) lies above the flank the bolt meets next; a bracket step (up to a sixteenth
    of a pitch) that crossed nothing at its foot passed it whole, and the lowering found
    that flank, 5e-3 to 9e-3 in lower. The first touch is where a python-fcl scan of the
    two whole meshes down from where the lowering started, in steps of 2e-5 in, first
    collides (brute force, bisected)."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    mech = Mechanics(spec, DEFAULT)
    rotation = mech._rotation(np.radians(cfg[:2]), cfg[2])
    found = mech.drop(rotation, np.zeros(2), None)
    assert found is not None
    reference = collider(spec)
    reach = DEFAULT.compliance_z

    def collides(zc: float) -> bool:
        return reference.collides(rotation, np.array([0.0, 0.0, zc]) - rotation[:, 2] * reach)

    z = found.start
    assert not collides(z)
    while not collides(z):
        z -= 2e-5
    free, hit = z + 2e-5, z
    while free - hit > 1e-8:
        mid = 0.5 * (free + hit)
        free, hit = (free, mid) if collides(mid) else (mid, hit)
    assert found.zc == pytest.approx(free, abs=1e-6)


@pytest.mark.parametrize("cfg", [(4, 0, 185), (2, -3, 40)])
def test_infinitely_stiff_compliance_keeps_the_held_tilt(quarter_20, cfg):
    """k -> infinity (1e6 N m/rad): the rest tilt is the held one within 1e-3 degree, and the
    bolt is simply lowered onto the nut at it: z_C is the exact first-touch height."""
    rest = Mechanics(quarter_20, RIGID).settle(*cfg)
    s = rest.state
    assert abs(s.roll - cfg[0]) <= 1e-3 and abs(s.pitch - cfg[1]) <= 1e-3
    h = exact_height(quarter_20, float(cfg[0]), float(cfg[1]), float(cfg[2]), 0.0)
    assert s.centre[2] == pytest.approx(h, abs=5e-6)


# -- energy bookkeeping -------------------------------------------------------------------------


@pytest.fixture(scope="module")
def mech_frictionless(quarter_20):
    return Mechanics(quarter_20, FRICTIONLESS)


def axial_torque(spec, state):
    """-sum lambda_i a . (r_i x n_i) about the bolt axis a through C (N m): the driver's
    torque without friction, recomputed from the contacts."""
    a = np.array(state.rotation)[:, 2] * spec.handedness
    centre = np.array(state.centre)
    m = METRES[spec.units]
    return -sum(
        c.force * float(a @ np.cross((np.array(c.point) - centre) * m, c.normal))
        for c in state.touching
    )


def closed_form_potential(spec, compliance, held, state):
    """U = F z_C + k_roll/2 (roll - roll0)^2 + k_pitch/2 (pitch - pitch0)^2 of a state's
    pose (mJ; the compliance centre held laterally), from the formula, not the model."""
    m = METRES[spec.units]
    droll, dpitch = (
        math.radians(a - b) for a, b in zip((state.roll, state.pitch), held, strict=True)
    )
    u = compliance.force * state.centre[2] * m
    u += 0.5 * compliance.roll_stiffness * droll**2 + 0.5 * compliance.pitch_stiffness * dpitch**2
    return 1e3 * u


@pytest.mark.parametrize(
    "cfg, events", [((2, -3, 40), False), ((0, 4, 250), False), ((3, 3, 70), True)]
)
def test_frictionless_work_equals_the_change_of_potential(
    mech_frictionless, quarter_20, cfg, events
):
    """Without friction and away from jumps the driver's work is the change of U (the
    envelope theorem: dU*/dphase = -sum lambda_i a.(r_i x n_i), the driver's torque): over a
    10-degree turn the trapezoid of the torques recomputed from the contacts equals
    U(last) - U(first) within 2 %, and the torques match the reported ones. The work's
    potential part is that change of U (mechanics.md, "The driver's work"): equal to the
    closed form of U at the two poses, work_friction = 0. Without events, and across a
    smooth change of contacts (no jump, no snap)."""
    run = search(mech_frictionless, *cfg, turns=10 / 360, step=2.0)
    kinds = {e.kind for e in run.events}
    if events:
        assert kinds <= {"contact-change"}, run.events
    else:
        assert not run.events
    assert run.work_friction == 0.0
    first, last = (
        closed_form_potential(quarter_20, FRICTIONLESS, cfg[:2], s)
        for s in (run.states[0], run.states[-1])
    )
    du = last - first  # mJ
    f = FRICTIONLESS.force
    assert run.work_potential == pytest.approx(du, rel=1e-9, abs=1e-12)
    for s in run.states:
        assert s.friction_torque == 0.0
        assert s.driver_torque == pytest.approx(
            axial_torque(quarter_20, s), abs=1e-6 * f * radius_m(quarter_20)
        )
    # The trapezoidal integral of the recomputed torques agrees too.
    phases = np.radians([s.phase for s in run.states])
    torques = np.array([axial_torque(quarter_20, s) for s in run.states])
    work = 1e3 * float(np.sum(0.5 * (torques[1:] + torques[:-1]) * np.diff(phases)))
    assert work == pytest.approx(du, rel=0.02, abs=f * 1e-6 * 0.0254 * 1e3)


# -- mirror symmetry ----------------------------------------------------------------------------

MIRRORED = [(4, 0, 185), (2, -3, 40), (-3, 2, 300), (1, 0.5, 10), (3, 3, 70), (0, 0, 5)]


@pytest.fixture(scope="module")
def mech_left(quarter_20):
    return Mechanics(left_hand(quarter_20), DEFAULT)


@pytest.mark.parametrize("cfg", MIRRORED)
def test_left_hand_thread_mirrors_the_right_hand_one(mech_left, q20_rests, cfg):
    """M = diag(1, -1, 1) maps the right-hand bodies onto the left-hand ones and
    Rx(r) Ry(p) Rz(f) onto Rx(-r) Ry(p) Rz(-f), and leaves U alone: settle(left, -roll,
    pitch, -phase) is the mirror image of settle(right, roll, pitch, phase): roll -> -roll,
    the same pitch (1e-3 degree), z_C (5e-6 in), class, regions and forces (1e-3 F), and
    contact points mirrored y -> -y (1e-4 in: the meshes are tessellated on their own)."""
    right = q20_rests[cfg].state
    left = mech_left.settle(-cfg[0], cfg[1], -cfg[2]).state
    assert left.classification == right.classification
    assert left.roll == pytest.approx(-right.roll, abs=1e-3)
    assert left.pitch == pytest.approx(right.pitch, abs=1e-3)
    assert left.centre[2] == pytest.approx(right.centre[2], abs=5e-6)
    assert left.potential == pytest.approx(right.potential, abs=DEFAULT.force * 5e-6 * 25.4)
    mirror = np.array([1.0, -1.0, 1.0])
    assert len(left.touching) == len(right.touching)
    unmatched = list(left.touching)
    for c in right.touching:
        p = np.array(c.point) * mirror
        k = int(np.argmin([np.linalg.norm(np.array(d.point) - p) for d in unmatched]))
        d = unmatched.pop(k)
        assert np.linalg.norm(np.array(d.point) - p) <= 1e-4, (c, d)
        np.testing.assert_allclose(d.normal, np.array(c.normal) * mirror, atol=1e-3)
        assert d.regions == c.regions
        assert d.force == pytest.approx(c.force, abs=1e-3 * DEFAULT.force)


def test_both_models_stand_on_the_scene_given_and_refuse_one_of_another_spec(quarter_20):
    """A scene handed to either model is the one it uses, and a scene of another thread
    pair is refused by both."""
    from threadmate import InputError
    from threadmate.contact import ContactAnalyzer, contact_scene
    from threadmate.geometry import spec_from_designation

    scene = contact_scene(quarter_20, chord=1e-4)
    assert Mechanics(quarter_20, DEFAULT, scene=scene).scene is scene
    assert ContactAnalyzer(quarter_20, scene=scene).scene is scene
    other = spec_from_designation("M6")
    with pytest.raises(InputError, match="the scene's spec differs from the spec given"):
        Mechanics(other, DEFAULT, scene=scene)
    with pytest.raises(InputError, match="the scene's spec differs from the spec given"):
        ContactAnalyzer(other, scene=scene)


@pytest.mark.parametrize("designation", ["1/4-20 UNC-2A/2B", "M6x1-6g/6H"])
def test_the_lowerings_check_for_a_vertex_deep_inside_agrees_with_every_vertex(designation):
    """A lowering that passed a thin wedge whole is caught by a vertex of one mesh lying
    inside the other exact body deeper than the meshes' deviation; the check asks only the
    vertices a compiled pass keeps. Brute force, at rest poses of the chamfered parts and
    those poses sunk by up to 0.02 pitch: every vertex of both meshes moved into the other
    body's frame and tested exactly (``contains``, ``surface_distance``). They agree at
    every pose, both ways."""
    from threadmate.geometry import with_parts

    spec = with_parts(designation)
    mech = Mechanics(spec, DEFAULT)
    scene, depth = mech.scene, 2 * mech.scene.deviation + mech.tolerance

    def brute(rotation, origin):
        for body, points in (
            (scene.bolt, (mech.engine.nut_vertices - origin) @ rotation),
            (scene.nut, mech.engine.bolt_vertices @ rotation.T + origin),
        ):
            inside = points[body.contains(points)]
            if np.any(body.surface_distance(inside) > depth):
                return True
        return False

    verdicts = []
    for roll, pitch, phase in [(1, -1, 100.0), (-2, 0, 250.0), (0, 3, 10.0), (2, 2, 190.0)]:
        rest = mech.settle(roll, pitch, phase).state
        rotation = np.array(rest.rotation)
        x, y, z = rest.centre
        for sunk in (0.0, 1e-4, 3e-4, 1e-3, 0.02):
            zc = z - sunk * spec.pitch
            pose = mech._pose(rotation, np.array([x, y]), zc)  # internal: the pose at zc
            got = mech._embedded(rotation, np.array([x, y]), zc)  # internal: no public form
            assert got == brute(pose.rotation, pose.origin), (roll, pitch, phase, sunk)
            verdicts.append(got)
    assert any(verdicts) and not all(verdicts)  # both answers asked
