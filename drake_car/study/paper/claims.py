"""The paper's study: two lane changes (a: left turn first, b: right turn first) × its friction
sets (the paper's three, or any number: ``sets``), and the verdict on each of the paper's claims
(its section 4), as a pure layer: runs (each a history and the scene that made it) in; study
columns, claims and their numbers out. Every label, μs and μd comes from the scene that ran;
each claim that compares sets names them (``sets.SetRoles``), and a claim about dry friction is
not applicable (verdict None) when no set is dry.

The claim logic works on histories (dicts of arrays) only, so it can be tested on synthetic
histories whose right verdict is known.
"""

import dataclasses
import math

import numpy as np

from drake_car.model.geometry import SIDES
from drake_car.scene.manoeuvres import Timeline
from drake_car.study.paper.sets import (  # noqa: F401 (the study's names, found here too)
    CASES, STUDY_CHANNELS, FrictionSet, StudyError, check_study_scenes, friction_of,
    numbers_text, roles_of, set_roles)

RUN_COLUMNS = (
    "t", "phase", "rack_m", "x_m", "y_m", "yaw_rad", "speed_mps", "dd_left_m", "dd_right_m",
    "v_left_mps", "v_right_mps", "creep_left_m", "creep_right_m", "beta_left", "mu1_left",
    "beta_right", "mu1_right", "N_left_N", "N_right_N", "Ffric_left_N", "Ffric_right_N",
    "rot_left_rad", "rot_right_rad", "Fz_fl_N", "Fz_fr_N", "Fz_rl_N", "Fz_rr_N",
    "rack_force_N", "steering_wheel_torque_Nm")
# "Practically zero" in the paper's verdicts, made explicit: 0.1 mm of rod displacement (the
# project's accuracy target).
DISPLACEMENT_THRESHOLD_M = 1e-4
SYMMETRY_TOLERANCE = 0.01  # of the largest |Δd|: "almost identical" curves
# Run columns from the friction's logged diagnostics (translation pair): name -> field.
FRICTION_CHANNELS = {"creep_{side}_m": "creep", "beta_{side}": "beta", "mu1_{side}": "mu1",
                     "N_{side}_N": "N", "Ffric_{side}_N": "friction"}


@dataclasses.dataclass
class StudyRun:
    name: str
    case: str  # "a" or "b"
    friction: FrictionSet
    columns: dict  # RUN_COLUMNS


def study_runs(runs: dict):
    """The study's view of ``runs`` (name -> sim.simulate.Run): each run's case, its friction
    set (numbered by μs, as the paper's sets 1-3 are) and its study columns."""
    roles = check_study_scenes({name: run.scene for name, run in runs.items()})
    return {name: StudyRun(name, *roles[name], study_columns(run.history))
            for name, run in runs.items()}


def study_timeline(runs: dict) -> Timeline:
    return next(iter(runs.values())).scene.manoeuvre.timeline


def run_of(study: dict, case, number):
    """The StudyRun of ``case`` with friction set ``number``."""
    for r in study.values():
        if r.case == case and r.friction.number == number:
            return r
    raise StudyError(f"no run of case {case} with friction set {number}")


def study_columns(h):
    """RUN_COLUMNS from a run's history. The run starts at rest in static equilibrium, so Δd is
    the overlap's change from its first sample (the paper's "increments from static
    equilibrium"; rod in +)."""
    missing = [c for c in ("x_m", "rack_m", "d_left_m", "Fz_fl_N") if c not in h]
    if missing:
        raise StudyError(f"a study run must log {STUDY_CHANNELS}; missing columns {missing}")
    out = {c: h[c] for c in ("t", "phase", "rack_m", "x_m", "y_m", "yaw_rad", "speed_mps")}
    dt = np.gradient(h["t"])
    for side in SIDES:
        d = h[f"d_{side}_m"]
        out[f"dd_{side}_m"] = d - d[0]
        # Rod velocity relative to the cylinder (extension +), from the recorded overlap.
        out[f"v_{side}_mps"] = -np.gradient(d) / dt
        for column, field in FRICTION_CHANNELS.items():
            # Friction off: no friction system, no log; the law's quantities are zero.
            out[column.format(side=side)] = h.get(f"friction_{side}_translation_{field}",
                                                  np.zeros_like(h["t"]))
        out[f"rot_{side}_rad"] = h[f"rot_{side}_rad"]
    for w in ("fl", "fr", "rl", "rr"):
        out[f"Fz_{w}_N"] = h[f"Fz_{w}_N"]
    for c in ("rack_force_N", "steering_wheel_torque_Nm"):  # NaN in a history without them
        out[c] = h.get(c, np.full(len(h["t"]), np.nan))
    return {c: out[c] for c in RUN_COLUMNS}


