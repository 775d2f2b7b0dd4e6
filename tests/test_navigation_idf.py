"""Image-difference functions and catchment areas: analytic cases."""

from types import SimpleNamespace

import numpy as np

from beeoptics.navigation import catchment, envmap, idf

#: A map grid of 2.5° rings turning onto itself every 5°: 9,216 directions, resampled in milliseconds.
SPACING_DEG, STEP_DEG = 2.5, 5.0


def synthetic():
    """An eye of 300 receptors of Δρ 10° looking all round, and a map of two classes: smooth blobs of light."""
    rng = np.random.default_rng(4)
    axes = rng.normal(size=(300, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    # Facets 1.5 mm out along their axes and 0.5 mm across: a map of surfaces some 10 cm away turns their kernels.
    across = np.cross(axes, rng.normal(size=(300, 3)))
    position = 1.5 * axes + 0.5 * across / np.linalg.norm(across, axis=1)[:, None]
    eye = SimpleNamespace(table=SimpleNamespace(axis=axes, position=position, delta_rho_deg=np.full(300, 10.0)),
                          receptor_set=SimpleNamespace(classes=("UV", "G"), lambda_max_nm=np.array([344.0, 544.0]),
                                                       achromatic=1))
    n = len(envmap.ring_grid(SPACING_DEG, STEP_DEG).directions)
    nearness = 10.0 * (1.0 + rng.uniform(size=n))
    env = envmap.EnvironmentMap(np.zeros(3), SPACING_DEG, STEP_DEG, np.zeros(1), None, {}, nearness, 8, 1, 1)
    centres = rng.normal(size=(12, 3))
    centres /= np.linalg.norm(centres, axis=1)[:, None]
    blobs = np.exp(8.0 * (env.grid.directions @ centres.T - 1.0))
    q = 1.0 + blobs @ rng.uniform(0.5, 2.0, (12, 2))
    return env, eye, (q, np.zeros_like(q))


def test_turned_views_are_the_resampled_ones_and_the_ridf_finds_the_turn():
    env, eye, q = synthetic()
    views = idf.turned_catches(env, eye, heading_step_deg=STEP_DEG, q=q, threads=3)
    assert views.shape == (72, 300, 2)
    # The same bits for any threads; every other heading is every other view.
    np.testing.assert_array_equal(idf.turned_catches(env, eye, heading_step_deg=STEP_DEG, q=q, threads=1), views)
    np.testing.assert_array_equal(idf.turned_catches(env, eye, heading_step_deg=2 * STEP_DEG, q=q), views[::2])
    for heading in (0.0, 35.0, 250.0):
        np.testing.assert_allclose(views[round(heading / STEP_DEG)],
                                   envmap.resampled_catches(env, eye, heading_deg=heading, q=q)[0], rtol=1e-12)
    # Against itself the rIDF is 0 at heading 0; against the view turned by 120° its minimum, 0, is at 120°.
    for reference in (0, 24):
        ridfs = idf.ridf(views, views[reference], eye.receptor_set)
        assert list(ridfs) == list(idf.signal_names(eye.receptor_set))
        for ridf in ridfs.values():
            assert ridf[reference] == 0.0 and np.argmin(ridf) == reference and ridf.min(initial=1.0) == 0.0
            assert np.all(np.delete(ridf, reference) > 0.0)
    heading, depth, width = idf.valley(ridfs["UV-G"], STEP_DEG)
    assert heading == 120.0 and depth == 1.0 and 0.0 < width < 180.0


def test_a_valley_of_one_minus_cosine_is_sixty_degrees_wide():
    # 1 − cos(θ − 90°): minimum 0 at 90°, median 1, half depth 0.5 reached 60° either side.
    theta = np.arange(360.0)
    heading, depth, width = idf.valley(np.stack([1.0 - np.cos(np.radians(theta - 90.0))] * 2))
    np.testing.assert_array_equal(heading, [90.0, 90.0])
    np.testing.assert_allclose(depth, 1.0)
    np.testing.assert_allclose(width, 60.0)


def test_a_bowl_drains_whole_and_a_ridge_stops_the_catchment():
    rows, columns = np.indices((9, 9))
    bowl = (rows - 4.0) ** 2 + (columns - 4.0) ** 2
    assert catchment.catchment(bowl, (4, 4)).all()
    # A ridge along column 6: beyond it the places drain to a minimum of their own at (4, 7); the ridge's own
    # places fall to the reference's side, the steeper.
    inside = catchment.catchment(bowl + 100.0 * (columns == 6), (4, 4))
    np.testing.assert_array_equal(inside, columns <= 6)
    x, y = 0.1 * columns, 0.1 * rows
    area, along, across = catchment.extent(inside, x, y, 0.0, 0.1)
    np.testing.assert_allclose([area, along, across], [63 * 0.01, 0.7, 0.9])
    # A reference that is not a minimum catches nothing.
    assert not catchment.catchment(bowl, (4, 5)).any()
