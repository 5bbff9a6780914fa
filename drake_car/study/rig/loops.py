"""The strut rig's study on a scene's car: loops for the friction sets at multiples of the
car's own side load at rest, friction against side load, amplitude and frequency, the rod's
rotation, and a fit to a measured (or synthetic) loop. Used by ``drake-car-strut-rig``."""

import dataclasses

import numpy as np

from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.sim.rigs.at_rest import strut_at_rest
from drake_car.sim.rigs.strut import (
    StrutRigOptions, rest_normal_force_N, run_strut_rig, simulate_strut_rig)
from drake_car.study.rig.analysis import LoopError, loop_statistics
from drake_car.study.rig.fit import fit_measured_loop

FRICTION_SETS = ((0.2, 0.15), (0.4, 0.3))  # the paper's dry sets
# Side loads as multiples of the car's own at rest (``sim.rigs.at_rest``: the side force at the
# top mount that gives the strut the car's normal force at rest).
LOOP_LOAD_FACTORS = (0.5, 1.0, 2.0)
SIDE_LOAD_FACTORS = (0.25, 0.5, 1.0, 2.0, 3.0)
# The synthetic measured loop: known parameters (the scene's friction law when it has a dry
# one, else these) plus [EST] a strut rig's noise, 10 N on the load cell and 2 µm on the
# stroke (an LVDT over ±20 mm at 0.01 % resolution), one seed.
SYNTHETIC_LAW = (0.3, 0.22)
SYNTHETIC_SIDE_FORCE_N = 1000.0
SYNTHETIC_NOISE = {"force_N": 10.0, "stroke_m": 2e-6, "seed": 23}


@dataclasses.dataclass
class RigStudy:
    """What ``rig_study`` made: ``loops`` {μs: [(side force, history)]}, ``rows`` (one per
    run), ``synthetic`` (options, history, noisy stroke, noisy force, fit) of the synthetic
    loop made with ``synthetic_law``, ``at_rest`` the car's strut at rest
    (``sim.rigs.at_rest.StrutAtRest``), ``runs`` how the rig's runs went (wall, CPU, steps)."""

    loops: dict
    rows: list
    synthetic: tuple
    synthetic_law: StrutFrictionParameters
    at_rest: object
    runs: dict


def scene_law(scene):
    """The friction law the rig takes from ``scene``: its dry law (μs > 0), else None."""
    friction = scene.friction
    return friction.law if friction is not None and friction.law.mu_s > 0 else None


def _row(options, law, history, car):
    """One run's row; a loop whose break-aways the analysis cannot resolve (a small stroke at
    this car's side load: its reversals stay within the creep) gets no forces, and says why."""
    try:
        stats = loop_statistics(history["stroke_m"], history["load_cell_N"], history["normal_N"],
                                sample_period_s=options.time_step_s)
    except LoopError as error:
        stats, note = None, str(error)
    else:
        note = ""
    nan = float("nan")
    return {"mu_s": law.mu_s, "mu_d": law.mu_d, "side_force_N": options.side_force_N,
            "amplitude_m": options.stroke_amplitude_m,
            "frequency_hz": options.stroke_frequency_hz,
            "rotation_amplitude_rad": options.rotation_amplitude_rad,
            "normal_N": rest_normal_force_N(car.front, options, law),
            "breakaway_N": float(np.mean([c.breakaway_N for c in stats.cycles])) if stats else nan,
            "sliding_N": float(np.mean([c.sliding_N for c in stats.cycles])) if stats else nan,
            "apparent_mu_s": stats.apparent_mu_s if stats else nan,
            "mu_d_measured": stats.mu_d if stats else nan,
            "max_friction_moment_Nm": float(np.max(np.abs(history["friction_moment_Nm"]))),
            "note": note}


