"""Bee colour spaces: adaptation, excitation, triangle, hexagon, COC and RNL.

The models the field uses to say where a stimulus lies in the honey bee's
colour space, as pavo (Maia et al. 2019) computes them, so that results can
be checked against it. Every function takes quantum catches or excitations
as arrays of shape (..., 3), in receptor order UV, B, G (pavo's s, m, l).

The chain for the hexagon and COC models, pavo's ``vismodel(...,
qcatch = "Ei", relative = FALSE, vonkries = TRUE)``:

1. catches Q_i = Σ_λ R(λ) I(λ) S_i(λ) Δλ (:func:`reflectance_catches`);
2. von Kries adaptation q_i = Q_i / Q_i,b to the adapting background
   (:func:`von_kries`), so that the background itself has q = 1;
3. excitation E = q / (q + 1) (:func:`excitation`), 0.5 for the background;
4. coordinates (:func:`hexagon`, :func:`coc`).

The Maxwell triangle (:func:`triangle`) uses relative catches and is the
bee colour triangle of Collins's Fig. 5b (§3.2, after Rose & Menzel 1981);
:func:`spectral_locus` gives the monochromatic lights for that figure and
for the hexagon. :func:`rnl_distance` is the receptor-noise-limited ΔS of
Vorobyev & Osorio (1998) with log receptor signals, as pavo's ``coldist``
with ``noise = "neural"``.

References
----------
Backhaus W (1991) Color opponent coding in the visual system of the
honeybee. Vision Res 31:1381–1397.
Chittka L (1992) The colour hexagon: a chromaticity diagram based on
photoreceptor excitations as a generalized representation of colour
opponency. J Comp Physiol A 170:533–543.
Chittka L, Shmida A, Troje N, Menzel R (1994) Ultraviolet as a component of
flower reflections, and the colour perception of Hymenoptera. Vision Res
34:1489–1508.
Kelber A, Vorobyev M, Osorio D (2003) Animal colour vision – behavioural
tests and physiological concepts. Biol Rev 78:81–118.
Maia R, Gruson H, Endler JA, White TE (2019) pavo 2: new tools for the
spectral and spatial analysis of colour in R. Methods Ecol Evol 10:1097–1107.
Rose R, Menzel R (1981) Luminance dependence of pigment color
discrimination in bees. J Comp Physiol 141:379–388.
Vorobyev M, Osorio D (1998) Receptor noise as a determinant of colour
thresholds. Proc R Soc B 265:351–358.
Vorobyev M, Osorio D, Bennett ATD, Marshall NJ, Cuthill IC (1998)
Tetrachromacy, oil droplets and bird plumage colours. J Comp Physiol A
183:621–633.
"""

from typing import NamedTuple

import numpy as np

#: Maxwell-triangle vertices (x, y) of pure UV, B and G catches: an
#: equilateral triangle of side √2 centred on the achromatic point, UV at the
#: top (Kelber et al. 2003; the vertices of pavo's x = (l − m)/√2,
#: y = √(2/3)(s − (l + m)/2), ``R/trispace.R@016edbabcb8d50d7670dd867c4c05169c4502f65``).
TRIANGLE_VERTICES = np.array([
    [0.0, np.sqrt(2.0 / 3.0)],
    [-1.0 / np.sqrt(2.0), -1.0 / np.sqrt(6.0)],
    [1.0 / np.sqrt(2.0), -1.0 / np.sqrt(6.0)],
])

#: Colour-hexagon vertices (x, y) of unit excitation of UV, B and G alone,
#: at unit distance from the centre, B at the top (Chittka 1992; the vertices
#: of pavo's x and y in ``R/hexagon.R@016edbabcb8d50d7670dd867c4c05169c4502f65``,
#: labelled E(B) above the centre, E(UV) and E(G) lower left and right in
#: ``R/hexplot.R@016edbabcb8d50d7670dd867c4c05169c4502f65``).
HEXAGON_VERTICES = np.array([
    [-np.sqrt(3.0) / 2.0, -0.5],
    [0.0, 1.0],
    [np.sqrt(3.0) / 2.0, -0.5],
])

