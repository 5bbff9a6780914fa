"""The lane change's rack calibrated for the car that runs: the profile (``LaneChange``'s
amplitude and second lobe) that moves the car's track ``shift_m`` sideways in phase III and
ends parallel (paper section 4: 3.7 m in 2.4 s at 60 km/h), as the paper's protocol has it:
one profile per car, used for every friction set of its study and mirrored for case b.

``adapted(scene)`` gives a scene whose lane change has no profile one (and resolves a launch
left out, ``scene.launch``): the shipped Escort's calibration where the content of its recorded
inputs is the scene's, else a cached calibration of the same inputs, else one made here and
cached (``sim.lane_change_cache``). A run that stops before phase III needs none. ``simulate``
(``sim.simulate.SceneRunner``), the sweeps and the studies call it before they run, so the saved
scene holds the profile that ran; they give it the runner (``run``: scene -> Run) that the
calibration's runs go through.

What the profile depends on (``calibration_scene``): the scene's car, tyres (the tyre file's
content), road, drive and timeline up to the end of phase III, and ``shift_m``. Not on: the
struts' friction and damping (the calibration runs lubricated struts at the car's default
``REFERENCE_STRUT_DAMPING_NSPM``, so a study's friction sets share one profile and differ only
by their friction, as the paper's do: on the shipped Escort the sets move the shift by 10 mm at
most, a_1 3.7006 m, a_3 3.7104 m, and 1250 against 1657 N s/m by less than 1 mm), the step
(the default 1 ms: accuracy on demand refines a run, not its input), the steering's release,
phase IV, the logging. Case a, from static equilibrium, to 0.05 s after phase III.

The calibration: Newton's method with finite differences on (amplitude, second lobe), from the
shipped profile, until the shift is within ``SHIFT_RESIDUAL_M`` of ``shift_m`` and the heading
change within ``HEADING_RESIDUAL_DEG`` (RunFailed when an iteration does not bring it closer:
a manoeuvre the car cannot do, or a timeline too short for one): a 25th of the run's own check of the shift
(``scene.manoeuvre_targets``: 0.05 m), a seventh of its check of the heading (0.072° at 60 km/h
over 2.4 s), leaving the rest to what the friction sets and the mirrored case add (on the
Escort up to 10 mm and 0.018°). Each iteration is three runs of the calibration scene.
"""

import dataclasses
import logging
import time

import numpy as np

from drake_car.law.errors import RunFailed
from drake_car.model.parameters import FrontSuspensionParameters
from drake_car.scene.launch import resolve_launch
from drake_car.scene.manoeuvre_targets import (
    SPEED_TOLERANCE_KPH, lane_change_metrics, speed_at_place_a_mps)
from drake_car.scene.manoeuvres import LaneChange, Timeline
from drake_car.scene.scene import (
    HeldRack, Logging, NoVisualization, Simulator, default_plant_config)
from drake_car.sim import lane_change_cache

log = logging.getLogger(__name__)

REFERENCE_STRUT_DAMPING_NSPM = FrontSuspensionParameters().strut_damping_Nspm
SHIFT_RESIDUAL_M = 0.002
HEADING_RESIDUAL_DEG = 0.01
MAX_ITERATIONS = 8
END_AFTER_S = 0.05
MAX_AMPLITUDE_M, LOBE_RANGE = 0.1, (0.5, 2.0)  # as LaneChange checks them


def calibration_scene(scene):
    """The scene a lane change's profile is calibrated on (see the module); its lane change
    without a profile."""
    m = scene.manoeuvre
    timeline = dataclasses.replace(m.timeline, calm_s=Timeline().calm_s)
    end = timeline.boundaries()[2] + END_AFTER_S
    car = dataclasses.replace(scene.car, front=dataclasses.replace(
        scene.car.front, strut_damping_Nspm=REFERENCE_STRUT_DAMPING_NSPM))
    return dataclasses.replace(
        scene, name="lane_change_calibration", car=car, friction=None,
        manoeuvre=LaneChange(case="a", timeline=timeline, shift_m=m.shift_m),
        steering=HeldRack(), plant=default_plant_config(), simulator=Simulator(end_time_s=end),
        logging=Logging(channels=["chassis"], record_period_s=0.01),
        visualization=NoVisualization())


def measure(calibrating, amplitude_m, second_lobe, *, run):
    """The lane change's metrics (``lane_change_metrics``) of the calibration scene with this
    profile, run by ``run`` (scene -> Run)."""
    manoeuvre = dataclasses.replace(calibrating.manoeuvre, amplitude_m=float(amplitude_m),
                                    second_lobe=float(second_lobe))
    history = run(dataclasses.replace(calibrating, manoeuvre=manoeuvre)).history
    metrics = lane_change_metrics(history, manoeuvre.timeline)
    speed = speed_at_place_a_mps(history, manoeuvre.timeline)
    if metrics is not None and speed is not None:
        metrics["speed_at_place_a_kph"] = 3.6 * speed
    return metrics


