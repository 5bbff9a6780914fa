"""Handling metrics from a run's history (pure functions of numpy arrays): steady-state circular
driving by the continuous (ramp-steer) method of ISO 4138, the step steer of ISO 7401, and the
single-track (bicycle) model they are judged against, built from the car's own mass, CoG,
wheelbase and its tyre's cornering stiffness at the static axle loads.

Signs are ISO 8855 (x forward, y left, z up): in a left turn the road-wheel angle δ, the yaw
rate r, the lateral acceleration a_y and the body's roll (right side down) are positive; the
sideslip β is positive when the velocity points left of the heading. A gradient is the slope of
a least-squares straight line over a stated range of a_y, in deg/g (1 g = 9.81 m/s²); the
understeer gradient is K = d(δ − L r/V)/d a_y (road-wheel angle, L the wheelbase, V the speed the
car actually holds, sample by sample).

Where the quantities are taken. The chassis channels are at the body origin O, on the ground
midway between the front contact points; the standards ask for the centre of gravity G, which
lies ``cog_offset_m`` = x behind O. In the heading frame, rigid-body kinematics give
a_y,G = a_y,O − x ṙ and v_y,G = v_y,O − x r (the point on the ground below G; the body's roll
acceleration times the CoG height is left out, it vanishes in steady state); given the mass,
a_y is the whole car's CoG's by Newton from the logged tyre forces instead. Which road-wheel
angle: ``steer_rad`` is what the caller passes: the angle the rack alone gives (the kinematic
rack-to-wheel relation: ISO's steering-wheel angle over the overall steering ratio), or the
measured mean of the two wheels (roll steer included).
"""

import math

import numpy as np

from drake_car.law.tyre.magic_formula import linear_tyre, magic_formula
from drake_car.model.parameters import GRAVITY_MPS2
from drake_car.law.errors import InputError

# rad per m/s² -> deg per g
DEG_PER_G = math.degrees(1.0) * GRAVITY_MPS2
# The linear range of a_y (m/s²) the gradients are fitted over: from where the ramp has left
# its start transient to 0.3 g, within which a passenger car's tyres stay near-linear.
DEFAULT_AY_RANGE = (0.5, 3.0)
# Bins of a_y (m/s²) for the local understeer gradient (how it grows towards the limit).
LOCAL_BINS = ((0.5, 1.5), (1.5, 3.0), (3.0, 4.5), (4.5, 5.5), (5.5, 6.5))


class HandlingError(InputError):
    """A run cannot give a metric (too few samples in the fit range, no steady state)."""


def fit_line(x, y):
    """Least-squares line y = slope x + intercept: (slope, intercept, rms residual)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.size < 2 or np.ptp(x) == 0:
        raise HandlingError("fit_line: needs at least two distinct x values")
    slope, intercept = np.polyfit(x, y, 1)
    rms = float(np.sqrt(np.mean((y - (slope * x + intercept)) ** 2)))
    return float(slope), float(intercept), rms


def _over_speed(value, speed):
    """value / speed where the car moves (> 0.5 m/s), 0 at rest."""
    moving = speed > 0.5
    return np.where(moving, value / np.where(moving, speed, 1.0), 0.0)


def road_wheel_steer_rad(history):
    """The measured road-wheel angle: the mean of the two front wheels' steer to the body."""
    return 0.5 * (history["steer_fl_rad"] + history["steer_fr_rad"])


def kinematic_steer_rad(rack_m, steering):
    """The road-wheel angle the rack alone gives (mean of left and right), from a kinematics
    table ``steering`` (``model.kinematics_sweep``: rack_m, steer_left_deg, steer_right_deg,
    chassis fixed at the design ride height)."""
    rack = np.asarray(steering["rack_m"], float)
    mean = 0.5 * (np.asarray(steering["steer_left_deg"]) + np.asarray(steering["steer_right_deg"]))
    return np.radians(np.interp(rack_m, rack, mean))


def tyre_lateral_force(history):
    """Σ of the four tyres' forces along the car's lateral axis (N, heading frame):
    Fx sin δ + Fy cos δ per wheel, δ the front wheels' measured steer to the body, none at
    the rear (the logged forces are in each wheel's contact frame)."""
    total = 0.0
    for w in ("fl", "fr", "rl", "rr"):
        steer = history[f"steer_{w}_rad"] if w in ("fl", "fr") else 0.0
        total = total + history[f"Fx_{w}_N"] * np.sin(steer) + history[f"Fy_{w}_N"] * np.cos(
            steer)
    return total


