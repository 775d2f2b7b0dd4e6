"""Figures of the eyes and their optics, drawn with matplotlib and written atomically.

The relaxation figure reproduces Collins' Fig. 7: the facet lattice at its
initial projection, during relaxation and at rest, seen along the eye's z-axis
and coloured by the target facet diameter.
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from beeoptics.atomic import atomic_path  # noqa: E402

#: PNG metadata without a version string, so figures do not change with matplotlib's.
_METADATA = {"Software": None}


def save(fig, path):
    """Write a figure as PNG atomically and close it."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=150, metadata=_METADATA, format="png")
    plt.close(fig)


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
    fig, axes = plt.subplots(1, s, figsize=(3.6 * s, 3.9), sharex=True, sharey=True,
                             constrained_layout=True)
    lo, hi = np.min(diameter_um), np.max(diameter_um)
    for k, ax in enumerate(np.atleast_1d(axes)):
        _eye_axes(ax, boundary_xy)
        marker = _marker_size(ax, fig, boundary_xy, snapshots.shape[1])
        dots = ax.scatter(*snapshots[k, :, :2].T, c=diameter_um[k], s=marker, vmin=lo, vmax=hi,
                          cmap="viridis", linewidths=0)
        stage = "initial grid" if k == 0 else "at rest" if k == s - 1 else "relaxing"
        ax.set_title(f"{stage}, iteration {iterations[k]}", fontsize=9)
    fig.colorbar(dots, ax=axes, label="target facet diameter, µm", shrink=0.8)
    fig.suptitle(f"{eye_name}: facet lattice relaxation (Collins Fig. 7)")
    save(fig, path)


def eye_map(points, values, boundary_xy, path, label, title):
    """A per-facet quantity over the eye, seen along its z-axis, shaded between facets."""
    fig, ax = plt.subplots(figsize=(5.2, 4.4), constrained_layout=True)
    _eye_axes(ax, boundary_xy)
    lo, hi = np.percentile(values, [1, 99])
    field = ax.tripcolor(*points[:, :2].T, values, shading="gouraud", vmin=lo, vmax=hi, cmap="magma")
    fig.colorbar(field, ax=ax, label=label)
    ax.set_title(title, fontsize=10)
    save(fig, path)
