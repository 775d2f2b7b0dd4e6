"""The interactive viewers, opened in a real browser: headless Chromium, the network blocked."""

import re

import numpy as np
import pytest

from beeoptics.images.headless import WINDOW, chromium, open_page
from beeoptics.io.errors import InputError
from beeoptics.io.imagefile import read_image
from beeoptics.io.receptortable import read_receptors
from beeoptics.io.table import read_table, write_table
from beeoptics.pipeline.images import viewer
from beeoptics.vision.receptorset import load_receptor_set

try:
    chromium()
    HAVE_CHROMIUM = True
except InputError:
    HAVE_CHROMIUM = False
HEIGHT, WIDTH = WINDOW[1], WINDOW[0]
needs_chromium = pytest.mark.skipif(not HAVE_CHROMIUM, reason="Chromium is not installed (make test installs "
                                    "Debian's chromium)")


def check_drawn_offline(page, tmp_path, fragment="", dom=False):
    """What a viewer must be: drawn with nothing fetched (no failed request, no script error), the map
    where it should be, and the page's own line saying it was drawn. Returns that line's figures, the
    screenshot (h, w, 3) and the DOM."""
    shot = tmp_path / f"{page.parent.parent.name}_{page.parent.name}.png"
    seen = open_page(page, shot, fragment, dom)
    assert not seen["errors"], seen["errors"]
    assert seen["drawn"] is not None, "the page never said it was drawn"
    image = read_image(shot)[0][..., :3]
    # The visual field's map fills the top of the page: points, not a blank page, the left eye's on
    # the left half (azimuth + to the bee's left) and the right eye's on the right.
    top = image[int(0.15 * HEIGHT):int(0.45 * HEIGHT), int(0.1 * WIDTH):int(0.9 * WIDTH)]
    inked = top.max(axis=-1) < 0.85
    half = inked.shape[1] // 2
    assert inked[:, :half].mean() > 0.002 and inked[:, half:].mean() > 0.002, \
        f"the map is blank ({inked.mean():.4f} of its pixels inked)"
    assert len(np.unique(np.round(top[inked] * 31), axis=0)) > 3
    return seen["drawn"], image, seen["dom"]


def viewers(workdir):
    found = sorted((workdir / "results").glob("*/*/viewer.html"))
    return [p for p in found if p.parts[-3] not in ("flights", "detection")]


@needs_chromium
def test_every_viewer_of_a_run_is_drawn_offline_with_its_receptors(workdir, tmp_path):
    pages = viewers(workdir)
    assert {(p.parts[-3], p.parts[-2]) for p in pages} == {("tiny", "open"), ("tiny", "flower"), ("tiny", "generated")}
    receptors = read_receptors(workdir / "results" / "eyes" / "tiny" / "receptors.csv")
    for page in pages:
        drawn, image, _ = check_drawn_offline(page, tmp_path)
        print(f"{page.relative_to(workdir)}: drawn in {drawn['drawn_ms']} ms, {page.stat().st_size} bytes")
        assert drawn["receptors"] == len(receptors.id)
        # The sphere and the colour hexagon below the map are drawn too.
        for box in ((0.6, 0.85, 0.1, 0.4), (0.6, 0.85, 0.55, 0.9)):
            part = image[int(box[0] * HEIGHT):int(box[1] * HEIGHT), int(box[2] * WIDTH):int(box[3] * WIDTH)]
            assert (part.max(axis=-1) < 0.85).mean() > 0.002, (page, box)


@needs_chromium
def test_a_receptors_hover_label_gives_its_numbers(workdir, tmp_path):
    page = workdir / "results" / "tiny" / "flower" / "viewer.html"
    receptors = read_receptors(workdir / "results" / "eyes" / "tiny" / "receptors.csv")
    k = len(receptors.id) // 3
    _, _, html = check_drawn_offline(page, tmp_path, f"#receptor={receptors.id[k]}", dom=True)
    label = " ".join(re.findall(r"<tspan[^>]*>([^<]*)</tspan>", html))
    assert f"receptor {receptors.id[k]}, {receptors.side[k]} eye" in label, label[:500]
    for words in ("azimuth", "Δφ, °", "Δρ, °", "facet, µm", "UV catch", "hex_x", "rnl_dS", "UV polarisation degree"):
        assert words in label, words
    axis = receptors.axis[k]
    assert f"elevation {np.degrees(np.arcsin(axis[2])):.1f}°" in label