def cog_motion(history, cog_offset_m, mass_kg=None):
    """Yaw rate, yaw acceleration, a_y, sideslip and speed at the CoG (``cog_offset_m`` behind
    the body origin) from the chassis channels. a_y: with ``mass_kg`` and the tyres logged, the
    whole car's CoG by Newton (the tyres' lateral forces over the mass: exact, no aerodynamics,
    free of the body's roll accelerations); else the body's point on the ground below the CoG
    (a_y,O − x ṙ; the same in steady state)."""
    t = history["t"]
    r = np.asarray(history["yaw_rate_radps"], float)
    rdot = np.gradient(r, t)
    speed_o, beta_o = history["speed_mps"], history["sideslip_rad"]
    vx = speed_o * np.cos(beta_o)
    vy = speed_o * np.sin(beta_o) - cog_offset_m * r
    moving = np.hypot(vx, vy) > 0.5
    if mass_kg is not None and "Fy_fl_N" in history:
        ay = tyre_lateral_force(history) / mass_kg
    else:
        ay = np.asarray(history["ay_mps2"], float) - cog_offset_m * rdot
    return {"yaw_rate": r, "yaw_accel": rdot, "ay": ay,
            "sideslip": np.where(moving, np.arctan2(vy, vx), 0.0),
            "speed": np.hypot(vx, vy)}


def first_time(phases, t, phase):
    """When ``phase`` begins (s); None if it never does."""
    for time, p in zip(t, phases):
        if p == phase:
            return float(time)
    return None


def ramp_window(history, ay, ay_range):
    """Samples of phase III (the ramp) with a_y inside ``ay_range``."""
    lo, hi = ay_range
    phase = np.asarray(history["phase"])
    mask = (phase == "III") & (ay >= lo) & (ay <= hi)
    if mask.sum() < 10:
        raise HandlingError(f"the ramp has {int(mask.sum())} samples with a_y in [{lo}, {hi}] "
                            "m/s²; steer further or widen the range")
    return mask


def steady_state(history, *, steer_rad, wheelbase_m, cog_offset_m, mass_kg=None,
                 wheel_steer_rad=None, ay_range=DEFAULT_AY_RANGE):
    """ISO 4138 continuous ramp steer at constant speed: the gradients over ``ay_range``.
    ``steer_rad``: the road-wheel angle K is defined on; ``wheel_steer_rad`` (optional): a
    second one (the measured wheels' angle) for a second K and yaw gain. ``mass_kg``: see
    ``cog_motion``."""
    g = cog_motion(history, cog_offset_m, mass_kg)
    ay, r, speed = g["ay"], g["yaw_rate"], g["speed"]
    w = ramp_window(history, ay, ay_range)
    t = history["t"]
    out = {"ay_range_mps2": list(ay_range), "t_range_s": [float(t[w][0]), float(t[w][-1])],
           "samples": int(w.sum()), "speed_mps": float(np.mean(speed[w])),
           "speed_range_mps": [float(speed[w].min()), float(speed[w].max())],
           "ay_rate_mps2_per_s": fit_line(t[w], ay[w])[0]}
    under = steer_rad - wheelbase_m * _over_speed(r, speed)
    k, k0, rms = fit_line(ay[w], under[w])
    out.update(understeer_gradient_deg_per_g=k * DEG_PER_G,
               understeer_intercept_deg=math.degrees(k0), understeer_rms_deg=math.degrees(rms),
               steer_gradient_deg_per_g=fit_line(ay[w], steer_rad[w])[0] * DEG_PER_G,
               roll_gradient_deg_per_g=fit_line(ay[w], history["roll_rad"][w])[0] * DEG_PER_G,
               sideslip_gradient_deg_per_g=fit_line(ay[w], g["sideslip"][w])[0] * DEG_PER_G,
               yaw_rate_gain_per_s=fit_line(steer_rad[w], r[w])[0])
    if "rack_force_N" in history:
        out["rack_force_gradient_N_per_g"] = (
            fit_line(ay[w], history["rack_force_N"][w])[0] * GRAVITY_MPS2)
    if wheel_steer_rad is not None:
        under_w = wheel_steer_rad - wheelbase_m * _over_speed(r, speed)
        out["understeer_gradient_wheel_deg_per_g"] = fit_line(ay[w], under_w[w])[0] * DEG_PER_G
        out["yaw_rate_gain_wheel_per_s"] = fit_line(wheel_steer_rad[w], r[w])[0]
    ramp = np.asarray(history["phase"]) != "I"
    out["max_ay_mps2"] = float(np.max(ay[ramp]))
    local = []
    for lo, hi in LOCAL_BINS:
        m = (np.asarray(history["phase"]) == "III") & (ay >= lo) & (ay <= hi)
        if m.sum() >= 10 and np.ptp(ay[m]) > 0.5 * (hi - lo):
            local.append({"ay_range_mps2": [lo, hi],
                          "understeer_gradient_deg_per_g":
                              fit_line(ay[m], under[m])[0] * DEG_PER_G})
    out["local_understeer"] = local
    return out