def rig_study(scene, *, quick=False):
    """The rig on the front strut of ``scene``'s car: loops for the paper's friction sets (the
    scene's law's other parameters: Δv, Δmax, shapes, eq. 4's form) at multiples of the car's
    side load at rest, friction against side load, amplitude, frequency and the rod's
    rotation, and the synthetic loop's fit (the scene's dry law, else ``SYNTHETIC_LAW``), all
    loaded as the car is: the side force at the top mount. Returns a ``RigStudy``."""
    car = scene.car
    template = scene_law(scene) or StrutFrictionParameters()
    at_rest = strut_at_rest(scene)
    base = at_rest.rig_options(stroke_amplitude_m=0.01, stroke_frequency_hz=0.5)
    rest_N = base.side_force_N
    cycles = 2.5
    loops, rows, runs = {}, [], _Runs()
    for mu_s, mu_d in FRICTION_SETS:
        law = dataclasses.replace(template, mu_s=mu_s, mu_d=mu_d)
        loops[mu_s] = []
        for factor in (LOOP_LOAD_FACTORS if quick else SIDE_LOAD_FACTORS):
            options = dataclasses.replace(base, side_force_N=factor * rest_N)
            h = runs.add(run_strut_rig(car, options, law, cycles=cycles))
            rows.append(_row(options, law, h, car))
            if factor in LOOP_LOAD_FACTORS:
                loops[mu_s].append((options.side_force_N, h))
        if quick:
            continue
        variants = [dict(stroke_amplitude_m=a) for a in (0.001, 0.005, 0.02)]
        variants += [dict(stroke_frequency_hz=f) for f in (0.1, 2.0)]
        variants += [dict(rotation_amplitude_rad=0.05, rotation_frequency_hz=0.7)]
        for change in variants:
            options = dataclasses.replace(base, **change)
            h = runs.add(run_strut_rig(car, options, law, cycles=cycles))
            rows.append(_row(options, law, h, car))
    law = scene_law(scene) or dataclasses.replace(template, mu_s=SYNTHETIC_LAW[0],
                                                  mu_d=SYNTHETIC_LAW[1])
    synthetic = synthetic_fit(car, dataclasses.replace(base, stroke_frequency_hz=1.0), law)
    return RigStudy(loops, rows, synthetic, law, at_rest, runs.record())


class _Runs:
    """The rig's runs' wall and CPU time and steps, summed."""

    def __init__(self):
        self.count, self.wall_s, self.cpu_s, self.steps = 0, 0.0, 0.0, 0

    def add(self, run):
        self.count += 1
        self.wall_s += run.wall_s
        self.cpu_s += run.cpu_s
        self.steps += run.steps
        return run.history

    def record(self):
        return {"runs": self.count, "wall_s": self.wall_s, "cpu_s": self.cpu_s,
                "steps": self.steps}


def synthetic_fit(car, options=None, law=None):
    """A loop made by the rig with a known law (default ``SYNTHETIC_LAW``) plus noise, and the
    fit to it (the law's other parameters as the fit's template); ``options`` default: a side
    force of ``SYNTHETIC_SIDE_FORCE_N`` at the lower mount, 10 mm at 1 Hz."""
    law = law or StrutFrictionParameters(mu_s=SYNTHETIC_LAW[0], mu_d=SYNTHETIC_LAW[1])
    options = options or StrutRigOptions(side_force_N=SYNTHETIC_SIDE_FORCE_N,
                                         stroke_amplitude_m=0.01, stroke_frequency_hz=1.0)
    h = simulate_strut_rig(car, options, law, cycles=5.0)
    rng = np.random.default_rng(SYNTHETIC_NOISE["seed"])
    stroke = h["stroke_m"] + rng.normal(0.0, SYNTHETIC_NOISE["stroke_m"], len(h["t"]))
    force = h["load_cell_N"] + rng.normal(0.0, SYNTHETIC_NOISE["force_N"], len(h["t"]))
    fit = fit_measured_loop(car, options, stroke, force, sample_period_s=options.time_step_s,
                            template=law)
    return options, h, stroke, force, fit
