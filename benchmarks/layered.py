"""The coating's base coupling against the layered model's exact answer: which approximation is closer.

    .venv/bin/python benchmarks/layered.py [--paths 4096]

The light a coated surface's base sends back through the coating, f_base(i, o) per steradian, at roughness α 0.05–0.6,
incidence and viewing angles 0–85° and base albedos 0.2, 0.5, 0.8 and 1, for η 1.5 (Mitsuba's and pbrt's plastic) and
1.32 (the meadow's grass, Comar et al. 2014), by
  - the random walk between the rough interface and the Lambertian base (beeoptics.light.layered: pbrt-v4's
    coated diffuse with no medium and no thickness), the reference;
  - Kelemen & Szirmay-Kalos's coupling with the base's own albedo, ρ/π (1 − E_i)(1 − E_o)/(1 − Ē) (the coating's
    until this benchmark was written);
  - Mitsuba 3's roughplastic with nonlinear internal scattering, ρ/π T_i T_o / (η² (1 − ρ F_dr)), T the rough
    interface's transmittance and F_dr its internal diffuse reflectance, integrated over the visible normals at 64
    cosines, as its eval_transmittance and eval_reflectance do (here by 64 × 64 midpoints, there by Gauss–Legendre);
  - the same with its default, linear, internal scattering (1 − F_dr in place of 1 − ρ F_dr);
  - the coating as it is: Kelemen's coupling with the base's albedo through the coating's internal reflections,
    ρ' = ρ (1 − F_dr)/(1 − ρ F_dr), F_dr the coating's hemispherical albedo from inside
    (beeoptics.light.coating.base_albedo).
The last line printed is one JSON object: for each model its relative error against the walk (``error``), and that of
its dependence on the albedo (``albedo``: f(ρ)/f(1) against the walk's, for ρ < 1, free of what both make of a white
base), median and largest over angles and albedos, per roughness (``by_alpha``) and over all (``all``); the walk's
white base's albedo at normal incidence (``white``: 1 less what its interface loses); and the walk's own Monte Carlo
error (the largest standard error relative to its value, ``walk_error``).
"""

import argparse

import numpy as np

from record import record

ALPHAS = (0.05, 0.1, 0.2, 0.3, 0.45, 0.6)
ANGLES_DEG = (0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0)
#: The base's albedos; the last, white, is what the others' dependence on the albedo is measured against.
ALBEDOS = (0.2, 0.5, 0.8, 1.0)
#: η of Mitsuba's and pbrt's plastics (polypropylene 1.49, about 1.5), and of the meadow's grass cuticle (Comar et al.
#: 2014).
ETAS = (1.5, 1.32)
#: Mitsuba 3's MI_ROUGH_TRANSMITTANCE_RES (src/bsdfs/roughplastic.cpp): cosines of its tables, and here also the
#: visible-normal nodes per dimension of its integrals.
NODES = 64


def roughplastic(mu_i, mu_o, rho, alpha, eta, nonlinear=True):
    """Mitsuba 3's roughplastic base term, per steradian (src/bsdfs/roughplastic.cpp), its interface's integrals by
    midpoints over the visible normals."""
    from beeoptics.light.layered import interface

    u = (np.arange(NODES) + 0.5) / NODES
    u1, u2 = np.meshgrid(u, u)

    def transmittance(mu):
        return interface(np.asarray(mu)[..., None, None], alpha, eta, u1, u2)[1].mean(axis=(-1, -2))

    inside = interface(u[:, None, None], alpha, 1.0 / eta, u1, u2)[0].mean(axis=(-1, -2))
    internal = 2.0 * np.mean(inside * u)
    return rho / np.pi * transmittance(mu_i) * transmittance(mu_o) / (eta**2 * (1.0 - (rho if nonlinear else 1.0)
                                                                                 * internal))


def coating_models(mu_i, mu_o, rho, alpha, eta):
    """Kelemen's coupling with ρ (before) and with the coating's ρ' (now), per steradian."""
    from beeoptics.light import coating

    table = coating.albedo_table(alpha, eta)
    kelemen = np.vectorize(lambda a, b: coating.coupling.py_func(a, b, table))(mu_i, mu_o) / np.pi
    return rho * kelemen, coating.base_albedo(rho, alpha, eta) * kelemen


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--paths", type=int, default=4096, help="the walk's paths per setting (default 4096)")
    parser.add_argument("--seed", type=int, default=0, help="the walk's seed (default 0)")
    args = parser.parse_args(argv)
    from beeoptics.light.layered import base_reflection

    mu = np.cos(np.radians(ANGLES_DEG))
    mu_i, mu_o, rho = np.meshgrid(mu, mu, ALBEDOS, indexing="ij")
    names = ("kelemen", "roughplastic", "roughplastic_linear", "coating")
    errors = {(name, kind): [] for name in names for kind in ("error", "albedo")}
    summary = {"paths": args.paths, "etas": ETAS, "alphas": ALPHAS, "angles_deg": ANGLES_DEG, "albedos": ALBEDOS,
               "by_alpha": {}, "white": {}}
    walk_error = 0.0

    def stats(e):
        return {"median": float(np.median(e)), "largest": float(e[np.argmax(np.abs(e))])}

    for alpha in ALPHAS:
        row = {key: [] for key in errors}
        for eta in ETAS:
            # Two halves of the paths, for the walk's own error.
            halves = [base_reflection(mu_i, mu_o, rho, alpha, eta, args.paths // 2, args.seed + k) for k in (0, 1)]
            walk = (halves[0] + halves[1]) / 2
            walk_error = max(walk_error, float(np.max(np.abs(halves[0] - halves[1]) / 2 / walk)))
            # The white base's albedo at normal incidence: ∫ f_base cos θ_o dω_o, by the midpoint rule in cos² θ_o.
            cos2 = (np.arange(64) + 0.5) / 64
            summary["white"][f"{alpha} {eta}"] = float(np.pi * base_reflection(
                1.0, np.sqrt(cos2), 1.0, alpha, eta, args.paths // 4, args.seed + 2).mean())
            kelemen, now = coating_models(mu_i, mu_o, rho, alpha, eta)
            models = {"kelemen": kelemen, "roughplastic": roughplastic(mu_i, mu_o, rho, alpha, eta),
                      "roughplastic_linear": roughplastic(mu_i, mu_o, rho, alpha, eta, nonlinear=False),
                      "coating": now}
            for name in names:
                row[name, "error"].append((models[name] / walk - 1.0).ravel())
                dependence = (models[name] / models[name][..., -1:]) / (walk / walk[..., -1:])
                row[name, "albedo"].append((dependence[..., :-1] - 1.0).ravel())
        summary["by_alpha"][str(alpha)] = {name: {} for name in names}
        for (name, kind), e in row.items():
            errors[name, kind].append(np.concatenate(e))
            summary["by_alpha"][str(alpha)][name][kind] = stats(np.concatenate(e))
    summary["all"] = {name: {kind: stats(np.concatenate(errors[name, kind])) for kind in ("error", "albedo")}
                      for name in names}
    summary["walk_error"] = walk_error
    record("layered", summary)


if __name__ == "__main__":
    main()