# -- the paper's claims, on histories -------------------------------------------------------

def places(history, timeline: Timeline):
    """Indices of place "a" (just before the lane change) and place "b" (end of the run)."""
    _, t3, _, _ = timeline.boundaries()
    t = history["t"]
    return max(int(np.searchsorted(t, t3) - 1), 0), len(t) - 1


def place_values(history, timeline: Timeline, column):
    """``column`` averaged over place a (the 0.3 s before the lane change) and place b (the
    last 0.5 s): the car still bounces on lightly damped tyres, a single sample would not do."""
    _, t3, _, _ = timeline.boundaries()
    t = history["t"]
    a = (t >= t3 - 0.3) & (t < t3)
    b = t >= t[-1] - 0.5
    values = np.asarray(history[column])
    if not a.any():
        a = np.arange(len(t)) == places(history, timeline)[0]
    return float(np.mean(values[a])), float(np.mean(values[b]))


# How long before the speed-up ends the return is measured from (the jerk ramp's end).
RETURN_BLEND_S = 0.3


def phase_one_return(history, timeline: Timeline, side, blend_s=RETURN_BLEND_S):
    """How far the rod moves once the car's acceleration falls back to zero (the last
    ``blend_s`` of the speed-up) until the lane change begins (m): the paper's "return
    movements" in the second part of phase I."""
    t = history["t"]
    t2, t3 = timeline.boundaries()[:2]
    window = (t >= t2 - blend_s) & (t < t3)
    dd = history[f"dd_{side}_m"][window]
    return float(np.max(dd) - np.min(dd)) if dd.size else 0.0


def count_reaching(mu1, mu_s):
    """How many times μ1 reaches μs (rising edges of μ1 ≥ μs)."""
    if mu_s <= 0:
        return 0
    at = np.asarray(mu1) >= mu_s * (1 - 1e-9)
    return int(np.sum(at[1:] & ~at[:-1]) + (1 if at.size and at[0] else 0))


def not_applicable(claim, why):
    """A claim the study's sets cannot decide (verdict None), with the reason."""
    return {"claim": claim, "number": f"not applicable: {why}", "reproduced": None,
            "applicable": False, "why": why}


NO_DRY_SET = "no friction set is dry (μs > 0)"


