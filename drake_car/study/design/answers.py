"""The design study's answers in plain words, with numbers (pure): where a map's outcome crosses
its threshold (no finer than each cell's error), what each line and mitigation does, which
factors decide, and how the study was made; every sentence about the car from its base scene."""

import math

import numpy as np

from drake_car.study.design.spec import factor, is_paper_car
from drake_car.study.design.tables import map_grid
from drake_car.study.design.unmeasured import NOT_MEASURED, finite, not_measured
from drake_car.study.design.unmeasured import why as unmeasured_why


def _crossing(xs, values, threshold):
    """The smallest x at which |value| exceeds ``threshold`` (linear between points), None
    if none does, -inf if the first already does."""
    v = np.abs(np.asarray(values, dtype=float))
    above = np.flatnonzero(v > threshold)
    if above.size == 0:
        return None
    i = int(above[0])
    if i == 0:
        return -math.inf
    x0, x1, v0, v1 = xs[i - 1], xs[i], v[i - 1], v[i]
    return x0 + (threshold - v0) / (v1 - v0) * (x1 - x0)


def _where(x, xs, label):
    return ("nowhere in the range" if x is None else
            f"already at {label} = {xs[0]:.3g}" if x == -math.inf else f"{label} ≈ {x:.3g}")


def _across_gap(x, at, xs, label):
    """``_where`` of a crossing at ``x`` found along the measured ``at`` of a row whose grid is
    ``xs``: where the two measured cells around it have an unmeasured one between them, the
    crossing is said to lie between them, not drawn through the gap."""
    if x is None or x == -math.inf:
        return _where(x, at, label)
    i = next(k for k in range(1, len(at)) if at[k - 1] <= x <= at[k])
    if any(at[i - 1] < g < at[i] for g in xs):
        return f"{label} between {at[i - 1]:.3g} and {at[i]:.3g} ({NOT_MEASURED} between)"
    return f"{label} ≈ {x:.3g}"


def boundary_lines(study, spec, rows, outcome, scale, threshold, unit, noise=0.0):
    """Plain words for a map's boundary: per row (y), where along x the outcome crosses the
    threshold; with errors (each cell's ``<outcome>_error`` where the rows have it, else
    ``noise``; in the outcome's scaled unit) > 0, where it surely exceeds it (|value| - error
    above the threshold) against where it may (|value| + error above it): a boundary is not
    drawn finer than the errors; the cells not converged are named with their values at each
    step. Cells not measured (``unmeasured.why``) are said, and no crossing is drawn through
    them: along a row, only the measured cells count, and a crossing between two measured cells
    with an unmeasured one between them is said to lie between them."""
    fx, fy = factor(study, spec.x), factor(study, spec.y)
    xs, ys, values = map_grid(study, spec, rows, outcome, scale)
    head = f"{unit} beyond the threshold over {fx.label} × {fy.label}: "
    measured = np.isfinite(values)
    if not measured.any():
        return f"{unit} over {fx.label} × {fy.label}: " \
            + not_measured(unmeasured_why(study, rows, outcome)) + "."
    errors = np.full(values.shape, float(noise))
    if rows and f"{outcome}_error" in rows[0]:
        errors = np.nan_to_num(map_grid(study, spec, rows, f"{outcome}_error", scale)[2])
    parts = []
    for j, y in enumerate(ys):
        ok = measured[j]
        if not ok.any():
            parts.append(f"{fy.label} = {y:.3g}: {NOT_MEASURED}")
            continue
        at = [x for x, m in zip(xs, ok) if m]
        v, e = np.abs(values[j][ok]), errors[j][ok]
        sure = _crossing(at, np.maximum(v - e, 0.0), threshold)
        maybe = _crossing(at, v + e, threshold)
        if sure != maybe:
            where = (f"from {_across_gap(maybe, at, xs, fx.label)} (within the error) to "
                     f"{_across_gap(sure, at, xs, fx.label)} (beyond it)")
        else:
            x = sure
            where = _where(x, at, fx.label) if x is None or x == -math.inf else \
                f"from {_across_gap(x, at, xs, fx.label)}"
        if not ok.all():
            where = (where.replace("nowhere in the range", "nowhere among the measured cells")
                     + f" ({NOT_MEASURED} at {fx.label} = "
                     + ", ".join(f"{x:.3g}" for x, m in zip(xs, ok) if not m) + ")")
        parts.append(f"{fy.label} = {y:.3g}: {where}")
    open_ = [f"{fx.label} {xs[k % len(xs)]:.3g}, {fy.label} {ys[k // len(xs)]:.3g} ("
             + " / ".join(f"{scale * float(x):+.2f}" for x in r[f"{outcome}_values"].split(";"))
             + ")" for k, r in enumerate(rows) if r.get(f"{outcome}_converged") == "no"]
    gaps = (f". Cells {NOT_MEASURED}: {unmeasured_why(study, rows, outcome)}"
            if not measured.all() else "")
    return (head + "; ".join(parts) + gaps
            + (f". Not converged at the finest step tried (values at each step): "
               f"{'; '.join(open_)}" if open_ else ""))


