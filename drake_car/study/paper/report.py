"""The paper's study as a summary (JSON-ready) and a report (Markdown), from the study's runs
and claims (pure: no simulation, no files).

The report is written for a reader of the paper: it defines its terms first (sets, cases,
phases, places, thresholds, peak and steady), gives every verdict beside its threshold, links
each claim to the figure that shows it, and gives every deciding number with its numerical error
estimate from the half-step rerun (|x(dt) - x(dt/2)|, and the extrapolated value where the
order of convergence is known), so that a reader sees how far each verdict is from flipping.
"""

import dataclasses
import math

from drake_car.study.paper.measures import claim_measures, error_estimates
from drake_car.study.paper.claims import (
    DISPLACEMENT_THRESHOLD_M, SYMMETRY_TOLERANCE, place_values, run_of)
from drake_car.study.paper.previous_car import previous_car_section


# -- formatting ------------------------------------------------------------------------------

SYMBOLS = {"<=": "≤", "<": "<", ">": ">", ">=": "≥", "==": "="}
# The figures that show each claim (files of drake_car.study.paper.figures.all_figures).
CLAIM_FIGURES = {1: ("claim1_return.png", "fig14_a.png", "fig14_b.png"),
                 2: ("fig14_a.png", "fig14_b.png", "fig15_a.png", "fig15_b.png"),
                 3: ("load_split.png",),
                 4: ("symmetry.png", "fig14_a.png", "fig15_b.png"),
                 5: ("rod_rotation.png",),
                 6: ("fig16.png",)}


def summary(study, claims, shifts, timeline, *, runs, half, figures, wall_s, provenance,
            replay=None):
    """``study``: name -> StudyRun; ``runs``: name -> sim Run (for how each was made);
    ``half``: the half-step check (or None): {"time_step_s", "verdicts", "numbers", "measures"
    (``claim_measures`` of the half-step runs)}; ``figures``: file -> what it shows;
    ``replay``: the run with a replay page, if any."""
    rod_positions = {}
    for name, r in study.items():
        rod_positions[name] = {}
        for side in ("left", "right"):
            at_a, at_b = place_values(r.columns, timeline, f"dd_{side}_m")
            rod_positions[name][f"dd_{side}_at_a_m"] = at_a
            rod_positions[name][f"dd_{side}_at_b_m"] = at_b
    sets = {n: dataclasses.asdict(run_of(study, "a", n).friction) for n in (1, 2, 3)}
    lubricated = [name for name, r in study.items() if r.friction.mu_s == 0]
    measures = claim_measures(study, timeline)
    t = next(iter(study.values())).columns["t"]
    t2, t3, t4, _ = timeline.boundaries()
    return {
        "claims": claims,
        "deciding_numbers": error_estimates(
            measures, None if half is None else half.get("measures"), lubricated),
        "friction_sets": sets,
        "cases": {"a": "lane change starting with a left turn (to the left lane and back "
                       "straight)",
                  "b": "lane change starting with a right turn (the mirror image of a)"},
        "phases_s": {"I": [0.0, t2], "II": [t2, t3], "III": [t3, t4],
                     "IV": [t4, float(t[-1])]},
        "places_s": {"a": [t3 - 0.3, t3], "b": [float(t[-1]) - 0.5, float(t[-1])]},
        "rod_positions": rod_positions,
        "rod_shift_b_minus_a_m": shifts,
        "runs": {name: run.record() | {"case": study[name].case,
                                       "friction_set": study[name].friction.number}
                 for name, run in runs.items()},
        "half_step_check": half,
        "timeline_s": dataclasses.asdict(timeline),
        "figures": figures,
        "replay": replay,
        "wall_s": wall_s,
        "provenance": provenance,
    }


def quantity(value, unit, error=False):
    """``value`` (SI) as the report writes it: mm, deg, N, %, a ratio or a count."""
    if value is None:
        return "-"
    if unit == "count":
        return f"{value:.0f}"
    scale, suffix, digits = {"m": (1e3, " mm", 3), "rad": (180 / math.pi, "°", 2),
                             "N": (1.0, " N", 0), "fraction": (100.0, " %", 2),
                             "ratio": (1.0, "", 3)}[unit]
    digits += 1 if error and unit in ("rad", "fraction") else 0
    shown = f"{scale * value:.{digits}f}"
    if error and value > 0 and float(shown) == 0:
        return f"< {10.0 ** -digits:g}{suffix}"
    return shown + suffix


def _threshold(m):
    return f"{SYMBOLS[m['relation']]} {quantity(m['threshold'], m['unit'])}"


