"""Calibrates the lane-change rack profile: the car's track shifts ``shift_m`` during the 2.4 s
of phase III and ends parallel (paper section 4: 3.7 m, 2.4 s, 60 km/h)."""

import dataclasses
import json
from pathlib import Path

import numpy as np

from drake_car.drive import lane_change_metrics, run_drive
from drake_car.manoeuvre import LaneChangeProfile, Timeline


CALIBRATED_PROFILE = Path(__file__).resolve().parents[1] / "scenes" / "lane_change_profile.json"


def calibrated_profile():
    """The lane-change profile calibrated by experiments/calibrate_lane_change.py."""
    if not CALIBRATED_PROFILE.is_file():
        raise FileNotFoundError(f"{CALIBRATED_PROFILE}: calibrated lane-change profile missing; "
                                "run experiments/calibrate_lane_change.py")
    return load_profile(CALIBRATED_PROFILE)


def calibrate_lane_change(*, shift_m=3.7, params=None, tyres=None, timeline=None,
                          start=None, tolerance_m=0.005, heading_tolerance_deg=0.05,
                          max_iterations=8, log=print):
    """Newton's method with finite differences on (amplitude, second lobe): the shift at the
    end of phase III equals ``shift_m`` and the heading change there is zero. Returns the
    profile and the iteration log."""
    timeline = timeline or Timeline()
    profile = start or LaneChangeProfile()
    end = timeline.boundaries()[2] + 0.05

    def metrics(p):
        run = run_drive("a", params, tyres=tyres, timeline=timeline, profile=p,
                        end_time_s=end, record_period_s=0.05)
        m = lane_change_metrics(run.history, timeline)
        return np.array([m["shift_m"] - shift_m, m["heading_change_deg"]]), m

    history = []
    x = np.array([profile.amplitude_m, profile.second_lobe])
    for iteration in range(max_iterations):
        current = dataclasses.replace(profile, amplitude_m=x[0], second_lobe=x[1])
        r, m = metrics(current)
        history.append({"amplitude_m": x[0], "second_lobe": x[1]} | m)
        log(f"calibration {iteration}: amplitude {x[0]:.6f} m, second lobe {x[1]:.4f}: "
            f"shift {m['shift_m']:.4f} m, heading change {m['heading_change_deg']:+.3f} deg")
        if abs(r[0]) < tolerance_m and abs(r[1]) < heading_tolerance_deg:
            return current, history
        jac = np.zeros((2, 2))
        for j, step in enumerate((0.01 * x[0], 0.02)):
            dx = np.zeros(2)
            dx[j] = step
            jac[:, j] = (metrics(dataclasses.replace(
                profile, amplitude_m=x[0] + dx[0], second_lobe=x[1] + dx[1]))[0] - r) / step
        x = x - np.linalg.solve(jac, r)
    raise RuntimeError(f"lane-change calibration did not converge in {max_iterations} "
                       f"iterations: {history[-1]}")


def save_profile(path, profile: LaneChangeProfile, history, provenance):
    data = {"profile": dataclasses.asdict(profile), "calibration": history,
            "provenance": provenance}
    path.write_text(json.dumps(data, indent=2) + "\n")


def load_profile(path):
    try:
        data = json.loads(Path(path).read_text())
    except json.JSONDecodeError as e:
        raise ValueError(f"{path}: not a lane-change profile: {e}") from e
    fields = data["profile"]
    return LaneChangeProfile(**{k: tuple(v) if isinstance(v, list) else v
                                for k, v in fields.items()})
