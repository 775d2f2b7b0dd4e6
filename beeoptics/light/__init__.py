"""Light: the scene and its materials, the sky and the sun, and the spectral tracer.

The tracer follows the split of Mitsuba 3 and pbrt-v4: the sampler
(:mod:`.sampler`), the sensors that start rays (:mod:`.sensors`: receptor
cones, the pinhole camera), surface scattering (:mod:`.scattering`), the
emitters (:mod:`.emitters`, with the sky and sun models of :mod:`.sky` and
:mod:`.sun`) and the integrator that joins them (:mod:`.integrator`),
traced in batches on threads (:mod:`.batching`). Scenes are read by
:mod:`.scene`, their spectra by :mod:`.materials` and :mod:`.fred`.
"""

from beeoptics._exports import exports

__all__, __getattr__ = exports(__name__, {
    "scene": ("Scene", "SceneObject", "load_scene", "raycasting_scene", "receptors_in_world"),
    "materials": ("material", "spectrum"),
    "fred": ("catalogue", "find", "matching", "median_reflectance", "reflectance"),
    "sky": ("Sky", "cie_daylight", "horizontal_irradiance", "luminance", "preetham_sky", "sky_coefficients",
            "uniform_sky"),
    "sun": ("Sun", "sun_disc"),
    "sampler": ("around", "shifted_halton", "tangent_frames", "uniform"),
    "sensors": ("cone_samples", "pinhole_rays"),
    "scattering": ("Surfaces", "lambert", "phong", "scatter"),
    "emitters": ("Lights", "sample_sun", "sees_sun"),
    "integrator": ("trace_paths",),
    "batching": ("SAMPLE_BLOCK", "TraceSettings", "trace_bundles"),
})
