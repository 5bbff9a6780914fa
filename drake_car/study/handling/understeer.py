"""The understeer budget: the measured understeer gradient of a ramp-steer run split into named
terms that sum to it.

The identity. Let α*_i = −α_i be wheel i's slip angle in the sign that gives a force towards
the turn (the logged α is ISO's: positive when the wheel moves to its left, the force is then
negative) and α*_f, α*_r the axles' means. For a rigid car in a steady turn at small angles
(tan α ≈ α, cos δ ≈ 1, V r ≈ a_y), the front axle moves at the angle (v + a r)/V to the heading
and the rear at (v − b r)/V, so

    δ_w − L r/V = α*_f − α*_r + ε                                                       (1)

with δ_w the front wheels' measured mean steer to the body and ε what (1) leaves out (steer of
the rear wheels to the body, none on this car's trailing arms whose pivots are lateral; the
left/right speed differences; β̇ in the ramp). The angle the rack alone gives, δ_k, differs from
δ_w by the roll steer, so K = d(δ_k − L r/V)/da_y = d(α*_f − α*_r)/da_y + dε/da_y
+ d(δ_k − δ_w)/da_y.

The force each axle must give follows from the steady lateral and yaw balances about the CoG
(a, b its distances to the front and rear axle; Mz the aligning moments; Fx the tyres'
longitudinal forces, δ_i and y_i the wheels' steer angles and lateral positions):

    Y_f = m a_y b/L − Σ_front Fx_i sin δ_i − (ΣMz + M_x)/L,   Y_r = m a_y a/L + (ΣMz + M_x)/L,
    M_x = −Σ y_i Fx_i cos δ_i                                                             (2)

plus the front Fy's own projections, Fy (cos δ − 1) on the lateral balance and y_i Fy_i sin δ_i
on the yaw balance (I_z ṙ is left out: it lands in the balance remainder). The slip angle an
axle needs for a force Y is the common slip angle of its two wheels at which their tyre forces
(the scene's Magic Formula, right tyres mirrored as the simulation does) at given loads Fz,
cambers γ and longitudinal slips κ sum to Y. Each axle's
slip is taken through a chain of stages, each changing one thing, and each term is the
gradient of the change of α*_f − α*_r from one stage to the next, so the terms telescope to
the measured value; the order of the chain is the order of the rows (an interaction of two
effects lands in the later one).
"""

import math

import numpy as np

from drake_car.law.tyre.magic_formula import linear_tyre, magic_formula
from drake_car.model.geometry import whole_car_cog_to_front_m
from drake_car.study.handling.measures import (
    DEFAULT_AY_RANGE,
    DEG_PER_G,
    HandlingError,
    cog_motion,
    first_time,
    fit_line,
    ramp_window,
    road_wheel_steer_rad,
)

WHEELS = ("fl", "fr", "rl", "rr")
MIRROR = {"fl": 1.0, "fr": -1.0, "rl": 1.0, "rr": -1.0}
# (key, term, how it is computed); the named terms, then the remainders.
TERMS = (
    ("tyres", "tyres at static loads, incl. CoG position",
     "single-track: m/L (b/C_f − a/C_r), Kyα of the .tir at the measured static wheel loads "
     "and cambers"),
    ("tyre_nonlinearity", "tyre non-linearity at static loads",
     "Magic Formula against its linearisation, static loads, over the fit range"),
    ("load_transfer", "wheel loads in the turn (lateral load transfer × load sensitivity)",
     "measured Fz per wheel instead of static"),
    ("camber", "camber (camber thrust and its effect on Kyα)", "measured γ per wheel"),
    ("aligning", "aligning moments in the yaw balance", "ΣMz/L moved from rear to front, (2)"),
    ("drive_yaw", "drive: yaw moment of unequal Fx (differential)", "M_x/L, (2)"),
    ("drive_lateral", "drive: lateral component of the front Fx", "Σ Fx sin δ, (2)"),
    ("drive_combined", "drive: combined slip (Fx reduces Fy)", "measured κ per wheel"),
    ("steer_projection", "steer-angle projection of the front Fy",
     "Fy (cos δ − 1) and the track × Fy sin δ yaw moment, (2)"),
    ("roll_steer", "roll steer (front wheels' steer beyond the rack's)",
     "δ_k − δ_w: the rack's kinematic angle (chassis fixed) against the measured wheels'"),
    ("compliance", "compliance", "none modelled: ideal joints, rigid top mounts and tie rods; "
     "K uses the measured rack position"),
    ("balance_remainder", "remainder: force balance",
     "measured axle forces against (2): I_z ṙ (the ramp is not quite steady), the CoG and "
     "the contact points off their nominal positions"),
    ("slip_spread", "remainder: left/right slip spread",
     "mean of the two wheels' measured slips against their common slip (Ackermann, toe, "
     "tyre relaxation in the ramp)"),
    ("kinematic_remainder", "remainder: kinematics",
     "ε of (1): rear-wheel steer, track, β̇, small-angle terms"),
)
NAMED = tuple(k for k, _, _ in TERMS if not k.endswith("remainder") and k != "slip_spread")