def car_words(study):
    """The study's car in a few words, from its base scene."""
    if is_paper_car(study):
        return "the paper's car as modelled here, the shipped Escort"
    car, front = study.base.car, study.base.car.front
    return (f"this car: {car.mass.total_mass_kg:g} kg, b = {1e3 * front.ball_joint_offset_b_m:.0f}"
            f" mm, l = {1e3 * front.guide_length_l_m:.0f} mm")


def answers(study, table, sobol, jam_states, mitigations, noise, line_rows=()):
    """The study's answers in plain words, with numbers. ``jam_states``: the Monte Carlo's
    ``group_summary``; ``mitigations``: ``mitigation_table``."""
    lines = []
    threshold = 100 * study.split_threshold
    base = jam_states
    if base["runs"]:
        newtons = base.get("split_N", {})
        median_N, p90_N = ((f" = {newtons['median']:.0f} N", f" = {newtons['p90']:.0f} N")
                           if newtons.get("n") else ("", ""))
        lines.append(
            f"The study's car ({car_words(study)}, μs = {study.base.friction.law.mu_s:g}) over "
            f"{base['runs']} jam states: the lasting split change is {base['split']['median']:.2f} "
            f"%{median_N} (median; 90 % of states below {base['split']['p90']:.2f} %{p90_N}), above "
            f"{threshold:g} % in {100 * base['split']['share_above']:.0f} % of them; "
            + (f"the pull is {base['pull']['median']:.2f} deg (median), above "
               f"{study.pull_threshold_deg:g} deg in {100 * base['pull']['share_above']:.0f} %."
               if base["pull"].get("n") else
               f"the pull {not_measured(_why(study, table, 'mc', 'pull_deg'))}."))
    for i, spec in enumerate(study.maps):
        rows = [r for r in table if r["name"].startswith(f"map{i}_")]
        lines.append(boundary_lines(study, spec, rows, "split_change_rel", 100.0, threshold,
                                    "The lasting split",
                                    100.0 * noise.get("split_change_rel", 0.0)))
        lines.append(boundary_lines(study, spec, rows, "pull_deg", 1.0,
                                    study.pull_threshold_deg, "The pull",
                                    noise.get("pull_deg", 0.0)))
    for i, line in enumerate(line_rows):
        of_line = [r for r in table if r["name"].startswith(f"line{i}_")]
        lines.append(_line_answer(study, line, threshold, noise, {
            key: unmeasured_why(study, of_line, key) for key in ("split_change_rel", "pull_deg")}))
    if sobol is not None:
        for outcome, rows in sobol.items():
            ranked = [r for r in rows if r["resolved"]]
            unresolved = [r["label"] for r in rows if not r["resolved"]]
            text = ", ".join(f"{r['label']} (ST {r['ST']:.2f} ± {r['ST_conf']:.2f})"
                             for r in ranked)
            lines.append(f"What decides {outcome}: {text or 'no factor resolved'}"
                         + (f"; not ranked (interval wider than the index): "
                            f"{', '.join(unresolved)}" if unresolved else "") + ".")
    if len(mitigations) > 1 and mitigations[0]["runs"]:
        lines.append(_mitigation_answer(mitigations, 100 * noise.get("split_change_rel", 0.0),
                                        _why(study, table, "mitigation", "pull_deg")))
    if noise:
        lines.append("Numerical error: the runs where the struts jam carry their own (see "
                     "\"Accuracy where the struts jam\" for how it was made); the others "
                     "the half-step sample's largest change, "
                     + _noise_words(study, table, noise) + ". Boundaries and "
                     "rankings closer than their errors are not resolved.")
    return lines


