"""The design study's rows reduced to what the report says (pure): the numerical noise, the
maps' grids, the Sobol indices, the distributions of the jam states and of each mitigation
(also state by state against its baseline), and the one-factor lines."""

import math

import numpy as np

from drake_car.scene.manoeuvre_targets import SPEED_TOLERANCE_KPH
from drake_car.study.design.spec import OUTCOMES, factor
from drake_car.study.design.sensitivity import factor_values, sobol_indices

# The outcomes the Sobol analysis ranks the factors on (hands-on runs).
SOBOL_OUTCOMES = ("split_change_rel", "rack_force_change_N")


def noise_levels(table, exclude=()):
    """Per outcome, the largest |x(dt) - x(dt/2)| over the half-step pairs (the noise below
    which no boundary or ranking is drawn), leaving out the pairs whose original is in
    ``exclude`` (the runs refined for accuracy: their own errors stand for them, and a branch
    jump of theirs is not the others' noise)."""
    by_name = {row["name"]: row for row in table}
    levels = {}
    for row in table:
        if row["role"] != "noise" or row["status"] != "ok" or row["of"] in exclude:
            continue
        original = by_name.get(row["of"])
        if original is None or original["status"] != "ok":
            continue
        for key in OUTCOMES:
            a, b = original[key], row[key]
            if math.isfinite(a) and math.isfinite(b):
                levels[key] = max(levels.get(key, 0.0), abs(a - b))
    return levels