def calibrate(calibrating, *, run, start=None):
    """The profile of calibration scene ``calibrating`` (see the module), its runs made by
    ``run`` (scene -> Run), from ``start`` (default: the shipped profile): {"profile",
    "residual" (the last run's shift, its error and heading change), "iterations", "cost"
    (wall and CPU seconds, runs)}. Raises RunFailed if it does not converge."""
    target = calibrating.manoeuvre.shift_m
    if start is None:
        start = lane_change_cache.shipped()["profile"]
    x = np.array([start["amplitude_m"], start["second_lobe"]], dtype=float)
    began, cpu_began = time.perf_counter(), time.process_time()
    iterations, runs = [], 0

    def residual(point):
        nonlocal runs
        runs += 1
        m = measure(calibrating, *point, run=run)
        return np.array([m["shift_m"] - target, m["heading_change_deg"]]), m

    scale = np.array([SHIFT_RESIDUAL_M, HEADING_RESIDUAL_DEG])
    before = np.inf
    for iteration in range(MAX_ITERATIONS):
        r, m = residual(x)
        iterations.append({"amplitude_m": float(x[0]), "second_lobe": float(x[1])} | m)
        log.info("lane-change calibration %d: amplitude %.6f m, second lobe %.4f: shift %.4f m"
                 ", heading change %+.4f deg", iteration, x[0], x[1], m["shift_m"],
                 m["heading_change_deg"])
        size = float(np.max(np.abs(r) / scale))
        if size >= before:  # Newton's steps no longer shrink it: the car cannot do it
            break
        before = size
        if size < 1.0:
            return {"profile": {"amplitude_m": float(x[0]), "second_lobe": float(x[1])},
                    "residual": {"shift_m": m["shift_m"], "shift_error_m": float(r[0]),
                                 "heading_change_deg": m["heading_change_deg"]},
                    "iterations": iterations,
                    "cost": {"wall_s": time.perf_counter() - began,
                             "cpu_s": time.process_time() - cpu_began, "runs": runs}}
        jacobian = np.zeros((2, 2))
        for j, step in enumerate((0.01 * x[0], 0.02)):
            dx = np.zeros(2)
            dx[j] = step
            jacobian[:, j] = (residual(x + dx)[0] - r) / step
        try:
            x = x - np.linalg.solve(jacobian, r)
        except np.linalg.LinAlgError:  # the profile does not move the car
            break
        x = np.array([min(max(x[0], 1e-4), MAX_AMPLITUDE_M), min(max(x[1], LOBE_RANGE[0]),
                                                                  LOBE_RANGE[1])])
    raise RunFailed(f"{calibrating.name}: the lane change's rack did not calibrate in "
                    f"{len(iterations)} iterations: {_last_words(iterations[-1], calibrating)}; "
                    "give the lane change's amplitude_m and second_lobe, or a manoeuvre this "
                    "car can do")


def _last_words(last, calibrating):
    """What the last calibration run did, in words: the shift and heading change it made and
    the speed it made them at, against what was asked."""
    timeline = calibrating.manoeuvre.timeline
    text = (f"the last run (amplitude {1e3 * last['amplitude_m']:.2f} mm, second lobe "
            f"{last['second_lobe']:.3f}) moved the car {last['shift_m']:.2f} m sideways (asked "
            f"{calibrating.manoeuvre.shift_m:g} m) and turned it by "
            f"{last['heading_change_deg']:+.2f} deg (asked 0)")
    speed = last.get("speed_at_place_a_kph")
    if speed is None:
        return text
    text += f", at {speed:.1f} km/h at place a (asked {timeline.speed_kph:g} km/h)"
    if abs(speed - timeline.speed_kph) > SPEED_TOLERANCE_KPH:
        text += (": the car did not reach its speed, so the lane change is another manoeuvre; "
                 "check its drive (drive.max_wheel_torque_Nm, drive.torque_within_grip) and "
                 "launch (manoeuvre.timeline.speed_up_s)")
    return text


def adapted(scene, *, run):
    """(the scene as it runs, what was adapted or None): its launch resolved (``scene.launch``)
    and its lane change's profile found or calibrated (see the module), a calibration's runs
    made by ``run`` (scene -> Run: ``sim.simulate.simulate``)."""
    scene = resolve_launch(scene)
    m = scene.manoeuvre
    if not isinstance(m, LaneChange) or m.calibrated:
        return scene, None
    if scene.end_time_s <= m.timeline.boundaries()[1]:
        return scene, None  # the rack rests throughout: no profile needed
    calibrating = calibration_scene(scene)
    content = lane_change_cache.content_sha256(calibrating)
    found = lane_change_cache.find(content)
    if found is None:
        log.info("%s: calibrating the lane change's rack for this car (no calibration of its "
                 "inputs found; runs of %.1f s: one an iteration, two more where it has not "
                 "converged; kept for the next run)",
                 scene.name, calibrating.end_time_s)
        found = calibrate(calibrating, run=run) | {
            "source": "calibrated now (no calibration of its inputs was found) and kept in the "
                      "calibration cache"}
        lane_change_cache.store(content, found)
    profile = found["profile"]
    manoeuvre = dataclasses.replace(m, amplitude_m=profile["amplitude_m"],
                                    second_lobe=profile["second_lobe"])
    return dataclasses.replace(scene, manoeuvre=manoeuvre), found | {"content_sha256": content}


def adapted_scenes(scenes: dict, *, run):
    """name -> the scene as it runs (``adapted``), for name -> Scene."""
    return {name: adapted(scene, run=run)[0] for name, scene in scenes.items()}
