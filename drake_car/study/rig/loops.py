"""The strut rig's study: loops for the friction sets at several side loads, friction against
side load, amplitude and frequency, the rod's rotation, and a fit to a measured (or synthetic)
loop. Used by ``drake-car-strut-rig``."""

import dataclasses

import numpy as np

from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.sim.strut_rig import StrutRigOptions, eq4_normal_force_N, simulate_strut_rig
from drake_car.study.rig.analysis import loop_statistics
from drake_car.study.rig.fit import fit_measured_loop

FRICTION_SETS = ((0.2, 0.15), (0.4, 0.3))  # the paper's dry sets
LOOP_SIDE_FORCES_N = (500.0, 1000.0, 2000.0)
SIDE_FORCES_N = (250.0, 500.0, 1000.0, 2000.0, 3000.0)
# The synthetic measured loop: known parameters plus [EST] a strut rig's noise, 10 N on the
# load cell and 2 µm on the stroke (an LVDT over ±20 mm at 0.01 % resolution), one seed.
SYNTHETIC_LAW = (0.3, 0.22)
SYNTHETIC_SIDE_FORCE_N = 1000.0
SYNTHETIC_NOISE = {"force_N": 10.0, "stroke_m": 2e-6, "seed": 23}


def _row(options, law, history, car):
    stats = loop_statistics(history["stroke_m"], history["load_cell_N"], history["normal_N"],
                            sample_period_s=options.time_step_s)
    return {"mu_s": law.mu_s, "mu_d": law.mu_d, "side_force_N": options.side_force_N,
            "amplitude_m": options.stroke_amplitude_m,
            "frequency_hz": options.stroke_frequency_hz,
            "rotation_amplitude_rad": options.rotation_amplitude_rad,
            "normal_N": eq4_normal_force_N(car.front, options),
            "breakaway_N": float(np.mean([c.breakaway_N for c in stats.cycles])),
            "sliding_N": float(np.mean([c.sliding_N for c in stats.cycles])),
            "apparent_mu_s": stats.apparent_mu_s, "mu_d_measured": stats.mu_d,
            "max_friction_moment_Nm": float(np.max(np.abs(history["friction_moment_Nm"])))}


def rig_study(car, *, quick=False):
    """Returns (loops {mu_s: [(side, history)]}, rows, synthetic (options, history, noisy
    stroke, noisy force, fit))."""
    base = StrutRigOptions(stroke_amplitude_m=0.01, stroke_frequency_hz=0.5)
    cycles = 2.5
    loops, rows = {}, []
    for mu_s, mu_d in FRICTION_SETS:
        law = StrutFrictionParameters(mu_s=mu_s, mu_d=mu_d)
        loops[mu_s] = []
        for side in (LOOP_SIDE_FORCES_N if quick else SIDE_FORCES_N):
            options = dataclasses.replace(base, side_force_N=side)
            h = simulate_strut_rig(car, options, law, cycles=cycles)
            rows.append(_row(options, law, h, car))
            if side in LOOP_SIDE_FORCES_N:
                loops[mu_s].append((side, h))
        if quick:
            continue
        variants = [dict(stroke_amplitude_m=a) for a in (0.001, 0.005, 0.02)]
        variants += [dict(stroke_frequency_hz=f) for f in (0.1, 2.0)]
        variants += [dict(rotation_amplitude_rad=0.05, rotation_frequency_hz=0.7)]
        for change in variants:
            options = dataclasses.replace(base, side_force_N=1000.0, **change)
            h = simulate_strut_rig(car, options, law, cycles=cycles)
            rows.append(_row(options, law, h, car))
    synthetic = synthetic_fit(car)
    return loops, rows, synthetic


def synthetic_fit(car):
    """A loop made by the rig with known (μs, μd) plus noise, and the fit to it."""
    mu_s, mu_d = SYNTHETIC_LAW
    options = StrutRigOptions(side_force_N=SYNTHETIC_SIDE_FORCE_N, stroke_amplitude_m=0.01,
                              stroke_frequency_hz=1.0)
    h = simulate_strut_rig(car, options, StrutFrictionParameters(mu_s=mu_s, mu_d=mu_d),
                           cycles=5.0)
    rng = np.random.default_rng(SYNTHETIC_NOISE["seed"])
    stroke = h["stroke_m"] + rng.normal(0.0, SYNTHETIC_NOISE["stroke_m"], len(h["t"]))
    force = h["load_cell_N"] + rng.normal(0.0, SYNTHETIC_NOISE["force_N"], len(h["t"]))
    fit = fit_measured_loop(car, options, stroke, force, sample_period_s=options.time_step_s)
    return options, h, stroke, force, fit
