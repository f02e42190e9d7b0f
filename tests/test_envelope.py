"""The polar grid of misalignment and the capture envelope (issue 29, items 1 and 2).

Every expected value is computed independently of the code under test: the polar form
against explicit rotation matrices, a polar library against a roll/pitch library swept at
the same held tilts, the envelope against direct counter-clockwise searches just inside
and just outside it.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from _cli import one_line, run_cli
from threadmate import InputError
from threadmate.contact import Compliance, search
from threadmate.geometry import held_tilt_from_polar, polar_from_held_tilt, spec_from_designation
from threadmate.library import PolarGrid, load, make_grid, read_grid, sweep

STATE = [
    "state_id",
    "held_roll",
    "held_pitch",
    "phase",
    "role",
    "classification",
    "roll",
    "pitch",
    "centre_z",
    "potential",
    "next_id",
    "transition",
    "transition_turn",
    "drop",
]


def _rx(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


@pytest.mark.parametrize(
    ("tilt", "direction"),
    [(0.5, 0.0), (1.0, 90.0), (2.0, 22.5), (3.5, 157.5), (4.0, 200.0), (1.25, 337.5)],
)
def test_polar_tilt_is_the_bolt_axis_size_and_azimuth(tilt, direction):
    """Roll and pitch from (size, direction) put the bolt axis ``Rx(roll) Ry(pitch) e_z``
    at that angle from +Z, leaning toward that azimuth (from +X toward +Y)."""
    roll, pitch = held_tilt_from_polar(tilt, direction)
    axis = _rx(roll) @ _ry(pitch) @ np.array([0.0, 0.0, 1.0])
    assert math.degrees(math.acos(axis[2])) == pytest.approx(tilt, abs=1e-9)
    azimuth = math.degrees(math.atan2(axis[1], axis[0])) % 360.0
    assert abs((azimuth - direction + 180.0) % 360.0 - 180.0) < 1e-9
    size, where = polar_from_held_tilt(roll, pitch)
    assert float(size) == pytest.approx(tilt, abs=1e-9)
    assert abs((float(where) - direction + 180.0) % 360.0 - 180.0) < 1e-9


def test_quarter_turn_directions_are_the_axes():
    """Direction 0 is a positive pitch, 90 a negative roll, 180 a negative pitch, 270 a
    positive roll (the bolt's head toward +X, +Y, -X, -Y)."""
    for direction, want in ((0, (0, 2)), (90, (-2, 0)), (180, (0, -2)), (270, (2, 0))):
        assert held_tilt_from_polar(2.0, direction) == pytest.approx(want, abs=1e-12)
    assert np.isnan(polar_from_held_tilt(0.0, 0.0)[1])


def test_polar_grid_holds_the_upright_tilt_once():
    grid = PolarGrid.parse("0:2:1", "0:360:90", "0:340:20")
    assert grid.tilt == (0.0, 1.0, 2.0) and len(grid.direction) == 4 and len(grid.phase) == 18
    assert len(grid.held_tilts) == 1 + 2 * 4 and grid.size == 9 * 18
    assert grid.held_tilts[0] == (0.0, 0.0)
    # config_id = i_held * n_phase + i_phase, size-major then direction.
    assert grid.configuration(18 * 3 + 2) == pytest.approx((0.0, -1.0, 40.0), abs=1e-12)
    assert read_grid(json.loads(json.dumps(grid.to_dict()))) == grid
    assert PolarGrid.parse("0", "0:360:10", "0").size == 1


def test_neighbours_step_in_size_and_direction():
    grid = PolarGrid.parse("0:2:1", "0:360:90", "0")
    pairs = set(grid.neighbours())
    up, p1, p2, r1 = (0.0, 0.0), grid.held_tilts[1], grid.held_tilts[5], grid.held_tilts[2]
    assert (up, p1) in pairs and (p1, up) in pairs  # upright to the first size
    assert (p1, p2) in pairs  # outward in one direction
    assert (p1, r1) in pairs  # round the circle at one size
    assert (up, p2) not in pairs


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"roll": "0", "tilt": "1"}, "two kinds of grid"),
        ({"tilt": "-1:2:1"}, "out of range"),
        ({"tilt": "0:50:1"}, "out of range"),
        ({"direction": "0:360:0"}, "must be positive"),
    ],
)
def test_bad_polar_grids_are_refused(kwargs, words):
    with pytest.raises(InputError, match=words):
        make_grid(**kwargs)


