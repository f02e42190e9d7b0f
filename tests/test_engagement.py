"""In phase, the snap and clockwise starts, against what the states themselves show.

docs/mechanics.md: a state is in phase when turning moves the bolt along the helix (the
compliance centre rises or falls the lead, P/360 per degree); a snap is proved by screwing
in; a clockwise start engages, rides or jams; no reported force exceeds what the load and
the spring can explain. Each check recomputes from the returned poses and contacts, or
walks the same mechanics by brute force (a fine step), never from the code's verdicts:

- the bolt's height along a screw-in, recomputed from its states, falls at the lead;
- the search's snap against a walk of 0.05-degree steps that needs no bisection;
- every rest state the search passes before its snap, turned a little counter-clockwise,
  does not rise at the lead (it is not engaged);
- a state the code calls in phase, turned a little either way, moves at the lead;
- contact forces within three times what the load and the spring press a contact with.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from _cli import run_cli
from _poses import axis_angle
from threadmate.contact import (
    CLICK_SPAN,
    IN_PHASE,
    LEAD_TOLERANCE,
    MAX_STEP,
    PROOF_FOLD_TOLERANCE,
    SCREW_IN,
    ClockwiseStarts,
    Compliance,
    Continuation,
    Mechanics,
    screw,
    search,
)
from threadmate.contact.mechanics import engagement
from threadmate.geometry import spec_from_designation, with_parts
from threadmate.library import sweep

FRICTIONLESS = Compliance(friction=0.0)


@pytest.fixture(scope="module")
def flat():
    return spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)


@pytest.fixture(scope="module")
def mech(flat):
    return Mechanics(flat, FRICTIONLESS)


@pytest.fixture(scope="module")
def upright_search(mech):
    return search(mech, 0.0, 0.0, 40.0)


def _rate(a, b):
    """Rise of the compliance centre per degree turned from ``a`` to ``b``."""
    return (b.centre[2] - a.centre[2]) / abs(b.phase - a.phase)


def test_a_snap_screws_in_at_the_lead(upright_search, flat):
    """The snap of the upright search, screwed in half a turn: once the bolt has come
    upright in the thread (the second quarter-turn), the compliance centre, read off every
    state of the clockwise continuation, falls the lead per turn (within 1 %), and the bolt
    ends within 0.05 degree of the nut's axis."""
    run = upright_search
    assert run.snap is not None
    proof = run.snap.engagement
    assert proof is not None and proof.engaged
    mech = Mechanics(flat, FRICTIONLESS)
    walk = Continuation(mech, 0.0, 0.0, sense="tighten", contact_changes=False)
    snap_state = run.states[-1]
    _, _, states = walk.advance(snap_state, snap_state.phase, 180.0)
    second = [s for s in states if snap_state.phase - s.phase >= 90.0]
    assert len(second) >= 10
    heights = np.array([s.centre[2] for s in second])
    phases = np.array([s.phase for s in second])
    slope = np.polyfit(phases, heights, 1)[0]  # per degree; phases decrease
    assert slope * 360.0 == pytest.approx(flat.lead, rel=0.01)
    end = np.array(states[-1].rotation)[:, 2]
    assert math.degrees(math.acos(min(1.0, end[2]))) < 0.05


def test_the_snap_is_where_a_fine_walk_drops(upright_search, mech):
    """Where the bolt's flank reaches the edge of the nut's thread start, a branch of rest
    states rides that new contact on to the in-phase window's edge. A walk in steps of
    0.05 degree from 345 degrees (no bisection, each step settled from the last) meets the
    drop where the search does, within 0.06 degree, with the same click within 2 %; the
    closed form of the planar analysis puts the window's edge at 348.78 degrees."""
    run = upright_search
    before = min(run.states, key=lambda s: abs(s.phase - 345.0))
    assert before.phase <= 345.3
    s, phase = before, before.phase
    while True:
        phase += 0.05
        nxt = mech.settle(0.0, 0.0, phase, start=s).state
        if s.centre[2] - nxt.centre[2] > mech.spec.pitch / 40:
            break
        s = nxt
        assert phase < 350.0
    assert run.snap.phase == pytest.approx(phase, abs=0.06)
    assert run.snap.drop == pytest.approx(s.centre[2] - nxt.centre[2], rel=0.02)
    assert abs(run.snap.phase - 348.78) < 0.5


def test_a_tilted_snap_is_where_a_fine_walk_drops(mech):
    """The same brute force at a held tilt of half a degree about -X (pitch a rounding
    error off zero, which must not matter): walked in 0.05-degree steps from the search's
    rest state nearest 340 degrees, the bolt rides the flank-on-edge contact to the drop,
    and the search's snap lies there (within 0.06 degree) with the same drop (2 %). A
    landing settled from a state further back on the branch than the last one can fall
    past the rest states that continue it, degrees before the drop."""
    roll, pitch = -0.5, math.cos(math.pi / 2)  # 6.1e-17
    run = search(mech, roll, pitch, 320.0)
    assert run.snap is not None
    s = min(run.states, key=lambda x: abs(x.phase - 340.0))
    assert abs(s.phase - 340.0) <= 0.5
    phase = s.phase
    while True:
        phase += 0.05
        nxt = mech.settle(roll, pitch, phase, start=s).state
        if s.centre[2] - nxt.centre[2] > mech.spec.pitch / 40:
            break
        s = nxt
        assert phase < 352.0
    assert run.snap.phase == pytest.approx(phase, abs=0.06)
    assert run.snap.drop == pytest.approx(s.centre[2] - nxt.centre[2], rel=0.02)