def _law(tyre, combined, linear):
    if linear:
        return lambda fz, kappa, alpha, gamma: linear_tyre(tyre, fz, kappa, alpha, gamma, 16.7)
    return lambda fz, kappa, alpha, gamma: magic_formula(tyre, fz, kappa, alpha, gamma, 16.7,
                                                         combined)


def axle_force(law, wheels, alpha):
    """Σ Fy (N, left +) of an axle's wheels [(mirror, Fz, κ, γ)] at the common ISO slip
    angle ``alpha``; right tyres mirrored as ``systems.tyre.TyreSystem`` does."""
    return sum(s * law(fz, kappa, s * alpha, s * gamma).fy for s, fz, kappa, gamma in wheels)


def axle_stiffness(law, wheels):
    """The axle's cornering stiffness at zero slip (N/rad, positive)."""
    return -sum(law(fz, kappa, 0.0, s * gamma).cornering_stiffness
                for s, fz, kappa, gamma in wheels)


def axle_slip(law, wheels, force, *, tol_N=1e-4, max_iterations=40):
    """The common ISO slip angle (rad) at which the axle gives ``force`` (Newton's method)."""
    stiffness = axle_stiffness(law, wheels)
    offset = axle_force(law, wheels, 0.0)
    alpha = (offset - force) / stiffness
    h = 1e-7
    for _ in range(max_iterations):
        f = axle_force(law, wheels, alpha) - force
        if abs(f) < tol_N:
            return alpha
        slope = (axle_force(law, wheels, alpha + h) - force - f) / h
        if not slope < 0:
            return math.nan  # beyond the tyres' peak: no slip gives this force
        alpha -= f / slope
    return math.nan


def _static(history, names):
    """Means over the last second before the steer starts (the straight, phase II)."""
    t = history["t"]
    start = first_time(history["phase"], t, "III")
    if start is None:
        raise HandlingError("the run has no steering phase (III)")
    mask = (t >= start - 1.0) & (t < start)
    if not mask.any():
        mask = t < start
    return {n: float(np.mean(history[n][mask])) for n in names}