def _why(study, table, role, outcome):
    """Why ``outcome`` is missing in the rows of ``role`` (None: it is not)."""
    return unmeasured_why(study, [r for r in table if r["role"] == role], outcome)


def _noise_words(study, table, noise):
    """"up to 0.01 % in the split and 0.02 deg in the pull", each outcome the half-step pairs
    did not measure said so, with why."""
    pairs = [r for r in table if r["role"] == "noise"]
    words = []
    for key, scale, unit, name in (("split_change_rel", 100.0, "%", "the split"),
                                   ("pull_deg", 1.0, "deg", "the pull")):
        if key in noise and math.isfinite(noise[key]):
            words.append(f"up to {scale * noise[key]:.2f} {unit} in {name}")
        else:
            reason = unmeasured_why(study, pairs, key)
            because = "no half-step pair has it" + (f": {reason}" if reason else "")
            words.append(f"{name} {not_measured(because)}")
    return " and ".join(words)


def _better(paired, noise):
    """A paired change that is a real improvement: lower in the median by more than the
    states' median error (their runs' own errors; ``noise`` where the pairs have none), and in
    more states than chance gives (sign test over the states resolved, p < 0.05)."""
    limit = paired.get("error_median", noise)
    return (paired.get("median", math.inf) < -limit
            and paired.get("sign_test_p", 1.0) < SIGN_TEST_LEVEL)


# The sign test's level, and the fewest states over which it can conclude at it: all n states
# one way give its smallest two-sided p, 2 / 2**n (0.031 at n = 6; 0.0625 at 5).
SIGN_TEST_LEVEL = 0.05
SIGN_TEST_STATES = next(n for n in range(1, 64) if 2 / 2 ** n < SIGN_TEST_LEVEL)


def _median_words(summary, unit, digits, why):
    """"median 5.71 %", or "not measured (why)" where no run of the group gave the value."""
    if not summary.get("n"):
        return not_measured(why)
    return f"median {summary['median']:.{digits}f} {unit}"


def _mitigation_answer(mitigations, noise, pull_why=None):
    """Mitigations judged state by state against the baseline: one helps when it lowers the
    |split| beyond the numerical noise (``noise``, %) and in more states than chance
    (``_better``); among those, one is the best only if it is also better than each other
    helper, state by state. Over fewer than ``SIGN_TEST_STATES`` states the sign test cannot
    conclude: such a mitigation is said not judged (not "none lower"). ``pull_why``: why a
    group's pull is missing (``unmeasured.why``)."""
    base = mitigations[0]
    ranked = sorted(mitigations[1:], key=lambda m: m["paired"].get("median", math.inf))

    def paired_words(p):
        n = p.get("n", 0)
        if not n:
            return "state by state: no state with both runs finished"
        lower = round(p["share_lower"] * n)
        return (f"state by state {p['median']:+.2f} % (lower beyond the runs' errors in "
                f"{100 * p['share_lower']:.0f} % of the states: {lower} of {n}"
                + (f", within them in {p['unresolved']}" if p.get('unresolved') else "")
                + (f", a run not converged in {p['not_converged']}"
                   if p.get('not_converged') else "") + ")")
    # The pull's why said once, with the baseline (the groups run the same states).
    text = "; ".join(
        f"{m['mitigation']}: {_median_words(m['split'], '%', 2, 'no run finished')}, "
        + (f"{100 * m['split']['share_above']:.0f} % of states above the threshold, "
           if m["split"].get("n") else "")
        + f"pull {_median_words(m['pull'], 'deg', 2, None)}; {paired_words(m['paired'])}"
        for m in ranked)
    judged = [m for m in ranked if m["paired"].get("n", 0) >= SIGN_TEST_STATES]
    not_judged = [m for m in ranked if m not in judged]
    head = (f"Mitigations over the same {base['runs']} states ({base['mitigation']}: split "
            f"{_median_words(base['split'], '%', 2, 'no run finished')}, pull "
            f"{_median_words(base['pull'], 'deg', 2, pull_why)}): {text}. ")
    cannot = ""
    if not_judged:
        counts = sorted({m["paired"].get("n", 0) for m in not_judged})
        n = counts[-1]
        why = (f"over {' or '.join(str(c) for c in counts)} states a sign test at "
               f"{100 * SIGN_TEST_LEVEL:g} % cannot conclude (even all {n} states one way give "
               f"p = {min(1.0, 2 / 2 ** n):.2f}; it needs {SIGN_TEST_STATES} states or more)")
        cannot = ((f"No mitigation is judged lower or higher than the baseline: {why}, so the "
                   "shares of states above are counts, not a verdict.") if not judged else
                  f"Not judged against the baseline ({why}): "
                  + ", ".join(m["mitigation"] for m in not_judged) + ".")
    if not judged:
        return head + cannot
    helps = [m for m in judged if _better(m["paired"], noise)]
    worse = [m["mitigation"] for m in judged if _better(
        {"median": -m["paired"].get("median", -math.inf),
         "sign_test_p": m["paired"].get("sign_test_p", 1.0)}, noise)]
    best = [m for m in helps if all(_better(m["against"][o["mitigation"]], noise)
                                    for o in helps if o is not m)]
    if not helps:
        verdict = "None lowers the split by more than the noise in more states than chance"
    elif best:
        verdict = f"The best: {best[0]['mitigation']}, also state by state against the others"
    else:
        a, b = helps[0], helps[1]
        vs = a["against"][b["mitigation"]]
        verdict = (f"{', '.join(m['mitigation'] for m in helps)} help, not separable from each "
                   f"other state by state ({a['mitigation']} against {b['mitigation']}: "
                   f"{vs['median']:+.2f} % median, lower in {100 * vs['share_lower']:.0f} % of "
                   "the states)")
    return (head + f"{verdict}. Lower than the baseline: "
            f"{', '.join(m['mitigation'] for m in helps) or 'none'}; higher: "
            f"{', '.join(worse) or 'none'} (beyond the states' median error, the runs' own "
            "where refined, and a sign test at 5 %)." + (" " + cannot if cannot else ""))