@pytest.mark.parametrize(
    "args",
    [
        ("--roll", "0", "--tilt", "1"),
        ("--pitch", "-1:1:1", "--direction", "0:360:90"),
        ("--tilt", "-1:1:1"),
        ("--tilt", "0:1:0.5", "--direction", "a:b:c"),
    ],
)
def test_sweep_refuses_mixed_or_bad_polar_grids(capsys, tmp_path, args):
    code, out, err = run_cli(capsys, "sweep", "1/4-20 UNC-2A/2B", *args, "-o", tmp_path / "lib")
    assert code == 2 and out == ""
    assert one_line(err).startswith("threadmate: error:")
    assert not (tmp_path / "lib").exists()


@pytest.mark.parametrize(
    "args",
    [
        ("--tolerance", "0"),
        ("--tilt", "0:50:1"),
        ("--direction", "0:360:-5"),
        ("--plot", "envelope.txt"),
        ("--workers", "0"),
    ],
)
def test_envelope_refuses_bad_input(capsys, tmp_path, args):
    code, out, err = run_cli(capsys, "envelope", "1/4-20 UNC-2A/2B", *args)
    assert code == 2 and out == ""
    assert one_line(err).startswith("threadmate: error:")


def test_envelope_refuses_a_library_with_compliance_options(capsys, tmp_path):
    lib = tmp_path / "lib"
    lib.mkdir()
    code, out, err = run_cli(capsys, "envelope", lib, "--force", "5")
    assert code == 2 and "--force" in one_line(err)
    code, out, err = run_cli(capsys, "envelope", lib)
    assert code == 2 and "not a threadmate library" in one_line(err)


@pytest.mark.slow
def test_polar_library_equals_the_roll_pitch_library_at_the_same_tilts(quarter_20, tmp_path):
    """Tilt 1 toward 90 degrees is held roll -1, pitch 0: the polar library (upright and
    that tilt) holds, row for row, the states of the roll/pitch library of rolls -1 and 0
    at pitch 0."""
    polar = sweep(
        quarter_20, tilt="0,1", direction="90", phase="0,180", out=tmp_path / "p", workers=1
    )
    square = sweep(quarter_20, roll="-1,0", pitch="0", phase="0,180", out=tmp_path / "s", workers=1)
    a = load(polar).sort_values("state_id").reset_index(drop=True)
    b = load(square).sort_values("state_id").reset_index(drop=True)
    assert len(a) == len(b) and len(a) > 4
    assert sorted(set(zip(a["held_roll"], a["held_pitch"], strict=True))) == [(-1.0, 0.0), (0, 0)]
    for column in STATE:
        x, y = a[column].to_numpy(), b[column].to_numpy()
        if x.dtype.kind == "f":
            np.testing.assert_allclose(x, y, rtol=0, atol=1e-12, err_msg=column)
        else:
            assert list(x) == list(y), column
    # A resumed sweep of another polar grid is refused, never mixed.
    with pytest.raises(Exception, match="grid directions"):
        sweep(quarter_20, tilt="0,1", direction="0,90", phase="0,180", out=polar, workers=1)


def _snaps_within_a_turn(spec, compliance, tilt, direction, phase) -> bool:
    roll, pitch = held_tilt_from_polar(tilt, direction)
    run = search(spec, roll, pitch, phase, compliance=compliance, turns=1.0)
    return run.snap is not None


