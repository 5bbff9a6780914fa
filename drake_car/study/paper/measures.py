"""The numbers behind each of the paper's claims (``claim_measures``): for each claim, its
deciding numbers with unit, threshold and the runs that decide them, plus context numbers, each
from the per-run outcomes (``outcomes``) with the error of the runs it comes from."""

import math

import numpy as np

from drake_car.model.geometry import SIDES
from drake_car.scene.manoeuvres import Timeline
from drake_car.study.paper.claims import (
    CASES, DISPLACEMENT_THRESHOLD_M, SYMMETRY_TOLERANCE, numbers_text, roles_of)

RELATIONS = {"<=": np.less_equal, "<": np.less, ">": np.greater, ">=": np.greater_equal,
             "==": np.equal}


def speed_up_load_change(history, timeline: Timeline, wheel="fl", blend_s=0.3):
    """How much the speed-up unloads a wheel (N, + = less than at rest): the peak, and the steady
    change (mean over the constant acceleration, without ``speed_profile``'s jerk ramps)."""
    t, fz = history["t"], np.asarray(history[f"Fz_{wheel}_N"])
    t0, t2 = timeline.settle_s, timeline.boundaries()[0]
    blend = min(blend_s, timeline.launch_s / 3)
    rest = float(fz[min(int(np.searchsorted(t, t0)), len(t) - 1)])
    speed_up, steady = (t >= t0) & (t < t2), (t >= t0 + blend) & (t < t2 - blend)
    peak = rest - float(np.min(fz[speed_up])) if speed_up.any() else 0.0
    return peak, (rest - float(np.mean(fz[steady])) if steady.any() else peak)


def claim_measures(table: dict, roles: dict):
    """Per claim (``evaluate_claims``' order) the numbers behind its verdict, from outcome rows
    ``table`` ((subject, outcome) -> {"value", "error", "converged", "unit", "steps_s",
    "values", ...}: ``outcomes.study_outcomes`` refined, or at one step) and ``roles`` (name ->
    (case, FrictionSet)). Each: {name, value, unit (m rad N fraction ratio count), relation,
    threshold, runs, decides, error, converged, margin, holds, decided, limited_by}. A
    row's error is its budget: the step's error plus the solver's (``sweep.refine``), and
    limited_by the larger of the two. A maximum (minimum)
    over runs is taken over each run's own value; its error is the largest of theirs
    (|max x - max y| <= max |x - y|), converged only if every run's is. Verdict: all
    ``decides`` ones hold; decided only if each one's margin exceeds its budget (converged: its
    error; not converged: the spread of its last three steps or windows' levels; a count:
    converged, and the peak that makes it clear of the threshold by more than the peak's
    error)."""
    names = {(c, f.number): n for n, (c, f) in roles.items()}
    sets = roles_of(roles)
    of = {k: [names[(c, k)] for c in CASES] for k in sets.numbers}
    pairs = [f"{names[('a', k)]}|{names[('b', k)]}" for k in sets.numbers]
    T = DISPLACEMENT_THRESHOLD_M

    def m(name, outcomes, subjects, relation=None, threshold=None, how=max, decides=True,
          threshold_error=0.0):
        rows = [(s, table[(s, o)]) for s in subjects for o in outcomes if (s, o) in table]
        subject, row = how(rows, key=lambda r: abs(r[1]["value"]))
        errors = [None if r["error"] is None else r["error"] + (r.get("solver_error") or 0.0)
                  for _, r in rows]
        worst = max(rows, key=lambda r: r[1]["error"] + (r[1].get("solver_error") or 0.0)
                    if r[1]["error"] is not None else -1.0)[1]
        converged = [r["converged"] for _, r in rows]
        out = {"name": name, "value": abs(float(row["value"])), "unit": row["unit"],
               "relation": relation, "threshold": None if threshold is None else
               float(threshold), "runs": subject.split("|"), "outcomes": list(outcomes),
               "decides": bool(decides and relation is not None),
               "error": None if None in errors else max(errors) + threshold_error,
               "converged": None if None in converged else all(converged),
               "steps_s": row["steps_s"], "values": row["values"],
               "route": row.get("route"), "finest_step_s": row.get("finest_step_s"),
               "limited_by": worst.get("limited_by")}
        return _judged(out)

    everyone = [n for k in sets.numbers for n in of[k]]
    one, two, six = [], [], []
    if sets.high is not None:
        high, a3 = sets.high, names[("a", sets.high)]
        others = [n for k in sets.others for n in of[k]]
        one = [m(f"rod movement as the acceleration ends, until the lane change: largest with "
                 f"set {high}", ["return_m"], of[high], "<=", T)]
        if others:
            one.append(m(f"the same: smallest with {numbers_text(sets.others)}", ["return_m"],
                         others, ">", T, how=min))
        one += [m(f"static friction's hold at rest, μs·N (set {high}, left strut)", ["hold_N"],
                  [a3]),
                m("front left wheel unloaded by the speed-up: peak", ["unload_peak_N"], [a3]),
                m("the same: steady (constant acceleration)", ["unload_steady_N"], [a3])]
        two = [m(f"largest |Δd(b) - Δd(a)| with set {high}", ["shift_left_m", "shift_right_m"],
                 of[high], ">", T)]
        lubricated = [k for k in sets.numbers if not _set(roles, k).dry]
        alone = [n for k in lubricated for n in of[k]]
        if alone and all((n, f"dd_{s}_{p}_m") in table for n in alone for s in SIDES
                         for p in "ab"):  # what the car does between the places by itself
            two.append(_shift_between_places(
                f"the same without dry friction ({numbers_text(lubricated)})", table, alone))
    three = [m("largest change of Δd_left - Δd_right from a to b", ["lr_change_m"], everyone,
               "<=", T),
             m("largest steady change of the front left-right load split, of the corner load",
               ["split_change"], everyone),
             m("the same in newtons", ["split_change_N"], everyone)]
    peak = m("peak |Δd|", ["peak_dd_m"], everyone)
    four = [m("largest |Δd(a, side) - Δd(b, other side)|", ["mirror_residual_m"], pairs, "<=",
              SYMMETRY_TOLERANCE * peak["value"],
              threshold_error=SYMMETRY_TOLERANCE * (peak["error"] or 0.0))]
    five = [m("largest |rotation| of a rod in its cylinder", ["rotation_rad"], everyone, "<",
              math.radians(3.0))]
    if sets.fig16 is not None:
        a2 = names[("a", sets.fig16)]
        six = [m(f"times μ1 reaches μs, {s} strut", [f"mu1_reaches_{s}"], [a2], "==", 2,
                 decides=s == "left") for s in SIDES]
        six += [m(f"largest μ1/μs, {s} strut (it counts on reaching 1)", [f"mu1_peak_{s}"],
                  [a2], ">=", 1, decides=False) for s in SIDES]
        for count, peak in zip(six[:2], six[2:]):
            # A count of threshold crossings is exact at each step, but a count of 0 is
            # decided only when the peak is clear of μs by more than the peak's error: a peak
            # within its error of μs could reach it at a finer step. (Once μ1 reaches μs the
            # peak is exactly 1, the law's cap: a count above 0 rests on the count alone.)
            if count["decided"] and count["value"] == 0 and peak["error"] is not None:
                count["decided"] = peak["margin"] > peak["error"]
    return [one, two, three, four, five, six]


