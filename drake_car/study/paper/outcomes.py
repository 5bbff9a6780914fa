"""The paper's study as outcomes: per run (or pair of mirror runs) the numbers its claims decide
with, each with the tolerance it must converge to (``TOLERANCES``, each with its reason), for
accuracy on demand (``sweep.refine``); and ``outcomes.csv``: one row per run and outcome with its
value, error, unit, step and whether it converged, which the report and figures read.

An outcome's error is always the same run's (or pair's) difference between steps, never a
comparison of two different runs; a claim's maximum over runs is taken afterwards
(``measures.claim_measures``)."""

import numpy as np

from drake_car.model.geometry import SIDES
from drake_car.results.files import read_csv, write_csv
from drake_car.study.paper.claims import (
    DISPLACEMENT_THRESHOLD_M, count_reaching, phase_one_return, place_values, roles_of,
    study_columns)
from drake_car.study.paper.measures import speed_up_load_change

MM = 1e-3
# outcome -> (tolerance, unit, drives the refinement, why this tolerance).
TOLERANCES = {
    "return_m": (0.2 * DISPLACEMENT_THRESHOLD_M, "m", True,
                 "claim 1 compares it with the 0.1 mm of \"practically zero\": a fifth of that"),
    "shift_left_m": (0.2 * DISPLACEMENT_THRESHOLD_M, "m", True,
                     "claim 2 (set 3 only): Δd(b) - Δd(a) against 0.1 mm, a fifth of it"),
    "shift_right_m": (0.2 * DISPLACEMENT_THRESHOLD_M, "m", True, "as shift_left_m"),
    "lr_change_m": (0.2 * DISPLACEMENT_THRESHOLD_M, "m", True,
                    "claim 3: the change of Δd_left - Δd_right against 0.1 mm, a fifth of it"),
    "split_change": (1e-3, "fraction", True,
                     "claim 3's lasting load split, in fractions of the corner load: 0.1 %, a "
                     "tenth of the 1 % load_split.png is read by, and a seventeenth of the gap "
                     "between the two branches a jammed strut takes (5.0 or 6.7 %)"),
    "split_change_N": (4.0, "N", False,
                       "claim 3's lasting load split in newtons, context: split_change's 0.1 % "
                       "of a 3-5 kN corner load"),
    "wheel_torque_change_Nm": (0.05, "N m", False,
                               "the lasting change of the steering-wheel torque the driver "
                               "holds, context: a twentieth of the unassisted column's 1 N m "
                               "of friction (scene.HandsOff), below which a released wheel "
                               "does not move"),
    "mirror_residual_m": (0.05 * MM, "m", True,
                          "claim 4, a pair a_k|b_k: against 1 % of the peak |Δd| (about "
                          "0.39 mm), an eighth of it"),
    "peak_dd_m": (0.1 * MM, "m", True,
                  "sets claim 4's threshold (1 % of it): 0.1 mm moves that by 0.001 mm"),
    "rotation_rad": (np.radians(0.01), "rad", True,
                     "claim 5: against 3°, reported to 0.01°"),
    "mu1_reaches_left": (0.0, "count", True, "claim 6 (case a, set 2): a count, exact"),
    "mu1_reaches_right": (0.0, "count", False, "claim 6's context: a count, exact"),
    "mu1_peak_left": (1e-3, "ratio", False,
                      "claim 6's context: μ1/μs, whether it reaches 1, to three decimals"),
    "mu1_peak_right": (1e-3, "ratio", False, "as mu1_peak_left"),
    "hold_N": (1.0, "N", False, "claim 1's context: μs·N at rest, to the newton"),
    "unload_peak_N": (1.0, "N", False, "claim 1's context, to the newton"),
    "unload_steady_N": (1.0, "N", False, "claim 1's context, to the newton"),
    **{f"dd_{s}_{p}_m": (0.1 * MM, "m", False, "the rod positions' table: 0.1 mm, the project's "
                         "accuracy target") for s in SIDES for p in "ab"},
}
DRIVES = {k for k, v in TOLERANCES.items() if v[2]}
COLUMNS = ("run", "outcome", "value", "error", "unit", "step_s", "converged", "tolerance",
           "observed_order", "steps_tried_s", "values_by_step", "run_wall_s", "solver_error",
           "limited_by", "route", "windows", "events_resolved", "finest_step_s",
           "resolution_cpu_s", "run_cpu_s")
