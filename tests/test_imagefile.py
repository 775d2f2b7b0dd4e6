import numpy as np

from beeoptics.io.imagefile import read_image, write_exr, write_png


def test_exr_channels_are_named_and_read_back_by_name(tmp_path):
    data = np.random.default_rng(0).random((5, 7, 3)).astype(np.float32)
    write_exr(tmp_path / "a.exr", data, ["UV", "B", "G"])
    pixels, names = read_image(tmp_path / "a.exr")
    assert sorted(names) == ["B", "G", "UV"]
    for k, name in enumerate(["UV", "B", "G"]):
        np.testing.assert_array_equal(pixels[..., names.index(name)], data[..., k])


def test_images_are_byte_identical_when_written_again(tmp_path):
    data = np.random.default_rng(1).random((4, 4, 3))
    write_exr(tmp_path / "a.exr", data, ["UV", "B", "G"])
    write_png(tmp_path / "a.png", data)
    first = (tmp_path / "a.exr").read_bytes(), (tmp_path / "a.png").read_bytes()
    write_exr(tmp_path / "a.exr", data, ["UV", "B", "G"])
    write_png(tmp_path / "a.png", data)
    assert first == ((tmp_path / "a.exr").read_bytes(), (tmp_path / "a.png").read_bytes())
    assert b"2000:01:01 00:00:00" in first[0]
