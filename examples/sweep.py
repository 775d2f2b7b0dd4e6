# %% [markdown]
# # A sweep of positions: how far away a flower stands out
#
# The honey-bee worker approaches the meadow's specimen daisy along its approach flight, from 2 m to
# 5 cm. At each distance the eye looks once, the scene and the eye held in memory, and the receptor
# looking most directly at the flower's centre gives the flower's colour against the grass, the
# background the eye adapts to: its distance in Chittka's colour hexagon and its
# receptor-noise-limited distance ΔS (Vorobyev & Osorio 1998, in just-noticeable differences), each
# with its Monte Carlo standard error. Up close that receptor sees the flower's centre; once the head
# is narrower than the receptor's acceptance cone (the worker's Δρ, 1.9–2.57°: Rigosi et al. 2017;
# Eheim & Wehner 1972), its colour mixes with the grass around it.
#
# Run it from the repository's folder, `.venv/bin/python examples/sweep.py`, or cell by cell (`# %%`
# cells). `BEEOPTICS_EXAMPLES_SMALL=1` runs it in seconds, as the tests do (a small test eye by a toy
# meadow's flower, three distances, few rays); `BEEOPTICS_EXAMPLES_OUT` is the folder the table and
# figure go to (`out/examples`).

# %%
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

import beeoptics
from beeoptics.headframe import direction_from_x_towards_y

SMALL = os.environ.get("BEEOPTICS_EXAMPLES_SMALL") == "1"
if SMALL:
    EYE, SCENE = "tests/data/eyes/tiny/eye.yaml", "tests/data/scenes/meadow_tiny/scene.yaml"
    # Its "flower 1", a Senecio doronicum head: daisy.obj, of unit radius, scaled by 0.025 about translate_m.
    FLOWER_M, FLOWER_RADIUS_M = np.array([0.15, 0.0, 0.06]), 0.025
    # The colours' adapting background: the lawn around it, a surface of its albedo in the scene's light.
    BACKGROUND = "lawn"
    DISTANCES_M = np.array([0.05, 0.3, 2.0])
    TRACE, STEP_NM = {"samples": 4, "depth": 1}, 20
else:
    # The meadow's mesh is generated from scenes/meadow/meadow.yaml the first time, in some seconds.
    EYE, SCENE = "eyes/worker/eye.yaml", "scenes/meadow/scene.yaml"
    # The specimen daisy: "its head, 4 cm across, faces up at (0.40, 0.00, 0.30) m" (scenes/meadow/meadow.yaml).
    FLOWER_M, FLOWER_RADIUS_M = np.array([0.40, 0.0, 0.30]), 0.02
    # The colours' adapting background: the meadow's grass, a surface of its reflectance in the scene's light.
    BACKGROUND = "grass"
    DISTANCES_M = np.geomspace(0.05, 2.0, 10)
    # A tenth of the configuration's 256 rays a look, with one bounce after the first surface: a few seconds
    # a look for the worker; the standard errors say what that costs.
    TRACE, STEP_NM = {"samples": 64, "depth": 2}, None
# From the front (-x), descending at 30° towards the flower, as the meadow's approach flight flies
# (scenes/meadow/flights/approach.csv), the head pitched down along the line of sight.
APPROACH_DEG = 30.0
OUT = Path(os.environ.get("BEEOPTICS_EXAMPLES_OUT", "out/examples"))
OUT.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# The eye and the scene are loaded once; each look only places the eye and traces it.

# %%
eye = beeoptics.load_eye(EYE)
scene = beeoptics.load_scene(SCENE, step_nm=STEP_NM)
along = np.radians(APPROACH_DEG)
to_flower = np.array([np.cos(along), 0.0, -np.sin(along)])
rows = []
for distance in DISTANCES_M:
    view = beeoptics.look(eye, scene, position_m=FLOWER_M - distance * to_flower, heading_deg=0.0,
                          pitch_deg=-APPROACH_DEG, seed=1, background=BACKGROUND, **TRACE)
    axes = direction_from_x_towards_y(view.catches.azimuth_deg, view.catches.elevation_deg)
    nearest = np.argmax(axes @ to_flower)
    colour = view.colour.iloc[nearest]
    rows.append({"distance_m": distance,
                 "flower_diameter_deg": 2 * np.degrees(np.arctan(FLOWER_RADIUS_M / distance)),
                 "receptor": colour.id, "side": colour.side,
                 "off_centre_deg": np.degrees(np.arccos(min(axes[nearest] @ to_flower, 1.0))),
                 **colour[["hex_r", "se_hex_r", "rnl_dS", "se_rnl_dS"]]})
sweep = pd.DataFrame(rows)

# %% [markdown]
# ## The table
#
# Per distance: the flower's angular diameter, the receptor that looks at it (id, eye, how far its
# axis is from the flower's centre) and the flower's hexagon distance `hex_r` (hexagon units, the
# corners at 1) and ΔS `rnl_dS` (JND) from the grass, each with its standard error.

# %%
sweep.to_csv(OUT / "sweep.csv", index=False)
print(sweep.round(4))

# %% [markdown]
# ## The figure
#
# Both distances against the distance to the flower (a logarithmic scale), the bars ± one standard
# error; ΔS = 1 is one just-noticeable difference (Vorobyev & Osorio 1998).

# %%
fig, (hexagon, rnl) = plt.subplots(1, 2, figsize=(10, 4), sharex=True, layout="constrained")
cm = 100 * sweep.distance_m
hexagon.errorbar(cm, sweep.hex_r, yerr=sweep.se_hex_r, marker="o", capsize=3)
hexagon.set_ylabel("hexagon distance from the background, hex_r")
rnl.errorbar(cm, sweep.rnl_dS, yerr=sweep.se_rnl_dS, marker="o", capsize=3)
rnl.axhline(1.0, color="0.5", ls="--", label="one just-noticeable difference")
rnl.set_ylabel("ΔS from the background (JND)")
rnl.legend()
for ax in (hexagon, rnl):
    ax.set_xlabel("distance to the flower (cm)")
    ax.set_xscale("log")
    ax.set_xticks([5, 10, 20, 50, 100, 200], ["5", "10", "20", "50", "100", "200"])
    ax.set_ylim(bottom=0)
fig.suptitle(f"{Path(EYE).parent.name} approaching a flower in {Path(SCENE).parent.name}")
fig.savefig(OUT / "sweep.png", dpi=150)