# How an outcome was made accurate: its run's whole step halved (global, ``sweep.refine``),
# its events resolved locally (local, ``study.paper.local_route``), or one step (none).
ROUTES = ("global", "local", "none")


def study_outcomes(columns: dict, roles: dict, timeline):
    """{(subject, outcome): (value, unit)} of study columns ``columns`` (name -> RUN_COLUMNS,
    all at one step; any subset of the study's runs); ``roles``: name -> (case, FrictionSet)
    (``claims.check_study_scenes``). A pair's outcome needs both of its runs. The highest
    dry set's runs give claims 1 and 2 their numbers, case a of Fig. 16's set claim 6's
    (``sets.SetRoles``)."""
    out = {}
    sets = roles_of(roles)
    for name, h in columns.items():
        case, friction = roles[name]

        def put(outcome, value):
            out[(name, outcome)] = (float(value), TOLERANCES[outcome][1])
        put("return_m", max(phase_one_return(h, timeline, s) for s in SIDES))
        at = {s: place_values(h, timeline, f"dd_{s}_m") for s in SIDES}
        for s in SIDES:
            put(f"dd_{s}_a_m", at[s][0])
            put(f"dd_{s}_b_m", at[s][1])
            if friction.number == sets.high:
                put(f"shift_{s}_m", at[s][1] - at[s][0])
        put("lr_change_m", (at["left"][1] - at["right"][1]) - (at["left"][0] - at["right"][0]))
        corner = 0.5 * (float(h["Fz_fl_N"][0]) + float(h["Fz_fr_N"][0]))
        fl, fr = (place_values(h, timeline, f"Fz_{w}_N") for w in ("fl", "fr"))
        put("split_change", ((fl[1] - fr[1]) - (fl[0] - fr[0])) / corner)
        put("split_change_N", (fl[1] - fr[1]) - (fl[0] - fr[0]))
        torque = place_values(h, timeline, "steering_wheel_torque_Nm")
        put("wheel_torque_change_Nm", torque[1] - torque[0])
        put("peak_dd_m", max(float(np.max(np.abs(h[f"dd_{s}_m"]))) for s in SIDES))
        put("rotation_rad", max(float(np.max(np.abs(h[f"rot_{s}_rad"]))) for s in SIDES))
        if (case, friction.number) == ("a", sets.fig16):
            for s in SIDES:
                put(f"mu1_reaches_{s}", count_reaching(h[f"mu1_{s}"], friction.mu_s))
                put(f"mu1_peak_{s}", np.max(h[f"mu1_{s}"]) / friction.mu_s
                    if friction.mu_s > 0 else 0.0)
        if (case, friction.number) == ("a", sets.high):
            t = h["t"]
            rest = min(int(np.searchsorted(t, timeline.settle_s)), len(t) - 1)
            peak, steady = speed_up_load_change(h, timeline)
            put("hold_N", friction.mu_s * h["N_left_N"][rest])
            put("unload_peak_N", peak)
            put("unload_steady_N", steady)
    for name, h in columns.items():
        case, friction = roles[name]
        mirror = next((m for m, (c, f) in roles.items()
                       if c != case and f.number == friction.number), None)
        if case == "a" and mirror in columns:
            b = columns[mirror]
            residual = max(float(np.max(np.abs(h[f"dd_{s}_m"] - b[f"dd_{o}_m"])))
                           for s, o in (("left", "right"), ("right", "left")))
            out[(f"{name}|{mirror}", "mirror_residual_m")] = (residual, "m")
    return out


def outcomes_of_runs(roles, timeline):
    """``study_outcomes`` of sim Runs (name -> Run), for ``sweep.refine.refine``."""
    return lambda runs: study_outcomes({n: study_columns(r.history) for n, r in runs.items()},
                                       roles, timeline)


def tolerances():
    return {k: v[0] for k, v in TOLERANCES.items()}


def at_one_step(values: dict, step_s=None):
    """Outcome rows of values at one step only (no error estimated): ``study_outcomes``'
    values as ``refine`` would give them, with converged and error None."""
    return {k: {"unit": unit, "tolerance": TOLERANCES[k[1]][0], "steps_s": [step_s],
                "values": [value], "value": value, "error": None, "converged": None,
                "observed_order": None, "step_s": step_s, "solver_error": None,
                "limited_by": None}
            for k, (value, unit) in values.items()}


