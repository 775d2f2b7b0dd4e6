"""The clear-sky daylight against measured daylight, and Hosek & Wilkie's sky against SPECTRL2's.

Prints, for the sun at 10–70° and turbidity 3 (the scenes' default), the
global horizontal irradiance of the scene's sky and sun as the tracer sees
them (the sky dome integrated over the hemisphere, plus the sun's disc):
its UV/VIS photon ratio and UV/G catch ratio (Peitsch et al. 1992) beside
the 10, 50 and 90th percentiles of the measured records like it
(:mod:`beeoptics.sky.daylightrecords`); how many of Granada's records
lie inside both data sets' ranges at once; then the diffuse irradiance
Hosek & Wilkie's own model gives, per channel, as a ratio to SPECTRL2's.
The last line is the same as one JSON object (``suns``: per elevation,
the model's and the records' ratios; ``both_ranges``; ``hosek_wilkie_over_spectrl2``).

    .venv/bin/python benchmarks/daylight.py
"""

import argparse

import numpy as np

from beeoptics.headframe import direction_from_x_towards_y
from beeoptics.sky import hosekwilkie
from beeoptics.sky.daylight import clear_sky
from beeoptics.sky.daylightrecords import (GRANADA_TOLERANCE, SPITSCHAN_FROM_NM, clear_like, granada,
                                             measured_ranges, uv_ratios)
from beeoptics.light.materials import ground_albedo
from beeoptics.sky.dome import _hemisphere, clear_sky_dome, horizontal_irradiance
from beeoptics.sky.sun import sun_disc
from beeoptics.spectra import grid
from beeoptics.vision.receptorset import curves, load_receptor_set
from record import record

TURBIDITY = 3.0


def scene_light(wl, elevation, albedo):
    daylight = clear_sky(wl, elevation, TURBIDITY, albedo)
    sun = sun_disc(daylight, 0.0)
    sky = clear_sky_dome("hosek_wilkie", daylight, sun.direction, TURBIDITY, albedo)
    return daylight, horizontal_irradiance(sky, sun, len(wl))


def main(argv=None):
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    wl = grid()
    albedo = ground_albedo("grass", wl, "benchmark", "grass")
    s = curves(load_receptor_set("apis_mellifera"), wl)
    result = {"turbidity": TURBIDITY, "ground": "grass", "suns": {}, "both_ranges": {}, "hosek_wilkie_over_spectrl2": {}}
    print(f"turbidity {TURBIDITY:g}, ground: grass (Feister & Grewe 1995); percentiles 10, 50, 90")
    print("sun  | Granada (300 nm) n  UV/VIS ours  measured            UV/G ours  measured"
          "            | Spitschan (360 nm) n  UV/VIS ours  measured            UV/G ours  measured")
    for elevation in (10, 30, 50, 70):
        daylight, light = scene_light(wl, elevation, albedo)
        r = measured_ranges(wl, light, elevation, s)
        result["suns"][elevation] = {name: {k: (np.asarray(v).tolist() if k in ("uv_vis", "uv_g") else v)
                                            for k, v in m.items()} for name, m in r.items()}
        row = f"{elevation:3d}° |"
        for name in ("granada", "spitschan"):
            m = r[name]
            row += f" {m['n']:4d}  {m['model_uv_vis']:.3f}"
            row += (f"  {m['uv_vis'][1]:.3f} [{m['uv_vis'][0]:.3f}–{m['uv_vis'][2]:.3f}]  {m['model_uv_g']:.3f}"
                    f"  {m['uv_g'][1]:.3f} [{m['uv_g'][0]:.3f}–{m['uv_g'][2]:.3f}] |") if m["n"] else "  (no records) |"
        print(row)
    print("\nThe two records disagree: Granada's records inside Granada's own 10–90 % (both ratios, from 300 nm)"
          " that are also inside Spitschan's (from 360 nm):")
    late = wl >= SPITSCHAN_FROM_NM
    for elevation in (10, 30, 50):
        _, light = scene_light(wl, elevation, albedo)
        r = measured_ranges(wl, light, elevation, s)
        records = granada(wl)
        records = records[clear_like(records, wl, light, GRANADA_TOLERANCE)]
        inside = np.ones(len(records), bool)
        for name, cut in (("granada", slice(None)), ("spitschan", late)):
            for ratio, values in zip(("uv_vis", "uv_g"), uv_ratios(wl[cut], records[:, cut], s[cut])):
                inside &= (values >= r[name][ratio][0]) & (values <= r[name][ratio][2])
        result["both_ranges"][elevation] = [int(inside.sum()), len(records)]
        print(f"{elevation:3d}° | {inside.sum()} of {len(records)}")
    print("\nHosek & Wilkie's own diffuse irradiance / SPECTRL2's, per channel (nm):")
    print("sun  | " + " ".join(f"{c:5.0f}" for c in hosekwilkie.CHANNELS_NM))
    d = _hemisphere()
    for elevation in (10, 30, 50, 70):
        a = np.interp(hosekwilkie.CHANNELS_NM, wl, albedo)
        own = np.pi * hosekwilkie.channel_radiance(d, direction_from_x_towards_y(0.0, elevation), TURBIDITY, a).mean(0)
        spectrl2 = np.interp(hosekwilkie.CHANNELS_NM, wl, clear_sky(wl, elevation, TURBIDITY, albedo).diffuse)
        result["hosek_wilkie_over_spectrl2"][elevation] = dict(zip(map(int, hosekwilkie.CHANNELS_NM),
                                                                   (own / spectrl2).round(4).tolist()))
        print(f"{elevation:3d}° | " + " ".join(f"{v:5.2f}" for v in own / spectrl2))
    record("daylight", result)


if __name__ == "__main__":
    main()
