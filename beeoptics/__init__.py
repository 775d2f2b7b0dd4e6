"""beeoptics: the visual field of honey-bee compound eyes, reconstructed spectrally.

After Collins, *Reconstructing the Visual Field of Compound Eyes*: hand-made
eye meshes are remeshed, covered with a relaxed lattice of facets, and each
receptor's acceptance cone is traced spectrally through a scene; the
receptors' catches are turned into images and tables of what the bee sees.

Data flows one way through the subpackages, each importing only those
before it: :mod:`beeoptics.eye` (eyes and their receptors) →
:mod:`beeoptics.sky` (daylight, the sun and the sky) →
:mod:`beeoptics.light` (scenes and the tracer) →
:mod:`beeoptics.vision` (catches and colour spaces) →
:mod:`beeoptics.images` (what people are shown). :mod:`beeoptics.io` (files)
lies under all of them and :mod:`beeoptics.pipeline` (the workflow's stages)
over all of them; :mod:`beeoptics.spectra`, :mod:`beeoptics.headframe`,
:mod:`beeoptics.raycasting` and :mod:`beeoptics.replicates` are shared by every stage. From
Python, :func:`load_eye`, :func:`load_scene`, :func:`look`, :func:`looks` and :func:`look_cones`
(:mod:`beeoptics.api`) are the one way to the tracer, for the workflow's stages and the command line too
(:mod:`beeoptics.navigation`, which it exposes, traces its environment maps as cones). See ``docs/architecture.md``.
"""

__version__ = "0.1.0"

from beeoptics._exports import exports

#: The Python API (:mod:`beeoptics.api`), and the views for navigation a homing agent needs
#: (:mod:`beeoptics.navigation`: a place's environment map, its views at every heading or one pose, the rIDF
#: against a snapshot, a grid's catchment area), imported on first use so that ``import beeoptics`` (and the
#: command line's ``--help``) stays quick.
__all__, __getattr__ = exports(__name__, {
    "api": ("load_eye", "load_scene", "look", "looks", "human_view", "human_srgb", "Eye", "Scene", "View",
            "look_cones", "Cones", "catches", "cone_rays"),
    "navigation": ("environment_map", "turned_catches", "resampled_catches", "ridf", "catchment"),
})
