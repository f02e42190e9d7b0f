"""Frames and poses against hand-computed rotations (conventions.md, "Frames")."""

from __future__ import annotations

import numpy as np
import pytest

from threadmate.geometry import Pose, bolt_rotation, rot_x, rot_y, rot_z


def test_elementary_rotations_are_active_right_handed():
    # +90 about Z carries +X to +Y: counter-clockwise seen from +Z.
    np.testing.assert_allclose(rot_z(90) @ [1, 0, 0], [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(rot_x(90) @ [0, 1, 0], [0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(rot_y(90) @ [0, 0, 1], [1, 0, 0], atol=1e-15)


def test_bolt_rotation_keeps_tilt_fixed_while_phase_turns():
    # The bolt axis depends on roll and pitch only: phase spins the bolt about its own axis.
    roll, pitch = 3.0, -2.0
    axes = [bolt_rotation(roll, pitch, ph)[:, 2] for ph in (0, 37, 180, 311)]
    for a in axes[1:]:
        np.testing.assert_allclose(a, axes[0], atol=1e-15)
    # Closed form of Rx(a) Ry(b) e_z.
    a, b = np.radians(roll), np.radians(pitch)
    np.testing.assert_allclose(
        axes[0], [np.sin(b), -np.sin(a) * np.cos(b), np.cos(a) * np.cos(b)], atol=1e-15
    )


def test_pose_maps_and_inverts():
    pose = Pose.from_angles(4.0, -3.0, 123.0, h=0.01, x=0.002, y=-0.001)
    pts = np.random.default_rng(1).normal(size=(20, 3))
    np.testing.assert_allclose(pose.to_bolt(pose.to_fixed(pts)), pts, atol=1e-14)
    np.testing.assert_allclose(pose.to_fixed([0, 0, 0]), [0.002, -0.001, 0.01])
    assert pose.angles() == pytest.approx((4.0, -3.0, 123.0))


def test_rotation_about_a_line_fixes_the_line():
    pose = Pose.from_angles(1.0, 2.0, 30.0, h=0.05)
    point = np.array([0.1, 0.05, 0.0])
    axis = np.array([0.3, -0.2, 0.1])
    turned = pose.rotated_about(point, axis, 7.5)
    # Points on the line stay put; the turn angle between the bolt axes is at most 7.5 deg.
    on_line = point + 0.37 * axis
    np.testing.assert_allclose(turned.to_fixed(pose.to_bolt(on_line)), on_line, atol=1e-14)
    cosang = np.clip(pose.axis @ turned.axis, -1, 1)
    assert np.degrees(np.arccos(cosang)) <= 7.5 + 1e-9


def test_axis_angle_rotation_matches_scipy():
    from scipy.spatial.transform import Rotation

    from threadmate.geometry import axis_angle_rotation

    rng = np.random.default_rng(0)
    for _ in range(50):
        axis, deg = rng.normal(size=3), rng.uniform(-400, 400)
        ref = Rotation.from_rotvec(axis / np.linalg.norm(axis) * np.radians(deg)).as_matrix()
        np.testing.assert_allclose(axis_angle_rotation(axis, deg), ref, atol=1e-14)
