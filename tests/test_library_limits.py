"""Absurd grids and steps: counted before anything is allocated or written, refused past
the stated limits with the count, the time it would take and how to raise the limit."""

from __future__ import annotations

import re
import time

import pytest

from _cli import refused
from threadmate import InputError, library

# The limits are internals with no public form (threadmate._validate owns them).
from threadmate._validate import (
    MAX_AXIS_VALUES,
    MAX_SEARCH_STEPS,
    MAX_STARTS,
    MAX_STARTS_CEILING,
    SWEEP_RATE,
)

DESIGNATION = "1/4-20 UNC-2A/2B"


def test_the_limits_are_the_stated_ones():
    # docs/network.md, "Cost and scale", states them.
    assert MAX_AXIS_VALUES == 100_000
    assert MAX_STARTS == 100_000 and MAX_STARTS_CEILING == 10_000_000
    assert MAX_SEARCH_STEPS == 36_000


def test_ten_million_rolls_are_refused_before_a_value_is_made(tmp_path, capsys):
    t0 = time.perf_counter()
    line = refused(capsys, "sweep", DESIGNATION, "--roll", "0:1:0.0000001", "-o", tmp_path / "lib")
    # 1 / 1e-7 steps and the stop: 10,000,001 values.
    assert "--roll: '0:1:0.0000001' gives 10,000,001 values" in line
    assert f"more than the {MAX_AXIS_VALUES:,}" in line
    assert time.perf_counter() - t0 < 5.0
    assert not (tmp_path / "lib").exists()


def test_a_sequence_of_too_many_distinct_values_isrefused():
    values = [i * 1e-4 for i in range(MAX_AXIS_VALUES + 1)]  # 0 .. 10 deg by 1e-4
    with pytest.raises(InputError, match="^roll: 100,001 values, more than the 100,000"):
        library.parse_range(values, "roll")
    assert len(library.parse_range(values[:-1], "roll")) == MAX_AXIS_VALUES


@pytest.mark.parametrize(
    ("roll", "pitch", "phase", "count"),
    [
        # 10,001 x 1 x 72 = 720,072: past the default limit, within the ceiling.
        ("0:1:0.0001", "0", None, 720_072),
        # 801 x 801 x 35,501 = 22,777,477,101: past the ceiling (a MemoryError before).
        ("-4:4:0.01", "-4:4:0.01", "0:355:0.01", 801 * 801 * 35_501),
        # 801 x 801 x 72 = 46,195,272 (started with no word before).
        ("-4:4:0.01", "-4:4:0.01", None, 46_195_272),
    ],
)
def test_too_many_starts_are_refused_with_the_count_and_the_time(
    tmp_path, capsys, roll, pitch, phase, count
):
    args = ["sweep", DESIGNATION, "--roll", roll, "--pitch", pitch, "--workers", "2"]
    args += ["--phase", phase] if phase else []
    t0 = time.perf_counter()
    line = refused(capsys, *args, "-o", tmp_path / "lib")
    assert time.perf_counter() - t0 < 5.0
    assert f"has {count:,} configurations" in line
    # The estimate at the stated rate on the 2 workers asked for.
    seconds = count / (SWEEP_RATE["mechanics"] * 2)
    match = re.search(r"that is about ([0-9.e+]+) (\w+) on 2 worker\(s\)", line)
    assert match, line
    unit = {"s": 1, "min": 60, "h": 3600, "days": 86400, "years": 365.25 * 86400}
    assert float(match.group(1)) * unit[match.group(2)] == pytest.approx(seconds, rel=0.01)
    if count > MAX_STARTS_CEILING:
        assert f"a library holds at most {MAX_STARTS_CEILING:,} starts" in line
    else:
        assert f"past the limit of {MAX_STARTS:,} starts" in line
        assert f"pass --max-starts {count} to run it" in line
    assert not (tmp_path / "lib").exists()


def test_max_starts_raises_and_lowers_the_limit(tmp_path, quarter_20, capsys):
    # roll 0, pitch 0, phases 0 and 180: two configurations.
    with pytest.raises(InputError, match="has 2 configurations.*past the limit of 1 starts"):
        library.sweep(quarter_20, "0", "0", "0:180:180", out=tmp_path / "a", max_starts=1)
    assert not (tmp_path / "a").exists()
    with pytest.raises(InputError, match="^max_starts must be a whole number from 1 to"):
        library.sweep(quarter_20, "0", "0", "0", out=tmp_path / "a", max_starts=10**8)
    line = refused(
        capsys,
        "sweep",
        DESIGNATION,
        "--model",
        "thesis",
        "--roll",
        "0",
        "--pitch",
        "0",
        "--phase",
        "0:180:180",
        "--max-starts",
        "1",
        "-o",
        tmp_path / "b",
    )
    assert "thesis model" in line and f"{SWEEP_RATE['thesis']:g} per second" in line
    lib = library.sweep(
        quarter_20, "0", "0", "0:180:180", out=tmp_path / "c", model="thesis", max_starts=2
    )
    assert library.info(lib)["complete"]


@pytest.mark.parametrize("command", ["search", "screw"])
def test_a_search_step_too_fine_is_refused_with_its_count(capsys, command):
    base = [command, DESIGNATION, "--roll", "0", "--pitch", "0", "--phase", "0"]
    t0 = time.perf_counter()
    line = refused(capsys, *base, "--step", "1e-9")
    assert time.perf_counter() - t0 < 5.0
    # One turn by 1e-9 deg: 360e9 steps.
    assert "--step 1e-09 deg over 1 turn(s) is 360,000,000,000 continuation steps" in line
    assert "give --step 0.01 or coarser" in line
    # Two turns by 0.01 deg: 72,000 steps; one turn by 0.01 is the most a search takes.
    line = refused(capsys, *base, "--step", "0.01", "--turns", "2")
    assert "72,000 continuation steps" in line and "--step 0.02" in line


def test_a_sweep_step_too_fine_is_refused_before_anything_is_written(tmp_path, quarter_20):
    with pytest.raises(InputError, match="360,000,000,000 continuation steps"):
        library.sweep(
            quarter_20, "0", "0", "0", out=tmp_path / "lib", step=1e-9, phase_tolerance=1e-9
        )
    assert not (tmp_path / "lib").exists()
