"""The sweep grid: range parsing, phase wrapping, configuration order (hand-written cases)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from threadmate import InputError
from threadmate.library import DEFAULT_GRID, Grid, parse_range


def test_closed_range_includes_stop_on_the_grid():
    assert parse_range("-4:4:1", "roll") == (-4.0, -3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0)
    # STOP off the grid is not added: 0, 3, 6 (9 would pass 7).
    assert parse_range("0:7:3", "pitch") == (0.0, 3.0, 6.0)


def test_fractional_steps_are_counted_not_accumulated():
    # Adding 0.1 ten times gives 0.9999999999999999; counting steps keeps 1.0 and 0.3.
    values = parse_range("0:1:0.1", "roll")
    assert len(values) == 11
    assert values[3] == 0.3 and values[-1] == 1.0
    assert parse_range("-1:1:0.5", "pitch") == (-1.0, -0.5, 0.0, 0.5, 1.0)


def test_phases_wrap_modulo_360_and_repeats_drop():
    phases = parse_range("0:360:5", "phase")
    assert len(phases) == 72
    assert phases[0] == 0.0 and phases[-1] == 355.0
    assert parse_range("350:370:5", "phase") == (0.0, 5.0, 10.0, 350.0, 355.0)
    assert parse_range("-90", "phase") == (270.0,)
    assert parse_range("0,360,720,90", "phase") == (0.0, 90.0)


def test_single_values_and_comma_lists():
    assert parse_range("2.5", "roll") == (2.5,)
    assert parse_range("3, -1, 3, 0:1:1", "pitch") == (-1.0, 0.0, 1.0, 3.0)
    assert parse_range(-0.0, "roll") == (0.0,)
    assert parse_range([4, -4, 0], "roll") == (-4.0, 0.0, 4.0)


@pytest.mark.parametrize(
    ("text", "option", "words"),
    [
        ("0:4:0", "roll", "step 0"),
        ("0:4:-1", "pitch", "step -1"),
        ("4:0:1", "roll", "below start"),
        ("a", "phase", "'a' is not a number"),
        ("0:x:1", "roll", "'x' is not a number"),
        ("1:2", "pitch", "START:STOP:STEP"),
        ("", "roll", "no values"),
        ("1,,2", "roll", "empty item"),
        ("0:50:5", "roll", "out of range"),
        ("-46", "pitch", "out of range"),
        ("nan", "phase", "not a finite angle"),
        ("0:1:1e-7", "roll", "gives 10,000,001 values, more than the 100,000"),
        ("0:1:0.1,0:10:0.0001", "pitch", "gives 100,001 values"),
        ("0:180:0.002,180:359:0.002", "phase", "179,501 values, more than the 100,000"),
    ],
)
def test_bad_ranges_name_the_angle(text, option, words):
    with pytest.raises(InputError) as err:
        parse_range(text, option)
    # The API's name of the angle, first (the command line makes it its option's).
    assert str(err.value).startswith(option) and "--" not in str(err.value)
    assert words in str(err.value)


def test_default_grid_is_the_thesis_grid():
    assert DEFAULT_GRID.shape == (9, 9, 72)
    assert DEFAULT_GRID.size == 5832
    assert DEFAULT_GRID.roll == tuple(float(v) for v in range(-4, 5))
    assert DEFAULT_GRID.phase == tuple(float(v) for v in range(0, 360, 5))
    assert Grid.parse() == DEFAULT_GRID


def test_config_ids_are_roll_major_phase_fastest():
    grid = Grid.parse("-1:1:1", "0,2", "0:270:90")
    # The documented order, written out by brute force.
    expected = list(itertools.product(grid.roll, grid.pitch, grid.phase))
    assert grid.size == len(expected) == 24
    assert [grid.configuration(i) for i in range(grid.size)] == expected
    assert np.array_equal(grid.configurations(range(grid.size)), np.array(expected))
    assert grid.config_id(2, 1, 3) == 23
    assert grid.configuration(23) == (1.0, 2.0, 270.0)
    with pytest.raises(InputError):
        grid.configuration(24)


def test_nearest_configuration_snaps_each_angle():
    grid = Grid.parse("-4:4:1", "-4:4:1", "0:355:5")
    cid, values = grid.nearest(0.4, -3.6, 358.0)  # phase 358 is nearer 0 than 355
    assert values == (0.0, -4.0, 0.0)
    assert cid == grid.config_id(4, 0, 0)
    _, values = grid.nearest(9.0, 0.0, -2.0)  # beyond the grid: the edge value
    assert values == (4.0, 0.0, 0.0)


def test_grid_round_trips_through_its_mapping():
    grid = Grid.parse("-2:2:0.5", "1", "10,20,200")
    assert Grid.from_dict(grid.to_dict()) == grid
    assert grid.to_dict()["size"] == 9 * 1 * 3


def test_an_angle_holds_at_most_a_hundred_thousand_values():
    # 0 .. 9.9999 by 1e-4: 99,999 steps and the start, exactly the limit.
    assert len(parse_range("0:9.9999:0.0001", "roll")) == 100_000
    grid = Grid.parse("0", "0:9.9999:0.0001", "0")
    assert grid.size == 100_000
    assert grid.describe(size=False) == "roll 0 x pitch 0..9.9999 (100000) x phase 0"
    assert grid.describe() == "roll 0 x pitch 0..9.9999 (100000) x phase 0 = 100000 configurations"
