"""Maps of the visual field: per-receptor values painted on the equirectangular map of both eyes.

The map's geometry, which receptor sees each direction, is the eye's
(:mod:`beeoptics.eye.fieldofview`); this paints values on it.
"""

import numpy as np


def paint(field, values):
    """Per-receptor values on the map, (h, w, c); NaN where no receptor sees."""
    values = np.asarray(values, float).reshape(len(values), -1)
    out = np.full((*field.receptor.shape, values.shape[1]), np.nan)
    seen = field.receptor >= 0
    out[seen] = values[field.receptor[seen]]
    return out
