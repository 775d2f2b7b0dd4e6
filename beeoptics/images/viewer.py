"""Interactive viewers: what each eye sees, one self-contained HTML page (plotly), every receptor one hover away.

A scene's viewer shows both eyes' receptors where they look: on an
equirectangular map of the visual field (azimuth to the bee's left, as the
PNG maps run) and on a sphere the reader turns, coloured by map3, by each
receptor class alone (over white's catch), by map2 (the human colour of the
receptor's light) and, where traced, by polarisation (hue the angle,
saturation the degree). Hovering a receptor gives its id, eye, azimuth and
elevation, Δφ, Δρ, facet diameter, catches, colour-space coordinates and
RNL distance. The species' colour space (the hexagon, where it has one) is
linked to the map: receptors selected in either (box or lasso) are
highlighted in the other, and enlarged on the sphere. A flight's viewer
has a slider over its frames.

The page embeds plotly.js (``include_plotlyjs=True``): it opens from disk,
with no network. plotly draws everything; the page's own script only links
the selection between the panels.

References
----------
Plotly Technologies Inc. (2015) Collaborative data science. https://plot.ly
"""

import json
import re
import textwrap

import numpy as np

from beeoptics.headframe import LEFT, RIGHT, eye_azimuth_elevation
from beeoptics.io.atomic import atomic_path

#: The figure's element: named, since plotly would name it at random and the page differ from run to run.
DIV_ID = "beeoptics-viewer"
#: Colour of the receptors a selection leaves out, and the size of a point on the map and the sphere.
UNSELECTED_OPACITY, MAP_MARKER, SPHERE_MARKER = 0.15, 3, 2
#: The page's script: every colouring is embedded once, and a colouring button recolours every trace
#: from it (each trace's copy would otherwise take the file again); a selection in the map or the
#: colour space selects the same receptors in both and enlarges them on the sphere (plotly's 3-D
#: scatter has no selection of its own).
PAGE_SCRIPT = r"""
var gd = document.getElementById('{plot_id}');
var colourings = %(colourings)s, linked = %(linked)s, traces = %(traces)s, sphere = %(sphere)d;
var n = %(n)d, ids = %(ids)s, az = %(az)s, el = %(el)s;
// A link to the page ending in #receptor=<id> opens that receptor's hover label on the map.
var m = /receptor=(\d+)/.exec(window.location.hash), k = m ? ids.indexOf(Number(m[1])) : -1;
if (k >= 0) { Plotly.Fx.hover(gd, {xval: az[k], yval: el[k]}, "xy"); }
// One line for whoever drives the page headless: when it was drawn.
console.log('beeoptics viewer: ' + JSON.stringify({drawn_ms: Math.round(performance.now()), receptors: n}));
gd.on('plotly_buttonclicked', function (ev) {
  var c = colourings[ev.button.label];
  if (c) { Plotly.restyle(gd, {'marker.color': traces.map(function () { return c; })}, traces); }
});
function pick(points) {
  var sizes = new Array(n).fill(%(small)d), chosen = [];
  points.forEach(function (p) { if (linked.indexOf(p.curveNumber) >= 0) { chosen.push(p.pointIndex); } });
  chosen.forEach(function (i) { sizes[i] = %(big)d; });
  Plotly.restyle(gd, {selectedpoints: linked.map(function () { return chosen; })}, linked);
  Plotly.restyle(gd, {'marker.size': [chosen.length ? sizes : %(small)d]}, [sphere]);
}
gd.on('plotly_selected', function (ev) { if (ev) { pick(ev.points); } });
gd.on('plotly_deselect', function () {
  Plotly.restyle(gd, {selectedpoints: linked.map(function () { return null; })}, linked);
  Plotly.restyle(gd, {'marker.size': [%(small)d]}, [sphere]);
});
"""


#: A flight's page says, for whoever drives it headless, when it was drawn and how many frames it has.
FLIGHT_SCRIPT = """
var gd = document.getElementById('{plot_id}');
console.log('beeoptics viewer: ' + JSON.stringify({drawn_ms: Math.round(performance.now()),
  receptors: gd.layout.meta.receptors, frames: gd.layout.meta.frames}));
"""

#: Where the head's directions lie on the map (azimuth + to the bee's left), in the head frame of
#: :mod:`beeoptics.headframe`.
ORIENTATION = [{"text": text, "x": x, "y": y, "xref": "x", "yref": "y", "showarrow": False,
                "font": {"size": 11, "color": "#555"}, "bgcolor": "rgba(255,255,255,0.7)"}
               for text, x, y in (("ahead", 0, -84), ("left", 90, -84), ("right", -90, -84), ("behind", 170, -84),
                                  ("behind", -170, -84), ("dorsal", 0, 86))]