def _error(row):
    if row["abs_diff"] is None:
        return "not estimated (--no_verify)"
    if row["unit"] == "count":
        return (f"count at dt/2: {row['half_value']:.0f}" if row["abs_diff"] else
                "same count at dt/2")
    text = quantity(row["abs_diff"], row["unit"], error=True)
    text = text if text.startswith("<") else "±" + text
    if row["extrapolated"] is not None:
        text += f" (extrapolated {quantity(row['extrapolated'], row['unit'])})"
    return text


def _flip(row):
    """How far the verdict of one measure is from flipping, in units of its error."""
    if row["margin"] is None or row["abs_diff"] is None:
        return "-"
    if row["unit"] == "count":
        return "same verdict at dt/2" if row["holds"] == row["holds_half"] else \
            "**flips at dt/2**"
    if row["holds"] != row["holds_half"]:
        return "**flips at dt/2**"
    if row["abs_diff"] == 0:
        return "no change at dt/2"
    n = row["margin"] / row["abs_diff"]
    if n < 1:  # the error is larger than the margin: the verdict is not robust
        return f"**{n:.2g} × the error** (within it)"
    return f"{n:.0f} × the error"


def _signed(value, digits):
    """``value`` with its sign, no "-0.00" for what rounds to zero."""
    shown = f"{value:+.{digits}f}"
    return shown[1:] if float(shown) == 0 else shown


def _span(interval):
    return f"{interval[0]:.3g} s to {interval[1]:.3g} s"


def _row(*cells):
    """A Markdown table row; a "|" inside a cell (|Δd|) is escaped."""
    return "| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |"


def _links(i, figures):
    shown = [f for f in CLAIM_FIGURES[i] if f in figures]
    return ", ".join(f"[{f}]({f})" for f in shown) or "-"


# -- the report ------------------------------------------------------------------------------

def report(s):
    """The Markdown report of a ``summary``."""
    prov = s["provenance"]
    lines = ["# The paper's study: lane change with strut friction", "",
             f"Made by `{prov['command']}`, commit {(prov['git_commit'] or 'unknown')[:10]}, drake "
             f"{prov['drake']}, {prov['created_utc']}; {s['wall_s']:.0f} s wall in all.", ""]
    lines += _terms(s)
    lines += _claims_table(s)
    lines += _numbers_table(s)
    lines += _disagreements(s)
    lines += _paper_drive(s)
    lines += previous_car_section(s)
    lines += _places_tables(s)
    lines += _runs_and_files(s)
    return "\n".join(lines)


def _paper_drive(s):
    """The verdicts with the paper's own drive (its front wheels' rotation prescribed: a
    locked front axle) beside this car's open differential."""
    locked = s.get("paper_drive")
    if not locked:
        return []
    lines = ["## The paper's own drive, for comparison", "",
             "The runs above drive the front wheels through an open differential (one torque "
             "split equally: a front-drive car). The paper prescribes both front wheels' "
             "rotation, which locks the front axle: about 2.5 deg/g more understeer on this car "
             "(experiments/handling.py), and the launch follows the prescribed speed even "
             "beyond the tyres' grip. The same six runs, the same rack input, with the paper's "
             "drive (the car then turns less and its struts see other loads):", "",
             "| # | open differential | the paper's drive | deciding number with the paper's "
             "drive |", "|---|---|---|---|"]
    for i, (claim, verdict, number) in enumerate(zip(s["claims"], locked["verdicts"],
                                                    locked["numbers"]), start=1):
        ours = "yes" if claim["reproduced"] else "no"
        theirs = "yes" if verdict else "no"
        if verdict != claim["reproduced"]:
            theirs = f"**{theirs}** (changes)"
        lines.append(f"| {i} | {ours} | {theirs} | {_cell(number)} |")
    return lines + [""]


def _cell(text):
    return str(text).replace("|", "\\|")