def _line_answer(study, line, threshold, noise, why=None):
    """A line's |split| and |pull| at each μs, over its measured points; ``why``: {outcome:
    why it is missing} (``unmeasured.why`` of the line's rows)."""
    why = why or {}
    parts = []
    for mu_s in study.line_mu_s:
        pts = [p for p in line["points"] if p["mu_s"] == mu_s]
        split = [abs(p["split_pct"]) for p in pts if math.isfinite(p["split_pct"])]
        pull = [abs(p["pull_deg"]) for p in pts if math.isfinite(p["pull_deg"])]
        if not split:
            parts.append(f"at μs = {mu_s:g} the |split| "
                         f"{not_measured(why.get('split_change_rel'))}")
            continue
        spread = max(split) - min(split)
        errors = [p.get("split_pct_error", math.nan) for p in pts]
        error = max(finite(errors) or [100 * noise.get("split_change_rel", 0.0)])
        resolved = spread > 2 * error
        open_ = sum(p.get("split_pct_converged") == "no" for p in pts)
        parts.append(f"at μs = {mu_s:g} the |split| runs {min(split):.2f} ... {max(split):.2f} % "
                     f"({'beyond' if resolved else 'within'} its errors"
                     + (f", {open_} not converged" if open_ else "")
                     + f"; above {threshold:g} % at "
                     f"{sum(v > threshold for v in split)} of {len(split)} values"
                     + (f"; {len(pts) - len(split)} {NOT_MEASURED}" if len(split) < len(pts)
                        else "") + ") and the |pull| "
                     + (f"{min(pull):.2f} ... {max(pull):.2f} deg"
                        + (f" ({NOT_MEASURED} at {len(pts) - len(pull)} of {len(pts)} values: "
                           f"{why.get('pull_deg')})" if len(pull) < len(pts) else "")
                        if pull else not_measured(why.get("pull_deg"))))
    values = ", ".join(f"{v:g}" for v in line_values(line))
    return f"{line['label']} ({values}): " + "; ".join(parts) + "."


def line_values(line):
    """A line's values in the order its points first give them."""
    seen = []
    for p in line["points"]:
        if p["value"] not in seen:
            seen.append(p["value"])
    return seen