#: The hexagon's outline, UV first, clockwise: each receptor vertex, then the
#: corner where it and the next receptor are fully excited (their vector sum).
HEXAGON_OUTLINE = np.stack([HEXAGON_VERTICES, HEXAGON_VERTICES + np.roll(HEXAGON_VERTICES, -1, 0)], 1).reshape(6, 2)

#: The six coarse bee-hue sectors of 60°, clockwise from the B vertex, each
#: starting 30° before the direction it is named after (Chittka et al. 1994;
#: pavo ``R/internal.R@0365a68becb92ee3b1fffe351389b7995b646834``, ``coarse_sec``).
COARSE_SECTORS = ("blue", "bluegreen", "green", "uvgreen", "uv", "uvblue")

#: Colour-opponent coding: rows give the A and B opponent channels as
#: weights of E_UV, E_B, E_G (Backhaus 1991; pavo
#: ``R/coc.R@016edbabcb8d50d7670dd867c4c05169c4502f65``).
COC_WEIGHTS = np.array([
    [-9.86, 7.70, 2.16],
    [-5.17, 20.25, -15.08],
])




class SpectralLocus(NamedTuple):
    """Coordinates of monochromatic lights: wavelengths (nm), triangle and hexagon (x, y), each (n, 2)."""

    wavelengths: np.ndarray
    triangle: np.ndarray
    hexagon: np.ndarray


def reflectance_catches(reflectance, illuminant, sensitivities, wavelengths):
    """Quantum catches of surfaces under an illuminant, as pavo's ``vismodel``.

    Q_i = Σ_λ R(λ) I(λ) S_i(λ) Δλ, with curves of area 1 nm
    (:func:`beeoptics.vision.sensitivity.unit_area`): on pavo's 1-nm grid
    pavo's plain sum, and on any grid the same integral as
    :func:`beeoptics.vision.catches.quantum_catches`. For the
    adapting background, pass the background's reflectance: its catches are
    the Q_b that :func:`von_kries` divides by.

    Parameters
    ----------
    reflectance : array_like, shape (n_wavelengths,) or (n_wavelengths, m)
        Reflectance as a fraction (not percent), one spectrum per column as
        :func:`beeoptics.spectra.read_pavo_csv` returns them.
    illuminant : array_like, shape (n_wavelengths,)
        Spectral photon flux; its scale cancels under von Kries adaptation.
    sensitivities : array_like, shape (n_wavelengths, 3)
        Receptor curves UV, B, G, e.g. from :mod:`beeoptics.vision.sensitivity`.
    wavelengths : array_like, shape (n_wavelengths,)
        The uniform grid, nm.

    Returns
    -------
    ndarray, shape (3,) or (m, 3)
        Quantum catches in the units of ``illuminant`` × nm.

    References
    ----------
    Maia et al. (2019), ``vismodel``.
    """
    step = float(wavelengths[1] - wavelengths[0])
    r = np.moveaxis(np.asarray(reflectance, float), 0, -1)
    return (r * np.asarray(illuminant, float)) @ np.asarray(sensitivities, float) * step


def von_kries(q, background_q):
    """Receptor-wise von Kries adaptation: catches relative to the adapting background's.

    Parameters
    ----------
    q : array_like, shape (..., 3)
        Quantum catches UV, B, G.
    background_q : array_like, shape (3,) or (..., 3)
        Catches of the adapting background, e.g. :func:`reflectance_catches`
        of a background spectrum or the mean catch of a scene.

    Returns
    -------
    ndarray, shape (..., 3)
        Dimensionless; the background itself gives 1 in every receptor.

    References
    ----------
    Maia et al. (2019), ``vismodel(vonkries = TRUE)``: k_i = 1 / Σ S_i I R_b.
    """
    return np.asarray(q, float) / np.asarray(background_q, float)


