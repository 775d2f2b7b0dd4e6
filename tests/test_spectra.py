"""Spectra in pavo's CSV layout, in and out."""

import numpy as np

from beeoptics.spectra import grid, read_pavo_csv, write_pavo_csv


def test_spectra_written_in_pavos_layout_read_back_the_same(tmp_path):
    wl = grid(300.0, 700.0, 1.0)
    spectra = {"petal": 0.5 + 0.4 * np.sin(wl / 40.0), "leaf": np.linspace(0.05, 0.45, len(wl))}
    write_pavo_csv(tmp_path / "out.csv", wl, spectra)
    assert (tmp_path / "out.csv").read_text().splitlines()[0] == "wl,petal,leaf"
    names, got_wl, values = read_pavo_csv(tmp_path / "out.csv")
    assert names == ["petal", "leaf"]
    np.testing.assert_array_equal(got_wl, wl)
    np.testing.assert_allclose(values, np.column_stack(list(spectra.values())), rtol=1e-8)


def test_percent_is_detected_as_pavo_does(tmp_path):
    wl = grid(300.0, 700.0, 10.0)
    write_pavo_csv(tmp_path / "percent.csv", wl, {"white": np.full(len(wl), 80.0)})
    np.testing.assert_allclose(read_pavo_csv(tmp_path / "percent.csv")[2], 0.8)


def test_pavos_flowers_round_trip_through_our_writer(tmp_path, shared_data):
    names, wl, values = read_pavo_csv(shared_data / "flowers_pavo.csv")
    assert len(names) == 36 and wl[0] == 300 and wl[-1] == 700
    write_pavo_csv(tmp_path / "flowers.csv", wl, dict(zip(names, values.T)))
    again = read_pavo_csv(tmp_path / "flowers.csv")
    assert again[0] == names
    np.testing.assert_allclose(again[2], values, rtol=1e-8, atol=1e-12)
    # Resampled onto the workflow's 5-nm grid, a 1-nm spectrum keeps its values at the grid's wavelengths.
    coarse = read_pavo_csv(shared_data / "flowers_pavo.csv", onto=grid())[2]
    np.testing.assert_allclose(coarse, values[::5], atol=1e-9)
