"""Figures of the eyes and their optics, drawn with matplotlib and written atomically.

The relaxation figure reproduces Collins' Fig. 7: the facet lattice at its
initial projection, during relaxation and at rest, seen along the eye's z-axis
and coloured by the target facet diameter.
"""

import textwrap

import numpy as np
from matplotlib import colormaps, patheffects
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import FormatStrFormatter, LogLocator, NullFormatter

from beeoptics.eye.optics import angular_sensitivity
from beeoptics.images.display import EXPOSURE_PERCENTILE
from beeoptics.io.atomic import atomic_path

#: PNG metadata without a version string, so figures do not change with matplotlib's.
_METADATA = {"Software": None}


def save(fig, path):
    """Write a figure as PNG atomically."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=150, metadata=_METADATA, format="png")


def _eye_axes(ax, boundary_xy):
    ax.plot(*np.vstack([boundary_xy, boundary_xy[:1]]).T, color="0.4", linewidth=0.6)
    ax.set_aspect("equal")
    ax.set_xlabel("eye x, mm")
    ax.set_ylabel("eye y, mm")


def _marker_size(ax, fig, boundary_xy, count):
    """Marker area, points², that makes dots about 70 % of the mean facet spacing."""
    x, y = boundary_xy.T
    area = 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))
    spacing = np.sqrt(area / count)
    width_pt = ax.get_position().width * fig.get_figwidth() * 72.0
    return (0.7 * spacing * width_pt / np.ptp(x)) ** 2


def relaxation(snapshots, iterations, diameter_um, boundary_xy, path, eye_name=""):
    """Collins Fig. 7: the lattice at each stored stage of relaxation.

    Parameters
    ----------
    snapshots : ndarray (s, n, 3)
        Facet positions, eye frame, mm, initial projection first and rest last.
    iterations : ndarray (s,)
        The iteration of each snapshot.
    diameter_um : ndarray (s, n)
        Target facet diameter at each position, µm.
    boundary_xy : ndarray (b, 2)
        The eye's rim, eye frame, mm.
    """
    s = len(snapshots)
    fig = Figure(figsize=(3.6 * s, 3.9), constrained_layout=True)
    axes = fig.subplots(1, s, sharex=True, sharey=True)
    lo, hi = np.min(diameter_um), np.max(diameter_um)
    for k, ax in enumerate(np.atleast_1d(axes)):
        _eye_axes(ax, boundary_xy)
        marker = _marker_size(ax, fig, boundary_xy, snapshots.shape[1])
        dots = ax.scatter(*snapshots[k, :, :2].T, c=diameter_um[k], s=marker, vmin=lo, vmax=hi,
                          cmap="viridis", linewidths=0)
        stage = "initial grid" if k == 0 else "at rest" if k == s - 1 else "relaxing"
        ax.set_title("as measured, not relaxed" if s == 1 else f"{stage}, iteration {iterations[k]}", fontsize=9)
    # One snapshot: an eye of given ommatidia (beeoptics.eye.given), drawn as they are.
    fig.colorbar(dots, ax=axes, label="facet diameter, µm" if s == 1 else "target facet diameter, µm", shrink=0.8)
    fig.suptitle(textwrap.fill(f"{eye_name}: " + ("the given ommatidia" if s == 1 else
                                                  "facet lattice relaxation (Collins Fig. 7)"), 40 * s))
    save(fig, path)


def eye_map(points, values, boundary_xy, path, label, title):
    """A per-facet quantity over the eye, seen along its z-axis, shaded between facets."""
    fig = Figure(figsize=(5.2, 4.4), constrained_layout=True)
    ax = fig.subplots()
    _eye_axes(ax, boundary_xy)
    lo, hi = np.percentile(values, [1, 99])
    field = ax.tripcolor(*points[:, :2].T, values, shading="gouraud", vmin=lo, vmax=hi, cmap="magma")
    fig.colorbar(field, ax=ax, label=label)
    ax.set_title(textwrap.fill(title, 60), fontsize=9)
    save(fig, path)


def sensitivities(wavelengths, receptors, names, overall, path, source):
    """Collins Fig. 6 and Fig. 5a: the receptor curves and, where the species has one, the overall S(λ).

    Parameters
    ----------
    wavelengths : ndarray (n,)
        nm.
    receptors : ndarray (n, k)
        The classes' curves, drawn each with its peak at one, coloured by the wavelength of its peak.
    names : sequence of str
        The classes.
    overall : ndarray (n,) or None
        S(λ), drawn on a log axis as von Helversen (1972) plots it.
    source : str
        Where the receptor curves come from, for the title.
    """
    fig = Figure(figsize=(9.0 if overall is not None else 5.0, 3.6), constrained_layout=True)
    axes = np.atleast_1d(fig.subplots(1, 2 if overall is not None else 1))
    left = axes[0]
    peaks = wavelengths[np.argmax(receptors, axis=0)]
    hue = colormaps["nipy_spectral"]((peaks - 300.0) / 400.0 * 0.9 + 0.05)
    for k, name in enumerate(names):
        left.plot(wavelengths, receptors[:, k] / receptors[:, k].max(), color=hue[k], label=f"S$_{{{name}}}$")
    left.set(xlabel="wavelength, nm", ylabel="relative sensitivity",
             title=textwrap.fill(f"receptor sensitivities (Fig. 6): {source}", 60))
    left.title.set_fontsize(9)
    left.legend(frameon=False)
    if overall is not None:
        axes[1].semilogy(wavelengths, overall, color="k")
        axes[1].set(xlabel="wavelength, nm", ylabel="S(λ), relative",
                    title="overall sensitivity (Fig. 5a)\npeaks 16 : 2.7 : 1 (von Helversen 1972)")
    for ax in axes:
        ax.set_xlim(wavelengths[0], wavelengths[-1])
    save(fig, path)


def angular_sensitivities(delta_rho_deg, delta_phi_deg, path, eye_name=""):
    """Receptor acceptance functions A(θ) of an eye, with its interommatidial angle marked.

    A(θ) is drawn at the 5th, 50th and 95th percentiles of the receptors'
    Δρ (once if every receptor has the same), against the median Δφ: where a
    neighbour's axis lies.

    Parameters
    ----------
    delta_rho_deg, delta_phi_deg : ndarray (n,)
        Each receptor's acceptance and interommatidial angles, degrees.
    """
    theta = np.linspace(0.0, 5.0, 501)
    levels = dict(zip(("5th percentile", "median", "95th percentile"), np.percentile(delta_rho_deg, [5, 50, 95])))
    if np.ptp(list(levels.values())) == 0.0:
        levels = {"every receptor": levels["median"]}
    curves = {f"Δρ {v:.2f}° ({k})": angular_sensitivity(np.radians(theta), np.radians(v)) for k, v in levels.items()}
    median_phi = float(np.nanmedian(delta_phi_deg))
    fig = Figure(figsize=(5.2, 3.6), constrained_layout=True)
    ax = fig.subplots()
    for label, a in curves.items():
        ax.plot(theta, a, label=label)
    ax.axhline(0.5, color="0.7", linewidth=0.6)
    ax.axvline(median_phi, color="0.4", linestyle="--", linewidth=0.8)
    ax.annotate(f"median Δφ {median_phi:.2f}°", (median_phi, 0.55), xytext=(4, 0),
                textcoords="offset points", fontsize=8)
    ax.set(xlabel="angle from the optical axis θ, °", ylabel="A(θ)", ylim=(0, 1.02),
           title=f"{eye_name}: acceptance function, A = exp(−2.77 θ²/Δρ²) (Snyder 1977)")
    ax.title.set_fontsize(9)
    ax.legend(frameon=False, fontsize=8)
    save(fig, path)


#: Spectral-locus labels closer than this, as a share of the outline's width, are merged ("550–700").
_LABEL_GAP = 0.06


def _locus_labels(wl, xy, width):
    """Every 50 nm labelled; a run of labels on one spot (the locus's saturated ends) as one range."""
    marks = [(w, p) for w, p in zip(wl, xy) if w % 50 == 0]
    groups = []
    for w, p in marks:
        if groups and np.hypot(*(p - groups[-1][1])) < _LABEL_GAP * width:
            groups[-1][2] = w
        else:
            groups.append([w, p, w])
    return [(f"{a:g}" if a == b else f"{a:g}–{b:g}", p) for a, p, b in groups]


def colour_space(points, colours, outline, loci, path, title, labels):
    """Receptor colours in a bee colour space (Collins Fig. 5b), with the spectral locus.

    Parameters
    ----------
    points : ndarray (n, 2)
        Coordinates of each receptor's colour.
    colours : ndarray (n, 3)
        sRGB in [0, 1] to draw each point with: the human colour of its light.
    outline : ndarray (k, 2)
        Vertices of the space's outline (triangle or hexagon), UV first,
        around the origin.
    loci : sequence of (wavelengths, xy, label)
        Spectral loci, monochromatic lights: the first a solid line with
        every 50 nm labelled, any further one dashed; each ``label`` the
        legend's words for it (which lights, at what intensity).
    labels : sequence of str
        Names of the receptor vertices, in the order of the first outline vertices.
    """
    fig = Figure(figsize=(5.4, 6.0), layout="constrained")
    ax = fig.subplots()
    ax.plot(*np.vstack([outline, outline[:1]]).T, color="0.5", linewidth=0.8)
    step = max(1, len(outline) // len(labels))
    for k, name in enumerate(labels):
        vertex = outline[k * step]
        out = vertex / np.linalg.norm(vertex)
        ax.annotate(name, vertex, xytext=8 * out, textcoords="offset points", fontsize=10, color="0.25",
                    ha="left" if out[0] > 0.3 else "right" if out[0] < -0.3 else "center",
                    va="bottom" if out[1] > 0.3 else "top" if out[1] < -0.3 else "center")
    for k, (_, xy, label) in enumerate(loci):
        ax.plot(*xy.T, color="k" if k == 0 else "0.45", linewidth=0.8, linestyle="-" if k == 0 else "--",
                label=label)
    width = np.ptp(outline[:, 0])
    wl, xy, _ = loci[0]
    for text, p in _locus_labels(wl, xy, width):
        ax.plot(*p, ".", color="k", markersize=3)
        ax.annotate(text, p, xytext=(3, 3), textcoords="offset points", fontsize=7)
    ax.scatter(*points.T, c=np.clip(colours, 0, 1), s=4, linewidths=0, alpha=0.7,
               label="each receptor's light, in its human colour (CIE 1931, sRGB)")
    ax.plot(0, 0, "+", color="0.3", label="the adapting background")
    margin = 0.12 * width
    ax.set_xlim(outline[:, 0].min() - margin, outline[:, 0].max() + margin)
    ax.set_ylim(outline[:, 1].min() - margin, outline[:, 1].max() + margin)
    ax.set_aspect("equal")
    ax.set_title(textwrap.fill(title, 60), fontsize=9)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    fig.legend(loc="outside lower center", fontsize=7, frameon=False, markerscale=3)
    save(fig, path)


def field_of_view(azimuth_deg, elevation_deg, seen, path, title, border=None):
    """One eye's field on an equirectangular map in its own azimuth, with a measured border.

    Parameters
    ----------
    azimuth_deg : ndarray (w,)
        Eye azimuth of each column, increasing, degrees (0 ahead, positive lateral).
    elevation_deg : ndarray (h,)
        Elevation of each row, decreasing.
    seen : ndarray of bool (h, w)
    border : (elevation, medial, lateral) arrays, optional
        The measured field's limits of azimuth at each elevation.
    """
    fig = Figure(figsize=(7.0, 3.9), layout="constrained")
    ax = fig.subplots()
    box = (azimuth_deg[0], azimuth_deg[-1], elevation_deg[-1], elevation_deg[0])
    ax.imshow(np.where(seen, 0.55, 0.92), extent=box, cmap="gray", vmin=0, vmax=1, interpolation="nearest",
              aspect="auto")
    if border is not None:
        e, medial, lateral = border
        ax.plot(np.concatenate([medial, lateral[::-1], medial[:1]]), np.concatenate([e, e[::-1], e[:1]]),
                color="tab:red", linewidth=1.2, label="measured border (Stürzl et al. 2010, after Seidl 1982)")
        ax.legend(loc="lower right", fontsize=7, frameon=False)
    ax.set(xlim=(box[0], box[1]), ylim=(-90, 90), xticks=range(-90, 271, 45), yticks=range(-90, 91, 30),
           xlabel="azimuth, ° (0 ahead, positive lateral)", ylabel="elevation, °")
    ax.grid(color="0.7", linewidth=0.3)
    ax.set_title(textwrap.fill(title, 90), fontsize=9)
    save(fig, path)


def _arrow(ax, start, direction, length, label):
    tip = start + length * np.asarray(direction)
    # White with a dark edge: legible on a black unlit half and a white sky alike.
    edge = [patheffects.withStroke(linewidth=2.2, foreground="0.1")]
    ax.annotate("", xy=tip, xytext=start, arrowprops={"arrowstyle": "-|>", "color": "w", "linewidth": 1.2,
                                                       "path_effects": edge})
    # Where the label goes is decided on screen, where a mirrored panel's x runs backwards.
    dx, dy = direction[0] * (-1 if ax.xaxis_inverted() else 1), direction[1]
    ax.annotate(label, tip, xytext=(4 * dx, 4 * dy), textcoords="offset points", fontsize=8, color="w",
                path_effects=edge, ha="left" if dx > 0.3 else "right" if dx < -0.3 else "center",
                va="bottom" if dy > 0.3 else "top" if dy < -0.3 else "center")


def retinas(images, extents, anterior, dorsal):
    """Both eyes' retinal images side by side, in millimetres, with their orientation and exposure: a figure
    for each of ``images``, written to its path.

    Figures of one kind (colour, or one channel with its colour bar) are laid
    out alike: one figure of each kind is laid out for the first of its
    images, then redrawn with each next image, title and caption (laying a
    figure out is most of its drawing).

    Parameters
    ----------
    images : iterable of (image, path, title, caption, colourbar_label)
        ``image`` (h, 2w, 3) or (h, 2w): display values in [0, 1], the left
        eye in the left half; NaN outside the eyes, shown as the light grey
        surround, so that a receptor that caught nothing (black) stands
        apart from it. ``caption``: the exposure, what maps catches to grey
        levels. ``colourbar_label``: for a single channel (drawn in grey, 0
        black to 1 white), the label of its colour bar, else None.
    extents : pair of (x0, x1, y_bottom, y_top)
        Each half's extent in the retinal plane, mm; the right eye's runs
        from larger to smaller x, since it is shown mirrored.
    anterior, dorsal : array_like (2,)
        The head's anterior and dorsal directions in the retinal plane.
    """
    drawn = {}
    for image, path, title, caption, colourbar_label in images:
        kind = (image.ndim, colourbar_label)
        if kind not in drawn:
            drawn[kind] = retina_figure(image, extents, anterior, dorsal, title, caption, colourbar_label)
            save(drawn[kind][0], path)
            # No layout engine from here on (not even "none", with which saving draws the figure twice).
            drawn[kind][0].set_layout_engine(None)
            continue
        fig, shown, heading, note, width = drawn[kind]
        for artist, half in zip(shown, _halves(image)):
            artist.set_data(half)
        heading.set_text(title)
        note.set_text(_caption(caption, width))
        save(fig, path)


def _halves(image):
    """The left and right eyes' halves of a retinal image, as imshow takes them: a channel masked where NaN,
    colours with an alpha channel that is zero there."""
    w = image.shape[1] // 2
    for half in (image[:, :w], image[:, w:]):
        yield np.ma.masked_invalid(half) if half.ndim == 2 else np.dstack([np.nan_to_num(half),
                                                                           np.isfinite(half).all(-1)])


def _caption(caption, width):
    # About 18 characters of 7-point text to the inch.
    return textwrap.fill(caption, int(18 * width))


def retina_figure(image, extents, anterior, dorsal, title, caption, colourbar_label):
    """A figure of :func:`retinas` (a matplotlib Figure), with what changes from image to image: the two images'
    artists, the title's and the caption's texts, and the figure's width, inches."""
    x0, x1, y0, y1 = extents[0]
    # Panels as wide as the eyes are, so that a tall eye does not leave the figure empty.
    aspect = min(max(abs(x1 - x0) / abs(y1 - y0), 0.4), 1.6)
    width = max(2.0 * 3.4 * aspect + (1.2 if colourbar_label else 0.6), 5.6)
    fig = Figure(figsize=(width, 5.4), layout="constrained")
    # The bottom strip is kept for the caption, which the layout engine would not always clear.
    fig.get_layout_engine().set(rect=(0.0, 0.1, 1.0, 0.9))
    axes = fig.subplots(1, 2, sharey=True)
    shown = []
    for ax, half, extent, name in zip(axes, _halves(image), extents, ("left eye", "right eye")):
        ax.set_facecolor("0.85")
        grey = dict(cmap="gray", vmin=0.0, vmax=1.0) if half.ndim == 2 else {}
        shown.append(ax.imshow(half, extent=extent, interpolation="nearest", **grey))
        ax.set_xlim(extent[0], extent[1])
        ax.set_aspect("equal")
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("retinal plane, mm")
        x0, x1, y0, y1 = extent
        # Below and behind the middle, so the anterior arrow crosses the panel.
        span = abs(x1 - x0)
        start = np.array([0.5 * (x0 + x1) - 0.34 * span * np.sign(anterior[0] or 1), y0 + 0.14 * (y1 - y0)])
        length = 0.12 * span
        _arrow(ax, start, dorsal, length, "dorsal")
        _arrow(ax, start, anterior, length, "anterior")
    axes[0].set_ylabel("retinal plane, mm")
    if colourbar_label is not None:
        fig.colorbar(shown[-1], ax=axes, label=colourbar_label, shrink=0.7)
    heading = fig.suptitle(title, fontsize=10)
    note = fig.text(0.5, 0.01, _caption(caption, width), ha="center", va="bottom", fontsize=7)
    return fig, shown, heading, note, width


def visual_field(panels, eyes, azimuth_deg, elevation_deg, human, path, title):
    """Equirectangular maps of the bee's visual field beside the human view of the same scene.

    Parameters
    ----------
    panels : dict of str to ndarray (h, w, 3)
        Title to display-ready RGB map, NaN where no receptor sees.
    eyes : ndarray (h, w)
        Bits of the eyes that see each direction; the binocular overlap
        (both bits) is outlined.
    azimuth_deg, elevation_deg : ndarray
        Pixel centres.
    human : ndarray (H, W, 3) or None
        The human pinhole render.
    """
    save(visual_field_figure(panels, eyes, azimuth_deg, elevation_deg, human, title, 5.2)[0], path)


def visual_field_frames(frames, eyes, azimuth_deg, elevation_deg):
    """:func:`visual_field` as RGB images (h, w, 3) of uint8, the frames of an animation, one for each of
    ``frames`` (panels, human, title: as :func:`visual_field` takes them), yielded in turn.

    One figure draws them all: laid out for the first frame, then redrawn
    with each frame's maps, human view and title (laying a figure out is
    most of its drawing, and every frame's layout is the first's).
    """
    fig = canvas = None
    for panels, human, title in frames:
        shown = [np.nan_to_num(rgb, nan=0.35) for rgb in panels.values()] + ([] if human is None else [human])
        if fig is None:
            fig, heading = visual_field_figure(panels, eyes, azimuth_deg, elevation_deg, human, title, 3.6)
            canvas = FigureCanvasAgg(fig)
            canvas.draw()
            fig.set_layout_engine(None)
        else:
            for ax, image in zip(fig.axes, shown):
                ax.images[0].set_data(image)
            heading.set_text(_field_title(title))
            canvas.draw()
        yield np.asarray(canvas.buffer_rgba())[..., :3].copy()


def _field_title(title):
    return title + " — white outline: binocular overlap; grey: not seen"


def visual_field_figure(panels, eyes, azimuth_deg, elevation_deg, human, title, panel_width_in):
    """The figure of :func:`visual_field` (a matplotlib Figure, ``panel_width_in`` inches a panel), and its
    title's text."""
    n = len(panels) + (human is not None)
    fig = Figure(figsize=(panel_width_in * n, panel_width_in * 0.73), layout="constrained", dpi=100)
    axes = fig.subplots(1, n)
    box = (azimuth_deg[0], azimuth_deg[-1], elevation_deg[-1], elevation_deg[0])
    for ax, (name, rgb) in zip(axes, panels.items()):
        ax.imshow(np.nan_to_num(rgb, nan=0.35), extent=box, interpolation="nearest")
        ax.contour(azimuth_deg, elevation_deg, (eyes == 3).astype(float), levels=[0.5],
                   colors="w", linewidths=0.8)
        ax.set(xlim=(180, -180), ylim=(-90, 90), xticks=range(-180, 181, 60), yticks=range(-90, 91, 30),
               xlabel="azimuth, ° (+ to the bee's left)", ylabel="elevation, °")
        ax.set_title(name, fontsize=9)
        ax.grid(color="0.6", linewidth=0.3)
    if human is not None:
        axes[-1].imshow(human)
        axes[-1].set_axis_off()
        axes[-1].set_title("human view (CIE 1931, sRGB)", fontsize=9)
    return fig, fig.suptitle(_field_title(title), fontsize=10)


def optic_flow(azimuth_deg, elevation_deg, flow_deg_s, path, title):
    """The optic flow of every receptor as arrows on the visual field (azimuth, elevation), coloured by speed.

    ``flow_deg_s`` (n, 2) are the components along increasing azimuth and
    elevation, degrees per second; arrows are drawn to a common scale.
    """
    speed = np.hypot(*flow_deg_s.T)
    fig = Figure(figsize=(9.0, 4.8), layout="constrained")
    ax = fig.subplots()
    # Azimuth increases to the left on these maps, as the bee's visual field is drawn.
    q = ax.quiver(azimuth_deg, elevation_deg, -flow_deg_s[:, 0], flow_deg_s[:, 1], speed, cmap="viridis",
                  angles="xy", scale_units="xy", scale=np.percentile(speed, 95) / 8.0 + 1e-12, width=0.0015)
    fig.colorbar(q, ax=ax, label="image speed, ° s⁻¹")
    ax.set(xlim=(180, -180), ylim=(-90, 90), xticks=range(-180, 181, 60), yticks=range(-90, 91, 30),
           xlabel="azimuth, ° (+ to the bee's left)", ylabel="elevation, °", aspect="equal")
    ax.grid(color="0.8", linewidth=0.3)
    ax.set_title(title, fontsize=9)
    save(fig, path)


def dorsal_rim(azimuth_deg, elevation_deg, microvilli_deg, pol, path, title):
    """The dorsal rim's POL units where they look (azimuth, elevation), coloured by their response,
    each with its microvilli's orientation (0° towards the zenith on the map) as a short line."""
    fig = Figure(figsize=(9.0, 3.8), layout="constrained")
    ax = fig.subplots()
    limit = max(float(np.nanmax(np.abs(pol))), 1e-9)
    dots = ax.scatter(azimuth_deg, elevation_deg, c=pol, cmap="coolwarm", vmin=-limit, vmax=limit, s=28,
                      edgecolors="0.3", linewidths=0.3)
    # Azimuth increases to the left, as on the visual-field maps; the anterior direction is
    # drawn towards azimuth 0.
    turn = np.radians(microvilli_deg)
    towards_front = -np.sign(azimuth_deg)
    dx, dy = 2.5 * np.sin(turn) * towards_front, 2.5 * np.cos(turn)
    ax.plot(np.stack([azimuth_deg - dx, azimuth_deg + dx]), np.stack([elevation_deg - dy, elevation_deg + dy]),
            color="k", linewidth=0.6)
    fig.colorbar(dots, ax=ax, label="POL response (R∥ − R⊥)/(R∥ + R⊥)")
    ax.set(xlim=(180, -180), ylim=(20, 90), xticks=range(-180, 181, 60), xlabel="azimuth, ° (+ to the bee's left)",
           ylabel="elevation, °")
    ax.grid(color="0.8", linewidth=0.3)
    ax.set_title(title, fontsize=9)
    save(fig, path)


def compass(rows, path, title):
    """The sky compass over a full turn: its estimate of the solar azimuth against the truth, and its error,
    per condition (``rows``: columns of the compass table)."""
    fig = Figure(figsize=(10.0, 4.2), layout="constrained")
    left, right = fig.subplots(1, 2)
    condition = np.asarray(rows["condition"])
    for name in dict.fromkeys(condition):
        k = condition == name
        truth, estimate = np.asarray(rows["solar_azimuth_deg"])[k], np.asarray(rows["estimate_deg"])[k]
        order = np.argsort(truth)
        left.plot(truth[order], estimate[order], ".", markersize=4, label=name)
        right.plot(np.asarray(rows["heading_deg"])[k], np.asarray(rows["error_deg"])[k], "-", linewidth=1.0,
                   label=name)
    left.plot([-180, 180], [-180, 180], color="0.5", linewidth=0.6)
    left.set(xlim=(-180, 180), ylim=(-180, 180), xticks=range(-180, 181, 90), yticks=range(-180, 181, 90),
             xlabel="true solar azimuth, head frame, °", ylabel="compass estimate, °", aspect="equal")
    right.axhline(0.0, color="0.5", linewidth=0.6)
    right.set(xlim=(0, 360), xticks=range(0, 361, 90), xlabel="heading turned from the scene's, °",
              ylabel="compass error, °")
    right.legend(fontsize=7)
    for ax in (left, right):
        ax.grid(color="0.85", linewidth=0.3)
    fig.suptitle(title, fontsize=9)
    save(fig, path)


#: Colours of the right eye's field, the left's and their overlap in :func:`eye_fields`.
FIELD_COLOURS = {1: (0.85, 0.45, 0.2), 2: (0.25, 0.5, 0.8), 3: (0.35, 0.25, 0.45)}


def eye_fields(fields, path, columns=3):
    """Both eyes' fields of several eye classes, one equirectangular panel each, head azimuth.

    Parameters
    ----------
    fields : dict of str to VisualField
        Eye class to its field (:func:`beeoptics.eye.fieldofview.visual_field`).
    """
    from beeoptics.eye.fieldofview import extent

    rows = -(-len(fields) // columns)
    fig = Figure(figsize=(3.3 * columns, 1.95 * rows + 0.5), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, columns, sharex=True, sharey=True)).ravel()
    for ax, (name, field) in zip(axes, fields.items()):
        rgb = np.full((*field.eyes.shape, 3), 0.93)
        for bits, colour in FIELD_COLOURS.items():
            rgb[field.eyes == bits] = colour
        # Azimuth runs towards the left across the map, as a bee facing the reader sees it.
        az = field.azimuth_deg
        ax.imshow(rgb, extent=(az[0], az[-1], field.elevation_deg[-1], field.elevation_deg[0]), aspect="auto",
                  interpolation="nearest")
        sr = extent(field)
        ax.set_title(f"{name}\n{sr['right_sr']:.2f} sr an eye, {sr['binocular_sr']:.2f} sr binocular", fontsize=7)
        ax.set(xlim=(180, -180), ylim=(-90, 90), xticks=range(-180, 181, 90), yticks=range(-90, 91, 45))
        ax.tick_params(labelsize=6)
        ax.grid(color="0.6", linewidth=0.3)
    for ax in axes[len(fields):]:
        ax.set_visible(False)
    fig.supxlabel("azimuth, ° (0 ahead, positive left)", fontsize=8)
    fig.supylabel("elevation, °", fontsize=8)
    fig.suptitle("Fields of view: right eye (orange), left eye (blue), both (purple); within Δρ/2 of an axis or "
                 "inside the lattice", fontsize=8)
    save(fig, path)


#: Taylor et al.'s (2019) scaling exponents against body size (intertegular width) within B. terrestris:
#: "We found a scaling exponent of 0.45 for eye surface area vs. ITW" (its square root, as all their areas:
#: "by taking the square root of areas"), and "the visual field of a single eye (we found 0.17 ...) and the
#: binocular regions (0.79 ...)".
TAYLOR_EXPONENTS = {"sqrt_corneal_area_mm": 0.45, "right_sr": 0.17, "binocular_sr": 0.79}


def allometry(rows, path, species="Bombus terrestris"):
    """The bumblebees' eye size, fields and Δφ against body size, beside Taylor et al.'s (2019) published trends.

    Each panel is log–log against intertegular width; a published exponent
    is drawn through the bees' geometric mean, and the bees' own
    least-squares exponent is given beside it. Facet counts are left out:
    most of the specimens' counts are taken from Taylor et al.'s allometry
    itself, so would only repeat it.

    Parameters
    ----------
    rows : list of dict
        Rows of the acuity table (:func:`beeoptics.pipeline.eyes.acuity_table`).
    """
    bees = [r for r in rows if r["species"] == species and np.isfinite(r["intertegular_width_mm"])]
    panels = (("sqrt_corneal_area_mm", "√(corneal area), mm"), ("right_sr", "one eye's field, sr"),
              ("binocular_sr", "binocular overlap, sr"), ("delta_phi_deg_p50", "median Δφ, °"))
    fig = Figure(figsize=(10.0, 2.9), layout="constrained")
    axes = fig.subplots(1, len(panels))
    itw = np.array([r["intertegular_width_mm"] for r in bees])
    for ax, (key, label) in zip(axes, panels):
        y = np.array([np.sqrt(r["corneal_area_mm2"]) if key == "sqrt_corneal_area_mm" else r[key] for r in bees])
        ok = np.isfinite(y) & (y > 0)
        ax.set(xscale="log", yscale="log", xlabel="intertegular width, mm")
        ax.set_title(label, fontsize=9)
        if ok.sum() >= 2:
            slope = np.polyfit(np.log(itw[ok]), np.log(y[ok]), 1)[0]
            ax.plot(itw[ok], y[ok], "o", color="tab:orange", label=f"ours: exponent {slope:.2f}")
            if key in TAYLOR_EXPONENTS:
                x = np.geomspace(itw[ok].min(), itw[ok].max(), 20)
                mid = np.exp(np.log(y[ok]).mean()) * (x / np.exp(np.log(itw[ok]).mean())) ** TAYLOR_EXPONENTS[key]
                ax.plot(x, mid, color="0.3", linewidth=1, label=f"Taylor et al. 2019: {TAYLOR_EXPONENTS[key]:.2f}")
            ax.legend(fontsize=7, frameon=False)
        # Plain numbers at a close set of steps: the data span less than a decade.
        ax.set_xticks([2, 3, 4, 5, 6], minor=False)
        ax.yaxis.set_major_locator(LogLocator(subs=(1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0)))
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(FormatStrFormatter("%g"))
            axis.set_minor_formatter(NullFormatter())
        ax.tick_params(labelsize=7)
    fig.suptitle(f"{species}: the eyes built here on Taylor et al.'s (2019) scans against body size; fields "
                 "from the corneal normals", fontsize=9)
    save(fig, path)


def detection_distances(tables, path, scene=""):
    """From how far each eye detects each species' flowers: one panel per eye, the achromatic and the
    chromatic criterion's first distances per approach with their intervals, by species, log scale.

    Parameters
    ----------
    tables : dict of str to dict
        Eye class to its approaches table (:func:`beeoptics.pipeline.detection.survey`).
    """
    fig = Figure(figsize=(4.2 * max(1, len(tables)), 4.0), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, max(1, len(tables)), sharey=True))
    for ax, (eye, t) in zip(axes, tables.items()):
        species = np.asarray(t["species"]).astype(str)
        names = sorted(set(species))
        for k, s in enumerate(names):
            for shift, (column, colour, label) in zip((-0.15, 0.15), (
                    ("first_achromatic", "tab:green", "green + colour contrast"),
                    ("first_chromatic", "tab:purple", "colour contrast alone"))):
                mine = species == s
                # Each approach's 95 % interval: between the first distances at which noise could not
                # flip the verdict and at which it could make it.
                near, far = (np.asarray(t[f"{column}_{end}_m"], float)[mine] for end in ("near", "far"))
                ax.vlines(np.full(mine.sum(), k + shift), np.where(np.isfinite(near), near, far), far, color=colour,
                          linewidth=0.6, alpha=0.5)
                d = np.asarray(t[f"{column}_m"], float)[mine]
                d = d[np.isfinite(d)]
                if d.size:
                    ax.plot(np.full(d.size, k + shift), d, "o", ms=3, color=colour, alpha=0.6,
                            label=label if k == 0 else None)
                    ax.plot([k + shift - 0.1, k + shift + 0.1], [np.median(d)] * 2, color=colour, linewidth=2)
        ax.set_xticks(range(len(names)), [n.replace("_", " ") for n in names], rotation=35, ha="right", fontsize=7,
                      style="italic")
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
        ax.tick_params(axis="y", which="both", labelsize=7)
        ax.set_title(eye, fontsize=9)
        ax.grid(axis="y", color="0.85", linewidth=0.5)
        ax.legend(fontsize=6, frameon=False, loc="upper right")
    axes[0].set_ylabel("detection distance, m (first approaching)")
    fig.suptitle(textwrap.fill(f"{scene}: from how far the bee first detects each flower (Giurfa et al.'s rule, "
                               "1996, its angles by eye region, 1999, as the traced receptors saw the flower "
                               "against its surround); bars: medians; lines: each approach's 95 % interval",
                               55 * max(1, len(tables))), fontsize=8)
    save(fig, path)


def flight_detection(columns, first, rule, path, title):
    """The target along a flight, against its distance: its angular size beside the rule's angles, and
    its contrasts beside the rule's thresholds, each criterion's first detection marked.

    Parameters
    ----------
    columns : dict of ndarray
        A flight's detection table (:func:`beeoptics.pipeline.flights.flight_products`).
    first : dict
        :func:`beeoptics.pipeline.flights.first_detections`.
    rule : dict or None
        The receptor set's ``detection`` rule.
    """
    d = columns["distance_m"]
    fig = Figure(figsize=(9.0, 3.6), layout="constrained")
    size, contrast = fig.subplots(1, 2, sharex=True)
    size.plot(d, columns["angular_diameter_deg"], color="0.2", label="angular diameter")
    size.plot(d, columns["receptors_covered"], color="tab:orange", label="receptors covered (≥ half)")
    contrast.plot(d, columns["green_dS"], color="tab:green", label="green contrast, receptor noise units")
    contrast.plot(d, columns["rnl_dS"], color="tab:purple", label="colour distance ΔS (RNL)")
    if rule is not None:
        # The rule's angles where the target falls, by eye region where the rule gives them so.
        for criterion, colour in (("achromatic", "tab:green"), ("chromatic", "tab:purple")):
            size.plot(d, columns[f"{criterion}_min_angle_deg"], color=colour, linestyle=":", linewidth=1,
                      label=f"{criterion}: its smallest angle")
        contrast.axhline(rule["chromatic"]["contrast"]["threshold"], color="0.5", linestyle=":", linewidth=1,
                         label="threshold, 1 JND")
    for name, colour, label in (("achromatic_detectable", "tab:green", "first detected: green + colour"),
                                ("chromatic_detectable", "tab:purple", "first detected: colour alone")):
        if first.get(name):
            for ax in (size, contrast):
                ax.axvline(first[name]["distance_m"], color=colour, linewidth=1.2,
                           label=f"{label}, {first[name]['distance_m']:.2f} m" if ax is size else None)
    for ax in (size, contrast):
        ax.set_xscale("log")
        ax.invert_xaxis()
        ax.set_xlabel("distance to the target, m")
        ax.grid(color="0.88", linewidth=0.5)
        ax.legend(fontsize=6, frameon=False)
        ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
    size.set_yscale("log")
    size.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    size.set_ylabel("degrees, receptors")
    contrast.set_ylabel("JND")
    fig.suptitle(textwrap.fill(title, 100), fontsize=9)
    save(fig, path)


def catchment_areas(panels, reference_xy, heading_deg, path, title):
    """Catchment areas on a grid of places: one panel per eye and signal, the tIDF in grey, its descent as
    arrows (each place's step to its next place), the catchment area outlined and the reference place and
    heading marked.

    Parameters
    ----------
    panels : list of (str, ndarray, ndarray, ndarray, ndarray, ndarray)
        Each panel's title, the places' x and y (rows, columns), m, the tIDF,
        whether each place is in the catchment area (bool) and each place's
        next place descending (flat indices, :func:`beeoptics.navigation.catchment.descent`).
    reference_xy : (float, float)
        The reference place, m.
    heading_deg : float
        The reference heading, degrees from +x towards +y.
    """
    columns = min(len(panels), 4)
    rows = -(-len(panels) // columns)
    fig = Figure(figsize=(2.6 * columns, 2.6 * rows + 0.5), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, columns, squeeze=False)).ravel()
    for ax, (label, x, y, field, inside, step) in zip(axes, panels):
        spacing = x[0, 1] - x[0, 0] if x.shape[1] > 1 else 1.0
        edges = (x.min() - spacing / 2, x.max() + spacing / 2, y.min() - spacing / 2, y.max() + spacing / 2)
        # Black at the display's exposure percentile, not at the maximum: a place inside a flower head differs
        # from the reference many times as much as the rest, which a maximum would leave white.
        ax.imshow(field, origin="lower", extent=edges, cmap="Greys", interpolation="nearest", vmin=0.0,
                  vmax=np.nanpercentile(field, EXPOSURE_PERCENTILE))
        ax.set_xlim(edges[:2])
        ax.set_ylim(edges[2:])
        moves = step.ravel() != np.arange(step.size)
        ax.quiver(x.ravel()[moves], y.ravel()[moves], (x.ravel()[step.ravel()] - x.ravel())[moves],
                  (y.ravel()[step.ravel()] - y.ravel())[moves], color="tab:orange", angles="xy", scale_units="xy",
                  scale=1.5, width=0.012)
        # Outlined on the grid padded with a ring of places outside, so that a catchment reaching its edge closes.
        ring = np.arange(-1, x.shape[1] + 1) * spacing + x[0, 0], np.arange(-1, x.shape[0] + 1) * spacing + y[0, 0]
        ax.contour(*ring, np.pad(inside.astype(float), 1), levels=[0.5], colors="tab:blue", linewidths=1.2)
        h = np.radians(heading_deg)
        ax.plot(*reference_xy, "o", color="tab:blue", ms=4)
        ax.annotate("", xy=(reference_xy[0] + spacing * np.cos(h), reference_xy[1] + spacing * np.sin(h)),
                    xytext=reference_xy, arrowprops={"arrowstyle": "->", "color": "tab:blue"})
        ax.set_title(label, fontsize=8)
        ax.set_aspect("equal")
        ax.tick_params(labelsize=6)
    for ax in axes[len(panels):]:
        ax.set_axis_off()
    fig.suptitle(textwrap.fill(f"{title} (grey: tIDF, darker higher, black from its {EXPOSURE_PERCENTILE:g}th "
                               "percentile; arrows: its descent, place to place; blue: the catchment area and the "
                               "reference place and heading; x, y in m)", 40 * columns), fontsize=8)
    save(fig, path)