@pytest.mark.slow
def test_envelope_agrees_with_direct_searches_inside_and_outside(tmp_path):
    """In the worst direction, every start phase snaps within one turn at the tolerated
    tilt (direct searches), and at the first failure the bisection found one does not.

    The standard 1/4-20 parts (chamfered point, countersunk nut) leaning toward +X (held
    pitch positive) snap from every phase upright and stop snapping by 4 degrees: a
    bracket to bisect."""
    from threadmate.design import envelope, plot_envelope

    spec = spec_from_designation("1/4-20 UNC-2A/2B")
    compliance = Compliance(force=10, stiffness=1)
    phases = (0.0, 180.0)
    env = envelope(
        spec,
        compliance=compliance,
        tilt="0,4",
        direction="0",
        phase="0,180",
        tolerance=0.5,
        workers=1,
    )
    doc = json.loads(json.dumps(env.to_dict()))
    assert doc["units"]["angle"] == "deg" and doc["units"]["work"] == "mJ"
    worst = doc["tolerated"]["100%"]["worst_directions"][0]
    row = next(x for x in doc["directions"] if x["direction"] == worst)
    inside, outside = row["tilt"]["100%"], row["first_failure"]["100%"]
    assert inside == env.tolerated_tilt
    assert outside is not None, doc["directions"]
    # Located by bisection, not read off the grid: within the tolerance of the failure.
    assert 0 < outside - inside <= 0.5 + 1e-9 and 0 < inside < 4
    for phase in phases:
        assert _snaps_within_a_turn(spec, compliance, inside, worst, phase), phase
    assert not all(
        _snaps_within_a_turn(spec, compliance, outside, worst, phase) for phase in phases
    )
    figure = plot_envelope(env, tmp_path / "envelope.png")
    assert figure.stat().st_size > 1000
    # Two phases: one short is 50 %, so the 95 % level asks both, and a note says so.
    assert row["tilt"]["95%"] == row["tilt"]["100%"]
    assert any("the 95 % level asks every phase" in note for note in doc["notes"])


@pytest.mark.slow
def test_an_envelope_whose_upright_fails_reports_every_held_tilt_it_computed():
    """Upright and the first size of every direction go out together (the workers stay
    busy); when the upright fails, the sizes still out are no longer needed, but each
    one computed is reported: probes and shares alike, whatever order the workers finish
    in.

    A torque limit of 1e-4 N m fails every start: screwing in from a snap turns the thread
    against friction, about mu F r_pitch / cos 30 = 0.15 x 10 N x 2.73 mm / 0.87 = 4.7e-3
    N m, less the load's 10 N x 1.27 mm / 2 pi = 2.0e-3 N m down the lead: 2.7e-3 N m,
    far above the limit. So upright and every tilt have a share of 0."""
    from threadmate.design import envelope

    flat = spec_from_designation("1/4-20 UNC-2A/2B", point="flat", countersink=False)
    directions = [0.0, 90.0, 180.0, 270.0]
    env = envelope(
        flat,
        compliance=Compliance(force=10, stiffness=1),
        tilt="0,2",
        direction=",".join(f"{d:g}" for d in directions),
        phase="300",
        tolerance=1.0,
        torque_limit=1e-4,
        workers=2,
    )
    doc = env.to_dict()
    assert env.tolerated_tilt == 0.0
    assert any("even upright" in note for note in doc["notes"]), doc["notes"]
    # The upright tilt once, and size 2 in each direction: every one was computed.
    assert env.probes == 1 + len(directions)
    assert [row["direction"] for row in doc["directions"]] == directions
    for row in doc["directions"]:
        assert [tuple(s) for s in row["shares"]] == [(0.0, 0.0), (2.0, 0.0)], row


@pytest.mark.parametrize(("phases", "noted"), [(18, True), (19, True), (20, False), (40, False)])
def test_a_level_that_asks_every_phase_is_noted(phases, noted):
    """With fewer than 20 start phases, 95 % of them is every phase (from 20 on, one
    phase short still meets 95 %): the envelope says its 95 % level is the 100 % one.
    The shares here are made up: every phase snaps upright, none at 1 deg."""
    import pandas as pd

    from threadmate.design._envelope import _result, _Search

    grid = PolarGrid.parse("0,1", "0", f"0:{360 - 360 / phases}:{360 / phases}")
    assert len(grid.phase) == phases
    search = _Search(grid.tilt, tolerance=1.0)
    for size in (0.0, 1.0):
        snapped = [size == 0.0] * phases
        search.outcomes[search.key(size, 0.0)] = pd.DataFrame(
            {
                "snapped": snapped,
                "failed": [False] * phases,
                "turn": [90.0] * phases,
                "work": [1.0] * phases,
                "click": [1e-3] * phases,
                "torque_peak": [1e-3] * phases,
            }
        )
    env = _result(
        search,
        [0.0],
        spec_from_designation("1/4-20 UNC-2A/2B"),
        Compliance(),
        grid,
        "test",
        2,
        0.0,
    )
    assert any("95 % level asks every phase" in n for n in env.notes) == noted


