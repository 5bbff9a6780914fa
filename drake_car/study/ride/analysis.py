"""The ride study's outcomes of one run and their numerical errors.

Over the analysed window (constant speed, after the speed-up's transients):

- ``aw_seat_mps2``: ISO 2631-1's Wk-weighted RMS vertical acceleration at the driver's seat
  point (the car's ``car.seat_point_m``, ``model.seat``; the record's mean removed by Wk's high
  pass);
- ``az_seat_rms_mps2``: the same unweighted (mean removed);
- ``roll_acc_rms_radps2``, ``pitch_acc_rms_radps2``: RMS of the body's angular acceleration
  about its x and y axes (unweighted; ISO 2631-1's rotational weighting is not applied);
- ``dlc_front``, ``dlc_rear``: the dynamic wheel-load coefficient, the RMS of a wheel's load
  fluctuation over its mean (static) load, the mean of the axle's two wheels;
- ``stick_left``, ``stick_right``: the share of samples in which the rod's translation pair is
  in the static phase (|v| <= Δv; 0 without friction);
- ``friction_mean_N``: the mean magnitude of the rods' axial friction force (the law's, both
  struts; 0 without friction), in the drive (it includes the stuck spells' lower force);
- ``normal_mean_N``: the mean eq. 4 normal force N of both rods (0 without friction).

``collect`` adds ``rig_friction_N`` = μd · normal_mean_N: the sliding friction force a strut
rig would measure at the car's mean side load, the "friction force" of the rig measurements
(Deubel et al.) the comfort is compared against.

``errors(coarse, fine)``: per outcome |coarse - fine|, the run against itself at half the step
(logged at the same instants).

Whether the car held its speed over the analysed window (``held_speed``): every sample within
``SPEED_TOLERANCE_KPH`` (1 km/h, the manoeuvres' own: ``scene.manoeuvre_targets``, applied
there to place a's mean, here to every sample) of the asked speed; a run that did not is not the ride at that speed (flagged by ``report``)."""

import math

import numpy as np
from scipy import signal

from drake_car.law.comfort.iso2631 import weighted_rms
from drake_car.scene.manoeuvre_targets import SPEED_TOLERANCE_KPH

OUTCOMES = ("aw_seat_mps2", "az_seat_rms_mps2", "roll_acc_rms_radps2", "pitch_acc_rms_radps2",
            "dlc_front", "dlc_rear", "stick_left", "stick_right", "friction_mean_N",
            "normal_mean_N")
WHEELS = ("fl", "fr", "rl", "rr")


def window(history, start_s):
    """The samples' mask at t >= start_s."""
    return np.asarray(history["t"]) >= start_s - 1e-9


def sample_period(history):
    t = np.asarray(history["t"])
    return float(np.median(np.diff(t)))


def outcomes(history, start_s):
    """The OUTCOMES of one run's history over t >= start_s."""
    w = window(history, start_s)
    dt = sample_period(history)
    az = np.asarray(history["az_seat_mps2"])[w]
    out = {"aw_seat_mps2": weighted_rms(az, dt),
           "az_seat_rms_mps2": float(np.std(az)),
           "roll_acc_rms_radps2": _rms(history["roll_acc_radps2"], w),
           "pitch_acc_rms_radps2": _rms(history["pitch_acc_radps2"], w)}
    dlc = {}
    for wheel in WHEELS:
        fz = np.asarray(history[f"Fz_{wheel}_N"])[w]
        dlc[wheel] = float(np.std(fz) / np.mean(fz))
    out["dlc_front"] = 0.5 * (dlc["fl"] + dlc["fr"])
    out["dlc_rear"] = 0.5 * (dlc["rl"] + dlc["rr"])
    for side in ("left", "right"):
        key = f"friction_{side}_translation_phase"
        out[f"stick_{side}"] = (float(np.mean(np.asarray(history[key])[w] == 0))
                                if key in history else 0.0)
    forces = [np.abs(np.asarray(history[f"friction_{side}_translation_friction"])[w])
              for side in ("left", "right") if f"friction_{side}_translation_friction" in history]
    out["friction_mean_N"] = float(np.mean(forces)) if forces else 0.0
    normals = [np.asarray(history[f"friction_{side}_translation_N"])[w]
               for side in ("left", "right") if f"friction_{side}_translation_N" in history]
    out["normal_mean_N"] = float(np.mean(normals)) if normals else 0.0
    return out


