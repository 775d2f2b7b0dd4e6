import numpy as np
import pytest

from beeoptics.eye.optics import AcceptanceModel, acceptance_angles, angular_sensitivity, snyder_delta_rho
from beeoptics.light.sensors import cone_samples


def test_acceptance_is_half_at_half_the_acceptance_angle():
    assert angular_sensitivity(0.0, 2.6) == 1.0
    assert angular_sensitivity(1.3, 2.6) == pytest.approx(0.5)
    # Eheim & Wehner (1972): exp(-0.41 θ²), θ in degrees, for Δρ = 2.57°.
    assert angular_sensitivity(1.0, 2.57) == pytest.approx(np.exp(-0.41), rel=0.02)


def test_snyder_gives_the_measured_acceptance_for_worker_facets():
    # λ/D for a 16 µm facet at 500 nm is 1.79°; with d/f = 1.7° that makes 2.47°.
    assert snyder_delta_rho(16.0) == pytest.approx(np.hypot(np.degrees(0.5 / 16.0), 1.7))
    assert 2.3 < snyder_delta_rho(16.0) < 2.7
    np.testing.assert_array_equal(acceptance_angles([15.0, 17.0], AcceptanceModel("fixed", 2.6)), [2.6, 2.6])
    with pytest.raises(ValueError):
        acceptance_angles([15.0], AcceptanceModel("gaussian"))


def test_cone_samples_follow_the_two_dimensional_gaussian():
    axes = np.tile([0.0, 0.0, 1.0], (50, 1))
    dirs, w = cone_samples(axes, 4.0, 4096, seed=7)
    theta = np.degrees(np.arccos(np.clip(dirs[..., 2], -1, 1)))
    # For a 2-D Gaussian of FWHM Δρ, half of the light comes from within Δρ/2.
    # A 1-D normal angle with uniform azimuth would put 76 % there.
    inside = (w * (theta < 2.0)).sum() / w.sum()
    assert inside == pytest.approx(0.5, abs=0.01)
    # The azimuth is uniform.
    phi = np.arctan2(dirs[..., 1], dirs[..., 0])
    hist = np.histogram(phi, bins=8, range=(-np.pi, np.pi))[0]
    assert hist.min() / hist.max() > 0.95


def test_cone_samples_are_seeded_and_do_not_depend_on_the_batch():
    axes = np.random.default_rng(1).normal(size=(10, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    whole, _ = cone_samples(axes, 2.6, 32, seed=3)
    part, _ = cone_samples(axes[4:], 2.6, 32, seed=3, streams=np.arange(4, 10))
    np.testing.assert_array_equal(whole[4:], part)
    other, _ = cone_samples(axes, 2.6, 32, seed=4)
    assert not np.allclose(whole, other)
