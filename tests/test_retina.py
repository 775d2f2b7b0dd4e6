import numpy as np
from scipy.spatial import cKDTree

from beeoptics.images.fieldmaps import paint
from beeoptics.images.retina import canvas, density, nearest_receptor, panel_extents


def lattice(n=30):
    x, y = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n))
    xy = np.column_stack([x.ravel(), y.ravel()])
    xy += np.random.default_rng(0).normal(0, 0.01, xy.shape)
    xy = np.vstack([xy, xy])
    sides = np.repeat(["right", "left"], n * n)
    return xy, sides


def test_a_voronoi_pixel_belongs_to_its_nearest_receptor():
    xy, sides = lattice()
    can = canvas(xy, 120)
    idx = nearest_receptor(can, xy, sides)
    inside = idx >= 0
    assert inside.mean() > 0.8
    for s in ("left", "right"):
        mine = np.flatnonzero(sides == s)
        px = can.xy[(can.side == s) & inside]
        want = mine[cKDTree(xy[mine]).query(px)[1]]
        np.testing.assert_array_equal(idx[(can.side == s) & inside], want)


def test_outside_the_convex_hull_is_empty():
    xy, sides = lattice()
    can = canvas(xy, 120)
    img = paint(nearest_receptor(can, xy, sides), np.ones(len(xy)))
    corner = np.abs(can.xy).max(-1) > 1.06
    assert np.isnan(img[corner, 0]).all()


def test_normalised_density_of_a_uniform_field_is_flat():
    xy, sides = lattice(40)
    # Crowd the receptors towards one side, as on a real eye.
    xy[:, 0] = np.sign(xy[:, 0]) * np.abs(xy[:, 0]) ** 1.5
    can = canvas(xy, 160)
    raw, flat = (image[..., 0] for image in density(can, xy, sides, np.ones(len(xy))))
    inner = np.abs(can.xy).max(-1) < 0.8
    # Both eyes lie on the same retinal-plane points here, as mirrored eyes do: the
    # kernel must still spread each eye's receptors over the gaps between them.
    assert np.isfinite(raw[inner]).all() and np.isfinite(flat[inner]).all()
    assert (raw[inner] > 0).all()
    # The raw estimate follows receptor density; the normalised one does not.
    assert np.std(raw[inner]) / np.mean(raw[inner]) > 0.1
    np.testing.assert_allclose(flat[inner], 1.0, rtol=1e-9)


def test_the_retinal_images_test_each_pixel_against_its_eyes_hull_once(monkeypatch):
    """The Voronoi and both density images share one test of the pixels against each eye's hull (it was made
    six times, a second of an eye's images job)."""
    from types import SimpleNamespace

    from beeoptics.images import retina

    calls = []
    within_hull = retina.within_hull
    monkeypatch.setattr(retina, "within_hull", lambda *args: calls.append(1) or within_hull(*args))
    xy, sides = lattice()
    # The eye's local frame: its x and y the head's x and z, so that the retinal plane holds the points as given.
    eye = SimpleNamespace(origin=np.zeros(3), rotation=np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]]))
    table = SimpleNamespace(position=np.column_stack([xy[:, 0], np.zeros(len(xy)), xy[:, 1]]), side=sides)
    colours = np.full((len(xy), 3), 0.5)
    images = retina.retinal_images(eye, table, colours, colours, colours, ["UV", "B", "G"], 60).images
    assert len(calls) == 2
    inner = np.abs(retina.canvas(xy, 60).xy).max(-1) < 0.8
    np.testing.assert_allclose(images["density_map3_normalised"][inner], retina.encode(0.5), rtol=1e-9)


def test_map3_shows_a_white_surface_white_and_the_dark_apart_from_outside(tmp_path):
    from beeoptics.images.display import bee_colours, encode
    from beeoptics.io.imagefile import read_image, write_png

    wl = np.arange(300.0, 701.0, 5.0)
    white_q = np.array([[2.0, 5.0, 9.0], [4.0, 10.0, 18.0]])
    # A white surface through each receptor catches what white does: (1, 1, 1), white.
    _, colours, _ = bee_colours(white_q, white_q, wl, np.ones((2, len(wl))), [(0,), (2,), (1,)])
    np.testing.assert_allclose(encode(colours), 1.0)
    # A receptor that caught nothing is black; no receptor at all (NaN) is transparent.
    write_png(tmp_path / "two.png", encode(np.array([[[0.0, 0.0, 0.0], [np.nan, np.nan, np.nan]]])))
    pixels, channels = read_image(tmp_path / "two.png")
    assert channels == ["R", "G", "B", "A"]
    np.testing.assert_array_equal(pixels[0], [[0, 0, 0, 1], [0, 0, 0, 0]])


def test_panels_are_measured_in_millimetres_and_the_right_eye_mirrored():
    xy, sides = lattice()
    can = canvas(xy, 120)
    (lx0, lx1, ly0, ly1), (rx0, rx1, ry0, ry1) = panel_extents(can)
    assert lx0 < -1 < 1 < lx1 and rx0 > 1 > -1 > rx1
    assert ly0 < -1 < 1 < ly1 and (ly0, ly1) == (ry0, ry1)
    np.testing.assert_allclose(lx1 - lx0, 120 * can.pixel_mm)
