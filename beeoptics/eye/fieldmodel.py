"""The worker's measured field of view and interommatidial angles (Seidl 1982, as Stürzl et al. 2010 model them).

Seidl (1982) charted the field of view of the honey bee's eyes and the
divergence angles between neighbouring ommatidia; Stürzl et al. (2010) cast
his worker data as a model of the ommatidial array, which this module
writes out. Directions are in one eye's convention
(:func:`beeoptics.headframe.eye_direction`): azimuth from straight ahead,
positive towards the eye's own side, elevation positive dorsal, degrees.

- The border of the right eye's field: for each elevation the medial and
  lateral limits of azimuth (the package's
  ``eye/data/apis_mellifera_worker_field_border_stuerzl2010.csv``), joined by monotone cubic
  interpolation (Fritsch & Carlson 1980, as Stürzl et al.'s implementation
  does). Above 180° the field reaches behind the head. At +69° and −74.5°
  the border closes round the whole ring of azimuths (−90° to 270°), so the
  eye also sees the polar caps beyond: the field is the band between the
  limits and the two caps, which take the closed ring's rows on to the
  poles (as bee_view's and InvertPy's builders of the same model do).
- The ommatidia sit in horizontal rows, ``Δφ_v/2`` apart in elevation,
  every other row shifted by half a step, so that an ommatidium's vertical
  neighbour in its column, two rows away, is ``Δφ_v`` away and its
  neighbour in the row ``Δφ_h``.
- Vertical Δφ rises linearly from 1.5° at the equator to 4.5° at the poles.
- Horizontal Δφ (a great-circle angle) is 3.7° straight ahead, falls to
  2.4° at 45° lateral, rises to 3.7° at 90° and to 4.6° at 150° and
  beyond; medially it rises from 3.7° at 0° to 4.6° at 45°. Above 50° of
  elevation, up or down, the excess over 3.7° shrinks linearly to nothing
  at the pole. (Stürzl et al.'s published implementation states the
  medial zones inconsistently between their dorsal and ventral halves;
  this module gives both the form of the lateral zones.)

References
----------
Seidl R (1982) Die Sehfelder und Ommatidien-Divergenzwinkel von
Arbeiterin, Königin und Drohn der Honigbiene (Apis mellifica). PhD thesis,
TH Darmstadt.
Stürzl W, Boeddeker N, Dittmar L, Egelhaaf M (2010) Mimicking honeybee
eyes with a 280° field of view catadioptric imaging system. Bioinspir
Biomim 5:036002.
Fritsch FN, Carlson RE (1980) Monotone piecewise cubic interpolation.
SIAM J Numer Anal 17:238–246.
"""

from functools import cache
from pathlib import Path

import numpy as np

from beeoptics.io.table import read_table

#: The border of the worker's field of view (Stürzl et al. 2010, after Seidl 1982).
BORDER_FILE = Path(__file__).parent / "data" / "apis_mellifera_worker_field_border_stuerzl2010.csv"
#: Vertical Δφ at the equator and at the poles, degrees (Stürzl et al. 2010, after Seidl 1982).
DELTA_PHI_V_EQUATOR, DELTA_PHI_V_POLE = 1.5, 4.5
#: Horizontal Δφ, degrees: the smallest (at 45° lateral), straight ahead and at 90°, the
#: largest (150° lateral and beyond, 45° medial) (Stürzl et al. 2010, after Seidl 1982).
DELTA_PHI_H_MIN, DELTA_PHI_H_MID, DELTA_PHI_H_MAX = 2.4, 3.7, 4.6
#: Elevation beyond which horizontal Δφ tends to its frontal value at the pole, degrees
#: (Stürzl et al. 2010).
POLAR_ONSET_DEG = 50.0
#: Grid of the model's tables: steps of elevation, and of the fraction along a row.
_STEPS = 1201


@cache
def border():
    """The field's border: elevations (deg) and PCHIP functions for the medial and lateral azimuth limits.

    Returns
    -------
    (low, high) : elevation range of the field, degrees
    medial, lateral : callables, elevation (deg) → azimuth (deg)
    """
    # scipy's interpolation and integration imported where used: the stages that import this module through
    # the eye's description and draw no field model would pay 0.4 s for them.
    from scipy.interpolate import PchipInterpolator

    t = read_table(BORDER_FILE, numeric=["lateral_elevation_deg", "lateral_azimuth_deg", "medial_elevation_deg",
                                         "medial_azimuth_deg"])
    lateral = PchipInterpolator(t["lateral_elevation_deg"], t["lateral_azimuth_deg"])
    medial = PchipInterpolator(t["medial_elevation_deg"], t["medial_azimuth_deg"])
    low = max(t["lateral_elevation_deg"][0], t["medial_elevation_deg"][0])
    high = min(t["lateral_elevation_deg"][-1], t["medial_elevation_deg"][-1])
    return (float(low), float(high)), medial, lateral


def delta_phi_vertical(elevation_deg):
    """Vertical Δφ between an ommatidium and the next in its column, degrees."""
    e = np.abs(np.asarray(elevation_deg, float))
    return DELTA_PHI_V_EQUATOR + (DELTA_PHI_V_POLE - DELTA_PHI_V_EQUATOR) * e / 90.0


