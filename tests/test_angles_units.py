"""The shared rules of angles, units and class names, against values worked by hand, and
the cross product of two vectors against numpy's."""

import math

import numpy as np
import pytest

# The shared rules: internals with no public form.
from threadmate._angles import SQRT3, TWO_PI, Z_AXIS, axis_angle, phase_difference, wrap_phase
from threadmate._units import METRES_PER_UNIT, MJ_PER_J, MM_PER_UNIT, to_metres, unit_scale
from threadmate.contact import (
    CLASSIFICATIONS,
    ERROR_CLASS,
    REST_CLASSES,
    TRANSITION_LABELS,
)
from threadmate.library import CLASS_ORDER


def test_wrap_phase_takes_a_phase_into_one_turn():
    assert wrap_phase(-90.0) == 270.0
    assert wrap_phase(725.0) == 5.0
    assert wrap_phase(360.0) == 0.0
    assert wrap_phase(-0.5 * math.pi, TWO_PI) == pytest.approx(1.5 * math.pi)
    np.testing.assert_array_equal(wrap_phase(np.array([-10.0, 370.0])), [350.0, 10.0])


def test_phase_difference_is_the_shorter_way_round():
    assert phase_difference(10.0, 350.0) == 20.0
    assert phase_difference(350.0, 10.0) == -20.0
    assert phase_difference(180.0, 0.0) == -180.0  # the half-open range [-180, 180)
    assert phase_difference(540.0) == -180.0
    assert phase_difference(0.1, -0.1, TWO_PI) == pytest.approx(0.2)
    np.testing.assert_allclose(phase_difference(np.array([0.0, 90.0]), 300.0), [60.0, 150.0])


def test_axis_angle_between_unit_axes():
    tilted = np.array([math.sin(math.radians(30.0)), 0.0, math.cos(math.radians(30.0))])
    assert axis_angle(tilted, Z_AXIS) == pytest.approx(30.0)
    assert axis_angle(-Z_AXIS, Z_AXIS) == 180.0
    assert axis_angle(Z_AXIS * (1.0 + 1e-15), Z_AXIS) == 0.0  # rounding past 1 is clipped
    with pytest.raises(ValueError):
        Z_AXIS[0] = 1.0  # read-only


def test_constants():
    assert TWO_PI == math.tau
    assert SQRT3 == pytest.approx(1.0 / math.tan(math.radians(30.0)))


def test_length_units_and_energy():
    assert MM_PER_UNIT == {"in": 25.4, "mm": 1.0}
    assert METRES_PER_UNIT == {"in": 0.0254, "mm": 0.001}
    assert unit_scale("in", "mm") == 25.4 and unit_scale("mm", "mm") == 1.0
    assert unit_scale("mm", "in") == pytest.approx(1.0 / 25.4)
    assert to_metres(2.0, "in") == pytest.approx(0.0508)
    assert MJ_PER_J * 0.25 == 250.0


def test_class_names_declared_once():
    assert REST_CLASSES == ("stable", "quasi-stable", "unstable", "in-phase")
    assert CLASSIFICATIONS == ("stable", "quasi-stable", "unstable", "in-phase", "no-contact")
    assert TRANSITION_LABELS == ("stable", "quasi-stable", "unstable")
    assert ERROR_CLASS == "error"
    assert CLASS_ORDER == ("unstable", "quasi-stable", "stable", "in-phase", "no-contact", "error")


def test_the_cross_product_of_two_vectors_is_numpys_to_the_last_bit():
    from threadmate._vectors import cross3

    rng = np.random.default_rng(11)
    for _ in range(20000):
        a = rng.normal(size=3) * 10 ** rng.uniform(-6, 3)
        b = rng.normal(size=3) * 10 ** rng.uniform(-6, 3)
        assert np.array_equal(cross3(a, b), np.cross(a, b))