def _terms(s):
    lines = ["## Sets and cases, and the terms used", "",
             "Six runs: two cases (a, b) × three friction sets (1, 2, 3); run `a_3` is case a "
             "with set 3. The friction is in the front struts' cylindrical joints (the rod "
             "sliding and turning in the cylinder); the rear has none.", ""]
    for n, f in sorted(s["friction_sets"].items()):
        what = (f"lubricated strut: no dry friction, {f['damping_Nspm']:g} N s/m of viscous "
                "damping" if f["mu_s"] == 0 else
                f"dry strut: static μs = {f['mu_s']:g}, kinetic μd = {f['mu_d']:g}, no viscous "
                "damping")
        lines.append(f"- **set {n}**: {what}")
    for case, what in s["cases"].items():
        lines.append(f"- **case {case}**: {what}")
    ph, pl = s["phases_s"], s["places_s"]
    tl = s["timeline_s"]
    lines += [
        f"- **phases** (on every figure): I {_span(ph['I'])}, at rest ({tl['settle_s']:g} s) "
        f"then the speed-up to {tl['speed_kph']:g} km/h; II {_span(ph['II'])}, straight at "
        f"speed; III {_span(ph['III'])}, the lane change (3.7 m); IV {_span(ph['IV'])}, "
        "straight in the new lane.",
        "- **Δd**: the change of a front strut's overlap (rod in the cylinder) from the car's "
        "static equilibrium at rest; + = the rod goes in (the body comes down).",
        f"- **places a and b**: the paper's \"before\" and \"after\" positions, here averages "
        f"over windows (the body still bounces on its tyres, one instant would not do): a = "
        f"{_span(pl['a'])} (the 0.3 s before the lane change), b = {_span(pl['b'])} (the last "
        "0.5 s); the figures shade them and give the averages.",
        f"- **thresholds**: \"practically zero\" = {1e3 * DISPLACEMENT_THRESHOLD_M:g} mm of rod "
        f"displacement (the project's accuracy target); \"almost identical\" curves = within "
        f"{100 * SYMMETRY_TOLERANCE:g} % of the largest |Δd|; the rod's rotation: below 3°; "
        "μ1 reaching μs: exactly twice.",
        "- **peak / steady** (for any load swing): *peak* is the largest excursion; *steady* "
        "is a mean over a stretch where the car is in a steady state (the constant acceleration "
        "of phase I, or the window of a place).",
    ]
    half = s["half_step_check"]
    if half is not None:
        steps = sorted(set(half["time_step_s"].values()))
        lines.append(
            "- **numerical error**: every run was repeated at half its time step "
            f"(dt/2 = {', '.join(f'{v:g}' for v in steps)} s). A number's error estimate is "
            "|x(dt) - x(dt/2)|; where the order of convergence is known (first order for the "
            "lubricated runs, set 1) the extrapolated value 2 x(dt/2) - x(dt) is given too. "
            "\"n × the error\" says how far a number is from its threshold in units of that "
            "estimate: the verdict flips only if the error were n times larger.")
    else:
        lines.append("- **numerical error**: not estimated (the half-step rerun was skipped "
                     "with --no_verify).")
    return lines + [""]


def _claims_table(s):
    half = s["half_step_check"]
    lines = ["## The paper's claims", "",
             _row("#", "claim", "reproduced", "deciding number vs threshold",
                  "numerical error", "figure"), "|---|---|---|---|---|---|"]
    for i, (c, rows) in enumerate(zip(s["claims"], s["deciding_numbers"]), start=1):
        verdict = "yes" if c["reproduced"] else "**no**"
        if half is not None:
            verdict += f" (at dt/2: {'yes' if half['verdicts'][i - 1] else 'no'})"
        deciding = [r for r in rows if r["decides"]]
        number = "; ".join(f"{r['name']}: **{quantity(r['value'], r['unit'])}**, needs "
                           f"{_threshold(r)}" for r in deciding)
        error = "; ".join(_error(r) for r in deciding)
        lines.append(_row(i, c["claim"], verdict, number, error, _links(i, s["figures"])))
    t2, t3 = s["phases_s"]["II"]
    return lines + [
        "", f"Claim 1 is judged on {_span((t2 - 0.3, t3))}: from 0.3 s before the "
        "acceleration ends to the lane change, the stretch in which the rods return after the "
        "speed-up (in the paper, all but set 3's). The paper counts that return to its phase "
        "I; the figures here start phase II where the speed-up ends.", ""]


def _numbers_table(s):
    lines = ["## Every number behind a verdict, with its numerical error", "",
             "Rows marked *context* do not decide the verdict; they say how near it is or why.",
             "", _row("claim", "number", "threshold", "at dt", "at dt/2",
                      "error |x(dt) - x(dt/2)|", "extrapolated", "margin to the threshold",
                      "decides"),
             "|---|---|---|---|---|---|---|---|---|"]
    for i, rows in enumerate(s["deciding_numbers"], start=1):
        for r in rows:
            threshold = _threshold(r) if r["relation"] is not None else "-"
            error = "-" if r["abs_diff"] is None else quantity(r["abs_diff"], r["unit"], True)
            margin = "-" if r["margin"] is None else \
                f"{quantity(r['margin'], r['unit'])} = {_flip(r)}"
            lines.append(_row(
                i, f"{r['name']} ({', '.join(r['runs'])})", threshold,
                quantity(r["value"], r["unit"]), quantity(r["half_value"], r["unit"]), error,
                quantity(r["extrapolated"], r["unit"]), margin,
                "yes" if r["decides"] else "*context*"))
    return lines + [""]