#: The same on the globe: (label, azimuth, elevation), degrees.
GLOBE_ORIENTATION = (("ahead", 0, 0), ("left", 60, 0), ("right", -60, 0), ("behind", 180, 0), ("dorsal", 0, 75),
                     ("ventral", 0, -75))


def _hex(rgb):
    """Display sRGB in [0, 1] (n, 3), NaN grey, as "#rrggbb" strings."""
    v = np.rint(np.clip(np.nan_to_num(np.asarray(rgb, float), nan=0.35), 0.0, 1.0) * 255).astype(int)
    return [f"#{c:06x}" for c in (v[:, 0] << 16 | v[:, 1] << 8 | v[:, 2]).tolist()]


def receptor_viewer(path, receptors, colours, hover, title, caption, colour_space=None, polarisation=None):
    """Write a scene's viewer: both eyes' receptors on the map, the sphere and the colour space.

    Parameters
    ----------
    path : path
        The HTML file, written atomically.
    receptors : ReceptorTable
    colours : dict of str to ndarray (n, 3)
        Display sRGB in [0, 1] of every receptor per colouring ("map3", "UV", …, "map2"), the first shown.
    hover : dict of str to ndarray (n,) or to (ndarray (n,), ndarray (n,))
        The numbers shown on hovering a receptor, by label (units in the label); a pair is a number
        and its standard error, shown as value ± error.
    colour_space : dict, optional
        ``x``, ``y`` (n,) of every receptor, ``outline`` (k, 2), ``locus`` (m, 2) with ``locus_label``,
        ``name``: the species' colour space, linked to the map.
    polarisation : ndarray (n, 3), optional
        Display colours of each receptor's polarisation, a further colouring.
    """
    import plotly.graph_objects as go
    import plotly.io as pio
    from plotly.subplots import make_subplots

    axis = np.asarray(receptors.axis, float)
    az, el = eye_azimuth_elevation(axis, LEFT)  # head-frame azimuth, + to the bee's left, as the maps run
    colourings = dict(colours)
    if polarisation is not None:
        colourings["polarisation"] = polarisation
    hexes = {k: _hex(v) for k, v in colourings.items()}
    first = next(iter(hexes))
    eye = np.where(np.asarray(receptors.side).astype(str) == RIGHT, "right", "left")
    values, lines = [receptors.id, az, el], []
    for label, v in hover.items():
        lines.append(f"{label} %{{customdata[{len(values)}]:.4g}}"
                     + (f" ± %{{customdata[{len(values) + 1}]:.2g}}" if isinstance(v, tuple) else ""))
        values += [np.asarray(x, float) for x in (v if isinstance(v, tuple) else (v,))]
    # float32: the hover shows four significant figures, an error two.
    custom = np.column_stack(values).astype(np.float32)
    template = ("receptor %{customdata[0]:.0f}, %{text} eye<br>azimuth %{customdata[1]:.1f}°, "
                "elevation %{customdata[2]:.1f}°<br>" + "<br>".join(lines) + "<extra></extra>")
    specs = [[{"type": "xy", "colspan": 2}, None], [{"type": "geo"}, {"type": "xy"}]]
    fig = make_subplots(rows=2, cols=2, specs=specs, row_heights=[0.55, 0.45], vertical_spacing=0.08,
                        subplot_titles=("the visual field, both eyes (azimuth + to the bee's left)",
                                        "the same on the sphere, as from its centre (drag to turn)",
                                        colour_space["name"] if colour_space else "no colour space for this species"))
    # The colours are set after plotly has built the figure, unchecked: it would check each of their
    # tens of thousands of strings one by one (a second and a half).
    marker = {"color": "#000000", "size": MAP_MARKER}
    common = dict(customdata=custom, text=eye, hovertemplate=template, showlegend=False,
                  unselected={"marker": {"opacity": UNSELECTED_OPACITY}})
    fig.add_trace(go.Scattergl(x=az, y=el, mode="markers", marker=marker, name="receptors", **common), 1, 1)
    # The sphere is a globe in orthographic projection (drawn as SVG: a WebGL 3-D scene took Chromium a
    # second more to draw), its longitude the azimuth's mirror, so that the globe seen from outside shows
    # each hemisphere as the bee, at its centre, sees it: left on the left, as on the map.
    fig.add_trace(go.Scattergeo(lon=-az, lat=el, mode="markers", marker={"color": "#000000", "size": SPHERE_MARKER},
                                customdata=custom, text=eye, hovertemplate=template, showlegend=False), 2, 1)
    fig.update_geos(projection={"type": "orthographic", "rotation": {"lon": 0, "lat": 0}}, showland=False,
                    showocean=False, showlakes=False, showrivers=False, showcountries=False, showcoastlines=False,
                    showframe=True, bgcolor="white", lonaxis={"showgrid": True, "dtick": 30, "gridcolor": "#ccc"},
                    lataxis={"showgrid": True, "dtick": 30, "gridcolor": "#ccc"})
    linked = [0]
    if colour_space:
        fig.add_trace(go.Scattergl(x=colour_space["x"], y=colour_space["y"], mode="markers",
                                   marker={"color": "#000000", "size": MAP_MARKER}, **common), 2, 2)
        linked.append(2)
        outline = np.vstack([colour_space["outline"], colour_space["outline"][:1]])
        fig.add_trace(go.Scatter(x=outline[:, 0], y=outline[:, 1], mode="lines", line={"color": "#888", "width": 1},
                                 hoverinfo="skip", name="the space's edge"), 2, 2)
        fig.add_trace(go.Scatter(x=colour_space["locus"][:, 0], y=colour_space["locus"][:, 1], mode="lines",
                                 line={"color": "#333", "width": 1, "dash": "dot"}, hoverinfo="skip",
                                 name=colour_space["locus_label"]), 2, 2)
        fig.update_xaxes(scaleanchor="y3", row=2, col=2)
        fig.update_xaxes(range=[-1.1, 1.1], row=2, col=2)
        fig.update_yaxes(range=[-1.1, 1.1], row=2, col=2)
    # The head's directions on the globe: on the equator and at the zenith (longitude the azimuth's mirror).
    names, azimuths, elevations = zip(*GLOBE_ORIENTATION)
    fig.add_trace(go.Scattergeo(lon=-np.array(azimuths), lat=elevations, text=names, mode="text", hoverinfo="skip",
                                showlegend=False, textfont={"size": 12, "color": "#333"}), 2, 1)
    buttons = [{"label": k, "method": "skip"} for k in hexes]
    fig.update_layout(
        title={"text": title, "x": 0.01, "y": 0.985}, height=1000, width=1300, dragmode="select",
        template="plotly_white", margin={"l": 60, "r": 20, "t": 110, "b": 150},
        updatemenus=[{"buttons": buttons, "x": 0.07, "y": 1.035, "xanchor": "left", "yanchor": "bottom",
                      "direction": "right", "type": "buttons", "showactive": True}],
        annotations=[*fig.layout.annotations, *ORIENTATION,
                     {"text": "<br>".join(textwrap.wrap(caption, 190)), "xref": "paper", "yref": "paper", "x": 0.0,
                      "y": -0.1, "yanchor": "top", "showarrow": False, "align": "left", "font": {"size": 11}},
                     {"text": "colour by:", "xref": "paper", "yref": "paper", "x": 0.0, "y": 1.045,
                      "showarrow": False, "xanchor": "left", "yanchor": "bottom"}],
        legend={"x": 0.55, "y": -0.02, "yanchor": "top"})
    fig.update_xaxes(range=[180, -180], title_text="azimuth, °", tickvals=list(range(-180, 181, 45)), row=1, col=1)
    fig.update_yaxes(range=[-90, 90], title_text="elevation, °", tickvals=list(range(-90, 91, 30)), row=1, col=1)
    script = PAGE_SCRIPT % {"colourings": json.dumps(hexes, separators=(",", ":")), "linked": json.dumps(linked),
                            "traces": json.dumps([0, 1, *linked[1:]]), "sphere": 1, "small": SPHERE_MARKER,
                            "n": len(az), "ids": json.dumps(np.asarray(receptors.id).tolist()),
                            "az": json.dumps(np.round(az, 3).tolist()), "el": json.dumps(np.round(el, 3).tolist()),
                            "big": 3 * SPHERE_MARKER}
    page = fig.to_plotly_json()
    # The receptors' traces: the map, the globe and, where there is one, the colour space.
    for k in (0, 1, *linked[1:]):
        page["data"][k]["marker"]["color"] = hexes[first]
    html = pio.to_html(page, validate=False, include_plotlyjs=True, full_html=True, post_script=script, div_id=DIV_ID,
                       config={"displaylogo": False, "responsive": True})
    with atomic_path(path) as tmp:
        tmp.write_text(shared_once(html), encoding="utf-8")