def map_grid(study, spec, rows, outcome="split_change_rel", scale=100.0):
    """(xs, ys, values[j][i] × scale) of a map from its rows (in map_points' order)."""
    fx, fy = factor(study, spec.x), factor(study, spec.y)
    xs, ys = factor_values(fx, spec.points), factor_values(fy, spec.points)
    values = np.full((len(ys), len(xs)), np.nan)
    for k, row in enumerate(rows):
        if row["status"] == "ok":
            values[k // len(xs), k % len(xs)] = scale * row[outcome]
    return xs, ys, values


def map_flags(study, spec, rows, column, flag):
    """Booleans[j][i] of a map: its row's ``column`` equals ``flag``."""
    flags = np.zeros((spec.points, spec.points), dtype=bool)
    for k, row in enumerate(rows):
        flags[k // spec.points, k % spec.points] = row.get(column) == flag
    return flags


def sobol_tables(study, rows):
    """{outcome: index rows} from the Sobol runs (in sample order); None if a run failed
    (Saltelli's estimators need every point)."""
    if any(r["status"] != "ok" for r in rows):
        return None
    return {key: sobol_indices(study, [r[key] for r in rows]) for key in SOBOL_OUTCOMES}


def distribution_summary(values, threshold):
    v = np.abs(np.asarray([x for x in values if math.isfinite(x)], dtype=float))
    if v.size == 0:
        return {"n": 0}
    return {"n": int(v.size), "median": float(np.median(v)),
            "p90": float(np.percentile(v, 90)), "max": float(np.max(v)),
            "share_above": float(np.mean(v > threshold))}


def group_summary(name, rows, study, reason=""):
    """The distributions of the split and the pull over ``rows`` (its ok runs)."""
    ok = [r for r in rows if r["status"] == "ok"]
    return {"mitigation": name, "reason": reason, "runs": len(ok),
            "not_converged": sum("no" in (r.get("split_change_rel_converged"),
                                          r.get("pull_deg_converged")) for r in ok),
            "split": distribution_summary([100 * r["split_change_rel"] for r in ok],
                                          100 * study.split_threshold),
            "split_N": distribution_summary([r["split_change_N"] for r in ok
                                             if "split_change_N" in r], math.inf),
            "pull": distribution_summary([r["pull_deg"] for r in ok],
                                         study.pull_threshold_deg)}


def mitigation_table(study, rows, baseline):
    """The mitigations' baseline group (named ``baseline``), then each mitigation, over the
    same jam states; each mitigation also state by state against the baseline (``paired``) and
    against every other mitigation (``against``: name -> paired change of this one)."""
    groups = [(baseline, "")] + [(m.name, " ".join(m.reason.split()))
                                 for m in study.mitigations]
    by_group = {name: {r["sample"]: r for r in rows if r["role"] == "mitigation"
                       and r["mitigation"] == name and r["status"] == "ok"}
                for name, _ in groups}
    table = []
    for name, reason in groups:
        entry = group_summary(name, list(by_group[name].values()), study, reason)
        if name != baseline:
            entry["paired"] = paired_change(by_group[baseline], by_group[name])
            entry["against"] = {other: paired_change(by_group[other], by_group[name])
                                for other, _ in groups[1:] if other != name}
        table.append(entry)
    return table


def paired_change(base, other):
    """|split| of ``other`` minus that of ``base`` in the same states (sample -> row), in %,
    each state's change against its own error (the two runs' ``split_change_rel_error``
    summed): the median change, the share of states where it is lower beyond that error (and
    higher), the states within it (``unresolved``) and those with a run not converged, the
    median error, and the two-sided sign test's p over the resolved states (the chance of so
    lopsided a count of lower and higher states if neither were better). Rows without errors
    (none has the column) count as exact, and no median error is given."""
    key, err = "split_change_rel", "split_change_rel_error"
    pairs = [(100 * (abs(other[k][key]) - abs(base[k][key])),
              100 * (_error(other[k], err) + _error(base[k], err)),
              "no" in (other[k].get(f"{key}_converged"), base[k].get(f"{key}_converged")))
             for k in sorted(base.keys() & other.keys())]
    pairs = [p for p in pairs if math.isfinite(p[0])]
    if not pairs:
        return {"n": 0}
    own = any(err in row for row in (*base.values(), *other.values()))
    lower = sum(c < -e for c, e, _ in pairs)
    higher = sum(c > e for c, e, _ in pairs)
    n, k = lower + higher, min(lower, higher)
    p = min(1.0, 2 * sum(math.comb(n, i) for i in range(k + 1)) / 2 ** n) if n else 1.0
    return {"n": len(pairs), "median": float(np.median([c for c, _, _ in pairs])),
            "share_lower": lower / len(pairs), "share_higher": higher / len(pairs),
            "unresolved": len(pairs) - n, "not_converged": sum(u for _, _, u in pairs),
            "sign_test_p": p} | ({"error_median": float(np.median([e for _, e, _ in pairs]))}
                                 if own else {})


def _error(row, column):
    """A row's error in ``column`` (0 where it has none: a row made without errors)."""
    value = row.get(column, 0.0)
    return value if math.isfinite(value) else 0.0


def line_tables(study, rows):
    """Per line: {key, label, reason, points: [{value, mu_s, split_pct, pull_deg}]}."""
    out = []
    for i, line in enumerate(study.lines):
        points = []
        for j, mu_s in enumerate(study.line_mu_s):
            for k, value in enumerate(line.values):
                row = next((r for r in rows if r["name"] == f"line{i}_mu{j}_{k:02d}"), None)
                ok = row is not None and row["status"] == "ok"
                points.append({
                    "value": value, "mu_s": mu_s,
                    "split_pct": 100 * row["split_change_rel"] if ok else math.nan,
                    "pull_deg": row["pull_deg"] if ok else math.nan,
                    "split_pct_error": (100 * row.get("split_change_rel_error", math.nan)
                                        if ok else math.nan),
                    "pull_deg_error": row.get("pull_deg_error", math.nan) if ok else math.nan,
                    "split_pct_converged": row.get("split_change_rel_converged", "-") if ok
                    else "-",
                    "pull_deg_converged": row.get("pull_deg_converged", "-") if ok else "-"})
        out.append({"key": line.key, "label": line.label or line.key,
                    "reason": " ".join(line.reason.split()), "points": points})
    return out


def manoeuvre_summary(study, rows):
    """Whether the runs ran their manoeuvre: the speed at place a within the tolerance of
    ``scene.manoeuvre_targets`` (the paper study's and ``drake-car-run``'s) of its timeline's
    (``speed_asked_kph``, the base's where a row lacks it); the runs that did not, by part,
    the slowest. A launch the car cannot follow
    (the speed-up line's shortest on a weaker car, the smoke test's 2.8 g) lands the lane change
    at another speed: those runs' outcomes are of that speed."""
    target = study.base.manoeuvre.timeline.speed_kph
    ran = [r for r in rows
           if r["status"] == "ok" and math.isfinite(r.get("speed_a_kph", math.nan))]
    off = [r for r in ran
           if abs(r["speed_a_kph"] - r.get("speed_asked_kph", target)) > SPEED_TOLERANCE_KPH]
    by_role = {}
    for r in off:
        by_role[r["role"]] = by_role.get(r["role"], 0) + 1
    slowest = min(off, key=lambda r: r["speed_a_kph"], default=None)
    return {"speed_kph": target, "tolerance_kph": SPEED_TOLERANCE_KPH, "runs": len(ran),
            "off": len(off), "off_by_role": by_role,
            "slowest": None if slowest is None else {"name": slowest["name"],
                                                     "speed_a_kph": slowest["speed_a_kph"]}}