def _rms(values, mask):
    v = np.asarray(values)[mask]
    return float(math.sqrt(np.mean((v - v.mean()) ** 2)))


def errors(coarse: dict, fine: dict):
    """Per outcome, |coarse - fine|: the numerical error of the coarse run (its twin at half
    the step as the reference)."""
    return {k: abs(coarse[k] - fine[k]) for k in OUTCOMES}


def seat_psd(history, start_s, segment_s=2.0):
    """(f (Hz), one-sided PSD of the seat's vertical acceleration ((m/s²)²/Hz)) over the
    window: Welch, Hann segments of ``segment_s`` (resolution 1/segment_s), half overlap."""
    w = window(history, start_s)
    dt = sample_period(history)
    az = np.asarray(history["az_seat_mps2"])[w]
    f, p = signal.welch(az - az.mean(), fs=1.0 / dt, nperseg=int(round(segment_s / dt)))
    return f, p


def window_speed_kph(history, start_s):
    """(lowest, highest) speed over the analysed window (km/h), the rear wheels' centres'
    forward speed (the ride study logs no chassis channels); NaN without the tyres' columns."""
    w = window(history, start_s)
    if "vx_rl_mps" not in history or not w.any():
        return math.nan, math.nan
    v = 3.6 * 0.5 * (np.asarray(history["vx_rl_mps"]) + np.asarray(history["vx_rr_mps"]))[w]
    return float(np.min(v)), float(np.max(v))


def held_speed(row):
    """Whether the run of ``row`` (``collect``) held its asked speed over the analysed window
    within ``SPEED_TOLERANCE_KPH`` (False where its speed was not logged: not shown held)."""
    low, high, asked = row["speed_min_kph"], row["speed_max_kph"], row["speed_kph"]
    return (math.isfinite(low) and math.isfinite(high)
            and max(abs(low - asked), abs(high - asked)) <= SPEED_TOLERANCE_KPH)


def collect(runs_by_name, start_of):
    """Rows (dicts) of the coarse runs in ``runs_by_name`` (name -> Run) whose half-step twin
    (name + "_half") is there too: the run's cell (road_class, speed_kph, mu_s, strut), its
    OUTCOMES and err_<outcome>, its launch (s), the speed range over its analysed window
    (km/h) and whether it held its speed (``held_speed``). ``start_of(scene)``: the analysed
    window's start (s)."""
    rows = []
    for name, run in runs_by_name.items():
        twin = runs_by_name.get(name + "_half")
        if name.endswith("_half") or twin is None:
            continue
        scene = run.scene
        coarse = outcomes(run.history, start_of(scene))
        fine = outcomes(twin.history, start_of(twin.scene))
        parts = name.split("_")
        mu_d = 0.0 if scene.friction is None else scene.friction.law.mu_d
        low, high = window_speed_kph(run.history, start_of(scene))
        rows.append({"name": name, "road_class": parts[0],
                     "launch_s": scene.manoeuvre.timeline.speed_up_s,
                     "speed_min_kph": low, "speed_max_kph": high,
                     "rig_friction_N": mu_d * coarse["normal_mean_N"],
                     "speed_kph": scene.manoeuvre.timeline.speed_kph,
                     "mu_s": 0.0 if scene.friction is None else scene.friction.law.mu_s,
                     "strut": parts[3] if len(parts) > 3 else "lubricated",
                     "wall_s": run.wall_s, "wall_half_s": twin.wall_s,
                     **coarse, **{f"err_{k}": v for k, v in errors(coarse, fine).items()}})
        rows[-1]["held_speed"] = held_speed(rows[-1])
    return rows
