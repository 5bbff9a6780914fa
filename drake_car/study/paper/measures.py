"""The numbers behind each of the paper's claims (``claim_measures``): for each claim, its
deciding numbers with unit, threshold and the runs that decide them, plus context numbers; the
report gives each with its numerical error from the half-step rerun."""

import math

import numpy as np

from drake_car.model.geometry import SIDES
from drake_car.scene.manoeuvres import Timeline
from drake_car.study.paper.claims import (
    CASES, DISPLACEMENT_THRESHOLD_M, SYMMETRY_TOLERANCE, count_reaching, phase_one_return,
    place_values)

RELATIONS = {"<=": np.less_equal, "<": np.less, ">": np.greater, ">=": np.greater_equal,
             "==": np.equal}


def speed_up_load_change(history, timeline: Timeline, wheel="fl", blend_s=0.3):
    """How much the speed-up unloads a wheel (N, + = less than at rest): the peak, and the steady
    change (mean over the constant acceleration, without ``speed_profile``'s jerk ramps)."""
    t, fz = history["t"], np.asarray(history[f"Fz_{wheel}_N"])
    t0, t2 = timeline.settle_s, timeline.boundaries()[0]
    blend = min(blend_s, timeline.speed_up_s / 3)
    rest = float(fz[min(int(np.searchsorted(t, t0)), len(t) - 1)])
    speed_up, steady = (t >= t0) & (t < t2), (t >= t0 + blend) & (t < t2 - blend)
    peak = rest - float(np.min(fz[speed_up])) if speed_up.any() else 0.0
    return peak, (rest - float(np.mean(fz[steady])) if steady.any() else peak)


def _m(name, value, unit, relation=None, threshold=None, runs=(), decides=True):
    return {"name": name, "value": float(value), "unit": unit, "relation": relation,
            "threshold": None if threshold is None else float(threshold), "runs": list(runs),
            "decides": bool(decides and relation is not None)}