def test_no_state_before_the_snap_moves_along_the_helix(upright_search, mech):
    """Every rest state of the search before its snap, settled 0.2 degree further
    counter-clockwise from itself, rises less than half the lead's share: none of them is
    engaged (called out of phase while unscrewing)."""
    lead = mech.spec.lead / 360.0
    rests = [
        s for s in upright_search.states[:-1] if s.classification in ("stable", "quasi-stable")
    ]
    assert len(rests) >= 10
    for s in rests[:: max(1, len(rests) // 12)]:
        nxt = mech.settle(0.0, 0.0, s.phase + 0.2, start=s).state
        assert _rate(s, nxt) < 0.5 * lead, (s.phase, s.region_combination)


@pytest.mark.parametrize("held, phase", [((0.0, 0.0), 5.0), ((1.0, 0.5), 10.0)])
def test_a_state_in_phase_moves_along_the_helix(mech, held, phase):
    """A rest state the code calls in phase (its load-carrying contacts on the helices),
    settled 1 degree either way from itself, moves along the helix: up turned
    counter-clockwise, down turned clockwise, by more than half the lead's share and not
    more than the lead's (a tilted bolt rights itself a little as it turns, so less than
    the lead). Out of phase, no state before a snap rises half as much (above)."""
    rest = mech.settle(*held, phase).state
    assert rest.classification == "in-phase"
    lead = mech.spec.lead / 360.0
    up = mech.settle(*held, phase + 1.0, start=rest).state
    down = mech.settle(*held, phase - 1.0, start=rest).state
    assert 0.5 * lead < _rate(rest, up) <= 1.02 * lead
    assert 0.5 * lead < -_rate(rest, down) <= 1.02 * lead


@pytest.mark.slow
def test_the_proof_locates_a_jump_down_to_a_degree_with_the_same_verdict():
    """The screw-in proof locates a fold the bolt leaves downward to
    ``PROOF_FOLD_TOLERANCE``, not to the phase tolerance (docs/mechanics.md, "The snap
    proved"): on a start in phase of the default parts whose screw-in jumps, then wedges
    (held at (-2, -2), at 140 degrees), the verdict is that of the proof locating it to the
    phase tolerance, the jump within the coarser tolerance of it, the descent within 1 % of
    the lead and the tilt at the end within 0.05 degree."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    mech = Mechanics(spec, Compliance())
    start = mech.settle(-2.0, -2.0, 140.0).state
    assert start.classification == "in-phase"
    proofs, jumps = [], []
    for fold in (PROOF_FOLD_TOLERANCE, None):
        walk = Continuation(
            mech, -2.0, -2.0, sense="tighten", contact_changes=False, fold_tolerance=fold
        )
        legs, events, states = walk.advance(start, 140.0, SCREW_IN)
        proofs.append(engagement(walk, start, legs, events, states, SCREW_IN, 0.5 * SCREW_IN))
        jumps.append([e.phase for e in events if e.kind == "jump"])
    coarse, fine = proofs
    assert len(jumps[1]) >= 1 and len(jumps[0]) == len(jumps[1])
    assert np.allclose(jumps[0], jumps[1], atol=PROOF_FOLD_TOLERANCE)
    assert coarse.engaged == fine.engaged
    assert abs(coarse.descent - fine.descent) <= 0.01 * spec.lead
    assert abs(coarse.tilt - fine.tilt) <= 0.05
    # The search's own proof is the coarse one.
    proof = Continuation(mech, -2.0, -2.0).prove(start, 140.0)
    assert (proof.engaged, proof.descent, proof.tilt) == (
        coarse.engaged,
        coarse.descent,
        coarse.tilt,
    )


@pytest.mark.slow
def test_a_proof_that_wedges_ends_at_the_wedge():
    """Screwing in, the driver stalls where the bolt wedges (docs/mechanics.md, "A fold
    is a fold only when no rest state continues the branch"): the proof of the start in
    phase of the default parts held (2, -2) at 140 degrees, whose screw-in wedges within
    its first half, walks no further. Its last state is the landing past the fold, above
    the state before it by the potential recomputed from the two poses (U = F z_C + k/2
    |tilt - held|^2), no state lies beyond it, and the proof's turn and descent are those
    up to it: the descent over the whole turn, which is shorter than the half judged."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    comp = Compliance()
    mech = Mechanics(spec, comp)
    start = mech.settle(2.0, -2.0, 140.0).state
    walk = Continuation(
        mech,
        2.0,
        -2.0,
        sense="tighten",
        contact_changes=False,
        fold_tolerance=PROOF_FOLD_TOLERANCE,
    )
    legs, events, states = walk.advance(start, 140.0, SCREW_IN)
    wedge = events[-1]
    assert wedge.kind == "jump"
    assert states[-1].phase == pytest.approx(wedge.phase, abs=1e-9)
    assert all(s.phase >= wedge.phase - 1e-9 for s in states)
    turned = 140.0 - wedge.phase
    assert turned < 0.5 * SCREW_IN

    def potential(s):  # J, the compliance centre's height in inches
        tilt = np.radians([s.roll - 2.0, s.pitch + 2.0])
        return comp.force * s.centre[2] * 0.0254 + 0.5 * float(np.dot(comp.stiffness, tilt**2))

    assert potential(states[-1]) > potential(states[-2])
    proof = engagement(walk, start, legs, events, states, SCREW_IN, 0.5 * SCREW_IN)
    assert proof.jammed and not proof.engaged
    assert proof.turn == pytest.approx(turned, abs=1e-9)
    descent = (start.centre[2] - states[-1].centre[2]) * 360.0 / turned
    assert proof.descent == pytest.approx(descent, rel=1e-12)


def test_screw_engages_from_a_start_out_of_phase(flat):
    """Upright from 100 degrees, turned clockwise: the bolt rides its tip face to the
    window, drops in, and then descends the lead per turn; recomputed from the states
    past the phase where the outcome is decided."""
    run = screw(flat, 0.0, 0.0, 100.0, compliance=FRICTIONLESS, turns=1.0)
    assert run.outcome == "engaged"
    after = [s for s in run.states if s.phase <= run.decided_phase]
    end = after[-1]
    last = [s for s in after if s.phase - end.phase <= 90.0]
    assert abs(last[0].phase - end.phase) >= 85.0
    fall = last[0].centre[2] - end.centre[2]
    assert fall * 360.0 / abs(last[0].phase - end.phase) == pytest.approx(flat.lead, rel=0.05)
    # It did not descend before: out of phase it rode the tip face.
    start, entered = run.states[0], after[0]
    assert abs(start.centre[2] - entered.centre[2]) < flat.pitch / 10


def test_screw_jams_where_the_tilted_bolt_wedges(flat):
    """Held pitch -4 degrees from 30 degrees, turned clockwise: engaged on one side, the
    bolt's tip meets the nut's thread on the other and no rest state continues the turn:
    the states end where it wedged, and the landing beyond it lies above the last one.
    (Held at -3 degrees the bolt rights itself between the flanks and screws in.)"""
    rights = screw(flat, 0.0, -3.0, 30.0, turns=1.0)
    assert rights.outcome == "engaged"
    # Where it slides pinched between the flanks, a contact point flickers across the
    # border of two regions: no contact change is told that the next undoes within 1 deg.
    changes = [e for e in rights.events if e.kind == "contact-change"]
    for a, b in zip(changes, changes[1:], strict=False):
        assert not (b.after == a.before and abs(b.phase - a.phase) < 1.0), (a, b)
    run = screw(flat, 0.0, -4.0, 30.0, turns=1.0)
    assert run.outcome == "jammed"
    assert run.decided_phase is not None
    assert all(s.phase >= run.decided_phase - 1e-9 for s in run.states)
    # Until the jam it screwed in along the helix.
    engaged = [s for s in run.states if s.classification == "in-phase"]
    assert len(engaged) >= 5
    rate = _rate(engaged[0], engaged[-1])
    assert rate == pytest.approx(-flat.lead / 360.0, rel=0.1)


def test_clockwise_starts_of_a_held_tilt_share_their_walks_and_say_what_screw_says():
    """``ClockwiseStarts`` (a sweep's clockwise starts), default parts held (-2, -2): a
    start whose clockwise walk comes onto an earlier start's walk takes it from there,
    and says what ``screw`` alone, walking the whole turn itself, says. The starts at 80
    and 100 degrees ride; at 140 and 160 they wedge at one fold, located by bisection to
    the phase tolerance on walks that meet it from states equal to the pose tolerance:
    within a few hundredths of a degree."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    mech = Mechanics(spec, Compliance())
    for first, later, outcome in ((80.0, 100.0, "riding"), (140.0, 160.0, "jammed")):
        starts = ClockwiseStarts(mech, -2.0, -2.0)
        assert starts.screw(first).outcome == outcome
        joined = starts.screw(later)
        alone = screw(mech, -2.0, -2.0, later)
        assert joined.outcome == alone.outcome == outcome
        if outcome == "jammed":
            assert joined.decided_phase == pytest.approx(alone.decided_phase, abs=0.05)
        else:
            assert joined.decided_phase is alone.decided_phase is None
        # The later start walked only to where it met the first's walk.
        assert joined.queries < alone.queries / 5
        assert abs(joined.states[-1].phase - alone.states[-1].phase) < 0.05


def _exact_interference():
    """``exact_interference`` of the dynamics check (docs/scripts): sampled surface points
    of each exact body inside the other (the geometry's ThreadBody, no contact code)."""
    import importlib.util
    import sys
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "docs" / "scripts" / "dynamics_check.py"
    spec = importlib.util.spec_from_file_location("dynamics_check", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module.exact_interference


def test_a_tilted_snap_screws_in_between_the_flanks(flat, mech):
    """Held pitch -3 degrees from 30 degrees, frictionless: the bolt jumps into the thread
    at 348.78 degrees, tilted 2.4 degrees. Screwed in from there, its tip meets the nut's
    flank below and the edge where the nut's thread starts meets its crest above: the
    thread pinches the bolt, and only tilting toward the nut's axis lets it go on (a
    MuJoCo simulation of the compliance chain screws it in from the same landing). The
    snap is proved; along the screw-in every pose is free of the exact bodies (within the
    meshes' chord), the bolt descends at the lead over the last half turn, and its axis
    turns toward the nut's."""
    run = search(mech, 0.0, -3.0, 30.0)
    assert run.snap is not None and run.snap.engagement is not None
    assert run.snap.phase == pytest.approx(348.78, abs=0.05)
    assert run.snap.engagement.engaged, run.snap.engagement.reason
    landing = run.states[-1]
    walk = Continuation(mech, 0.0, -3.0, contact_changes=False, sense="tighten")
    _, events, states = walk.advance(landing, run.snap.phase, 180.0)
    assert not [e for e in events if abs(e.drop) > flat.pitch / 40]
    interference = _exact_interference()
    for s in states[:: max(1, len(states) // 12)] + [states[-1]]:
        pose = (s.centre[2], s.roll, s.pitch, s.phase)
        assert interference(flat, pose) < 5e-6, s.phase
    half = [s for s in states if s.phase <= run.snap.phase - 90.0]
    fall = half[0].centre[2] - half[-1].centre[2]
    assert fall * 360.0 / abs(half[0].phase - half[-1].phase) == pytest.approx(flat.lead, rel=0.1)

    def tilt(s):
        return math.degrees(
            math.acos(math.cos(math.radians(s.roll)) * math.cos(math.radians(s.pitch)))
        )

    assert tilt(states[-1]) < tilt(landing) - 0.5


@pytest.mark.slow
def test_a_landing_still_righting_itself_is_proved_by_turning_on():
    """The standard 1/4-20 parts held at roll -1 degree, from 130 degrees: the bolt jumps
    into the thread near 137 degrees tilted about 2.5 degrees more than held, and the
    thread draws it upright as it is screwed in. Over the second half of the first half
    turn it still rights itself and descends well short of the lead; the proof turns on
    and finds it engaged. Recomputed from one clockwise walk of a whole turn from the
    landing: the compliance centre falls short of the lead over 90..180 degrees and at the
    lead over the last quarter turn, and the bolt ends nearly upright."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    mech = Mechanics(spec)
    run = search(mech, -1.0, 0.0, 130.0)
    assert run.snap is not None and run.snap.engagement is not None
    proof = run.snap.engagement
    assert proof.engaged, proof.reason
    assert SCREW_IN < proof.turn <= 360.0
    landing = run.states[-1]
    walk = Continuation(mech, -1.0, 0.0, contact_changes=False, sense="tighten")
    _, _, states = walk.advance(landing, run.snap.phase, 360.0)

    def per_turn(lo, hi):
        part = [s for s in states if lo <= run.snap.phase - s.phase <= hi]
        return (part[0].centre[2] - part[-1].centre[2]) * 360.0 / (part[0].phase - part[-1].phase)

    assert per_turn(90.0, 180.0) < 0.9 * spec.lead
    assert per_turn(270.0, 360.0) == pytest.approx(spec.lead, rel=0.02)
    tilt = np.degrees(np.arccos(np.asarray(states[-1].rotation)[2, 2]))
    assert tilt < 0.1


@pytest.mark.slow
def test_a_proof_joins_the_walk_of_an_earlier_one_on_its_branch():
    """The standard 1/4-20 parts held at roll -1 degree, in phase at 140 and 145 degrees:
    screwed in from 145, the bolt reaches at 140 the state the walk from 140 started at,
    and one continuation proving both joins the earlier walk there. Its proof of 145 is
    that of a fresh continuation (the same verdict, the descent within 1 % of the lead,
    the tilt within 0.05 degree) for a fraction of the collision queries."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    mech = Mechanics(spec)
    first, later = (mech.settle(-1.0, 0.0, phase).state for phase in (140.0, 145.0))
    assert first.classification == later.classification == "in-phase"
    walk = Continuation(mech, -1.0, 0.0)
    walk.prove(first, 140.0)
    before = mech.engine.queries
    joined = walk.prove(later, 145.0)
    cost_joined = mech.engine.queries - before
    before = mech.engine.queries
    fresh = Continuation(mech, -1.0, 0.0).prove(later, 145.0)
    cost_fresh = mech.engine.queries - before
    assert joined.engaged == fresh.engaged
    assert joined.turn == fresh.turn
    assert abs(joined.descent - fresh.descent) <= 0.01 * spec.lead
    assert abs(joined.tilt - fresh.tilt) <= 0.05
    assert cost_joined < 0.5 * cost_fresh


@pytest.mark.slow
def test_a_proof_halves_the_steps_that_leave_its_branch():
    """The standard 1/4-20 parts held at roll -2 degrees, in phase at 140 degrees: screwed
    in, the bolt is pinched between the flanks and a 5-degree step's settle leaves the
    branch where shorter ones stay on it. The proof halves such steps; the same walk as a
    search takes it (every step that leaves the branch closed in on by bisection to the
    phase tolerance) reaches the same verdict, its descent over the last half screw-in
    within 1 % of the lead and its tilt within 0.05 degree."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    mech = Mechanics(spec)
    start = mech.settle(-2.0, 0.0, 140.0).state
    assert start.classification == "in-phase"
    proof = Continuation(mech, -2.0, 0.0).prove(start, 140.0)
    walk = Continuation(mech, -2.0, 0.0, contact_changes=False, sense="tighten")
    legs, events, states = walk.advance(start, 140.0, proof.turn)
    # Judged as the proof is: over the last half screw-in.
    bisected = engagement(walk, start, legs, events, states, proof.turn, 0.5 * SCREW_IN)
    assert proof.engaged and bisected.engaged
    assert abs(proof.descent - bisected.descent) <= 0.01 * spec.lead
    assert abs(proof.tilt - bisected.tilt) <= 0.05


@pytest.mark.slow
def test_a_coarse_search_proves_its_snaps_as_a_fine_one_does():
    """The default parts (chamfered point, countersunk nut) held at (2, 1), in phase at
    140 degrees, the axis 1.4 degrees from upright: screwed in, the thread draws it
    upright. A search at the longest step allowed (10 degrees) proves the landing as one
    at 2.5 degrees does (the same verdict, the descent over the last half screw-in within
    1 % of the lead, the tilt at the end within 0.05 degree): its clockwise walk steps by
    at most TIGHTEN_STEP. (Walked in steps of 10 degrees, the landing rides on tilted 2
    degrees without descending.)"""
    spec = with_parts("1/4-20 UNC-2A/2B")
    mech = Mechanics(spec)
    start = mech.settle(2.0, 1.0, 140.0).state
    assert start.classification == IN_PHASE
    coarse = Continuation(mech, 2.0, 1.0, step=MAX_STEP).prove(start, 140.0)
    fine = Continuation(mech, 2.0, 1.0, step=2.5).prove(start, 140.0)
    assert fine.engaged and abs(fine.descent - spec.lead) <= LEAD_TOLERANCE * spec.lead
    assert coarse.engaged == fine.engaged
    assert abs(coarse.descent - fine.descent) <= 0.01 * spec.lead
    assert abs(coarse.tilt - fine.tilt) <= 0.05


@pytest.mark.slow
def test_screwing_in_from_a_pose_in_phase_whose_descent_stopped_short_is_no_jump():
    """The standard 1/4-20 parts held at pitch 1.5 degrees, in phase at 120 degrees,
    screwed in by the screw-in turn. In the thread some descents stop short of the balance
    (class unstable) at poses the engagement rule calls in phase (kind in-phase), and the
    next one balances: nothing jumps there. Recomputed here from the poses, every step of
    the walk falls by the lead's share of its turn to within pitch / 40 and turns the axis
    by less than 0.5 degree; the walk reports no jump, and its verdict is that of a walk of
    2.5-degree steps, the descent within 1 % of the lead and the tilt within 0.05
    degree."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    mech = Mechanics(spec)
    start = mech.settle(0.0, 1.5, 120.0).state
    assert start.classification == "in-phase"
    proofs = []
    for step in (5.0, 2.5):
        walk = Continuation(
            mech,
            0.0,
            1.5,
            step=step,
            contact_changes=False,
            sense="tighten",
            fold_tolerance=PROOF_FOLD_TOLERANCE,
        )
        legs, events, states = walk.advance(start, 120.0, SCREW_IN)
        proofs.append(engagement(walk, start, legs, events, states, SCREW_IN, 0.5 * SCREW_IN))
        if step == 5.0:
            stopped_short = [
                s for s in states if (s.classification, s.kind) == ("unstable", "in-phase")
            ]
            assert stopped_short
            assert not [e for e in events if e.kind in ("jump", "snap")]
            path = [start, *states]
            for a, b in zip(path, path[1:], strict=False):
                share = spec.lead * abs(b.phase - a.phase) / 360.0
                fall = a.centre[2] - b.centre[2]
                assert abs(fall - share) <= spec.pitch / 40, (a.phase, b.phase, fall, share)
                assert axis_angle(a.rotation, b.rotation) < 0.5, (a.phase, b.phase)
    coarse, fine = proofs
    assert coarse.engaged and fine.engaged
    assert abs(coarse.descent - fine.descent) <= 0.01 * spec.lead
    assert abs(coarse.tilt - fine.tilt) <= 0.05


def test_forces_stay_within_what_the_load_and_spring_explain(flat):
    """Where two contacts' line passes near the compliance centre (held pitch -3, the tip
    rim against the bore's edge near 348.7 degrees) the rigid balance asks for hundreds of
    newtons under a 10 N load. Every reported contact force of the search stays within
    three times the load plus the spring's moment over the bolt's radius, recomputed here
    from each state's tilt; such states are marked near-singular."""
    comp = Compliance()
    run = search(flat, 0.0, -3.0, 30.0, compliance=comp)
    radius = 0.5 * flat.bolt.major * 0.0254
    marked = 0
    for s in run.states:
        spring = max(
            abs(comp.roll_stiffness * math.radians(s.roll - 0.0)),
            abs(comp.pitch_stiffness * math.radians(s.pitch + 3.0)),
        )
        bound = 3.0 * (comp.force + spring / radius)
        for c in s.touching:
            if math.isfinite(c.force):
                assert c.force <= bound * (1 + 1e-9), (s.phase, c.regions, c.force)
        marked += s.near_singular
    assert marked >= 1


def test_cli_screw_json_and_exit(capsys):
    """threadmate screw --json prints one document with units, the outcome and the
    descent per turn; it exits 0 engaged, 3 otherwise; bad input exits 2."""
    args = ["screw", "1/4-20 UNC-2A/2B", "--point", "flat", "--no-countersink"]
    code, out, err = run_cli(
        capsys, *args, "--roll", "0", "--pitch", "0", "--phase", "100", "--json"
    )
    assert code == 0, err
    doc = json.loads(out)
    assert doc["outcome"] == "engaged"
    assert doc["units"]["length"] == "in" and doc["units"]["torque"] == "N m"
    assert doc["descent_per_turn"] == pytest.approx(0.05, rel=0.05)
    code, out, _ = run_cli(capsys, *args, "--roll", "0", "--pitch", "-4", "--phase", "30", "--json")
    assert code == 3
    assert json.loads(out)["outcome"] == "jammed"
    code, out, err = run_cli(
        capsys, *args, "--roll", "0", "--pitch", "0", "--phase", "0", "--torque-limit", "-1"
    )
    assert code == 2 and "--torque-limit" in err and not out
    assert "Traceback" not in err


@pytest.mark.slow
def test_run_with_screw_reports_the_clockwise_starts(flat, tmp_path):
    """threadmate run --screw (the pipeline's ``clockwise``): every start's row records what
    it does turned clockwise directly, as ``screw`` from that start says, and the report
    gives the share engaged by held tilt."""
    from threadmate.library import load
    from threadmate.pipeline import run_pipeline

    result = run_pipeline(
        flat, tmp_path / "run", roll="0", pitch="0", phase="100", workers=1, clockwise=True
    )
    rows = load(result.libraries[0])
    starts = rows[rows["role"] == "start"].set_index("phase")
    assert starts.loc[100.0, "clockwise"] == screw(flat, 0.0, 0.0, 100.0).outcome == "engaged"
    report = result.report.read_text(encoding="utf-8")
    assert "## Clockwise starts" in report and "| +0 | 100% |" in report


@pytest.mark.parametrize(
    "cfg, engaged",
    [
        ((0, 0, 5), True),
        ((1, 0.5, 10), True),
        ((0, 0, 100), False),
        ((0, 0, 200), False),
        ((2, 1, 300), False),
    ],
)
def test_in_phase_on_the_exact_bodies(quarter_20, cfg, engaged):
    """The class against the exact bodies (``_exact_geometry``: the profile formula, no
    mesh): at the rest state's own tilt, the bolt turned 0.5 degree either way and lowered
    to first touch. Where the code says in phase, the exact height moves with the turn at
    more than half the lead's share (the thread carries the bolt along the helix); where it
    says out of phase, at less than a tenth of it (the end slides round on the nut's
    entry). The height at the state's own phase is the exact one within 5e-6 in."""
    from _exact_geometry import exact_centre_height, rot

    mech = Mechanics(quarter_20, FRICTIONLESS)
    rest = mech.settle(*cfg).state
    assert (rest.classification == "in-phase") == engaged, rest.region_combination
    roll, pitch, phase = rest.roll, rest.pitch, cfg[2]
    here = exact_centre_height(quarter_20, rot(roll, pitch, phase))
    assert here == pytest.approx(rest.centre[2], abs=5e-6)
    up = exact_centre_height(quarter_20, rot(roll, pitch, phase + 0.5))
    down = exact_centre_height(quarter_20, rot(roll, pitch, phase - 0.5))
    rate = (up - down) / (quarter_20.lead / 360.0)
    assert rate > 0.5 if engaged else abs(rate) < 0.1


@pytest.mark.slow
def test_the_library_records_the_snaps_window():
    """The standard parts (chamfered point, countersunk nut) held (1, 1) from phase 0: the
    point rides a shallow basin before the snap, and a settle started a little further
    along it falls into the thread early: the snap is a window (``search``: from about
    124 degrees to the snap at 135). The library's continuation keeps the states of its
    steps, a subset of the search's (which adds one either side of each contact change),
    so its window, looked for from those states, lies within the search's; its snap and
    click are the search's. Only the snap's row has a window."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    run = search(spec, 1.0, 1.0, 0.0)
    assert run.snap is not None and run.snap_window is not None
    lo, hi = run.snap_window
    assert hi == pytest.approx(run.snap.phase) and hi - lo > 1.0
    rows = sweep(spec, [1.0], [1.0], [0.0], workers=1)
    snaps = rows[rows["transition"] == "snap"]
    assert len(snaps) == 1
    assert 0.0 <= snaps["snap_window"].iloc[0] <= hi - lo + 0.01
    assert snaps["drop"].iloc[0] == pytest.approx(run.snap.drop, rel=1e-6)
    assert rows.loc[rows["transition"] != "snap", "snap_window"].isna().all()


def test_the_click_is_the_whole_fall_a_sensor_sees(flat, mech):
    """Held (0, -3) from 30 degrees, frictionless: the bolt rides the nut's top face
    until about 348.7 degrees, then the branch falls steeply (many leads per degree) for
    its last hundredths of a degree before it ends in the snap. A sensor sees the whole
    fall, as a dynamic simulation does: the click is the highest the branch stands within
    the last degree of turn (``CLICK_SPAN``) less the landing. The branch is followed
    independently here in steps of 0.05 degree from the search's state at 345 to a
    hundredth of a degree before the snap: it does not engage before the snap, and what
    it jumps on the way (a walk of other steps can leave a steep stretch by a small jump)
    lies within that last degree; the click is larger than the jump's own drop. Just
    before the fall the walk tips onto the bore's edge, propped on the tip's rim by a
    contact whose normal lies nearly level: a near-singular state, whose height the click
    passes over."""
    run = search(mech, 0.0, -3.0, 30.0)
    assert run.snap is not None and run.snap.engagement is not None
    assert run.snap.engagement.engaged
    landing = run.states[-1]
    walk = Continuation(mech, 0.0, -3.0, step=0.05)
    state = next(s for s in run.states if s.phase == pytest.approx(345.0))
    end = run.snap.phase - 0.01
    _, events, states = walk.advance(state, 345.0, end - 345.0)
    assert not [e for e in events if e.kind == "snap"]
    assert all(e.phase >= run.snap.phase - CLICK_SPAN for e in events if e.kind == "jump")
    # (A state whose rigid balance is near-singular, propped on a contact whose normal
    # lies level, is no height a sensor sees: a hair of contact compliance lets the bolt
    # down from it, as the dynamics check's stiff contacts do.)
    top = max(
        s.centre[2]
        for s in states
        if s.phase >= run.snap.phase - CLICK_SPAN and not s.near_singular
    )
    assert run.snap.click == pytest.approx(top - landing.centre[2], rel=0.01)
    assert run.snap.click > run.snap.drop * 1.1


def test_a_smooth_snap_clicks_its_drop(upright_search):
    """Upright, the bolt rides the top face and climbs a little onto the edge where the
    nut's thread starts, up to the window's edge: the highest it stands before the snap
    is where it jumps, and the click is the jump's own drop."""
    snap = upright_search.snap
    assert snap is not None
    assert snap.click == pytest.approx(snap.drop, rel=1e-9)


def _proof_at(mech, friction, torque_limit=None):
    """The proof of the upright bolt started in phase at phase 0 (the start settled anew)
    with ``friction``, on ``mech``'s bodies."""
    m = Mechanics(mech.spec, Compliance(friction=friction), scene=mech.scene)
    start = m.settle(0.0, 0.0, 0.0).state
    assert start.classification == IN_PHASE
    return Continuation(m, 0.0, 0.0, torque_limit=torque_limit).prove(start, 0.0)


@pytest.fixture(scope="module")
def proof_015(mech):
    return _proof_at(mech, 0.15)


def test_a_proof_judges_alike_up_to_the_friction_where_a_torque_passes_its_limit(mech, proof_015):
    """The frictions a proof judges alike at (``Engagement.frictions``) end where a
    torque of its walk passes the limit: made again with the friction just inside the
    upper end, the proof engages as at 0.15; just outside, it jams on its torque. With no
    friction the friction parts tell no proportion, and no other friction is alike."""
    proof = proof_015
    low, high = proof.frictions
    assert proof.engaged and low == 0.0 and 0.15 < high < math.inf
    inside, outside = _proof_at(mech, high * (1 - 1e-3)), _proof_at(mech, high * (1 + 1e-3))
    assert inside.engaged and not inside.jammed
    assert outside.jammed and outside.reason.startswith("the tightening torque reaches")
    assert _proof_at(mech, 0.0).frictions == (0.0, 0.0)


def test_a_proof_scaled_to_another_friction_is_the_proof_made_there(mech, proof_015):
    """A proof that jams on its torque (a limit of half its peak) judges alike from a
    friction below its own on; scaled to 0.25 it is the proof made at 0.25: the same
    verdict and turn, the same words with the torque there, the same peak torque."""
    limit = 0.5 * proof_015.torque_peak
    jam = _proof_at(mech, 0.15, limit)
    low, high = jam.frictions
    assert jam.jammed and 0.0 < low < 0.15 and high == math.inf
    there = _proof_at(mech, 0.25, limit)
    scaled = jam.scaled(0.25 / 0.15)
    assert (scaled.engaged, scaled.jammed, scaled.turn) == (there.engaged, there.jammed, there.turn)
    assert scaled.reason == there.reason != jam.reason
    assert scaled.torque_peak == pytest.approx(there.torque_peak, rel=1e-9)


def _helix_rate(spec, state, phase, half=0.5):
    """How fast the bolt at ``state``'s own tilt rises as it is turned the loosening way,
    per the lead's share of the turn, turned ``half`` degree either way about ``phase``:
    each pose lowered to first touch on the whole meshes (python-fcl's yes/no query,
    bisected). Near 1 where the thread carries the bolt along the helix."""
    from _exact_geometry import rot
    from _fcl import collider

    meshes = collider(spec)
    x, y, z = state.origin
    heights = [
        meshes.first_touch(rot(state.roll, state.pitch, phase + d), x, y, z, 0.2 * spec.pitch)
        for d in (-half, half)
    ]
    return spec.handedness * (heights[1] - heights[0]) / (2 * half * spec.lead / 360.0)


def _screw_rate(spec, state, phase, turn=1.0):
    """How far the bolt at ``state``'s own tilt descends when turned ``turn`` degrees
    clockwise (tightening) from ``phase``, per the lead's share of the turn: both poses
    lowered to first touch on the whole meshes (python-fcl's yes/no query, bisected). 1
    where the bolt moves along the helix."""
    from _exact_geometry import rot
    from _fcl import collider

    meshes = collider(spec)
    x, y, z = state.origin
    here, there = (
        meshes.first_touch(rot(state.roll, state.pitch, p), x, y, z, 0.2 * spec.pitch)
        for p in (phase, phase - spec.handedness * turn)
    )
    return (here - there) / (turn * spec.lead / 360.0)


@pytest.mark.slow
def test_a_landing_in_the_thread_whose_descent_stopped_short_is_proved():
    """M6x1 held 1.65 degrees toward +X (pitch), searched from phase 20: at about 131
    degrees the bolt drops some 0.06 mm off the countersink onto the nut's crest corner
    with its flank, tilted back nearly upright, and the descent there stops short of the
    balance (the spring pulls the tilt back; no rest state, though the contacts lie on
    the helices). Such a landing is proved by screwing in like any other: it screws in,
    so it is the snap. (Before, only a landing whose descent balanced was proved: the
    search turned on out of the thread and found no snap within the turn.)

    Checked without the code's verdicts: the proof descends at the standard's lead (1 mm
    per turn for M6x1) within 10 %, and the landing turned half a degree either way at its
    own tilt and lowered to first touch on the whole meshes moves at more than half the
    lead's share: the thread carries it along the helix."""
    spec = spec_from_designation("M6x1-6g/6H")
    assert spec.lead == pytest.approx(1.0)
    result = search(spec, 0.0, 1.65, 20.0)
    snap = result.snap
    assert snap is not None and snap.kind == "snap"
    assert 125.0 < snap.phase < 135.0 and snap.drop > 0.05
    proof = snap.engagement
    assert proof is not None and proof.engaged
    assert abs(proof.descent - spec.lead) <= 0.1 * spec.lead
    landing = result.states[-1]
    assert landing.classification == IN_PHASE and "+F" in landing.region_combination
    assert _helix_rate(spec, landing, snap.phase) > 0.5


@pytest.mark.slow
def test_a_start_in_the_thread_whose_descent_stopped_short_is_proved():
    """The standard 1/4-20 parts held at pitch 1 degree, phase 160: the start's descent
    stops short of the balance with the bolt's flank on the nut's crest corner (class
    unstable, contacts on the helices). It is proved as a start in phase is: it screws
    in, so the search snaps where it starts, and the start is classed in phase. Checked
    as above: the proof descends at the standard's lead (20 threads per inch) within 10 %,
    and the start turned half a degree either way moves along the helix on the whole
    meshes."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    assert spec.lead == pytest.approx(1 / 20)
    mech = Mechanics(spec)
    rest = mech.settle(0.0, 1.0, 160.0)
    assert (rest.state.kind, rest.state.classification) == (IN_PHASE, "unstable")
    result = search(mech, 0.0, 1.0, 160.0)
    assert result.snap is not None and result.snap_turn == 0.0
    proof = result.snap.engagement
    assert proof is not None and proof.engaged
    assert abs(proof.descent - spec.lead) <= 0.1 * spec.lead
    start = result.states[0]
    assert start.classification == IN_PHASE
    assert _helix_rate(spec, start, 160.0) > 0.5


@pytest.mark.slow
@pytest.mark.parametrize(
    ("designation", "start", "window"),
    [("M8x1.25-6g/6H", 120.0, (140.0, 141.5)), ("M8x1.25-6g/6H LH", 240.0, (218.5, 220.0))],
    ids=["right-hand", "left-hand"],
)
def test_a_landing_carried_partly_by_the_thread_that_screws_in_is_the_snap(
    designation, start, window
):
    """M8x1.25 held 1.5 degrees toward -X (pitch -1.5), searched from phase 120: at about
    140.9 degrees the bolt's point drops some 0.21 mm off the nut's crest into the
    thread, onto the nut's flank, with the bolt's thread on the countersink. Not every
    contact carrying it lies on the helices, so the contacts alone do not call it in
    phase; but it screws in, so it is the snap, and its click is that fall. (Before, it
    was taken for a jump, and the snap came some 2.4 degrees later where the contacts
    first all lay on the helices, with no fall at all: a click of -1e-5 mm.)

    The left-hand pair is its mirror image: M = diag(1, -1, 1) maps the right-hand pair
    onto it and a search from phase f with roll r onto one from -f with -r, turned the
    other way (counter-clockwise loosens a right-hand thread, clockwise a left-hand one).
    So it snaps at 360 degrees less, about 219.1, with the same click, the probe that asks
    whether the landing follows the helix turning it tightening for its hand.

    Checked without the code's verdicts: the proof descends at the standard's lead
    (1.25 mm per turn) within 10 %, and the landing turned half a degree either way at
    its own tilt and lowered to first touch on the whole meshes moves at more than half
    the lead's share, turned the loosening way."""
    spec = spec_from_designation(designation)
    assert spec.lead == pytest.approx(1.25)
    result = search(spec, 0.0, -1.5, start)
    snap = result.snap
    assert snap is not None and window[0] < snap.phase < window[1]
    assert snap.click > 0.2 and snap.drop > 0.2
    proof = snap.engagement
    assert proof is not None and proof.engaged
    assert abs(proof.descent - spec.lead) <= 0.1 * spec.lead
    landing = result.states[-1]
    assert landing.classification == IN_PHASE and landing.kind != IN_PHASE
    regions = {c.nut_region for c in landing.contacts if c.force > 0.0}
    assert "+F" in regions and "countersink" in regions
    assert _helix_rate(spec, landing, snap.phase) > 0.5


@pytest.mark.slow
def test_a_landing_on_the_countersink_that_screws_in_is_the_snap():
    """The default 1/4-20 parts (chamfered point, countersunk nut), frictionless, held
    2 degrees toward +X (pitch 2) and searched from phase 120: the independent dynamics
    simulation (``docs/scripts/dynamics_check.py --ends --start=0,2,120 --lead-in 5``;
    validation.md, "Against the dynamics simulation, the default parts") jumps at 137.22
    degrees by 0.00157 in onto the countersink, the bolt's chamfered thread on it, and
    the bolt turned back from that landing descends at the lead: the snap, though no
    contact on the nut's thread carries the landing. The search must find it there, with
    that click, and its landing must move along the helix on the whole meshes."""
    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    mech = Mechanics(spec, Compliance(force=10.0, stiffness=1.0, friction=0.0))
    result = search(mech, 0.0, 2.0, 120.0, turns=1)
    snap = result.snap
    assert snap is not None
    assert abs(snap.phase - 137.22) < 0.5
    assert abs(snap.click - 0.00157) < 0.05 * 0.00157
    landing = result.states[-1]
    assert {c.nut_region for c in landing.contacts if c.force > 0.0} == {"countersink"}
    assert abs(_helix_rate(spec, landing, snap.phase) - 1.0) < 0.1
    assert abs(_screw_rate(spec, landing, snap.phase) - 1.0) < 0.1


@pytest.mark.slow
def test_a_bolt_that_rides_into_phase_without_a_jump_is_the_snap(monkeypatch):
    """M8x1.25 with its standard ends held 2 degrees toward -X (pitch -2), searched from
    phase 140: the bolt's crest rides the countersink with its point on the nut's crest
    or flank, rising at about two thirds of the lead as it turns: turned at its own tilt,
    it moves ever more nearly along the helix, with no fall. The helix probe's windows
    are thresholds on such a smooth change (docs/mechanics.md, "The helix probe's
    windows"); the thread's (more than half the lead's share) holds the start already.
    Narrowed to the entry's (within a quarter of the share), the ride crosses it at
    about 153.7 degrees: there the walk must notice that it passed into phase without
    a jump, prove it and call it the snap, with no click.

    Checked without the code's verdicts, on the whole meshes (python-fcl's yes/no query,
    bisected): the start, turned a degree clockwise at its own tilt and lowered, descends
    by well under three quarters of the lead's share (about 0.6); the state the snap
    reports, by about three quarters of it; and the proof descends at the standard's
    lead (1.25 mm) within 10 %."""
    from threadmate.contact.mechanics import _search

    monkeypatch.setitem(_search.HELIX_SHARES, "thread", _search.HELIX_SHARES["entry"])
    spec = spec_from_designation("M8x1.25-6g/6H")
    result = search(Mechanics(spec, Compliance()), 0.0, -2.0, 140.0, turns=1)
    snap = result.snap
    assert snap is not None and 145.0 < snap.phase < 165.0
    assert "without a jump" in snap.note
    # No fall, no tip: continuous (the jump's thresholds, pitch / 40 and 0.5 degree).
    assert abs(snap.drop) < spec.pitch / 40 and snap.tilt_change < 0.5
    assert abs(snap.click) < spec.pitch / 40
    start, entered = result.states[0], result.states[-1]
    assert _screw_rate(spec, start, 140.0) < 0.7
    assert 0.7 < _screw_rate(spec, entered, snap.phase) < 1.25
    proof = snap.engagement
    assert proof is not None and proof.engaged
    assert abs(proof.descent - 1.25) <= 0.1 * 1.25
