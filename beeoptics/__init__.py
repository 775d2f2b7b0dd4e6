"""beeoptics: the visual field of honey-bee compound eyes, reconstructed spectrally.

After Collins, *Reconstructing the Visual Field of Compound Eyes*: hand-made
eye meshes are remeshed, covered with a relaxed lattice of facets whose
axes are the surface normals, and each receptor's acceptance cone is traced
spectrally through a scene; the receptors' catches are turned into images
of what the bee sees.
"""

__version__ = "0.1.0"