def steady_state_series(history, *, steer_rad, wheelbase_m, cog_offset_m, mass_kg=None):
    """The columns the steady-state figures and CSV show (deg, m/s², N)."""
    g = cog_motion(history, cog_offset_m, mass_kg)
    columns = {"t": history["t"], "ay_mps2": g["ay"], "speed_mps": g["speed"],
               "steer_deg": np.degrees(steer_rad),
               "understeer_deg": np.degrees(
                   steer_rad - wheelbase_m * _over_speed(g["yaw_rate"], g["speed"])),
               "yaw_rate_degps": np.degrees(g["yaw_rate"]),
               "roll_deg": np.degrees(history["roll_rad"]),
               "sideslip_cog_deg": np.degrees(g["sideslip"])}
    if "rack_force_N" in history:
        columns["rack_force_N"] = history["rack_force_N"]
    return columns


# -- step steer (ISO 7401) ------------------------------------------------------------------

def _crossing(t, y, level, start):
    """First time at or after index ``start`` where y reaches ``level`` (y rising), linearly
    interpolated; None if never."""
    above = np.nonzero(y[start:] >= level)[0]
    if above.size == 0:
        return None
    i = start + int(above[0])
    if i == 0 or y[i] == y[i - 1]:
        return float(t[i])
    return float(t[i - 1] + (level - y[i - 1]) * (t[i] - t[i - 1]) / (y[i] - y[i - 1]))


def step_response(t, steer, response, *, steady_window_s=1.0):
    """ISO 7401 step-steer characteristics of one response channel: the steady value (mean over
    the last ``steady_window_s``), its gain per unit steer, the response time (from 50 % of the
    steer input to 90 % of the steady response), the peak response time (from 50 % steer to the
    response's peak) and the overshoot (peak over steady, %). A response without a peak before
    the steady window has no peak response time (None) and 0 overshoot."""
    t, steer, y = (np.asarray(v, float) for v in (t, steer, response))
    steady_mask = t >= t[-1] - steady_window_s
    steer_ss, y_ss = float(np.mean(steer[steady_mask])), float(np.mean(y[steady_mask]))
    if not (math.isfinite(steer_ss) and math.isfinite(y_ss)):  # a model that stopped before
        nan = float("nan")  # its steady window (the cross-check's): no characteristic at all
        return {"steady": nan, "gain": nan, "steer_50pct_s": None, "response_time_s": nan,
                "peak_response_time_s": nan, "peak": nan, "overshoot_pct": nan}
    if steer_ss == 0 or y_ss == 0:
        raise HandlingError("step_response: the steer or the response has no steady value")
    s, sy = np.sign(steer_ss), np.sign(y_ss)
    u, v = s * steer / abs(steer_ss), sy * y / abs(y_ss)  # both normalised to 1 at steady state
    moved = np.nonzero(u > 0.01)[0]
    start = int(moved[0]) if moved.size else 0
    t50 = _crossing(t, u, 0.5, start)
    t90 = _crossing(t, v, 0.9, start)
    after = np.arange(t.size) >= start
    i_peak = int(np.argmax(np.where(after, v, -np.inf)))
    has_peak = not steady_mask[i_peak] and v[i_peak] > 1.0
    return {"steady": y_ss, "gain": y_ss / steer_ss, "steer_50pct_s": t50,
            "response_time_s": None if t90 is None or t50 is None else t90 - t50,
            "peak_response_time_s": (float(t[i_peak] - t50) if has_peak and t50 is not None
                                     else None),
            "peak": float(sy * abs(y_ss) * v[i_peak]),
            "overshoot_pct": float(100 * (v[i_peak] - 1.0)) if has_peak else 0.0}


