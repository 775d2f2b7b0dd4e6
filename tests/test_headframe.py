import numpy as np
import pytest

from beeoptics.headframe import eye_azimuth_elevation, eye_direction, eye_rotation, mirror


def test_right_eye_lies_at_negative_y():
    # Azimuth is positive towards the eye's own side: the right eye's lateral is -y.
    np.testing.assert_allclose(eye_direction(90, 0, "right"), [0, -1, 0], atol=1e-12)
    np.testing.assert_allclose(eye_direction(90, 0, "left"), [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(eye_direction(0, 90), [0, 0, 1], atol=1e-12)


@pytest.mark.parametrize("side", ["right", "left"])
def test_azimuth_elevation_inverts_direction(side):
    az, el = np.meshgrid(np.linspace(-170, 170, 7), np.linspace(-80, 80, 5))
    got_az, got_el = eye_azimuth_elevation(eye_direction(az, el, side), side)
    np.testing.assert_allclose(got_az, az, atol=1e-9)
    np.testing.assert_allclose(got_el, el, atol=1e-9)


def test_eye_rotation_is_orthonormal_and_points_its_z_along_the_axis():
    r = eye_rotation(71.1, -2.75, 10.0)
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(r) == pytest.approx(1.0)
    np.testing.assert_allclose(r[2], eye_direction(71.1, -2.75), atol=1e-12)


def test_mirror_flips_y_only():
    np.testing.assert_array_equal(mirror([[1.0, 2.0, 3.0]]), [[1.0, -2.0, 3.0]])


def test_a_sideways_eye_has_anterior_along_x_and_dorsal_along_y_in_its_plane():
    from beeoptics.headframe import eye_rotation, in_eye_plane

    anterior, dorsal = in_eye_plane(eye_rotation(90.0, 0.0))
    np.testing.assert_allclose(anterior, [1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(dorsal, [0.0, 1.0], atol=1e-12)
    # Rolled by 30 degrees about its axis, the head's directions turn the other way in the eye's plane.
    anterior, _ = in_eye_plane(eye_rotation(90.0, 0.0, 30.0))
    np.testing.assert_allclose(anterior, [np.cos(np.radians(30)), -np.sin(np.radians(30))], atol=1e-12)
