"""Maps of receptors: per-receptor values painted on the pixels each receptor shows.

A map's geometry, which receptor each pixel shows, is the eye's: on the
equirectangular map of the visual field (:mod:`beeoptics.eye.fieldofview`)
or in the retinal plane (:func:`beeoptics.images.retina.nearest_receptor`);
found once, it paints every image of the same eye.
"""

import numpy as np

from beeoptics.images.display import encode


def paint(receptor, values):
    """Per-receptor values (n, c) on a map whose pixels show receptors ``receptor`` (h, w; −1 none): (h, w, c),
    NaN where no receptor is shown."""
    values = np.asarray(values, float).reshape(len(values), -1)
    out = np.full((*receptor.shape, values.shape[1]), np.nan)
    seen = receptor >= 0
    out[seen] = values[receptor[seen]]
    return out


def field_images(receptor, colours, srgb):
    """A view's visual-field maps (h, w, 3) in [0, 1] from each receptor's map3 and map2 colours (n, 3)
    (:func:`beeoptics.images.display.bee_colours`): ``map3`` sRGB-encoded, ``map2`` as it is; NaN where
    no receptor sees."""
    return {"map3": np.where((receptor >= 0)[..., None], encode(paint(receptor, colours)), np.nan),
            "map2": paint(receptor, srgb)}