def _rack_words(study, adapted=(), shipped_rack=None, smoke=False):
    """How the rack ran: calibrated for the car (the shipped one's, or this car's where
    ``adapted`` says so, ``study.design.base_car``), or as the base scene gives it."""
    m, shipped = study.base.manoeuvre, is_paper_car(study)
    if any(words.startswith("the rack calibrated") for words in adapted):
        return (f"the rack profile calibrated for this car on the study's own timeline "
                f"({1e3 * m.amplitude_m:.2f} mm, second lobe {m.second_lobe:.3f}: {m.shift_m:g} m "
                "sideways" + ("; --quick's shortened lane change moves it less)" if smoke
                              else ")"))
    amplitude, lobe = shipped_rack or (m.amplitude_m, m.second_lobe)
    if (m.amplitude_m, m.second_lobe) != (amplitude, lobe):
        return (f"its rack profile as the base scene gives it ({1e3 * m.amplitude_m:.2f} mm, "
                f"second lobe {m.second_lobe:.3f})")
    return ("the rack profile calibrated for it (3.7 m sideways at 60 km/h)" if shipped else
            f"the rack profile calibrated for the shipped car ({1e3 * amplitude:.2f} mm), not "
            "for this one: its lane change need not be the paper's 3.7 m")


def _severity_words(study):
    """The severity factor's range (the rack amplitude it sets) in mm and in the base's."""
    m = study.base.manoeuvre
    for f in study.factors:
        if f.key == "manoeuvre.amplitude_m" and m.amplitude_m:
            return (f"; the runs that vary the severity set the amplitude itself, "
                    f"{1e3 * f.low:.2f} ... {1e3 * f.high:.2f} mm: {f.low / m.amplitude_m:.2f} "
                    f"... {f.high / m.amplitude_m:.2f} times this one")
    return ""


def method(study, adapted=(), shipped_rack=None, smoke=False):
    """How the study was made (the base scene's manoeuvre, equilibrium, step); ``adapted``:
    what was adapted to the user's car (``study.design.base_car``), ``shipped_rack`` the
    shipped car's calibrated (amplitude_m, second_lobe)."""
    t = study.base.manoeuvre.timeline
    shipped = is_paper_car(study)
    where = "" if shipped else " with the shipped car (not measured on this car)"
    return [
        f"Every run: the lane change of the base scene ({t.steer_s:g} s at {t.speed_kph:g} "
        f"km/h, {_rack_words(study, adapted, shipped_rack, smoke)}{_severity_words(study)}) "
        "from static equilibrium, "
        f"with rest {t.settle_s:g} s, speed-up {t.speed_up_s:g} s, straight {t.straight_s:g} s "
        f"and {t.calm_s:g} s after the manoeuvre (the paper's: 0.8, 3.0, 1.2 and 2.6 s; the car "
        "starts at rest in static equilibrium, so the rest needs no length of its own). "
        f"Measured 2026-11-23 on the default study{where}, 8 Sobol points and 3 jam states: a "
        "calm phase of 1.5 s instead of 2.6 s moves the lasting split by at most 0.03 % and "
        "the rack force by 2.1 N; 1.0 s would move the split by up to 3.5 % (the car is still "
        "settling).",
        f"The static equilibrium settled for {study.base.simulator.equilibrium_settle_s:g} s at "
        f"{1e3 * (study.base.simulator.equilibrium_time_step_s or 1e-3):g} ms (the default: "
        f"6 s at 1 ms). Measured 2026-11-23 on the base scene{where} and a Sobol point: "
        "against 6 s at 1 ms, 3 s moves the rods' rest overlap by 0.22 mm and the lasting "
        "split by 0.3 N (of a 4 kN corner: 0.007 %); at 4 ms instead of 1 ms the 3 s settle "
        "moves them by 0.01 mm and 0.02 N more.",
        f"μd = {study.mu_d_ratio:g} μs wherever μs varies (the paper's ratio).",
        "Places a and b: the 0.3 s before the lane change and the last 0.5 s of the calm "
        "phase after it, with hands on and off alike.",
        "Hands off: the driver lets go where the calm phase ends; the pull is the heading "
        f"change over the next {study.pull_distance_m:g} m; the steering wheel's inertia and "
        "the column's friction as in scene.HandsOff, the wheel geared to the rack by the car's "
        f"rack gain ({1e3 * study.base.car.front.rack_gain_m_per_rad:g} mm/rad). The "
        "steering-wheel torque: the rack force times that gain, hands on.",
        "Mitigations: compared over the same jam states at μs = "
        f"{study.mitigation_mu_s if study.mitigation_mu_s is not None else study.base.friction.law.mu_s:g}"
        ", against the car as it is there.",
        f"Sobol: Saltelli's sample, {study.sobol_base_samples} base samples over "
        f"{len(study.factors)} factors ({study.sobol_base_samples * (len(study.factors) + 2)} "
        "runs), first-order and total indices with 95 % bootstrap intervals (SALib).",
    ]
