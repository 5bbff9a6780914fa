"""The paper's study: two lane changes (a: left turn first, b: right turn first) × three friction
sets, and the verdict on each of the paper's claims (DESIGN.md §5).

The claim logic works on histories (dicts of arrays) only, so it can be tested on synthetic
histories whose right verdict is known.
"""

import dataclasses
import math
import time

import numpy as np

from drake_car.assembly import DEFAULT_TIME_STEP_S, TyreSetup
from drake_car.drive import lane_change_metrics, run_drive
from drake_car.manoeuvre import Timeline
from drake_car.model.geometry import SIDES
from drake_car.scene import SCENES_DIR, load_scene, resolve
from drake_car.settle import run_settle

# Paper section 4: (μs, μd); set 1 is the lubricated strut with 1250 N s/m of damping.
FRICTION_SETS = {1: (0.0, 0.0), 2: (0.2, 0.15), 3: (0.4, 0.3)}
CASES = ("a", "b")
RUN_COLUMNS = (
    "t", "phase", "rack_m", "x_m", "y_m", "yaw_rad", "speed_mps", "dd_left_m", "dd_right_m",
    "v_left_mps", "v_right_mps", "creep_left_m", "creep_right_m", "beta_left", "mu1_left",
    "beta_right", "mu1_right", "N_left_N", "N_right_N", "Ffric_left_N", "Ffric_right_N",
    "rot_left_rad", "rot_right_rad", "Fz_fl_N", "Fz_fr_N", "Fz_rl_N", "Fz_rr_N")
# "Practically zero" in the paper's verdicts, made explicit: 0.1 mm of rod displacement (the
# project's accuracy target).
DISPLACEMENT_THRESHOLD_M = 1e-4
SYMMETRY_TOLERANCE = 0.01  # of the largest |Δd|: "almost identical" curves


def run_name(case, number):
    return f"{case}_{number}"


PAPER_STUDY_SCENES = SCENES_DIR / "paper_study.yaml"


@dataclasses.dataclass
class RunConfig:
    """One run of the study: the car and its friction come from the run's scene in
    scenes/paper_study.yaml (with ``scene_text`` on top); the numerical settings here (step,
    scheme, tyre fidelity, timeline) override the scene's for sweeps."""

    case: str
    friction_set: int
    time_step_s: float = DEFAULT_TIME_STEP_S
    timeline: Timeline = dataclasses.field(default_factory=Timeline)
    scheme: str = "fast"
    record_period_s: float = 0.01
    tyres: TyreSetup = dataclasses.field(default_factory=TyreSetup)
    scene_text: str = ""
    scene_file: str = str(PAPER_STUDY_SCENES)
    sap_pacer: bool = True

    @property
    def name(self):
        return run_name(self.case, self.friction_set)

    def scene(self):
        return load_scene(self.scene_file, child=self.name, scene_text=self.scene_text)

    def car(self):
        resolved = resolve(self.scene())
        friction = resolved.friction
        if friction is not None:
            friction = dataclasses.replace(friction, scheme=self.scheme)
        return resolved.params, friction


# What a study run logs (all of it: the figures and the claims use every group).
STUDY_CHANNELS = ("chassis", "steering", "struts", "tyres", "friction")
# Run columns from the friction's logged diagnostics (translation pair): name -> field.
FRICTION_CHANNELS = {"creep_{side}_m": "creep", "beta_{side}": "beta", "mu1_{side}": "mu1",
                     "N_{side}_N": "N", "Ffric_{side}_N": "friction"}


@dataclasses.dataclass
class StaticEquilibrium:
    """The car at rest on its tyres with lubricated struts: where every run starts (as a
    multibody code's static analysis precedes its dynamic run) and what Δd is measured from
    (the paper's "increments from static equilibrium")."""

    positions: np.ndarray  # the car's generalized positions
    overlap_m: dict  # d per side
    corner_loads_N: dict
    max_abs_velocity: float  # of the car's generalized velocities over the last 0.5 s
    time_step_s: float
    duration_s: float


_EQUILIBRIA = {}
EQUILIBRIUM_SETTLE_S = 6.0


