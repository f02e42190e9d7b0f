"""The shared validation (threadmate._validate) and JSON conversion (threadmate._json)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from threadmate import InputError, SpecError

# The shared rules: internals with no public form.
from threadmate._json import json_text, to_jsonable
from threadmate._validate import (
    MAX_LENGTH,
    MIN_LENGTH,
    check_length,
    check_number,
    check_range,
)


@pytest.mark.parametrize("value", [True, "1", None, [1.0], complex(1, 0)])
def test_check_number_refuses_non_numbers(value):
    with pytest.raises(InputError, match="--x must be a number"):
        check_number("--x", value)


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, np.float32("nan")])
def test_check_number_refuses_non_finite(value):
    with pytest.raises(InputError, match="--x must be a finite number"):
        check_number("--x", value)


def test_check_number_accepts_numpy_scalars():
    assert check_number("x", np.float32(0.5)) == 0.5
    assert check_number("x", np.int64(3)) == 3.0
    assert type(check_number("x", np.int64(3))) is float


def test_check_range_names_the_range_and_the_error_class():
    assert check_range("--k", 5, 1, 10) == 5.0
    with pytest.raises(
        SpecError,
        match=r"spec key 'starts' is out of range: 17; give a "
        r"value from 1 to 16",
    ):
        check_range("spec key 'starts'", 17, 1, 16, error=SpecError)


def test_check_length_for_compliance_z():
    # The check the command line uses for --compliance-z: a signed, finite coordinate.
    assert check_length("--compliance-z", -0.5, "in", signed=True) == -0.5
    assert check_length("--compliance-z", 0, "in", signed=True) == 0.0
    with pytest.raises(InputError) as exc:
        check_length("--compliance-z", 1e308, "mm", signed=True)
    assert str(exc.value) == (
        "--compliance-z is out of range: 1e+308 mm; give a value from "
        f"{-MAX_LENGTH:g} to {MAX_LENGTH:g} mm"
    )


def test_check_length_sizes():
    assert check_length("p", MIN_LENGTH, "in") == MIN_LENGTH
    assert check_length("f", 0, "in", zero_ok=True) == 0.0
    assert check_length("f", 1e-9, "in", zero_ok=True) == 1e-9
    for value in (0, -1.0, MIN_LENGTH / 2, MAX_LENGTH * 2):
        with pytest.raises(InputError, match="'p'"):
            check_length("'p'", value, "in")
    with pytest.raises(InputError, match="0 or a positive length"):
        check_length("f", -1e-9, "in", zero_ok=True)


def test_to_jsonable_converts_numpy_and_friends():
    doc = {
        1: np.float64(0.5),
        "a": np.array([[1, 2]]),
        "b": (np.bool_(True), np.int32(3)),
        "c": [np.float32(np.inf), math.nan],
        "d": Path("x/y"),
        "e": {"z", "a"},
    }
    plain = to_jsonable(doc)
    assert plain == {
        "1": 0.5,
        "a": [[1, 2]],
        "b": [True, 3],
        "c": [None, None],
        "d": "x/y",
        "e": ["a", "z"],
    }
    assert type(plain["b"][0]) is bool and type(plain["b"][1]) is int
    assert json.loads(json_text(doc)) == plain
    assert json_text({"x": 1}, indent=None) == '{"x": 1}\n'


@pytest.mark.parametrize(
    ("array", "text"),
    [
        (np.array([1.5, -2.0]), "[1.5, -2.0]"),
        (np.array([[1, 2], [3, 4]], dtype=np.int32), "[[1, 2], [3, 4]]"),
        (np.array([True, False]), "[true, false]"),
        (np.array(["+F", "root"]), '["+F", "root"]'),
        (np.array([1.0, np.nan, -np.inf]), "[1.0, null, null]"),
        (np.array([np.float64(0.25), "a"], dtype=object), '[0.25, "a"]'),
    ],
)
def test_json_text_of_an_array(array, text):
    """An array's JSON text, written out by hand: numbers, booleans and strings as JSON
    has them, a NaN or an infinity as null, whatever the dtype."""
    assert json_text(array, None, end="") == text
