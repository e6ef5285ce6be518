"""Writes the 2D wave-flume scenes of pipelines/waves/ (docs/waves.md, docs/validation.md "Waves in a flume").

    python3 pipelines/waves/make_flume.py [--out DIR]

A flume of still-water depth h with a paddle at x = 0 (piston, or flap hinged on the bed), gauges at 1, 1.25,
1.5 and 2 wavelengths, a wall at the far end and a damping zone one wavelength long before it. The resolution
is given as particles per wave height (H / dx); the set-up is the engineering one (docs/validation.md).
Each scene's `description` gives the linear-theory wave (k, L, stroke) it is meant to make.
"""
import argparse
import json
import math
import os


def wave_number(omega, h, g=9.81):
    k0h = omega * omega * h / g
    kh = k0h / math.tanh(k0h ** 0.75) ** (2.0 / 3.0)
    for _ in range(50):
        t = math.tanh(kh)
        step = (kh * t - k0h) / (t + kh * (1 - t * t))
        kh -= step
        if abs(step) <= 1e-15 * kh:
            break
    return kh / h


def piston_hs(kh):
    return 2 * (math.cosh(2 * kh) - 1) / (math.sinh(2 * kh) + 2 * kh)


def flap_hs(kh):
    return 4 * (math.sinh(kh) / kh) * (kh * math.sinh(kh) - math.cosh(kh) + 1) / (math.sinh(2 * kh) + 2 * kh)


def r(x, n=6):
    return round(x, n)


def to_3d(scene, width):
    """The same flume as a basin section `width` wide, periodic across (y), vertical z."""
    def v3(p, y):
        return [p[0], y, p[1]]
    scene["dimension"] = 3
    scene["domain"] = {"min": v3(scene["domain"]["min"], 0.0), "max": v3(scene["domain"]["max"], width),
                       "periodic": [False, True, False]}
    scene["gravity"] = [0.0, 0.0, -9.81]
    for b in scene["bodies"]:
        b["min"], b["max"] = v3(b["min"], 0.0), v3(b["max"], width)
        m = b.get("motion")
        if m and "hinge" in m:
            m["hinge"] = v3(m["hinge"], width / 2)
    for p in scene["probes"]:
        if "from" in p:
            p["from"] = v3(p["from"], width / 2)
    z = scene["physics"].get("damping_zone")
    if z:
        z["from"], z["to"] = v3(z["from"], 0.0), v3(z["to"], 0.0)
    scene["description"] = scene["description"].replace("2D wave flume", "3D basin section %g m wide (periodic across)" % width)
    return scene


