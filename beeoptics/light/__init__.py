"""Light: the scene and its materials, and the spectral tracer.

The tracer follows the split of Mitsuba 3 and pbrt-v4: the sampler
(:mod:`.sampler`), the sensors that start rays (:mod:`.sensors`: receptor
cones, the pinhole camera), surface scattering (:mod:`.scattering`), the
emitters (:mod:`.emitters`: the sky and the sun of :mod:`beeoptics.sky`, and
glowing materials), polarised light's
frames and Mueller matrices (:mod:`.mueller`) and the integrator that joins them (:mod:`.integrator`),
traced in batches on threads (:mod:`.batching`), each receptor as independent replicates whose
spread is its error, to the precision asked (:mod:`.precision`); what lies between two
Embree casts is compiled (:mod:`beeoptics.jit`). Scenes are read by
:mod:`.scene`, their spectra by :mod:`.materials` and :mod:`.fred`.
"""

from beeoptics._exports import exports

__all__, __getattr__ = exports(__name__, {
    "scene": ("Scene", "SceneObject", "bee_camera", "load_scene", "raycasting_scene",
              "posed", "receptors_in_world", "relit"),
    "materials": ("ground_albedo", "material", "spectrum"),
    "fred": ("catalogue", "find", "matching", "median_reflectance", "reflectance"),
    "mueller": ("depolarise", "double_angle", "fresnel", "plane_normal", "reflect", "reflect_column"),
    "sampler": ("around", "shifted_halton", "tangent_frame", "tangent_frames", "uniform", "uniform1"),
    "sensors": ("cone_density", "cone_samples", "cone_sigma", "pinhole_rays"),
    "scattering": ("Surfaces", "phong", "scatter"),
    "emitters": ("Lights", "sample_sun"),
    "integrator": ("trace_paths",),
    "batching": ("SAMPLE_BLOCK", "TraceSettings", "trace_bundles"),
    "precision": ("Precision", "adaptive_samples", "form_errors", "replicate_samples"),
})