def _shift_between_places(name, table, runs):
    """Context: the largest |Δd(b) - Δd(a)| over ``runs`` and sides, from their rods' place
    values (dd_*_a_m, dd_*_b_m); its error the two places' budgets summed."""
    best = None
    for run in runs:
        for side in SIDES:
            a, b = table[(run, f"dd_{side}_a_m")], table[(run, f"dd_{side}_b_m")]
            value = abs(b["value"] - a["value"])
            if best is None or value > best["value"]:
                errors = [r["error"] for r in (a, b)]
                best = {
                    "name": name, "value": value, "unit": "m", "relation": None,
                    "threshold": None, "runs": [run], "outcomes": [f"dd_{side}_a_m",
                                                                   f"dd_{side}_b_m"],
                    "decides": False,
                    "error": None if None in errors else sum(
                        r["error"] + (r.get("solver_error") or 0.0) for r in (a, b)),
                    "converged": None if None in (a["converged"], b["converged"])
                    else bool(a["converged"] and b["converged"]),
                    "steps_s": b["steps_s"],
                    "values": ([abs(y - x) for x, y in zip(a["values"], b["values"])]
                               if a["values"] and b["values"] else b["values"]),
                    "route": b.get("route"), "finest_step_s": b.get("finest_step_s"),
                    "limited_by": b.get("limited_by")}
    return _judged(best)


def _set(roles, number):
    """The FrictionSet numbered ``number`` in ``roles`` (name -> (case, FrictionSet))."""
    return next(f for _, f in roles.values() if f.number == number)


def _judged(m):
    m["holds"] = m["margin"] = m["decided"] = None
    if m["relation"] is None:
        return m
    m["holds"] = holds(m)
    m["margin"] = abs(m["value"] - m["threshold"])
    if m["error"] is not None:
        # A count is exact at each step: decided when converged. Any other number is decided
        # when its margin exceeds its whole budget: the error of a converged value, or, where
        # the values did not converge at first order, the spread of its last three steps (or
        # of its windows' last three levels) plus the solver's (b_3's claim-2 shift
        # 7.336 / 7.333 / 7.330 mm against 0.1 mm, differences of 3 µm that do not shrink).
        spread = m["route"] == "local" or len(m["values"] or []) >= 3
        m["decided"] = (bool(m["converged"]) if m["unit"] == "count"
                        else m["margin"] > m["error"] and (bool(m["converged"]) or spread))
    return m


def holds(measure, value=None):
    """Whether ``value`` (default: the measure's own) meets the measure's threshold."""
    value = measure["value"] if value is None else value
    return bool(RELATIONS[measure["relation"]](value, measure["threshold"]))


def verdict(rows):
    """(reproduced, decided) of a claim from its measures: decided None when no error was
    estimated; (None, None) for a claim with no measures (not applicable to the study's
    sets)."""
    deciding = [r for r in rows if r["decides"]]
    if not deciding:
        return None, None
    decided = [r["decided"] for r in deciding]
    return (all(r["holds"] for r in deciding),
            None if None in decided else all(decided))
