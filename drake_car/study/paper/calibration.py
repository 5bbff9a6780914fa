"""Calibrates the lane change's rack amplitude and second lobe: the car's track shifts
``shift_m`` during phase III and ends parallel (paper section 4: 3.7 m in 2.4 s at 60 km/h).
The runs start, as every study run does, at rest in static equilibrium."""

import dataclasses
import json
import math

import numpy as np

from drake_car.scene.manoeuvres import LaneChange
from drake_car.scene.scene import Logging, Scene
from drake_car.sim.simulate import simulate


def lane_change_metrics(history, timeline):
    """Lateral shift of the car over phase III and heading change at its end (None when the
    history stops before phase III ends)."""
    t = history["t"]
    _, t3, t4, _ = timeline.boundaries()
    if t[-1] < t4:
        return None
    i3, i4 = np.searchsorted(t, t3), min(np.searchsorted(t, t4), len(t) - 1)
    heading = history["yaw_rad"]
    y = history["y_m"]
    return {"shift_m": float(y[i4] - y[i3]),
            "heading_change_deg": float(math.degrees(heading[i4] - heading[i3])),
            "final_heading_deg": float(math.degrees(heading[-1] - heading[i3])),
            "final_shift_m": float(y[-1] - y[i3])}


def calibrate_lane_change(scene: Scene, *, shift_m=3.7, tolerance_m=0.002,
                          heading_tolerance_deg=0.05, max_iterations=8, log=print):
    """Newton's method with finite differences on (amplitude, second lobe), starting from the
    scene's lane change (case a). Returns the calibrated LaneChange and the iteration log."""
    start = scene.manoeuvre
    if not isinstance(start, LaneChange):
        raise ValueError(f"scene {scene.name!r}: calibration needs a !LaneChange manoeuvre")
    timeline = start.timeline
    end = timeline.boundaries()[2] + 0.05
    base = dataclasses.replace(
        scene, simulator=dataclasses.replace(scene.simulator, end_time_s=end),
        logging=Logging(channels=["chassis"], record_period_s=0.05))

    def metrics(amplitude, lobe):
        manoeuvre = dataclasses.replace(start, case="a", amplitude_m=amplitude,
                                        second_lobe=lobe)
        run = simulate(dataclasses.replace(base, manoeuvre=manoeuvre))
        m = lane_change_metrics(run.history, timeline)
        return np.array([m["shift_m"] - shift_m, m["heading_change_deg"]]), m

    history = []
    x = np.array([start.amplitude_m, start.second_lobe])
    for iteration in range(max_iterations):
        r, m = metrics(*x)
        history.append({"amplitude_m": x[0], "second_lobe": x[1]} | m)
        log(f"calibration {iteration}: amplitude {x[0]:.6f} m, second lobe {x[1]:.4f}: "
            f"shift {m['shift_m']:.4f} m, heading change {m['heading_change_deg']:+.3f} deg")
        if abs(r[0]) < tolerance_m and abs(r[1]) < heading_tolerance_deg:
            return dataclasses.replace(start, amplitude_m=float(x[0]),
                                       second_lobe=float(x[1])), history
        jac = np.zeros((2, 2))
        for j, step in enumerate((0.01 * x[0], 0.02)):
            dx = np.zeros(2)
            dx[j] = step
            jac[:, j] = (metrics(*(x + dx))[0] - r) / step
        x = x - np.linalg.solve(jac, r)
    raise RuntimeError(f"lane-change calibration did not converge in {max_iterations} "
                       f"iterations: {history[-1]}")


def save_calibration(path, manoeuvre: LaneChange, history, provenance):
    data = {"profile": {"amplitude_m": manoeuvre.amplitude_m,
                        "second_lobe": manoeuvre.second_lobe},
            "calibration": history, "provenance": provenance}
    path.write_text(json.dumps(data, indent=2) + "\n")