def step_steer(history, *, steer_rad, cog_offset_m, mass_kg=None, steady_window_s=1.0):
    """ISO 7401 step steer from a run: yaw rate and lateral acceleration at the CoG (response
    times, peak response times, overshoot, gains), roll and sideslip at the CoG, the speed
    held; ``steer_rad`` the road-wheel angle the gains are per; ``mass_kg``: see
    ``cog_motion``."""
    g = cog_motion(history, cog_offset_m, mass_kg)
    t = history["t"]
    start = first_time(history["phase"], t, "III")
    keep = t >= (start - 0.5 if start is not None else t[0])
    channels = {"yaw_rate": g["yaw_rate"], "lateral_acceleration": g["ay"],
                "roll": np.asarray(history["roll_rad"]), "sideslip": g["sideslip"]}
    out = {name: step_response(t[keep], steer_rad[keep], y[keep],
                               steady_window_s=steady_window_s)
           for name, y in channels.items()}
    out["speed_mps"] = float(np.mean(g["speed"][keep][t[keep] >= t[-1] - steady_window_s]))
    out["steer_deg"] = math.degrees(float(np.mean(steer_rad[t >= t[-1] - steady_window_s])))
    return out


# -- the single-track model -----------------------------------------------------------------

def axle_cornering_stiffness(tyre, axle_load_N, *, gamma_rad=0.0, linear=False, vx=16.7):
    """Cornering stiffness of an axle (N/rad, positive): two tyres of ``tyre`` (a
    ``law.tyre.magic_formula.MagicFormulaTyre``) at half the axle load each, zero slip."""
    law = linear_tyre if linear else magic_formula
    f = law(tyre, 0.5 * axle_load_N, 0.0, 0.0, gamma_rad, vx)
    return -2.0 * f.cornering_stiffness


def single_track(*, mass_kg, wheelbase_m, cog_to_front_m, front_stiffness, rear_stiffness,
                 speed_mps):
    """The linear single-track model at ``speed_mps``: understeer gradient K = m/L (b/C_f −
    a/C_r), yaw-rate gain r/δ = V/(L + K V²), sideslip gradient at the CoG b/V² − m a/(L C_r),
    characteristic (K > 0) or critical (K < 0) speed sqrt(L/|K|)."""
    m, L, a = mass_kg, wheelbase_m, cog_to_front_m
    b = L - a
    k = m / L * (b / front_stiffness - a / rear_stiffness)
    v = speed_mps
    return {"front_stiffness_N_per_rad": front_stiffness,
            "rear_stiffness_N_per_rad": rear_stiffness, "speed_mps": v,
            "understeer_gradient_deg_per_g": k * DEG_PER_G,
            "yaw_rate_gain_per_s": v / (L + k * v * v),
            "sideslip_gradient_deg_per_g": (b / v ** 2 - m * a / (L * rear_stiffness)) * DEG_PER_G,
            "characteristic_speed_kph": 3.6 * math.sqrt(L / abs(k)) if k else None}


def single_track_response(t, steer_rad, *, speed_mps, mass_kg, yaw_inertia_kgm2,
                          cog_to_front_m, wheelbase_m, front_stiffness, rear_stiffness,
                          relaxation_length_m=0.0, substeps=10):
    """The linear single-track model's response to a road-wheel steer series (RK4 between the
    samples of ``t``, steer linearly interpolated): yaw rate, a_y and sideslip at the CoG.
    ``relaxation_length_m`` > 0 lags each axle's force by σ/V (the tyres' transient slip)."""
    t, steer = np.asarray(t, float), np.asarray(steer_rad, float)
    m, iz, v = mass_kg, yaw_inertia_kgm2, speed_mps
    a = cog_to_front_m
    b = wheelbase_m - a
    lag = relaxation_length_m / v

    def forces(x, d):
        vy, r = x[0], x[1]
        return (front_stiffness * (d - (vy + a * r) / v), rear_stiffness * (-(vy - b * r) / v))

    def rhs(x, d):
        ff, fr = forces(x, d) if lag == 0 else (x[2], x[3])
        dx = [(ff + fr) / m - v * x[1], (a * ff - b * fr) / iz]
        if lag:
            tf, tr = forces(x, d)
            dx += [(tf - x[2]) / lag, (tr - x[3]) / lag]
        return np.array(dx)

    x = np.zeros(4 if lag else 2)
    out = np.zeros((t.size, 3))
    for i in range(t.size):
        if i:
            h = (t[i] - t[i - 1]) / substeps
            for k in range(substeps):
                s0 = t[i - 1] + k * h
                d0, d1, d2 = np.interp([s0, s0 + h / 2, s0 + h], t, steer)
                k1 = rhs(x, d0)
                k2 = rhs(x + h / 2 * k1, d1)
                k3 = rhs(x + h / 2 * k2, d1)
                k4 = rhs(x + h * k3, d2)
                x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        ff, fr = forces(x, steer[i]) if lag == 0 else (x[2], x[3])
        out[i] = (x[1], (ff + fr) / m, math.atan2(x[0], v))
    return {"yaw_rate": out[:, 0], "ay": out[:, 1], "sideslip": out[:, 2]}