def test_the_bisection_brackets_each_level_within_the_tolerance():
    """The search along a direction, on a known share of snapping phases (a step profile:
    every phase up to 1.23 deg, 60 % up to 2.61 deg, none beyond), brackets the 100 % and
    50 % crossings within the tolerance and puts the 95 % one with the 100 % one."""
    import pandas as pd

    from threadmate.design._envelope import _Search

    def outcomes(size: float) -> pd.DataFrame:
        n = 20
        share = 1.0 if size <= 1.23 else (0.6 if size <= 2.61 else 0.0)
        snapped = [i < round(share * n) for i in range(n)]
        return pd.DataFrame({"snapped": snapped, "failed": [False] * n})

    grid = PolarGrid.parse("0:4:0.5", "0,90", "0")
    search = _Search(grid.tilt, tolerance=0.05)
    probes = 0
    while True:
        wanted = {search.key(s, d) for d in (0.0, 90.0) for s in search.needed(d)}
        wanted -= set(search.outcomes)
        if not wanted:
            break
        for key in wanted:
            search.outcomes[key] = outcomes(key[0])
            probes += 1
    for d in (0.0, 90.0):
        known = search.evaluated(d)
        for level, edge in ((1.0, 1.23), (0.95, 1.23), (0.5, 2.61)):
            lo, hi = search.bracket(known, level)
            assert lo <= edge < hi and hi - lo <= 0.05 + 1e-12, (d, level, lo, hi)
        # Walked no further out than the first size where fewer than half snap.
        assert max(s for s, _ in known) == 3.0
    assert probes < 2 * 20


@pytest.mark.parametrize("floor", [0.0, 0.5, 1.0, 1.2, 1.25, 1.3, 1.5, 2.0, 3.0])
def test_a_floor_stops_the_search_once_the_envelope_is_known_below_it(floor):
    """With a floor, the search stops as soon as some direction fails at a size no larger
    than it, and only then: the envelope located whole lies at or below the floor exactly
    when the search stops, and above it the search asks every held tilt it asks without
    one. The profile is made up, as above (every phase snaps up to 1.23 deg in direction
    0, up to 2.61 in direction 90); upright failing, one held tilt settles it."""
    import pandas as pd

    from threadmate.design._envelope import _Search

    edge = {0.0: 1.23, 90.0: 2.61}

    def outcomes(size: float, d: float | None, upright_fails: bool) -> pd.DataFrame:
        snaps = not upright_fails and (d is None or size <= edge[d])
        return pd.DataFrame({"snapped": [snaps] * 4, "failed": [False] * 4})

    grid = PolarGrid.parse("0:4:0.5", "0,90", "0")

    def located(with_floor, upright_fails=False):
        search = _Search(grid.tilt, tolerance=0.05, upright_alone=with_floor)
        while not (with_floor and search.at_most((0.0, 90.0), floor)):
            wanted = {search.key(s, d) for d in (0.0, 90.0) for s in search.needed(d)}
            wanted -= set(search.outcomes)
            if not wanted:
                break
            for key in wanted:
                search.outcomes[key] = outcomes(*key, upright_fails)
        return search

    def tolerated(search):
        return min(search.bracket(search.evaluated(d), 1.0)[0] for d in (0.0, 90.0))

    whole, floored = located(False), located(True)
    stopped = floored.at_most((0.0, 90.0), floor)
    assert stopped == (tolerated(whole) <= floor)
    if stopped:
        assert tolerated(floored) <= floor and len(floored.outcomes) <= len(whole.outcomes)
    else:
        assert floored.outcomes.keys() == whole.outcomes.keys()
    failing = located(True, upright_fails=True)
    assert list(failing.outcomes) == [(0.0, None)] and tolerated(failing) == 0.0
