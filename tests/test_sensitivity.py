import numpy as np
import pytest
from scipy.signal import argrelmax

from beeoptics.io.errors import InputError
from beeoptics.vision.receptorset import TEMPLATE, curves, load_receptor_set, overall
from beeoptics.vision.sensitivity import govardovskii_a1, receptor_sensitivities
from beeoptics.spectra import read_pavo_csv

WL = np.arange(300.0, 701.0)
APIS = load_receptor_set("apis_mellifera")


def test_template_peaks_at_lambda_max():
    for lm in (436.0, 544.0):
        s = govardovskii_a1(WL, lm)
        assert WL[np.argmax(s)] == lm
        assert s.max() == pytest.approx(1.0, abs=0.02)
    # The β band lifts the UV receptor's short-wavelength side, pulling its peak 2 nm down.
    assert abs(WL[np.argmax(govardovskii_a1(WL, 344.0))] - 344.0) <= 2


def test_receptor_curves_sum_to_one_on_pavos_1_nm_grid():
    s = receptor_sensitivities(WL, APIS.lambda_max_nm)
    np.testing.assert_allclose(s.sum(0), 1.0)
    assert tuple(WL[np.argmax(s, 0)][1:]) == tuple(APIS.lambda_max_nm[1:])


def test_overall_sensitivity_has_von_helversens_peaks_and_ratio():
    s = overall(APIS, WL, curves(APIS, WL, TEMPLATE))
    peaks = WL[argrelmax(s)[0]]
    assert len(peaks) == 3
    np.testing.assert_allclose(peaks, [345, 440, 550], atol=8)
    heights = s[argrelmax(s)[0]]
    np.testing.assert_allclose(heights / heights[-1], [16, 2.7, 1], rtol=0.03)


def test_templates_match_the_measured_curves_of_peitsch_et_al(shared_data):
    names, wl, measured = read_pavo_csv(shared_data / "apis_sensitivity_peitsch1992.csv")
    model = receptor_sensitivities(wl, APIS.lambda_max_nm)
    for k in range(3):
        assert abs(wl[np.argmax(measured[:, k])] - wl[np.argmax(model[:, k])]) <= 15
        assert np.corrcoef(measured[:, k], model[:, k])[0, 1] > 0.95


def test_the_honey_bees_curves_are_peitschs_measurements_as_pavo_ships_them(shared_data):
    _, _, measured = read_pavo_csv(shared_data / "apis_sensitivity_peitsch1992.csv")
    np.testing.assert_allclose(curves(APIS, WL), measured / measured.sum(0), rtol=1e-12)


def test_the_measured_uv_receptor_reaches_past_400_nm_where_the_template_does_not():
    def uv_share_above_400(c):
        return c[WL > 400.0, 0].sum() / c[:, 0].sum()

    # Measured: 6.0 % of the UV receptor's sensitivity lies above 400 nm; the template: 0.2 %.
    assert uv_share_above_400(curves(APIS, WL)) == pytest.approx(0.060, abs=0.003)
    assert uv_share_above_400(curves(APIS, WL, TEMPLATE)) == pytest.approx(0.002, abs=0.001)


def test_a_receptor_set_is_data_checked_by_its_schema(tmp_path):
    # A set of one's own, beside the eye: its classes name its columns.
    own = APIS.path.read_text().replace("file: apis_mellifera_peitsch1992.csv\n", "")
    (tmp_path / "set.yaml").write_text(own)
    mine = load_receptor_set("set.yaml", base=tmp_path)
    assert mine.classes == ("UV", "B", "G") and mine.curves_file is None
    # Without measured curves the set's own are the template at its λmax.
    np.testing.assert_allclose(curves(mine, WL), curves(APIS, WL, TEMPLATE))
    bad = own.replace("  green: G\n", "  green: L\n")
    (tmp_path / "bad.yaml").write_text(bad)
    with pytest.raises(InputError, match="bad.yaml: display.green: names class 'L'"):
        load_receptor_set("bad.yaml", base=tmp_path)
    with pytest.raises(InputError, match="eye.yaml: receptors: no receptor set 'none'"):
        load_receptor_set("none", base=tmp_path, source=tmp_path / "eye.yaml")