def delta_phi_horizontal(azimuth_deg, elevation_deg):
    """Horizontal Δφ between neighbours in a row, a great-circle angle, degrees."""
    a, e = np.broadcast_arrays(np.asarray(azimuth_deg, float), np.asarray(elevation_deg, float))
    polar = np.clip((90.0 - np.abs(e)) / (90.0 - POLAR_ONSET_DEG), 0.0, 1.0)
    rise = DELTA_PHI_H_MAX - DELTA_PHI_H_MID
    lateral = np.select(
        [a <= 45.0, a <= 90.0],
        [DELTA_PHI_H_MID + (a / 45.0) * (DELTA_PHI_H_MIN - DELTA_PHI_H_MID),
         DELTA_PHI_H_MIN + ((a - 45.0) / 45.0) * (DELTA_PHI_H_MID - DELTA_PHI_H_MIN)],
        DELTA_PHI_H_MID + np.clip((a - 90.0) / 60.0, 0.0, 1.0) * rise * polar,
    )
    medial = DELTA_PHI_H_MID + np.clip(-a / 45.0, 0.0, 1.0) * rise * polar
    return np.where(a >= 0.0, lateral, medial)


def azimuth_step(azimuth_deg, elevation_deg):
    """The azimuth between neighbours in a row, degrees: the great-circle Δφ_h at that elevation."""
    half = np.radians(delta_phi_horizontal(azimuth_deg, elevation_deg)) / 2.0
    ratio = np.sin(half) / np.cos(np.radians(elevation_deg))
    return np.degrees(2.0 * np.arcsin(np.clip(ratio, 0.0, 1.0)))


def ring(elevation_deg):
    """The medial and lateral azimuth limits of the field's row at each elevation, degrees: the border's,
    and beyond its ends, where it has closed round the whole ring, the closed ring's (the caps)."""
    (low, high), medial, lateral = border()
    e = np.clip(np.asarray(elevation_deg, float), low, high)
    return medial(e), lateral(e)


def inside(azimuth_deg, elevation_deg, caps=True):
    """Whether directions lie in the field, for eye azimuths in (−180, 180]; with ``caps`` False, only
    in the band the border draws (between −74.5° and 69°), without the polar caps beyond it."""
    (low, high), _, _ = border()
    a, e = np.broadcast_arrays(np.asarray(azimuth_deg, float), np.asarray(elevation_deg, float))
    lo, hi = ring(e)
    # The lateral limit passes 180° near the poles: the field then wraps behind the head.
    seen = ((a >= lo) & (a <= hi)) | (a + 360.0 <= hi) | (a - 360.0 >= lo)
    return seen if caps else seen & (e >= low) & (e <= high)


@cache
def _tables():
    """Elevation grid, the cumulative share of ommatidia below each elevation, and each row's
    azimuth as a function of the share of its ommatidia medial to it; from pole to pole (the caps)."""
    from scipy.integrate import cumulative_trapezoid  # as in border

    elevation = np.linspace(-90.0, 90.0, _STEPS)
    share = np.linspace(0.0, 1.0, _STEPS)
    lo, hi = ring(elevation)
    azimuth = lo[:, None] + share[None, :] * (hi - lo)[:, None]
    per_degree = 1.0 / azimuth_step(azimuth, elevation[:, None])
    along = cumulative_trapezoid(per_degree, azimuth, axis=1, initial=0.0)
    row = along[:, -1]
    below = cumulative_trapezoid(row * rows_per_degree(elevation), elevation, initial=0.0)
    inverse = np.stack([np.interp(share, a / a[-1], z) for a, z in zip(along, azimuth)])
    return elevation, below, inverse, row, azimuth, along


def ommatidia_count():
    """How many ommatidia the model's field holds (one eye)."""
    return float(_tables()[1][-1])


def row_count(elevation_deg):
    """Ommatidia in the row at each elevation."""
    elevation, _, _, row, _, _ = _tables()
    return np.interp(elevation_deg, elevation, row)


def rows_per_degree(elevation_deg):
    """Rows of ommatidia per degree of elevation: they lie Δφ_v/2 apart."""
    return 2.0 / delta_phi_vertical(elevation_deg)


def ommatidia_medial_of(azimuth_deg, elevation_deg):
    """Ommatidia of the row at each elevation that look medially of an azimuth."""
    elevation, _, _, _, azimuth, along = _tables()
    k = np.clip(np.rint((np.asarray(elevation_deg, float) - elevation[0]) / (elevation[1] - elevation[0])),
                0, len(elevation) - 1).astype(int)
    a = np.broadcast_to(np.asarray(azimuth_deg, float), k.shape)
    return np.array([np.interp(x, azimuth[i], along[i]) for x, i in zip(a.ravel(), k.ravel())]).reshape(k.shape)


def direction_of_shares(below, medial_share):
    """Directions of the ommatidia with the given shares of the eye below them and of their row medial to them.

    The inverse of the model's distribution of ommatidia (a Knothe–Rosenblatt
    map): ``below`` in [0, 1] fixes the elevation, ``medial_share`` in
    [0, 1] the azimuth along that row.

    Returns
    -------
    azimuth_deg, elevation_deg : ndarray
    """
    from scipy.interpolate import RegularGridInterpolator  # as in border

    elevation, cumulative, inverse = _tables()[:3]
    e = np.interp(np.asarray(below, float) * cumulative[-1], cumulative, elevation)
    along = RegularGridInterpolator((elevation, np.linspace(0.0, 1.0, _STEPS)), inverse)
    share = np.clip(np.asarray(medial_share, float), 0.0, 1.0)
    return along(np.stack(np.broadcast_arrays(e, share), -1)), e