def flume(name, paddle, h, H, kh, per_height, periods, damping=True, zone_lengths=1.0, order=1, awas=None,
          h_over_dx=1.414, ramp_periods=2.0, zone_at=2.1, gauges=(1.0, 1.25, 1.5, 2.0), digits=6):
    """zone_at: where the damping zone starts, in wavelengths from the paddle (the far wall follows it after
    zone_lengths L); gauges beyond it are dropped. h_over_dx above 1.5 gives the walls, bed and paddle 4 layers
    (Wendland C2's support 2 h must lie inside them: 3.4 dx at 1.7), else 3. digits: decimals of the lengths
    written; a spacing that is not a round number needs more than 6, or a wall 4 dx thick rounds below 4 dx and
    the sampler fits only 3 layers in it (the fixed scenes have dx = 8 or 4 mm and keep 6)."""
    def r(x, n=digits):
        return round(x, max(n, digits))
    k = kh / h
    omega = math.sqrt(9.81 * k * math.tanh(kh))
    T = 2 * math.pi / omega
    L = 2 * math.pi / k
    rows = int(round(h * per_height / H))  # whole rows of particles in the depth: the water is exactly h deep
    dx = h / rows
    hs = piston_hs(kh) if paddle == "piston" else flap_hs(kh)
    S = H / hs
    xzone = zone_at * L
    length = xzone + zone_lengths * L
    length = math.ceil(length / dx - 1e-9) * dx
    gauges = [g for g in gauges if g < zone_at]
    lay = 4 if h_over_dx > 1.5 else 3  # wall layers that hold the kernel's support 2 h
    motion = {"type": paddle, "waves": "regular", "height": H, "period": r(T, 9), "ramp": r(ramp_periods * T, 6)}
    if order == 2:
        motion["order"] = 2
    if awas is not None:  # active absorption at the paddle (docs/waves.md), e.g. {} or {"gain": "linear"}
        motion["awas"] = awas
    if paddle == "flap":
        motion["hinge"] = [r(-0.5 * lay * dx), 0.0]
    back = S / 2 + 0.05
    scene = {
        "name": name,
        "description": ("2D wave flume (%s), linear theory: h = %g m, H = %g m, T = %.6f s, kh = %g, k = %.6f rad/m, "
                        "L = %.6f m, H/S = %.6f, stroke S = %.6f m; H/dx = %g; gauges at %s L from the paddle; %s. "
                        "Analyse with paraview/wave_analysis.py RUN --depth %g --from %.3f --pair g125:%.6f,g150:%.6f "
                        "--theory %g:%.6f" % (paddle, h, H, T, kh, k, L, hs, S, per_height, gauges,
                                             "damping zone %.2f L from x = %.4f m" % (zone_lengths, xzone)
                                             if damping else "no damping zone (a wall reflects)", h,
                                             (1.0 + 2.0) * T, 1.25 * L, 1.5 * L, H, T)),
        "dimension": 2,
        "domain": {"min": [r(-back - (lay + 1) * dx), r(-(lay + 1) * dx)], "max": [r(length + (lay + 1) * dx), r(2.2 * h)]},
        "particles": {"spacing": dx, "max_count": 2000000},
        "kernel": {"type": "wendland_c2", "h_over_dx": h_over_dx},
        "fluid": {"rho0": 1000.0, "c0": "auto", "c0_factor": 10},
        "gravity": [0.0, -9.81],
        "physics": {"density": "continuity", "riemann": {}},
        "boundary": {"model": "dummy_adami"},
        "integrator": {"type": "symplectic_euler", "cfl": 0.2},
        "time": {"end": r(periods * T, 6)},
        "output": {"every": r(T / 4, 6), "probes_every": r(T / 50, 6)},
        "bodies": [
            {"kind": "fluid", "shape": "box", "min": [0.0, 0.0], "max": [r(length), h], "initial_pressure": "hydrostatic"},
            {"kind": "boundary", "shape": "box", "min": [r(-back), r(-lay * dx)], "max": [r(length + lay * dx), 0.0],
             "layers": lay},
            {"kind": "boundary", "shape": "box", "min": [r(length), 0.0], "max": [r(length + lay * dx), r(1.6 * h)],
             "layers": lay},
            {"kind": "boundary", "shape": "box", "min": [r(-lay * dx), 0.0], "max": [0.0, r(1.6 * h)], "layers": lay,
             "motion": motion},
        ],
        "probes": [{"type": "water_height", "name": "g%03d" % int(round(100 * g)), "from": [r(g * L), 0.0]}
                   for g in gauges] + [{"type": "force", "name": "paddle", "body": 3}],
    }
    if damping:
        scene["physics"]["damping_zone"] = {"from": [r(xzone), 0.0], "to": [r(xzone + zone_lengths * L), 0.0],
                                            "beta": 10, "profile": "quadratic"}
    return scene


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)))
    a = ap.parse_args()
    scenes = [
        flume("piston_flume_2d", "piston", 0.2, 0.04, 1.5, 10, 10),
        flume("flap_flume_2d", "flap", 0.2, 0.04, 1.5, 10, 10),
        # the piston flume with active absorption at the paddle added (docs/waves.md), 20 periods
        flume("piston_flume_awas_2d", "piston", 0.2, 0.04, 1.5, 10, 20, awas={}),
        # the flap flume with active absorption (the flap's gain, docs/waves.md "A flap"), 20 periods
        flume("flap_flume_awas_2d", "flap", 0.2, 0.04, 1.5, 10, 20, awas={}),
        to_3d(flume("piston_basin_3d", "piston", 0.2, 0.04, 1.5, 5, 10), 0.096),
    ]
    for s in scenes:
        path = os.path.join(a.out, s["name"] + ".json")
        with open(path, "w") as f:
            json.dump(s, f, indent=1)
            f.write("\n")
        print(path)


if __name__ == "__main__":
    main()
