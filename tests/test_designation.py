"""Designation parsing: accepted forms, defaults, canonical text, and clear refusals."""

from __future__ import annotations

import re

import pytest

from threadmate import DesignationError, InputError
from threadmate.geometry import (
    MATERIAL_CONDITIONS,
    Designation,
    ThreadLimits,
    parse_designation,
    spec_from_designation,
    thread_limits,
)


@pytest.mark.parametrize(
    ("text", "canonical", "major", "tpi"),
    [
        ("1/4-20 UNC-2A/2B", "1/4-20 UNC-2A/2B", 0.25, 20),
        ("1/4-20 UNC-2A", "1/4-20 UNC-2A/2B", 0.25, 20),
        ("1/4-20 UNC", "1/4-20 UNC-2A/2B", 0.25, 20),
        ("1/4-20 UNC-2B", "1/4-20 UNC-2A/2B", 0.25, 20),
        ("1/4-20 UNC-3B/3A", "1/4-20 UNC-3A/3B", 0.25, 20),
        ("1/4-20 UNC-3A/2B", "1/4-20 UNC-3A/2B", 0.25, 20),
        ("#10-24 UNC", "#10-24 UNC-2A/2B", 0.19, 24),
        ("10-24 UNC", "#10-24 UNC-2A/2B", 0.19, 24),
        ("# 10 - 24 unc", "#10-24 UNC-2A/2B", 0.19, 24),
        ("0.250-20 UNC-2A", "1/4-20 UNC-2A/2B", 0.25, 20),
        ("0.19-32 UNF", "#10-32 UNF-2A/2B", 0.19, 32),
        ("1/2-13 UNC-2A/2B LH", "1/2-13 UNC-2A/2B LH", 0.5, 13),
        ("1/2-13 unc-2a/2b-lh", "1/2-13 UNC-2A/2B LH", 0.5, 13),
        ("  1/4 - 20   UNC - 2A / 2B ", "1/4-20 UNC-2A/2B", 0.25, 20),
        ("1-8 UNC", "1-8 UNC-2A/2B", 1.0, 8),
        ("1 1/4-7 UNC", "1 1/4-7 UNC-2A/2B", 1.25, 7),
        ("1-1/4-7 UNC-3A", "1 1/4-7 UNC-3A/3B", 1.25, 7),
        ("2-4.5 UNC", "2-4.5 UNC-2A/2B", 2.0, 4.5),
        ("#0-80 UNF-3A/3B", "#0-80 UNF-3A/3B", 0.06, 80),
        ("5-40 UNC", "#5-40 UNC-2A/2B", 0.125, 40),
        ("1/2-28 UN-2A", "1/2-28 UN-2A/2B", 0.5, 28),
        ("2-12 UN", "2-12 UN-2A/2B", 2.0, 12),
        ("1/4-20 UNRC-2A/2B", "1/4-20 UNRC-2A/2B", 0.25, 20),
        ("19/64-36 UNS", "19/64-36 UNS-2A/2B", 19 / 64, 36),
        ("7/16-28 UNEF-3A", "7/16-28 UNEF-3A/3B", 0.4375, 28),
    ],
)
def test_unified_forms(text, canonical, major, tpi):
    des = parse_designation(text)
    assert isinstance(des, Designation)
    assert des.text == canonical == str(des)
    assert des.system == "unified" and des.units == "in"
    assert des.major == pytest.approx(major)
    assert des.tpi == tpi and des.pitch == pytest.approx(1 / tpi)
    assert des.hand == ("left" if "LH" in canonical else "right")
    # The canonical text parses to itself.
    assert parse_designation(des.text) == des