def evaluate_claims(study: dict, timeline: Timeline):
    """Verdicts on the paper's claims. ``study``: name -> StudyRun (``study_runs``). Returns
    (a list of claim dicts, the rod shifts from place a to b per run and side); a claim about
    dry friction has verdict None (not applicable) when no set is dry."""
    runs = {name: r.columns for name, r in study.items()}
    roles = set_roles(r.friction for r in study.values())

    def run_name(case, number):
        return run_of(study, case, number).name

    first = runs[run_name("a", roles.numbers[0])]
    static_loads = {"fl": float(first["Fz_fl_N"][0]), "fr": float(first["Fz_fr_N"][0])}
    sets = {r.friction.number: r.friction for r in study.values()}
    high = None if roles.high is None else sets[roles.high]
    high_set = None if high is None else \
        f"set {high.number} (μs = {high.mu_s:g}, μd = {high.mu_d:g})"
    claims = []

    def moved(name, side):
        return phase_one_return(runs[name], timeline, side)

    # 1. High friction: rods do not return in phase I (Fig. 14, curve 3); the lower sets' do.
    returns = {name: max(moved(name, s) for s in SIDES) for name in runs}
    if high is None:
        claims.append(not_applicable("with the highest friction the rods do not return in "
                                     "phase I", NO_DRY_SET))
    else:
        top = max(returns[run_name(c, high.number)] for c in CASES)
        low = min((returns[run_name(c, n)] for c in CASES for n in roles.others),
                  default=math.inf)
        h3 = runs[run_name("a", high.number)]
        t = h3["t"]
        at_rest = int(np.searchsorted(t, timeline.settle_s))
        speed_up = (t >= timeline.settle_s) & (t < timeline.boundaries()[0])
        normal = float(h3["N_left_N"][at_rest])
        unloading = float(h3["Fz_fl_N"][at_rest] - np.min(h3["Fz_fl_N"][speed_up])) \
            if speed_up.any() else 0.0
        capacity = high.mu_s * normal
        others = numbers_text(roles.others)
        claims.append({
            "claim": f"with {high_set} the rods do not return in phase I"
                     + (f"; with {others} they do" if roles.others else ""),
            "number": f"rod movement as the acceleration ends, until the lane change: set "
                      f"{high.number} {1e3 * top:.3f} mm"
                      + (f"; {others} at least {1e3 * low:.3f} mm" if roles.others else ""),
            "value_m": top, "reproduced": bool(top <= DISPLACEMENT_THRESHOLD_M < low),
            "figure": "fig14_a.png, fig14_b.png (phase I)",
            "why": f"the strut's normal force at rest is N = {normal:.0f} N, so static "
                   f"friction holds at most μs·N = {capacity:.0f} N of axial load, while the "
                   f"speed-up changes each front wheel's load by {unloading:.0f} N"
                   + (" (more than the friction can hold: the rod breaks free as the car "
                      "accelerates and again when the acceleration ends)"
                      if unloading > capacity else "")
                   + "; N comes from the strut's bending (eq. 4), which the ball-joint "
                   "offset b and the spring line set"})

    # 2. After the manoeuvre, high friction leaves the rods at a new position (place b).
    shifts = {}
    for name, h in runs.items():
        shifts[name] = {}
        for s in SIDES:
            at_a, at_b = place_values(h, timeline, f"dd_{s}_m")
            shifts[name][s] = at_b - at_a
    if high is None:
        claims.append(not_applicable("with the highest friction the rods stop at a new "
                                     "position after the manoeuvre", NO_DRY_SET))
    else:
        new_position = max(abs(v) for c in CASES
                           for v in shifts[run_name(c, high.number)].values())
        claims.append({
            "claim": f"with {high_set} the rods stop at a new position after the manoeuvre "
                     "(place b differs from place a)",
            "number": f"largest |Δd(b) - Δd(a)| with set {high.number}: "
                      f"{1e3 * new_position:.3f} mm",
            "value_m": new_position,
            "reproduced": bool(new_position > DISPLACEMENT_THRESHOLD_M),
            "figure": "fig14_*.png, fig15_*.png (places a and b)"})

    # 3. Left-right difference at b: nearly zero, so no lasting wheel-load change. The verdict
    # is on the rods (the paper's criterion); the load split it causes is reported beside, in
    # N and in % of the corner load.
    worst_diff, worst_load, worst_N = 0.0, 0.0, 0.0
    details = {}
    corner = 0.5 * (static_loads["fl"] + static_loads["fr"])
    for name, h in runs.items():
        left = place_values(h, timeline, "dd_left_m")
        right = place_values(h, timeline, "dd_right_m")
        fl, fr = place_values(h, timeline, "Fz_fl_N"), place_values(h, timeline, "Fz_fr_N")
        diff = (left[1] - right[1]) - (left[0] - right[0])
        split = (fl[1] - fr[1]) - (fl[0] - fr[0])
        relative = abs(split) / corner
        details[name] = {"left_minus_right_change_m": diff, "front_load_split_change_N": split,
                         "front_load_split_change_rel": relative}
        worst_diff = max(worst_diff, abs(diff))
        worst_load = max(worst_load, relative)
        worst_N = max(worst_N, abs(split))
    claims.append({
        "claim": "the left-right rod difference after the manoeuvre is practically zero: "
                 "no lasting change of the wheel-load distribution",
        "number": f"largest change of Δd_left - Δd_right from a to b {1e3 * worst_diff:.3f} mm; "
                  f"the front left-right load split changes by up to {worst_N:.0f} N "
                  f"({100 * worst_load:.2f} % of the corner load, {corner:.0f} N)",
        "value_m": worst_diff, "reproduced": bool(worst_diff <= DISPLACEMENT_THRESHOLD_M),
        "figure": "wheel_loads.png", "per_run": details,
        "why": "after the lane change the dry struts stick at different extensions left and "
               "right, and the coil springs carry the difference into the wheel loads: "
               + "; ".join(f"{n}: Δd_L-Δd_R {1e3 * d['left_minus_right_change_m']:+.2f} mm, "
                           f"load split {d['front_load_split_change_N']:+.0f} N "
                           f"({100 * d['front_load_split_change_rel']:.2f} %)"
                           for n, d in sorted(details.items()))})

    # 4. Symmetry: Fig. 14a ≈ Fig. 15b and 14b ≈ 15a. The car is mirror-symmetric, so the
    # difference is numerical (stick-slip amplifies round-off into different stick positions);
    # "almost identical" made explicit: within 1 % of the largest |Δd|.
    worst_sym, peak = 0.0, 0.0
    for n in roles.numbers:
        a, b = runs[run_name("a", n)], runs[run_name("b", n)]
        for side, other in (("left", "right"), ("right", "left")):
            worst_sym = max(worst_sym, float(np.max(np.abs(a[f"dd_{side}_m"]
                                                            - b[f"dd_{other}_m"]))))
        peak = max(peak, float(np.max(np.abs(a["dd_left_m"]))),
                   float(np.max(np.abs(a["dd_right_m"]))))
    claims.append({
        "claim": "Fig. 14a ≈ Fig. 15b and 14b ≈ 15a (the car is symmetric)",
        "number": f"largest |Δd(a, side) - Δd(b, other side)| {1e3 * worst_sym:.4f} mm "
                  f"(peak |Δd| {1e3 * peak:.1f} mm)",
        "value_m": worst_sym, "reproduced": bool(worst_sym <= SYMMETRY_TOLERANCE * peak),
        "why": "the car and its cases are mirror images, so the difference is numerical: a "
               "dry strut that sticks near its break-away load breaks free a step earlier or "
               "later in the mirrored run and sticks elsewhere; its size changes with the "
               "step",
        "figure": "fig14_a.png vs fig15_b.png, fig14_b.png vs fig15_a.png"})

    # 5. Rod rotation stays below 3 deg.
    rotation = max(float(np.max(np.abs(h[f"rot_{s}_rad"]))) for h in runs.values()
                   for s in SIDES)
    rack = max(float(np.max(np.abs(h["rack_m"]))) for h in runs.values())
    claims.append({
        "claim": "the rod's rotation in the cylinder stays below 3 deg",
        "number": f"largest |rotation| {math.degrees(rotation):.2f} deg",
        "value_rad": rotation, "reproduced": bool(math.degrees(rotation) < 3.0),
        "figure": "rot_* columns of the run CSVs",
        "why": f"the rod does not turn with the body (universal top mount), so its rotation in "
               f"the cylinder is the knuckle's steer angle; the lane change needed "
               f"{1e3 * rack:.1f} mm of rack, i.e. road-wheel angles of that size on this car "
               "(its understeer and steering ratio set them)"})

    # 6. μ1 reaches μs only twice (Fig. 16: case a, the paper's set 2, μs = 0.2).
    if roles.fig16 is None:
        claims.append(not_applicable("in Fig. 16 μ1 reaches μs only twice", NO_DRY_SET))
        return claims, shifts
    fig16 = sets[roles.fig16]
    mu_s = fig16.mu_s
    h2 = runs[run_name("a", fig16.number)]
    counts = {s: count_reaching(h2[f"mu1_{s}"], mu_s) for s in SIDES}
    peaks = {s: float(np.max(h2[f"mu1_{s}"]) / mu_s) for s in SIDES}
    claims.append({
        "claim": f"in Fig. 16 (case a, set {fig16.number}: μs = {fig16.mu_s:g}, μd = "
                 f"{fig16.mu_d:g}) μ1 reaches μs only twice",
        "number": f"μ1 reaches μs {counts['left']} times (left strut), "
                  f"{counts['right']} times (right strut)",
        "value": counts, "reproduced": bool(counts["left"] == 2),
        "figure": "fig16.png",
        "why": f"μ1 reaches μs when the creep reaches Δmax while the rod sticks; here the "
               f"largest μ1/μs is {peaks['left']:.3f} (left) and {peaks['right']:.3f} (right): "
               "the stick phases end (the load reverses or the rod breaks free) before the "
               "creep saturates, which depends on N and on the loads of this car"})
    return claims, shifts