def excitation(q):
    """Receptor excitation E = q / (q + 1), the hyperbolic transform of adapted catches.

    With von-Kries-adapted catches the half-saturation point is the
    adapting background, which gives E = 0.5.

    Parameters
    ----------
    q : array_like, shape (..., 3)
        Von-Kries-adapted quantum catches, dimensionless.

    Returns
    -------
    ndarray, shape (..., 3)
        Excitations in [0, 1).

    References
    ----------
    Chittka (1992); Maia et al. (2019), ``vismodel(qcatch = "Ei")``.
    """
    q = np.asarray(q, float)
    return q / (q + 1.0)


def triangle(q):
    """Maxwell colour-triangle coordinates of catches.

    The catches are made relative (summing to one), then placed by their
    barycentric weights on :data:`TRIANGLE_VERTICES`:
    x = (G − B)/√2, y = √(2/3)·(UV − (B + G)/2). Equal catches fall at the
    origin. The result does not depend on the catches' overall scale.

    Parameters
    ----------
    q : array_like, shape (..., 3)
        Quantum catches UV, B, G (raw or adapted), not all zero.

    Returns
    -------
    ndarray, shape (..., 2)
        x, y; dimensionless.

    References
    ----------
    Kelber et al. (2003); Maia et al. (2019), ``trispace``.
    """
    q = np.asarray(q, float)
    return (q / q.sum(axis=-1, keepdims=True)) @ TRIANGLE_VERTICES


def hexagon(e):
    """Colour-hexagon coordinates of excitations.

    x = (√3/2)(E_G − E_UV), y = E_B − (E_UV + E_G)/2: the sum of unit
    vectors towards :data:`HEXAGON_VERTICES` weighted by the excitations,
    so that equal excitations fall at the origin.

    Parameters
    ----------
    e : array_like, shape (..., 3)
        Excitations E_UV, E_B, E_G from :func:`excitation`.

    Returns
    -------
    ndarray, shape (..., 2)
        x, y; dimensionless, Euclidean distances between points are the
        hexagon's colour distances.

    References
    ----------
    Chittka (1992); Maia et al. (2019), ``hexagon``.
    """
    return np.asarray(e, float) @ HEXAGON_VERTICES


def hexagon_polar(xy):
    """Hue angle and saturation of hexagon coordinates, as pavo reports them.

    Parameters
    ----------
    xy : array_like, shape (..., 2)
        Hexagon coordinates from :func:`hexagon`.

    Returns
    -------
    hue : ndarray, shape (...)
        Degrees in [0, 360), clockwise from the B vertex (12 o'clock), so
        the G vertex is at 120° and the UV vertex at 240°. At the origin,
        where hue is undefined, this gives 90° as pavo does.
    r : ndarray, shape (...)
        Distance from the achromatic centre; 1 at the vertices.

    References
    ----------
    Chittka et al. (1994); pavo ``R/internal.R@0365a68becb92ee3b1fffe351389b7995b646834``,
    ``angle360``.
    """
    xy = np.asarray(xy, float)
    x, y = xy[..., 0], xy[..., 1]
    return (90.0 - np.arctan2(y, x) * 180.0 / np.pi) % 360.0, np.hypot(x, y)


def hexagon_sector(hue, r):
    """Coarse bee-hue sector of hexagon points (one of :data:`COARSE_SECTORS`, or "achro").

    Parameters
    ----------
    hue, r : array_like
        Hue angle (degrees) and distance from the centre, from :func:`hexagon_polar`.

    Returns
    -------
    ndarray of str
        "achro" where r is zero. pavo instead labels hue exactly 0° (the
        pure B direction) "achro" and the centre "green"; this labels the
        centre, which is what "achromatic" means.

    References
    ----------
    Chittka et al. (1994); pavo ``coarse_sec``.
    """
    # Shift by half a sector so each sector's lower edge lands on a multiple of 60°.
    index = np.floor(((np.asarray(hue, float) + 30.0) % 360.0) / 60.0).astype(int)
    index = np.where(np.asarray(r) == 0.0, len(COARSE_SECTORS), index)
    return np.array(COARSE_SECTORS + ("achro",))[index]