@pytest.mark.parametrize(
    ("text", "canonical", "major", "pitch"),
    [
        ("M6x1-6g/6H", "M6x1-6g/6H", 6, 1.0),
        ("M6x1", "M6x1-6g/6H", 6, 1.0),
        ("M6", "M6x1-6g/6H", 6, 1.0),
        ("M8", "M8x1.25-6g/6H", 8, 1.25),
        ("M10x1.25-6g", "M10x1.25-6g/6H", 10, 1.25),
        ("M10x1.25-6H", "M10x1.25-6g/6H", 10, 1.25),
        ("M6x1-6g/6H-LH", "M6x1-6g/6H-LH", 6, 1.0),
        ("M6x1 LH", "M6x1-6g/6H-LH", 6, 1.0),
        ("m8 lh", "M8x1.25-6g/6H-LH", 8, 1.25),
        ("M 6 x 1 - 6g / 6H", "M6x1-6g/6H", 6, 1.0),
        ("M6X1-6G/6H", "M6x1-6g/6H", 6, 1.0),  # all capitals: first class is the bolt's
        ("M6x1-6H/6g", "M6x1-6g/6H", 6, 1.0),
        ("M6x1-5g6g/6H", "M6x1-5g6g/6H", 6, 1.0),
        ("M6x1-6e/6G", "M6x1-6e/6G", 6, 1.0),
        ("M20x1.5-4h/5H", "M20x1.5-4h/5H", 20, 1.5),
        ("M1.6", "M1.6x0.35-6g/6H", 1.6, 0.35),
        ("M64", "M64x6-6g/6H", 64, 6.0),
        ("M1.2", "M1.2x0.25-6h/5H", 1.2, 0.25),  # ISO 965-1 default up to M1.4
        ("M1x0.2", "M1x0.2-6h/4H", 1.0, 0.2),  # only grade 4 is tabulated for the nut
    ],
)
def test_iso_forms(text, canonical, major, pitch):
    des = parse_designation(text)
    assert des.text == canonical
    assert des.system == "iso" and des.units == "mm" and des.series == "M"
    assert des.major == pytest.approx(major) and des.pitch == pytest.approx(pitch)
    assert parse_designation(des.text) == des


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "empty"),
        ("hello", "cannot read"),
        ("1/4-21 UNC", "21 threads per inch is not in the UNC series"),
        ("1/4-20 UNEF", "not in the UNEF series"),
        ("1/4-20 UNX", "unknown thread series 'UNX'"),
        ("1/4-20", "names no series"),
        ("3/16-24 UNC", "unknown size '3/16'"),
        ("#13-24 UNC", "unknown numbered size '#13'"),
        ("9-4 UN", "too coarse"),
        ("13-4 UN", "ASME B1.1 covers 0.060 to 6 in"),
        ("1/4-20 UNC-4A", "unknown thread class '4A'"),
        ("1/4-20 UNC-2C", "unknown thread class '2C'"),
        ("1/4-20 UNC-2A/3A", "two external classes"),
        ("1/4-20 UNC-2A/2B XYZ", "class part"),
        ("1/4-18 UN-2A", "not a UN constant-pitch series"),
        ("1/2-28 UNEF-1A", "classes 1A and 1B apply only"),
        ("M7.5", "unknown ISO 261 size 'M7.5'"),
        ("M6x0.9", "pitch 0.9 is not an ISO 261 pitch for M6"),
        ("M6x1.25", "not an ISO 261 pitch"),
        ("M5.5", "no coarse pitch"),
        ("M6x1-6k", "unknown tolerance position 'k'"),
        ("M6x1-6g/6g", "two external tolerance classes"),
        ("M6x1-5g", "no external major-diameter (Td) tolerance grade 5"),
        ("M6x1-6g/9H", "no internal pitch-diameter tolerance grade 9"),
        ("M1.6-6e", "no fundamental deviation 'e'"),
        ("M6x1-6g6h", "mixes positions"),
        ("M6x1-6g/6H-XX", "tolerance part"),
        ("M100", "unknown ISO 261 size"),
    ],
)
def test_bad_designations_name_the_problem(text, message):
    with pytest.raises(DesignationError, match=re.escape(message)):
        parse_designation(text)
    # The same refusal comes from every entry point, and it is an InputError (exit 2).
    with pytest.raises(InputError):
        spec_from_designation(text)


def test_non_text_is_refused():
    with pytest.raises(DesignationError, match="must be text"):
        parse_designation(0.25)  # type: ignore[arg-type]


def test_limits_object():
    lim = thread_limits(parse_designation("1/4-20 UNC"))
    assert isinstance(lim, ThreadLimits)
    assert lim.designation == "1/4-20 UNC-2A/2B" and lim.units == "in"
    assert lim.bolt.tolerance_class == "2A" and lim.nut.tolerance_class == "2B"
    doc = lim.to_dict()
    assert doc["bolt"]["major"] == [0.2408, 0.2489]
    assert set(doc["nut"]) >= {"major", "pitch_diameter", "minor"}
    # Frozen dataclass.
    with pytest.raises(AttributeError):
        lim.pitch = 1.0  # type: ignore[misc]


@pytest.mark.parametrize(
    ("alias", "expected"),
    [
        ("max", "max"),
        ("maximum", "max"),
        ("MMC", "max"),
        ("min", "min"),
        ("Minimum", "min"),
        ("lmc", "min"),
        ("mean", "mean"),
    ],
)
def test_condition_aliases(alias, expected):
    assert expected in MATERIAL_CONDITIONS
    got = spec_from_designation("M6", alias)
    want = spec_from_designation("M6", expected)
    assert got == want


def test_unknown_condition_is_refused():
    with pytest.raises(InputError, match="unknown material condition 'nominal'"):
        spec_from_designation("M6", "nominal")


def test_conditions_order_the_fit():
    # Maximum material leaves the least axial clearance, minimum material the most; the
    # mean lies halfway (every diameter is the midpoint of its limits).
    specs = {c: spec_from_designation("3/8-16 UNC-2A/2B", c) for c in ("max", "mean", "min")}
    clearance = {c: s.axial_clearance for c, s in specs.items()}
    assert clearance["max"] < clearance["mean"] < clearance["min"]
    assert clearance["mean"] == pytest.approx((clearance["max"] + clearance["min"]) / 2)
    assert specs["max"].bolt.major > specs["min"].bolt.major
    assert specs["max"].nut.minor < specs["min"].nut.minor


def test_left_hand_designation_gives_left_hand_spec():
    spec = spec_from_designation("1/2-13 UNC-2A/2B LH")
    assert spec.hand == "left" and spec.designation == "1/2-13 UNC-2A/2B LH"
    assert spec_from_designation("1/2-13 UNC-2A/2B").hand == "right"