def claim_measures(study: dict, timeline: Timeline):
    """Per claim (``evaluate_claims``' order) the numbers behind its verdict: dicts {name, value,
    unit (m rad N fraction ratio count), relation, threshold, runs, decides}; verdict: all
    ``decides`` ones hold."""
    runs, T = {n: r.columns for n, r in study.items()}, DISPLACEMENT_THRESHOLD_M
    names = {(r.case, r.friction.number): n for n, r in study.items()}
    of = {k: [names[(c, k)] for c in CASES] for k in (1, 2, 3)}
    a2, a3 = names[("a", 2)], names[("a", 3)]
    ret = {n: max(phase_one_return(h, timeline, s) for s in SIDES) for n, h in runs.items()}
    hi, lo = max(of[3], key=ret.get), min(of[1] + of[2], key=ret.get)
    rest = min(int(np.searchsorted(runs[a3]["t"], timeline.settle_s)), len(runs[a3]["t"]) - 1)
    normal, (peak, steady) = runs[a3]["N_left_N"][rest], speed_up_load_change(runs[a3], timeline)
    one = [_m("rod movement as the acceleration ends, until the lane change: largest with "
              "set 3", ret[hi], "m", "<=", T, [hi]),
           _m("the same: smallest with sets 1-2", ret[lo], "m", ">", T, [lo]),
           _m("static friction's hold at rest, μs·N (set 3, left strut)",
              study[a3].friction.mu_s * normal, "N", runs=[a3]),
           _m("front left wheel unloaded by the speed-up: peak", peak, "N", runs=[a3]),
           _m("the same: steady (constant acceleration)", steady, "N", runs=[a3])]
    at = {n: {s: place_values(h, timeline, f"dd_{s}_m") for s in SIDES} for n, h in runs.items()}
    shift = {n: max(abs(b - a) for a, b in at[n].values()) for n in runs}
    two = [_m("largest |Δd(b) - Δd(a)| with set 3", shift[k := max(of[3], key=shift.get)],
              "m", ">", T, [k])]
    diff = {n: abs((v["left"][1] - v["right"][1]) - (v["left"][0] - v["right"][0]))
            for n, v in at.items()}
    corner = 0.5 * sum(float(runs[names[("a", 1)]][f"Fz_{w}_N"][0]) for w in ("fl", "fr"))
    split = {n: abs(np.subtract(*place_values(h, timeline, "Fz_fl_N"))
                    - np.subtract(*place_values(h, timeline, "Fz_fr_N"))) / corner
             for n, h in runs.items()}
    three = [_m("largest change of Δd_left - Δd_right from a to b", max(diff.values()), "m",
                "<=", T, [max(diff, key=diff.get)]),
             _m("largest steady change of the front left-right load split, of the corner load",
                max(split.values()), "fraction", runs=[max(split, key=split.get)])]
    sym, peak_dd = {}, 0.0
    for k in (1, 2, 3):
        a, b = runs[names[("a", k)]], runs[names[("b", k)]]
        sym[k] = max(float(np.max(np.abs(a[f"dd_{s}_m"] - b[f"dd_{o}_m"])))
                     for s, o in (("left", "right"), ("right", "left")))
        peak_dd = max(peak_dd, *(float(np.max(np.abs(a[f"dd_{s}_m"]))) for s in SIDES))
    k = max(sym, key=sym.get)
    four = [_m("largest |Δd(a, side) - Δd(b, other side)|", sym[k], "m", "<=",
               SYMMETRY_TOLERANCE * peak_dd, [names[("a", k)], names[("b", k)]])]
    rot = {n: max(float(np.max(np.abs(h[f"rot_{s}_rad"]))) for s in SIDES)
           for n, h in runs.items()}
    five = [_m("largest |rotation| of a rod in its cylinder", max(rot.values()), "rad", "<",
               math.radians(3.0), [max(rot, key=rot.get)])]
    h2, mu2 = runs[a2], study[a2].friction.mu_s
    six = [_m(f"times μ1 reaches μs, {s} strut", count_reaching(h2[f"mu1_{s}"], mu2), "count",
              "==", 2, [a2], decides=s == "left") for s in SIDES]
    six += [_m(f"largest μ1/μs, {s} strut (it counts on reaching 1)", np.max(h2[f"mu1_{s}"])
               / mu2 if mu2 > 0 else 0.0, "ratio", ">=", 1, [a2], decides=False) for s in SIDES]
    return [one, two, three, four, five, six]


# Where the order of convergence in the time step is known: the lubricated runs (no dry
# friction) converge at first order (README, "What accuracy costs"); with dry friction the
# stick-slip events make it irregular, so no extrapolation is given there.
FIRST_ORDER = 1


def holds(measure, value=None):
    """Whether ``value`` (default: the measure's own) meets the measure's threshold."""
    value = measure["value"] if value is None else value
    return bool(RELATIONS[measure["relation"]](value, measure["threshold"]))


def error_estimates(measures, half_measures=None, first_order_runs=()):
    """``measures`` (``paper.claim_measures`` at the run's step) with their numerical error
    from ``half_measures`` (the same at half the step): per measure ``half_value``,
    ``abs_diff`` = |x(dt) - x(dt/2)|, ``order`` and ``extrapolated`` (Richardson, where every
    run deciding it is in ``first_order_runs``), ``margin`` = |x - threshold|, ``holds`` and
    ``holds_half``."""
    out = []
    for i, claim in enumerate(measures):
        rows = []
        for j, m in enumerate(claim):
            row = dict(m, half_value=None, abs_diff=None, order=None, extrapolated=None,
                       margin=None, holds=None, holds_half=None)
            if m["relation"] is not None:
                row["holds"] = holds(m)
                row["margin"] = abs(m["value"] - m["threshold"])
            if half_measures is not None:
                h = half_measures[i][j]
                row["half_value"] = h["value"]
                row["abs_diff"] = abs(m["value"] - h["value"])
                if m["relation"] is not None:
                    row["holds_half"] = holds(h)
                if m["unit"] != "count" and m["runs"] and set(m["runs"]) <= set(first_order_runs):
                    p = 2.0 ** FIRST_ORDER
                    row["order"] = FIRST_ORDER
                    row["extrapolated"] = (p * h["value"] - m["value"]) / (p - 1)
            rows.append(row)
        out.append(rows)
    return out
