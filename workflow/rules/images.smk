# Images of what each eye saw, one job per eye and scene: Voronoi, density and channel images in
# the retinal plane, the visual field beside the human view, the colour-space figures and the
# interactive viewer (a self-contained HTML page). What an eye's images are depends on its receptor
# set (a channel image per class, the colour spaces it has), so there is one rule per receptor set
# among the run's eyes, each for those eyes only.

RETINAL_CAPTIONS = {"voronoi_map3": "voronoi_map3", "voronoi_map2": "voronoi_map2", "density_map3": "density_map3",
                    "density_map3_normalised": "density_map3_normalised"}


def image_outputs(receptor_set):
    """The images rule's outputs for the eyes of a receptor set, marked for the report."""
    base = "results/{eye}/{scene}/"
    retinal = {"category": "Retinal images", "subcategory": "{eye} in {scene}"}
    out = {name: report(base + file, caption=f"../report/{RETINAL_CAPTIONS.get(name, 'channel')}.rst", **retinal)
           for name, file in retinal_images(receptor_set).items() if name != "exr"}
    out["exr"] = base + "catches.exr"
    out["figure"] = report(base + FIELD_MAPS["figure"], caption="../report/visual_field.rst",
                           category="Visual field", subcategory="{eye} in {scene}")
    out["field_exr"] = base + FIELD_MAPS["exr"]
    out.update({name: report(base + file, caption="../report/colour_space.rst", category="Colour spaces",
                             subcategory="{eye} in {scene}")
                for name, file in colour_figures(receptor_set).items()})
    # The viewer is linked from the visual field's caption, not embedded: each page carries its own
    # plotly.js (4.8 MB), and the report would hold one copy a viewer.
    out["viewer"] = base + VIEWER["viewer"]
    return out


def polarisation_table(wildcards):
    """The polarisation stage's table, for the eyes and scenes it runs in (config polarisation): the viewer
    colours receptors by it too."""
    pol = config["polarisation"]
    traced = wildcards.eye in pol["eyes"] and wildcards.scene in pol["scenes"]
    return {"polarisation": f"results/{wildcards.eye}/{wildcards.scene}/polarisation/polarisation.csv"} if traced else {}


for set_name in dict.fromkeys(rs.name for rs in RECEPTOR_SETS.values()):
    set_eyes = [e for e, rs in RECEPTOR_SETS.items() if rs.name == set_name]

    rule:
        name:
            f"images_{set_name}"
        input:
            unpack(polarisation_table),
            eye=eye_sources,
            receptors="results/eyes/{eye}/receptors.csv",
            responses="results/{eye}/{scene}/responses.csv",
            irradiance="results/{eye}/{scene}/irradiance.npz",
            human="results/scenes/{scene}/human.png",
            curves=sensitivity_files,
        output:
            **image_outputs(RECEPTOR_SETS[set_eyes[0]]),
        wildcard_constraints:
            eye="|".join(set_eyes),
        params:
            eye=eye_file,
            width_px=config["images"]["width_px"],
            field_width_px=config["images"]["visual_field_width_px"],
            receptor_curves=config["colour"]["sensitivities"],
        log:
            "results/logs/images/{eye}/{scene}.log",
        script:
            "../scripts/images.py"