def coc(e):
    """Colour-opponent-coding coordinates (A, B) of excitations.

    A = −9.86 E_UV + 7.70 E_B + 2.16 E_G,
    B = −5.17 E_UV + 20.25 E_B − 15.08 E_G. Each row of weights sums to
    zero, so equal excitations fall at the origin.

    Parameters
    ----------
    e : array_like, shape (..., 3)
        Excitations E_UV, E_B, E_G from :func:`excitation`.

    Returns
    -------
    ndarray, shape (..., 2)
        A, B; COC units (city-block distances in this plane are Backhaus's
        colour distances).

    References
    ----------
    Backhaus (1991); Maia et al. (2019), ``coc``.
    """
    return np.asarray(e, float) @ COC_WEIGHTS.T


def coc_distance(e1, e2):
    """City-block (Manhattan) distance |ΔA| + |ΔB| between excitations in the COC plane.

    Parameters
    ----------
    e1, e2 : array_like, shape (..., 3)
        Excitations E_UV, E_B, E_G.

    Returns
    -------
    ndarray, shape (...)
        COC units.

    References
    ----------
    Backhaus (1991); Maia et al. (2019), ``coldist`` on a COC colour space.
    """
    return np.abs(coc(e1) - coc(e2)).sum(axis=-1)


def neural_noise(densities, weber, reference=-1):
    """Receptor noise e_i from relative receptor densities and one Weber fraction.

    The Weber fraction measured for one receptor class sets the noise of a
    single receptor, v = weber·√(n_ref/Σn); a class of relative density n_i
    pools its receptors, e_i = v/√(n_i/Σn) = weber·√(n_ref/n_i).

    Parameters
    ----------
    densities : array_like, shape (3,)
        Relative numbers of UV, B and G receptors.
    weber : float
        Weber fraction of the reference class.
    reference : int
        Index of the reference class; the last (G, pavo's "longest") by default.

    Returns
    -------
    ndarray, shape (3,)
        Noise (Weber fraction) of each class; ``weber`` for the reference.

    References
    ----------
    Vorobyev & Osorio (1998); pavo ``R/coldist.R@01b835e420d1b88e38a89954ec1161a88f470c53``,
    ``newreceptornoise`` with ``noise = "neural"``.
    """
    n = np.asarray(densities, float)
    return weber * np.sqrt(n[reference] / n)


def rnl_distance(q1, q2, weber):
    """Receptor-noise-limited colour distance ΔS of n receptor classes, in just-noticeable differences.

    Receptor signals are log catches, f_i = ln q_i, so that the noise is a
    constant Weber fraction e_i (Weber–Fechner), and ΔS is the noise-weighted
    length of Δf with its achromatic (common) component removed,

    ΔS² = Δfᵀ (W − w wᵀ / Σw) Δf,  w_i = 1/e_i², W = diag(w),

    which for a trichromat is Vorobyev & Osorio's
    ΔS² = [e_UV²(Δf_G − Δf_B)² + e_B²(Δf_G − Δf_UV)² + e_G²(Δf_UV − Δf_B)²]
          / [(e_UV e_B)² + (e_UV e_G)² + (e_B e_G)²],
    and for any n pavo's formula by subsets of receptors. Scaling all
    catches of one stimulus by a common factor leaves ΔS unchanged, and so
    does von Kries adaptation of both to one background.

    Parameters
    ----------
    q1, q2 : array_like, shape (..., n)
        Quantum catches of the colour classes (raw or adapted, not excitations), all positive.
    weber : array_like, shape (n,) or (..., n)
        Noise e_i of each class as a Weber fraction, given per class or
        from :func:`neural_noise`; a species' receptor set states and cites them.

    Returns
    -------
    ndarray, shape (...)
        ΔS, JND.

    References
    ----------
    Vorobyev & Osorio (1998); Vorobyev et al. (1998) for log signals;
    Maia et al. (2019), ``coldist(noise = "neural")``.
    """
    df = np.log(np.asarray(q1, float)) - np.log(np.asarray(q2, float))
    w = 1.0 / np.asarray(weber, float) ** 2
    # Δfᵀ(W − w wᵀ/Σw)Δf as Σ w (Δf − Δf̄)², Δf̄ the noise-weighted mean: no cancellation when ΔS is small.
    mean = (w * df).sum(-1, keepdims=True) / w.sum(-1, keepdims=True)
    return np.sqrt((w * (df - mean) ** 2).sum(-1))