def _why_one(s):
    rows = s["deciding_numbers"][0]
    hold, peak, steady = (rows[k]["value"] for k in (2, 3, 4))
    mu_s = s["friction_sets"][3]["mu_s"]
    normal = hold / mu_s if mu_s else 0.0
    verdict = ("both exceed what static friction holds: the rod breaks free as the car "
               "accelerates and again when the acceleration ends" if steady > hold else
               "the steady change is within what static friction holds, the peak is not: the "
               "rod breaks free as the acceleration sets in" if peak > hold else
               "both are within what static friction holds")
    return (f"the strut's normal force at rest is N = {normal:.0f} N (eq. 4, from the strut's "
            f"bending, which the ball-joint offset b and the spring line set), so static "
            f"friction holds at most μs·N = {hold:.0f} N of axial load; the speed-up unloads "
            f"each front wheel by {steady:.0f} N steady (at constant acceleration) and by "
            f"{peak:.0f} N at its peak (the body pitching as the acceleration sets in): "
            f"{verdict}")


def _why_three(c):
    runs = c.get("per_run", {})
    return ("after the lane change the dry struts stick at different extensions left and "
            "right, and the coil springs carry the difference into the wheel loads (steady "
            "changes from place a to place b, window averages): "
            + "; ".join(f"{n}: Δd_L-Δd_R {_signed(1e3 * d['left_minus_right_change_m'], 2)} "
                        f"mm, load split {_signed(d['front_load_split_change_N'], 0)} N "
                        f"({100 * d['front_load_split_change_rel']:.2f} % of the corner load)"
                        for n, d in sorted(runs.items())))


def _disagreements(s):
    bad = [(i, c) for i, c in enumerate(s["claims"], start=1) if not c["reproduced"]]
    if not bad:
        return []
    lines = ["## Where the model disagrees with the paper, and why", ""]
    for i, c in bad:
        why = _why_one(s) if i == 1 else _why_three(c) if i == 3 else c.get("why", "")
        lines.append(f"- **{i}. {c['claim']}** ({_links(i, s['figures'])}): "
                     f"{why.rstrip('.')}.")
    return lines + [""]


def _places_tables(s):
    lines = ["## Rod positions at places a and b (window averages)", "",
             "| run | Δd left a [mm] | Δd left b [mm] | Δd right a [mm] | Δd right b [mm] |",
             "|---|---|---|---|---|"]
    for name, pos in sorted(s["rod_positions"].items()):
        lines.append(f"| {name} | {1e3 * pos['dd_left_at_a_m']:.3f} | "
                     f"{1e3 * pos['dd_left_at_b_m']:.3f} | {1e3 * pos['dd_right_at_a_m']:.3f} | "
                     f"{1e3 * pos['dd_right_at_b_m']:.3f} |")
    per_run = s["claims"][2].get("per_run") if len(s["claims"]) > 2 else None
    if per_run:
        lines += ["", "## Front left-right split from place a to place b (steady: window "
                  "averages)", "",
                  "| run | change of Δd_left - Δd_right [mm] | change of Fz_fl - Fz_fr [N] | "
                  "of the corner load [%] |", "|---|---|---|---|"]
        for name, d in sorted(per_run.items()):
            lines.append(_row(name, _signed(1e3 * d["left_minus_right_change_m"], 3),
                              _signed(d["front_load_split_change_N"], 1),
                              f"{100 * d['front_load_split_change_rel']:.2f}"))
    return lines + [""]


def _runs_and_files(s):
    lines = ["## Runs", "", "| run | case | set | wall [s] | real-time factor | "
             "frozen SAP steps | scene hash |", "|---|---|---|---|---|---|---|"]
    for name, info in sorted(s["runs"].items()):
        lines.append(f"| {name} | {info['case']} | {info['friction_set']} | "
                     f"{info['wall_s']:.1f} | {info['real_time_factor']:.2f} | "
                     f"{info['frozen_sap_steps']} | `{info['scene_hash']}` |")
    lines += ["", "Each run's scene, as it ran, is `<run>/scene.yaml` (rerun it with "
              "`python -m drake_car.run --scene <run>/scene.yaml --out DIR`). Frozen SAP steps: "
              "steps in which Drake's solver returned its initial guess "
              "(`drake_car/systems/sap_pacer.py`); the pacer keeps them at 0.", "",
              "## Files", ""]
    figures = s["figures"]
    items = figures.items() if isinstance(figures, dict) else ((f, "") for f in figures)
    for name, what in items:
        lines.append(f"- [{name}]({name})" + (f": {what}" if what else ""))
    lines += ["- [diagram_overview.svg](diagram_overview.svg): the Diagram at a glance (each "
              "system once, the plant's connected ports only, the loggers as one box); "
              "[diagram.svg](diagram.svg): every port",
              ""]
    if s.get("replay"):
        page = f"{s['replay']}/replay.html"
        lines[-1:] = [f"- [{page}]({page}): the Meshcat replay of run {s['replay']} (open it "
                      "in a browser, no network needed; Meshcat's "
                      "controls play, pause and scrub it)", ""]
    return lines