def understeer_budget(history, car, tyre, *, kinematic_steer_rad, combined=True, linear=False,
                      ay_range=DEFAULT_AY_RANGE, max_samples=250):
    """The budget of a ramp-steer run (``history`` with the chassis, steering and tyres
    channels) of ``car`` (``CarParameters``) on ``tyre`` (``MagicFormulaTyre``; ``combined``
    and ``linear`` as the scene's tyres). ``kinematic_steer_rad``: the rack's road-wheel angle
    per sample. Returns rows (key, term, gradient in deg/g, share of the measured value),
    the measured gradient, the named terms' sum, the remainders, and the series."""
    law = _law(tyre, combined, linear)
    a, L, m = whole_car_cog_to_front_m(car), car.wheelbase_m, car.mass.total_mass_kg
    b = L - a
    half = {"fl": car.front.track_m / 2, "fr": -car.front.track_m / 2,
            "rl": car.rear.track_m / 2, "rr": -car.rear.track_m / 2}
    motion = cog_motion(history, a, m)
    ay_all = motion["ay"]
    window = np.nonzero(ramp_window(history, ay_all, ay_range))[0]
    idx = window[np.unique(np.linspace(0, window.size - 1, min(max_samples, window.size))
                           .round().astype(int))]
    static = _static(history, [f"{q}_{w}_{u}" for w in WHEELS
                               for q, u in (("Fz", "N"), ("gamma", "rad"))])
    h = {k: np.asarray(v)[idx] for k, v in history.items() if k != "phase"}
    ay, r, speed = ay_all[idx], motion["yaw_rate"][idx], motion["speed"][idx]
    steer = {"fl": h["steer_fl_rad"], "fr": h["steer_fr_rad"],
             "rl": np.zeros(idx.size), "rr": np.zeros(idx.size)}

    def wheels(axle, k, loads, cambers, slips):
        return [(MIRROR[w], loads(w, k), slips(w, k), cambers(w, k))
                for w in (("fl", "fr") if axle == "f" else ("rl", "rr"))]

    def static_fz(w, k):
        return static[f"Fz_{w}_N"]

    def static_gamma(w, k):
        return static[f"gamma_{w}_rad"]

    def fz(w, k):
        return float(h[f"Fz_{w}_N"][k])

    def gamma(w, k):
        return float(h[f"gamma_{w}_rad"][k])

    def kappa(w, k):
        return float(h[f"kappa_{w}"][k])

    def no_slip(w, k):
        return 0.0

    stiffness = {axle: axle_stiffness(law, wheels(axle, 0, static_fz, static_gamma, no_slip))
                 for axle in "fr"}
    offset = {axle: axle_force(law, wheels(axle, 0, static_fz, static_gamma, no_slip), 0.0)
              for axle in "fr"}
    stages = np.zeros((11, idx.size))  # α*_f − α*_r at each stage
    for k in range(idx.size):
        fx = {w: float(h[f"Fx_{w}_N"][k]) for w in WHEELS}
        fy = {w: float(h[f"Fy_{w}_N"][k]) for w in WHEELS}
        cos = {w: math.cos(steer[w][k]) for w in WHEELS}
        sin = {w: math.sin(steer[w][k]) for w in WHEELS}
        mz = sum(h[f"Mz_{w}_Nm"][k] for w in WHEELS) / L
        mx = -sum(half[w] * fx[w] * cos[w] for w in WHEELS) / L
        lateral = sum(fx[w] * sin[w] for w in ("fl", "fr"))
        # The front Fy's own projections: cos δ on the lateral balance, track × sin δ on yaw.
        my = sum(half[w] * fy[w] * sin[w] for w in WHEELS) / L
        projection = sum(fy[w] * (cos[w] - 1.0) for w in ("fl", "fr"))
        f0 = {"f": m * ay[k] * b / L, "r": m * ay[k] * a / L}
        f_mz = {"f": f0["f"] - mz, "r": f0["r"] + mz}
        f_mx = {"f": f_mz["f"] - mx, "r": f_mz["r"] + mx}
        f_lat = {"f": f_mx["f"] - lateral, "r": f_mx["r"]}
        f_fy = {"f": f_lat["f"] - my - projection, "r": f_lat["r"] + my}
        measured = {"f": h["Fy_fl_N"][k] + h["Fy_fr_N"][k], "r": h["Fy_rl_N"][k] + h["Fy_rr_N"][k]}
        row = []
        for axle in "fr":
            rows = [(offset[axle] - f0[axle]) / stiffness[axle]]
            for force, loads, cambers, slips in (
                    (f0, static_fz, static_gamma, no_slip), (f0, fz, static_gamma, no_slip),
                    (f0, fz, gamma, no_slip), (f_mz, fz, gamma, no_slip),
                    (f_mx, fz, gamma, no_slip), (f_lat, fz, gamma, no_slip),
                    (f_lat, fz, gamma, kappa), (f_fy, fz, gamma, kappa),
                    (measured, fz, gamma, kappa)):
                rows.append(axle_slip(law, wheels(axle, k, loads, cambers, slips),
                                      float(force[axle])))
            names = ("fl", "fr") if axle == "f" else ("rl", "rr")
            rows.append(float(np.mean([h[f"alpha_{w}_rad"][k] for w in names])))
            row.append(rows)
        stages[:, k] = -(np.array(row[0]) - np.array(row[1]))
    if not np.all(np.isfinite(stages)):
        raise HandlingError("understeer_budget: an axle force lies beyond its tyres' peak "
                            f"within a_y {ay_range} m/s²; narrow the range")
    wheel_steer = road_wheel_steer_rad(history)[idx]
    under_w = wheel_steer - L * r / speed
    series = {key: stages[i] - stages[i - 1] if i else stages[0]
              for i, key in enumerate(("tyres", "tyre_nonlinearity", "load_transfer", "camber",
                                       "aligning", "drive_yaw", "drive_lateral",
                                       "drive_combined", "steer_projection",
                                       "balance_remainder", "slip_spread"))}
    series["kinematic_remainder"] = under_w - stages[-1]
    series["roll_steer"] = np.asarray(kinematic_steer_rad)[idx] - wheel_steer
    series["compliance"] = np.zeros(idx.size)
    measured_k = fit_line(ay, np.asarray(kinematic_steer_rad)[idx] - L * r / speed)[0] * DEG_PER_G
    gradients = {key: fit_line(ay, s)[0] * DEG_PER_G for key, s in series.items()}
    named = sum(gradients[k] for k in NAMED)
    rows = [{"key": key, "term": term, "how": how, "gradient_deg_per_g": gradients[key],
             "share_pct": 100 * gradients[key] / measured_k if measured_k else None}
            for key, term, how in TERMS]
    single = m / L * (b / stiffness["f"] - a / stiffness["r"]) * DEG_PER_G
    return {"rows": rows, "measured_deg_per_g": measured_k,
            "measured_wheel_deg_per_g": fit_line(ay, under_w)[0] * DEG_PER_G,
            "named_sum_deg_per_g": named, "remainder_deg_per_g": measured_k - named,
            "remainder_pct": 100 * (measured_k - named) / measured_k if measured_k else None,
            "ay_range_mps2": list(ay_range), "samples": int(idx.size),
            "static_wheel_loads_N": {w: static[f"Fz_{w}_N"] for w in WHEELS},
            "static_cambers_deg": {w: math.degrees(static[f"gamma_{w}_rad"]) for w in WHEELS},
            "axle_stiffness_N_per_rad": {"front": stiffness["f"], "rear": stiffness["r"]},
            "single_track_deg_per_g": single,
            "series": {"t": h["t"], "ay_mps2": ay} | {k: np.degrees(v) for k, v in series.items()}}