def shared_once(html):
    """The page with the hover data every trace holds written once, as a variable the traces name: the
    same numbers, decoded by plotly for each trace at its first drawing, a third of the file."""
    blobs = set(re.findall(r'"customdata":(\{"dtype":"f4","bdata":"[^"]*","shape":"[^"]*"\})', html))
    if len(blobs) != 1:  # plotly wrote them otherwise: keep its page as it is
        return html
    blob = blobs.pop()
    head, body = html.split("<body>", 1)
    return head + "<body>\n<script>var beeopticsHover = " + blob + ";</script>" + body.replace(blob, "beeopticsHover")


def flight_viewer(path, receptors, frames, catches, classes, times_s, title, caption):
    """Write a flight's viewer: map3 of every receptor on the visual field, a slider over the frames.

    Parameters
    ----------
    frames : ndarray (frames, n, 3)
        Display sRGB in [0, 1] of every receptor at every frame.
    catches : ndarray (frames, n, classes)
        Each receptor's catches at each frame, shown on hovering it.
    classes : sequence of str
        The receptor classes, naming ``catches``'s last axis.
    times_s : ndarray (frames,)
    """
    import plotly.graph_objects as go
    import plotly.io as pio

    axis = np.asarray(receptors.axis, float)
    az, el = eye_azimuth_elevation(axis, LEFT)  # head-frame azimuth, + to the bee's left, as the maps run
    eye = np.where(np.asarray(receptors.side).astype(str) == RIGHT, "right", "left")
    fixed = np.column_stack([receptors.id, az, el]).astype(np.float32)
    custom = [np.column_stack([fixed, c]).astype(np.float32) for c in catches]
    template = ("receptor %{customdata[0]:.0f}, %{text} eye<br>azimuth %{customdata[1]:.1f}°, "
                "elevation %{customdata[2]:.1f}°<br>"
                + "<br>".join(f"{c} ÷ white's %{{customdata[{k + 3}]:.3g}}" for k, c in enumerate(classes))
                + "<extra></extra>")
    colours = [_hex(f) for f in frames]
    # The colours are set after plotly has built the figure, unchecked, as in receptor_viewer.
    fig = go.Figure(go.Scattergl(x=az, y=el, mode="markers", marker={"color": "#000000", "size": MAP_MARKER},
                                 customdata=custom[0], text=eye, hovertemplate=template, showlegend=False))
    fig.frames = [go.Frame(data=[{"marker": {"color": "#000000"}, "customdata": d}], name=str(k))
                  for k, d in enumerate(custom)]
    steps = [{"label": f"{t:.2f} s", "method": "animate",
              "args": [[str(k)], {"mode": "immediate", "frame": {"duration": 0, "redraw": True},
                                  "transition": {"duration": 0}}]} for k, t in enumerate(times_s)]
    fig.update_layout(
        title={"text": title, "x": 0.01}, height=720, width=1300, template="plotly_white",
        xaxis={"range": [180, -180], "title": "azimuth, ° (+ to the bee's left)",
               "tickvals": list(range(-180, 181, 45))},
        yaxis={"range": [-90, 90], "title": "elevation, °", "tickvals": list(range(-90, 91, 30))},
        sliders=[{"steps": steps, "currentvalue": {"prefix": "t = "}, "x": 0.05, "len": 0.9}],
        updatemenus=[{"type": "buttons", "x": 0.0, "y": -0.12, "xanchor": "left", "buttons": [
            {"label": "play", "method": "animate",
             "args": [None, {"frame": {"duration": 100, "redraw": True}, "fromcurrent": True}]}]}],
        annotations=[*ORIENTATION, {"text": "<br>".join(textwrap.wrap(caption, 190)), "xref": "paper",
                                    "yref": "paper", "x": 0.0, "y": -0.3, "showarrow": False, "align": "left",
                                    "font": {"size": 11}}],
        margin={"b": 170}, meta={"receptors": len(az), "frames": len(colours)})
    page = fig.to_plotly_json()
    page["data"][0]["marker"]["color"] = colours[0]
    for frame, c in zip(page["frames"], colours):
        frame["data"][0]["marker"]["color"] = c
    with atomic_path(path) as tmp:
        pio.write_html(page, tmp, validate=False, include_plotlyjs=True, full_html=True, auto_play=False,
                       post_script=FLIGHT_SCRIPT, div_id=DIV_ID, config={"displaylogo": False, "responsive": True})
