"""Vision: each species' receptor set, the receptors' spectral sensitivities, their catches, adaptation, the
bee colour spaces and their standard errors, the human observer to compare with, receptors' polarisation
sensitivity and the sky compass.

Names follow pavo's where pavo has the concept (Maia et al. 2019), so R users recognise them.
"""

from beeoptics._exports import exports

__all__, __getattr__ = exports(__name__, {
    "sensitivity": ("govardovskii_a1", "measured_sensitivities", "overall_sensitivity", "overall_weights",
                    "receptor_sensitivities", "unit_area"),
    "receptorset": ("DEFAULT_CURVES", "DEFAULT_SET", "SPECIES", "TEMPLATE", "ReceptorSet", "brightness_weights",
                    "curves", "describe", "load_receptor_set", "overall"),
    "catches": ("photon_flux", "quantum_catches"),
    "adaptation": ("background_catches",),
    "colourspace": ("colour_coordinates", "coc", "coc_distance", "excitation", "hexagon", "hexagon_polar",
                    "hexagon_sector", "reflectance_catches", "rnl_distance", "spectral_locus", "triangle", "von_kries",
                    "widest_spectral_locus"),
    "pavo": ("PAVO_NAMES", "vismodel_table"),
    "uncertainty": ("colour_columns", "delta_se", "mean_se", "quadrature", "replicate_se", "spread_se"),
    "human": ("srgb", "tristimulus"),
    "polarisation": ("DORSAL_RIM_PS", "analyser_efficiency", "analyser_ps", "degree_and_angle", "head_frame_stokes",
                     "receptor_catch"),
    "compass": ("STEP_DEG", "candidate_suns", "expected_responses", "pol_responses", "read_out", "wrap_deg"),
})
