import numpy as np
import pytest
from scipy.signal import argrelmax

from beeoptics.vision.sensitivity import (LAMBDA_MAX_APIS, PEITSCH_1992_FILE, TEMPLATE, govardovskii_a1,
                                          overall_sensitivity, receptor_sensitivities, sensitivities)
from beeoptics.spectra import read_pavo_csv

WL = np.arange(300.0, 701.0)


def test_template_peaks_at_lambda_max():
    for lm in (436.0, 544.0):
        s = govardovskii_a1(WL, lm)
        assert WL[np.argmax(s)] == lm
        assert s.max() == pytest.approx(1.0, abs=0.02)
    # The β band lifts the UV receptor's short-wavelength side, pulling its peak 2 nm down.
    assert abs(WL[np.argmax(govardovskii_a1(WL, 344.0))] - 344.0) <= 2


def test_receptor_curves_sum_to_one_as_in_pavo():
    s = receptor_sensitivities(WL)
    np.testing.assert_allclose(s.sum(0), 1.0)
    assert tuple(WL[np.argmax(s, 0)][1:]) == LAMBDA_MAX_APIS[1:]


def test_overall_sensitivity_has_von_helversens_peaks_and_ratio():
    s = overall_sensitivity(WL)
    peaks = WL[argrelmax(s)[0]]
    assert len(peaks) == 3
    np.testing.assert_allclose(peaks, [345, 440, 550], atol=8)
    heights = s[argrelmax(s)[0]]
    np.testing.assert_allclose(heights / heights[-1], [16, 2.7, 1], rtol=0.03)


def test_templates_match_the_measured_curves_of_peitsch_et_al(shared_data):
    names, wl, measured = read_pavo_csv(shared_data / "apis_sensitivity_peitsch1992.csv")
    model = receptor_sensitivities(wl)
    for k in range(3):
        assert abs(wl[np.argmax(measured[:, k])] - wl[np.argmax(model[:, k])]) <= 15
        assert np.corrcoef(measured[:, k], model[:, k])[0, 1] > 0.95


def test_the_default_curves_are_peitschs_measurements_as_pavo_ships_them(shared_data):
    assert PEITSCH_1992_FILE.read_bytes() == (shared_data / "apis_sensitivity_peitsch1992.csv").read_bytes()
    _, _, measured = read_pavo_csv(shared_data / "apis_sensitivity_peitsch1992.csv")
    np.testing.assert_allclose(sensitivities(WL), measured / measured.sum(0), rtol=1e-12)


def test_the_measured_uv_receptor_reaches_past_400_nm_where_the_template_does_not():
    def uv_share_above_400(curves):
        return curves[WL > 400.0, 0].sum() / curves[:, 0].sum()

    # Measured: 6.0 % of the UV receptor's sensitivity lies above 400 nm; the template: 0.2 %.
    assert uv_share_above_400(sensitivities(WL)) == pytest.approx(0.060, abs=0.003)
    assert uv_share_above_400(sensitivities(WL, TEMPLATE)) == pytest.approx(0.002, abs=0.001)