def rnl_metric(weber):
    """The receptor-noise-limited chromatic distance's metric: M with ΔS² = Δfᵀ M Δf (:func:`rnl_distance`).

    Parameters
    ----------
    weber : array_like, shape (n,)
        Noise e_i of each colour class as a Weber fraction.

    Returns
    -------
    ndarray, shape (n, n)
        M = W − w wᵀ / Σw, w_i = 1/e_i², W = diag(w), JND² per unit log catch²; M·1 = 0.
    """
    w = 1.0 / np.asarray(weber, float) ** 2
    return np.diag(w) - np.outer(w, w) / w.sum()


def spectral_locus(sensitivities, wavelengths, background_q, flux):
    """Triangle and hexagon coordinates of monochromatic lights, one per grid wavelength.

    Each light is the stimulus whose I·R is ``flux`` in one grid bin and
    zero elsewhere, so its catches are what :func:`reflectance_catches`
    gives for that spike: Q_i = flux·S_i(λ)·Δλ. They are adapted to the
    background (:func:`von_kries`), then mapped with :func:`triangle` and,
    through :func:`excitation`, :func:`hexagon`. The triangle locus does not
    depend on ``flux``; the hexagon's does, because excitation saturates, so
    a hexagon locus is only defined for a stated intensity.

    Parameters
    ----------
    sensitivities : array_like, shape (n_wavelengths, 3)
        Receptor curves UV, B, G.
    wavelengths : array_like, shape (n_wavelengths,)
        The uniform grid, nm.
    background_q : array_like, shape (3,)
        Catches of the adapting background, in the units of
        :func:`reflectance_catches` (ones for no adaptation).
    flux : float or array_like, shape (n_wavelengths,)
        Photon flux of each light in its bin, in the units of illuminant ×
        reflectance.

    Returns
    -------
    SpectralLocus
        Wavelengths (nm) and the (n, 2) triangle and hexagon coordinates.

    References
    ----------
    Chittka (1992); Collins §3.2, Fig. 5b (after Rose & Menzel 1981).
    """
    wl = np.asarray(wavelengths, float)
    step = float(wl[1] - wl[0])
    flux = np.broadcast_to(np.asarray(flux, float), wl.shape)
    q = von_kries(flux[:, None] * np.asarray(sensitivities, float) * step, background_q)
    return SpectralLocus(wl, triangle(q), hexagon(excitation(q)))


#: Intensities searched by :func:`widest_spectral_locus`, relative to the reference flux.
LOCUS_INTENSITIES = np.logspace(-4.0, 4.0, 161)


