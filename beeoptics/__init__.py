"""beeoptics: the visual field of honey-bee compound eyes, reconstructed spectrally.

After Collins, *Reconstructing the Visual Field of Compound Eyes*: hand-made
eye meshes are remeshed, covered with a relaxed lattice of facets, and each
receptor's acceptance cone is traced spectrally through a scene; the
receptors' catches are turned into images and tables of what the bee sees.

Data flows one way through the subpackages, each importing only those
before it: :mod:`beeoptics.eye` (eyes and their receptors) →
:mod:`beeoptics.light` (scenes, daylight and the tracer) →
:mod:`beeoptics.vision` (catches and colour spaces) →
:mod:`beeoptics.images` (what people are shown). :mod:`beeoptics.io` (files)
lies under all of them and :mod:`beeoptics.pipeline` (the workflow's stages)
over all of them; :mod:`beeoptics.spectra`, :mod:`beeoptics.headframe`,
:mod:`beeoptics.raycasting` and :mod:`beeoptics.replicates` are shared by every stage. See
``docs/architecture.md``.
"""

__version__ = "0.1.0"
