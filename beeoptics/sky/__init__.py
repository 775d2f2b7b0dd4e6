"""The sky and the sun: daylight's spectra, the sky's radiance over its dome and its polarisation.

The clear-sky daylight of SPECTRL2 (:mod:`.daylight`; measured records to
hold it against, :mod:`.daylightrecords`) is spread over the sun's disc
(:mod:`.sun`) and the sky's dome (:mod:`.dome`), shaped wavelength by
wavelength by Hosek & Wilkie's model (:mod:`.hosekwilkie`) and polarised
(:mod:`.skypolarisation`); the tracer's emitters (:mod:`beeoptics.light.emitters`)
sample it from the table of :mod:`.sampling`. Nothing here knows a scene's
geometry: a scene's light section (:mod:`beeoptics.light.scene`) asks for it.
"""

from beeoptics._exports import exports

__all__, __getattr__ = exports(__name__, {
    "daylight": ("Daylight", "angstrom_beta", "clear_sky", "write_daylight"),
    "hosekwilkie": ("CHANNELS_NM", "channel_radiance", "channel_shape", "channel_weights", "shape_radiance"),
    "dome": ("CLEAR_SKIES", "Sky", "cie_daylight", "clear_sky_dome", "horizontal_irradiance", "luminance",
             "sky_coefficients", "uniform_sky", "white_radiance"),
    "skypolarisation": ("MODELS", "basis_depolarisation", "degree", "depolarisation_factor", "king_factor",
                        "max_degree", "neutral_points_deg", "patterns", "polarisation", "polarisations",
                        "sky_polarisation"),
    "sun": ("Sun", "sun_disc"),
    "sampling": ("sample_sky", "sky_density", "sky_table"),
})