def static_equilibrium(params, time_step_s=DEFAULT_TIME_STEP_S,
                       duration_s=EQUILIBRIUM_SETTLE_S) -> StaticEquilibrium:
    """Settles the lubricated car (friction off; the strut damping does not change the
    equilibrium and is set to the lubricated 1250 N s/m so that it settles fast). Cached."""
    params = dataclasses.replace(params, front=dataclasses.replace(
        params.front, strut_damping_Nspm=1250.0))
    key = (repr(params), time_step_s, duration_s)
    if key not in _EQUILIBRIA:
        settled = run_settle(params, duration_s=duration_s, time_step_s=time_step_s)
        _EQUILIBRIA[key] = StaticEquilibrium(
            settled.positions, settled.strut_overlap_m, settled.corner_loads_N,
            settled.max_abs_generalized_velocity_last_half_s, time_step_s, duration_s)
    return _EQUILIBRIA[key]


def run_one(config: RunConfig, start: StaticEquilibrium | None = None, meshcat=None):
    """Simulates one run from ``start`` (default: the static equilibrium of the run's car at
    the default step); returns (columns RUN_COLUMNS, info, the DriveRun). Δd is measured from
    the start's overlaps."""
    params, friction = config.car()
    if start is None:
        start = static_equilibrium(params)
    d_static = start.overlap_m
    began = time.perf_counter()
    run = run_drive(config.case, params, friction=friction, tyres=config.tyres,
                    timeline=config.timeline, time_step_s=config.time_step_s,
                    record_period_s=config.record_period_s, meshcat=meshcat,
                    channels=STUDY_CHANNELS, sap_pacer=config.sap_pacer,
                    initial_positions=start.positions)
    wall = time.perf_counter() - began
    h = run.history
    out = {c: h[c] for c in ("t", "phase", "rack_m", "x_m", "y_m", "yaw_rad", "speed_mps")}
    dt = np.gradient(h["t"])
    for side in SIDES:
        out[f"dd_{side}_m"] = h[f"d_{side}_m"] - d_static[side]
        # Rod velocity relative to the cylinder (extension +), from the recorded overlap.
        out[f"v_{side}_mps"] = -np.gradient(h[f"d_{side}_m"]) / dt
        for column, field in FRICTION_CHANNELS.items():
            # Friction off: no friction system, no log; the law's quantities are zero.
            out[column.format(side=side)] = h.get(f"friction_{side}_translation_{field}",
                                                  np.zeros_like(h["t"]))
        out[f"rot_{side}_rad"] = h[f"rot_{side}_rad"]
    for w in ("fl", "fr", "rl", "rr"):
        out[f"Fz_{w}_N"] = h[f"Fz_{w}_N"]
    out = {c: out[c] for c in RUN_COLUMNS}
    simulated = float(h["t"][-1])
    info = {"wall_s": wall, "simulated_s": simulated, "real_time_factor": simulated / wall,
            "time_step_s": config.time_step_s, "scheme": config.scheme,
            "frozen_sap_steps": run.monitor.frozen_steps,
            "first_frozen_sap_step_s": run.monitor.first_frozen_time_s,
            "lane_change": lane_change_metrics(h, config.timeline)}
    return out, info, run


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


def phase_one_return(history, timeline: Timeline, side, blend_s=0.3):
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


