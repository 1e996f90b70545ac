"""The directions of a pose part without Blender: which side of an object each way of setting it
names, the side captured from a rotation, the angle an object is from it, and the cone drawn for
its tolerance."""
import math

import numpy as np
import pytest

from many_worlds.core import pose_target


def rotation_about(axis, degrees):
    """3x3 rotation matrix (object to world) about a unit axis."""
    x, y, z = axis
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + s * k + (1 - c) * k @ k


def test_each_way_of_setting_a_pose_names_an_axis_and_a_direction():
    assert pose_target.directions("UPRIGHT") == ((0, 0, 1), (0, 0, 1))
    assert pose_target.directions("AXIS", "NEG_Y", "POS_X") == ((0, -1, 0), (1, 0, 0))
    assert pose_target.directions("AS_POSED", captured=(0.0, 1.0, 0.0)) == ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    # Nothing captured yet: no part to query.
    assert pose_target.directions("AS_POSED") is None
    assert pose_target.describe("AXIS", "NEG_Y", "POS_X") == ("local -Y", "+X")
    assert pose_target.describe("AS_POSED", captured=(0.0, -1.0, -0.0)) == ("captured side (0.00, -1.00, 0.00)", "up")


def test_the_captured_side_is_the_one_facing_up_and_is_then_zero_degrees_away():
    # Turned 90° about X, an object faces up with its local +Y.
    rotation = rotation_about((1, 0, 0), 90)
    side = pose_target.captured_axis(rotation)
    np.testing.assert_allclose(side, (0, 1, 0), atol=1e-12)
    assert pose_target.angle_deg(rotation, side, pose_target.UP) == pytest.approx(0, abs=1e-6)
    # Any rotation: R·(R⁻¹·up) is up.
    rotation = rotation_about(np.array((1, 2, 3)) / math.sqrt(14), 73)
    assert pose_target.angle_deg(rotation, pose_target.captured_axis(rotation), (0, 0, 2)) == pytest.approx(0, abs=1e-6)
    # Lying on its side, an upright part is 90° off; upside down, 180°.
    assert pose_target.angle_deg(rotation_about((0, 1, 0), 90), (0, 0, 1), (0, 0, 1)) == pytest.approx(90)
    assert pose_target.angle_deg(rotation_about((1, 0, 0), 180), (0, 0, 1), (0, 0, 1)) == pytest.approx(180)


def test_the_cone_of_a_tolerance_opens_by_that_angle_around_its_direction():
    origin, target = np.array((1.0, 2.0, 3.0)), (0.0, 0.0, 2.0)
    points = pose_target.cone_segments(origin, target, 30, 0.5, circle_segments=16, generators=4)
    assert points.shape == (2 * (1 + 16 + 4), 3)
    np.testing.assert_allclose(points[:2], [origin, origin + (0, 0, 0.5)])
    # Every point of the circle and every line from the apex: 0.5 from the apex, 30° off the direction.
    rim = points[2:]
    rim = rim[np.linalg.norm(rim - origin, axis=1) > 1e-9] - origin
    np.testing.assert_allclose(np.linalg.norm(rim, axis=1), 0.5)
    np.testing.assert_allclose(np.degrees(np.arccos(rim[:, 2] / 0.5)), 30)