@needs_chromium
def test_a_flights_viewer_has_a_slider_over_its_frames(workdir, tmp_path):
    page = workdir / "results" / "flights" / "dive" / "tiny" / "viewer.html"
    views = np.load(workdir / "results" / "flights" / "dive" / "tiny" / "views.npz")
    drawn, _, html = check_drawn_offline(page, tmp_path, dom=True)
    assert drawn["frames"] == len(views["t_s"]) and drawn["receptors"] == views["catches"].shape[1]
    assert "slider" in html and f"{views['t_s'][-1]:.2f} s" in html


@needs_chromium
def test_the_check_fails_on_a_viewer_that_loads_plotly_from_the_network(workdir, tmp_path):
    page = workdir / "results" / "tiny" / "flower" / "viewer.html"
    text = page.read_text()
    # The same page with plotly.js fetched from its CDN, as plotly's include_plotlyjs="cdn" writes it.
    start = text.index("<script>/**")
    end = text.index("</script>", start) + len("</script>")
    online = tmp_path / "online" / "viewer.html"
    online.parent.mkdir()
    online.write_text(text[:start] + '<script src="https://cdn.plot.ly/plotly-3.0.1.min.js"></script>' + text[end:])
    with pytest.raises(AssertionError):
        check_drawn_offline(online, tmp_path)


def test_a_viewer_written_again_is_the_same_bytes(workdir, tmp_path):
    """Same inputs, same page (plotly names its figure's element at random unless told a name)."""
    from beeoptics.pipeline.images import viewer
    from beeoptics.vision.receptorset import receptor_set_of

    results = workdir / "results"
    pages = []
    for k in range(2):
        pages.append(tmp_path / f"viewer_{k}.html")
        viewer(results / "eyes" / "tiny" / "receptors.csv", results / "tiny" / "flower" / "responses.csv",
               results / "tiny" / "flower" / "irradiance.npz", {"viewer": pages[-1]},
               receptor_set=receptor_set_of(workdir / "eyes" / "tiny" / "eye.yaml"), title="tiny in flower")
    assert pages[0].read_bytes() == pages[1].read_bytes()


@needs_chromium
def test_with_standard_errors_the_hover_gives_each_catch_plus_or_minus_its_error(workdir, tmp_path):
    run = workdir / "results" / "tiny" / "flower"
    # The workflow's own errors set aside: this table's are chosen, for a few columns only.
    table = {k: v for k, v in read_table(run / "responses.csv", text=["side"]).items() if not k.startswith("se_")}
    for name in ("UV", "B", "G", "hex_x"):
        table[f"se_{name}"] = 0.0123 * np.abs(np.asarray(table[name], float))
    write_table(tmp_path / "responses.csv", table)
    page = tmp_path / "tiny" / "flower" / "viewer.html"
    page.parent.mkdir(parents=True)
    viewer(workdir / "results" / "eyes" / "tiny" / "receptors.csv", tmp_path / "responses.csv",
           run / "irradiance.npz", {"viewer": page}, receptor_set=load_receptor_set("apis_mellifera"))
    receptors = read_receptors(workdir / "results" / "eyes" / "tiny" / "receptors.csv")
    k = int(np.argmax(table["UV"]))
    _, _, html = check_drawn_offline(page, tmp_path, f"#receptor={receptors.id[k]}", dom=True)
    label = " ".join(re.findall(r"<tspan[^>]*>([^<]*)</tspan>", html))
    for name in ("UV catch", "B catch", "G catch", "hex_x"):
        assert re.search(rf"{name} \S+ ± \S+", label), (name, label[:800])
    # Only those: a column without its error shows the number alone.
    assert label.count("±") == 4 and "rnl_dS" in label, label[:800]