def evaluate_claims(runs: dict, timeline: Timeline, static_loads: dict):
    """Verdicts on the paper's claims. ``runs``: name -> history (columns RUN_COLUMNS).
    ``static_loads``: Fz at rest of fl, fr (N). Returns a list of claim dicts."""
    claims = []

    def moved(name, side):
        return phase_one_return(runs[name], timeline, side)

    # 1. High friction: rods do not return in phase I (Fig. 14, curve 3).
    returns = {name: max(moved(name, s) for s in SIDES) for name in runs}
    high = max(returns[run_name(c, 3)] for c in CASES)
    low = min(returns[run_name(c, n)] for c in CASES for n in (1, 2))
    h3 = runs[run_name("a", 3)]
    t = h3["t"]
    at_rest = int(np.searchsorted(t, timeline.settle_s))
    speed_up = (t >= timeline.settle_s) & (t < timeline.boundaries()[0])
    normal = float(h3["N_left_N"][at_rest])
    mu_s = FRICTION_SETS[3][0]
    unloading = float(h3["Fz_fl_N"][at_rest] - np.min(h3["Fz_fl_N"][speed_up])) \
        if speed_up.any() else 0.0
    capacity = mu_s * normal
    claims.append({
        "claim": "with (0.4, 0.3) the rods do not return in phase I",
        "number": f"rod movement as the acceleration ends, until the lane change: set 3 "
                  f"{1e3 * high:.3f} mm; sets 1-2 at least {1e3 * low:.3f} mm",
        "value_m": high, "reproduced": bool(high <= DISPLACEMENT_THRESHOLD_M < low),
        "figure": "fig14_a.png, fig14_b.png (phase I)",
        "why": f"the strut's normal force at rest is N = {normal:.0f} N, so static friction "
               f"holds at most μs·N = {capacity:.0f} N of axial load, while the speed-up "
               f"changes each front wheel's load by {unloading:.0f} N"
               + (" (more than the friction can hold: the rod breaks free as the car "
                  "accelerates and again when the acceleration ends)" if unloading > capacity
                  else "") + "; N comes from the strut's bending (eq. 4), which the ball-joint "
               "offset b and the spring line set"})

    # 2. After the manoeuvre, high friction leaves the rods at a new position (place b).
    shifts = {}
    for name, h in runs.items():
        shifts[name] = {}
        for s in SIDES:
            at_a, at_b = place_values(h, timeline, f"dd_{s}_m")
            shifts[name][s] = at_b - at_a
    new_position = max(abs(v) for c in CASES for v in shifts[run_name(c, 3)].values())
    claims.append({
        "claim": "with (0.4, 0.3) the rods stop at a new position after the manoeuvre "
                 "(place b differs from place a)",
        "number": f"largest |Δd(b) - Δd(a)| with set 3: {1e3 * new_position:.3f} mm",
        "value_m": new_position, "reproduced": bool(new_position > DISPLACEMENT_THRESHOLD_M),
        "figure": "fig14_*.png, fig15_*.png (places a and b)"})

    # 3. Left-right difference at b: nearly zero, so no lasting wheel-load change. The verdict
    # is on the rods (the paper's criterion); the load split it causes is reported beside.
    worst_diff, worst_load = 0.0, 0.0
    details = {}
    for name, h in runs.items():
        left = place_values(h, timeline, "dd_left_m")
        right = place_values(h, timeline, "dd_right_m")
        fl, fr = place_values(h, timeline, "Fz_fl_N"), place_values(h, timeline, "Fz_fr_N")
        diff = (left[1] - right[1]) - (left[0] - right[0])
        split = (fl[1] - fr[1]) - (fl[0] - fr[0])
        relative = abs(split) / (0.5 * (static_loads["fl"] + static_loads["fr"]))
        details[name] = {"left_minus_right_change_m": diff, "front_load_split_change_N": split,
                         "front_load_split_change_rel": relative}
        worst_diff = max(worst_diff, abs(diff))
        worst_load = max(worst_load, relative)
    claims.append({
        "claim": "the left-right rod difference after the manoeuvre is practically zero: "
                 "no lasting change of the wheel-load distribution",
        "number": f"largest change of Δd_left - Δd_right from a to b {1e3 * worst_diff:.3f} mm; "
                  f"the front left-right load split changes by up to "
                  f"{100 * worst_load:.2f} % of the corner load",
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
    for n in FRICTION_SETS:
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
               f"the cylinder is the knuckle's steer angle; the calibrated lane change needs "
               f"{1e3 * rack:.1f} mm of rack, i.e. road-wheel angles of that size on this car "
               "(its understeer and steering ratio set them)"})

    # 6. μ1 reaches μs only twice (Fig. 16: case a, set 2).
    mu_s = FRICTION_SETS[2][0]
    h2 = runs[run_name("a", 2)]
    counts = {s: count_reaching(h2[f"mu1_{s}"], mu_s) for s in SIDES}
    peaks = {s: float(np.max(h2[f"mu1_{s}"]) / mu_s) for s in SIDES}
    claims.append({
        "claim": "in Fig. 16 (case a, set 2) μ1 reaches μs only twice",
        "number": f"μ1 reaches μs {counts['left']} times (left strut), "
                  f"{counts['right']} times (right strut)",
        "value": counts, "reproduced": bool(counts["left"] == 2),
        "figure": "fig16.png",
        "why": f"μ1 reaches μs when the creep reaches Δmax while the rod sticks; here the "
               f"largest μ1/μs is {peaks['left']:.3f} (left) and {peaks['right']:.3f} (right): "
               "the stick phases end (the load reverses or the rod breaks free) before the "
               "creep saturates, which depends on N and on the loads of this car"})
    return claims, shifts