def write_outcomes(path, outcomes: dict, run_wall_s=None, run_cpu_s=None):
    """``outcomes.csv``: one row per run (or pair) and outcome, in ``COLUMNS``; converged is
    yes, no or "-" (not judged: a single step, or an outcome the local route gives no error);
    the steps tried and the values at each are ";"-joined; solver_error is the solver axis'
    (``sweep.refine``; nan without one) and limited_by the axis whose error is the larger ("-"
    without an error); how it was made accurate (``ROUTES``) and, locally, the windows, the
    events in them, the finest step a window used and the windows' CPU time; the runs'
    simulation wall and CPU time (all steps tried)."""
    rows = sorted(outcomes.items())
    wall, cpu = run_wall_s or {}, run_cpu_s or {}

    def num(value):
        return float("nan") if value is None else float(value)
    columns = {
        "run": [s for (s, _), _ in rows], "outcome": [o for (_, o), _ in rows],
        "value": [float(r["value"]) for _, r in rows],
        "error": [float("nan") if r["error"] is None else float(r["error"]) for _, r in rows],
        "unit": [r["unit"] for _, r in rows],
        "step_s": [float(r["step_s"] or float("nan")) for _, r in rows],
        "converged": [{True: "yes", False: "no", None: "-"}[r["converged"]] for _, r in rows],
        "tolerance": [float("nan") if r["tolerance"] is None else float(r["tolerance"])
                      for _, r in rows],
        "observed_order": [float("nan") if r["observed_order"] is None
                           else float(r["observed_order"]) for _, r in rows],
        "steps_tried_s": [";".join(f"{s:g}" for s in r["steps_s"] if s is not None)
                          for _, r in rows],
        "values_by_step": [";".join(repr(float(v)) for v in r["values"]) for _, r in rows],
        "run_wall_s": [float(sum(wall.get(n, float("nan")) for n in s.split("|")))
                       for (s, _), _ in rows],
        "solver_error": [float("nan") if r.get("solver_error") is None
                         else float(r["solver_error"]) for _, r in rows],
        "limited_by": [r.get("limited_by") or "-" for _, r in rows],
        "route": [r.get("route", "global" if r["converged"] is not None else "none")
                  for _, r in rows],
        "windows": [int(r.get("windows", 0)) for _, r in rows],
        "events_resolved": [int(r.get("events_resolved", 0)) for _, r in rows],
        "finest_step_s": [num(r.get("finest_step_s", min(
            (x for x in r["steps_s"] if x is not None), default=None))) for _, r in rows],
        "resolution_cpu_s": [num(r.get("resolution_cpu_s")) for _, r in rows],
        "run_cpu_s": [float(sum(cpu.get(n, float("nan")) for n in s.split("|")))
                      for (s, _), _ in rows]}
    assert tuple(columns) == COLUMNS
    write_csv(path, columns)


def read_outcomes(path):
    """``outcomes.csv`` back as (subject, outcome) -> row (as ``refine`` gives them)."""
    c = read_csv(path)
    out = {}
    for i, (subject, outcome) in enumerate(zip(c["run"], c["outcome"])):
        def num(column):
            v = float(c[column][i])
            return None if np.isnan(v) else v
        steps = str(c["steps_tried_s"][i])
        values = str(c["values_by_step"][i])
        out[(subject, outcome)] = {
            "unit": c["unit"][i], "value": float(c["value"][i]), "error": num("error"),
            "step_s": num("step_s"), "tolerance": num("tolerance"),
            "converged": {"yes": True, "no": False}.get(c["converged"][i]),
            "observed_order": num("observed_order"),
            "steps_s": [float(s) for s in steps.split(";") if s],
            "values": [float(v) for v in values.split(";") if v],
            "run_wall_s": num("run_wall_s"), "solver_error": num("solver_error"),
            "limited_by": None if c["limited_by"][i] == "-" else str(c["limited_by"][i])}
        if "route" in c:  # written since the local route (older files: global or one step)
            out[(subject, outcome)] |= {
                "route": c["route"][i], "windows": int(float(c["windows"][i])),
                "events_resolved": int(float(c["events_resolved"][i])),
                "finest_step_s": num("finest_step_s"),
                "resolution_cpu_s": num("resolution_cpu_s"), "run_cpu_s": num("run_cpu_s")}
    return out