def widest_spectral_locus(sensitivities, wavelengths, background_q, flux):
    """The spectral locus with each light at the intensity that puts it furthest out in the hexagon.

    Excitation saturates, so a monochromatic light's hexagon point first
    moves out from the centre as it brightens, then back in as every
    receptor saturates. Each wavelength's light is taken at the intensity,
    among ``flux`` × :data:`LOCUS_INTENSITIES`, that puts it furthest from
    the centre: the outer boundary of what monochromatic lights can reach,
    the locus as Chittka (1992) draws it reaching out. The triangle
    coordinates do not depend on intensity.

    Parameters
    ----------
    sensitivities, wavelengths, background_q
        As for :func:`spectral_locus`.
    flux : float
        The reference photon flux (a white surface's under the scene's light, say).

    Returns
    -------
    SpectralLocus
        As :func:`spectral_locus`'s.
    ndarray, shape (n_wavelengths,)
        Each light's intensity relative to ``flux``.
    """
    loci = [spectral_locus(sensitivities, wavelengths, background_q, flux * k) for k in LOCUS_INTENSITIES]
    hexagons = np.stack([locus.hexagon for locus in loci])
    best = np.argmax(np.hypot(hexagons[..., 0], hexagons[..., 1]), axis=0)
    widest = hexagons[best, np.arange(len(best))]
    return SpectralLocus(loci[0].wavelengths, loci[0].triangle, widest), LOCUS_INTENSITIES[best]


def colour_coordinates(q, background_q, receptor_set):
    """Every colour-space coordinate of a set of catches, as named columns.

    The coordinates that apply to the species (its receptor set: the
    triangle, the hexagon and the COC for the honey bee, the triangle and
    hexagon for a trichromat, the RNL distance wherever its receptor noise is
    published) of the classes its colour vision compares. A receptor that
    caught no light (every class's catch zero, as when it looks into the
    black below a sky-only scene) has no colour: its coordinates are NaN
    (empty fields in a CSV) and ``lit`` is 0.

    Parameters
    ----------
    q : array_like, shape (n, classes)
        Quantum catches of every class of the set, in the units of ``background_q``.
    background_q : array_like, shape (classes,) or (n, classes)
        Catches of the adapting background.
    receptor_set : ReceptorSet
        :mod:`beeoptics.vision.receptorset`.

    Returns
    -------
    dict of ndarray (n,)
        ``lit`` (1 where the receptor caught light, else 0), ``q_<class>``
        (von Kries) and ``E_<class>`` of every class; where they apply
        ``hex_x, hex_y, hex_hue_deg, hex_r``, ``coc_A, coc_B``, ``tri_x,
        tri_y`` (of the adapted catches, so the background is at the centre)
        and ``rnl_dS`` (JND from the background).
    """
    q = np.asarray(q, float)
    lit = (q > 0.0).any(axis=-1)
    # Coordinates of the lit receptors only: the others' are not numbers.
    adapted = np.full(q.shape, np.nan)
    adapted[lit] = von_kries(q[lit], np.broadcast_to(background_q, q.shape)[lit])
    e = excitation(adapted)
    columns = {"lit": lit.astype(int)}
    columns.update({f"q_{k}": adapted[:, i] for i, k in enumerate(receptor_set.classes)})
    columns.update({f"E_{k}": e[:, i] for i, k in enumerate(receptor_set.classes)})
    colour = receptor_set.chromatic
    if "hexagon" in receptor_set.spaces:
        hexagon_xy = hexagon(e[:, colour])
        hue, r = hexagon_polar(hexagon_xy)
        columns.update(hex_x=hexagon_xy[:, 0], hex_y=hexagon_xy[:, 1], hex_hue_deg=hue, hex_r=r)
    if "coc" in receptor_set.spaces:
        a_b = coc(e[:, colour])
        columns.update(coc_A=a_b[:, 0], coc_B=a_b[:, 1])
    if "triangle" in receptor_set.spaces:
        tri = triangle(adapted[:, colour])
        columns.update(tri_x=tri[:, 0], tri_y=tri[:, 1])
    if receptor_set.weber is not None:
        columns["rnl_dS"] = rnl_distance(adapted[:, colour], np.ones(len(colour)), receptor_set.weber)
    return columns
