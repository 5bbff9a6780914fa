"""The paper's study as a summary (JSON-ready) and a report (Markdown), from the study's runs
and claims (pure: no simulation, no files).

The report is written for a reader of the paper: it defines its terms first (sets, cases,
phases, places, thresholds, peak and steady), gives every verdict beside its threshold, links
each claim to the figure that shows it, and gives every deciding number from ``outcomes.csv``
(``sweep.refine``) with its numerical error (the step's plus the solver's) or "not converged"
with the values at each step; a verdict whose margin does not exceed its error is "undecided
at the finest step tried"."""

import dataclasses
import math

from drake_car.study.paper.local_route import error_method, local_error, resolution_section
from drake_car.study.paper.measures import claim_measures, verdict
from drake_car.study.paper.claims import DISPLACEMENT_THRESHOLD_M, SYMMETRY_TOLERANCE, run_of
from drake_car.study.paper import manoeuvre
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


def summary(study, claims, shifts, timeline, *, runs, outcomes, figures, wall_s, provenance,
            refinement=None, replay=None):
    """``study``: name -> StudyRun (at the scenes' own step: the figures' curves); ``runs``:
    name -> sim Run (for how each was made); ``outcomes``: the rows of ``outcomes.csv``
    ((run, outcome) -> row: ``outcomes.read_outcomes``), from which every deciding number and
    verdict comes; ``refinement``: how accuracy on demand went ({"rounds", "wall_s",
    "stopped", "finest_step_s", "needed_step_s"}), None when the step was not refined;
    ``figures``: file -> what it shows; ``replay``: the run with a replay page, if any."""
    roles = {n: (r.case, r.friction) for n, r in study.items()}
    measures = claim_measures(outcomes, roles)
    claims = [dict(c) for c in claims]
    for c, rows in zip(claims, measures):  # the histories' verdict kept aside, as such
        c["at_the_runs_step"] = {k: c.pop(k) for k in ("reproduced", "number", "per_run")
                                 if k in c}
        c["reproduced"], c["decided"] = verdict(rows)
    rod_positions = {name: {f"dd_{side}_at_{p}_m": outcomes[(name, f"dd_{side}_{p}_m")]["value"]
                            for side in ("left", "right") for p in "ab"} for name in study}
    sets = {n: dataclasses.asdict(run_of(study, "a", n).friction) for n in (1, 2, 3)}
    t = next(iter(study.values())).columns["t"]
    t2, t3, t4, _ = timeline.boundaries()
    return {
        "claims": claims,
        "deciding_numbers": measures,
        "friction_sets": sets,
        "cases": {"a": "lane change starting with a left turn (to the left lane and back "
                       "straight)",
                  "b": "lane change starting with a right turn (the mirror image of a)"},
        "phases_s": {"I": [0.0, t2], "II": [t2, t3], "III": [t3, t4],
                     "IV": [t4, float(t[-1])]},
        "places_s": {"a": [t3 - 0.3, t3], "b": [float(t[-1]) - 0.5, float(t[-1])]},
        "rod_positions": rod_positions,
        "rod_shift_b_minus_a_m": shifts,
        "split_changes": {name: {k: outcomes[(name, k)] for k in ("lr_change_m", "split_change")}
                          for name in study},
        "runs": {name: run.record() | {"case": study[name].case,
                                       "friction_set": study[name].friction.number}
                 for name, run in runs.items()},
        "refinement": refinement,
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
    """A measure's numerical error as the report writes it: "±e" where converged, "not
    converged" with the values at each step where not."""
    if row.get("route") == "local":
        return local_error(row, quantity(row["error"] or 0.0, row["unit"], error=True))
    if row["error"] is None:
        return "not estimated (--no_verify: one step only)"
    if not row["converged"]:
        return "not converged: " + _by_step(row)
    if row["unit"] == "count":
        return "converged (the same count at the last steps)"
    text = quantity(row["error"], row["unit"], error=True)
    return (text if text.startswith("<") else "±" + text) + \
        f" (converged at {1e3 * min(row['steps_s']):g} ms)"


def _by_step(row):
    return ", ".join(f"{quantity(v, row['unit'])} at {1e3 * h:g} ms"
                     for h, v in zip(row["steps_s"], row["values"]))


def _flip(row):
    """How far the verdict of one measure is from flipping, in units of its error."""
    if row["margin"] is None or row["error"] is None:
        return "-"
    if not row["converged"]:
        return "**not converged**"
    if row["unit"] == "count":
        return "exact (a converged count)"
    if row["error"] == 0:
        return "no change between the last steps"
    n = row["margin"] / row["error"]
    if n <= 1:  # the error is larger than the margin: the verdict is not decided
        return f"**{n:.2g} × the error** (within it)"
    return f"{n:.0f} × the error"


def _verdict(c, s):
    """yes / **no**, or undecided at the finest step tried."""
    word = "yes" if c["reproduced"] else "**no**"
    if c.get("decided") is False:
        r = s.get("refinement") or {}
        return (f"undecided at the finest step tried ({1e3 * r.get('finest_step_s', 0):g} ms, "
                f"{r.get('wall_s', 0):.0f} s of wall); at it: {word.strip('*')}")
    return word


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
    lines += manoeuvre.manoeuvre_flag(s) + _terms(s) + manoeuvre.manoeuvre_section(s)
    lines += _claims_table(s)
    lines += _numbers_table(s)
    lines += _disagreements(s)
    lines += _paper_drive(s)
    lines += resolution_section(s.get("refinement"))
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
             "(drake-car-handling), and the launch follows the prescribed speed even "
             "beyond the tyres' grip. The same six runs, the same rack input, with the paper's "
             "drive (the car then turns less and its struts see other loads):", "",
             "| # | open differential | the paper's drive | deciding number with the paper's "
             "drive |", "|---|---|---|---|"]
    for i, (claim, locked_verdict, number) in enumerate(zip(s["claims"], locked["verdicts"],
                                                           locked["numbers"]), start=1):
        ours, theirs = ("yes" if v else "no" for v in (claim["reproduced"], locked_verdict))
        if locked_verdict != claim["reproduced"]:
            theirs = f"**{theirs}** (changes)"
        lines.append(_row(i, ours, theirs, number))
    return lines + [""]


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
    ph, pl, tl = s["phases_s"], s["places_s"], s["timeline_s"]
    lines += [
        f"- **phases** (on every figure): I {_span(ph['I'])}, at rest ({tl['settle_s']:g} s) "
        f"then the speed-up to {tl['speed_kph']:g} km/h{manoeuvre.launch_words(s)}; II "
        f"{_span(ph['II'])}, straight at speed; III {_span(ph['III'])}, the lane change "
        f"({manoeuvre.shift_words(s)}); IV {_span(ph['IV'])}, straight in the new lane.",
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
    lines.append(error_method(s.get("refinement")))
    return lines + [""]


def _claims_table(s):
    lines = ["## The paper's claims", "",
             _row("#", "claim", "reproduced", "deciding number vs threshold",
                  "numerical error", "figure"), "|---|---|---|---|---|---|"]
    for i, (c, rows) in enumerate(zip(s["claims"], s["deciding_numbers"]), start=1):
        deciding = [r for r in rows if r["decides"]]
        number = "; ".join(f"{r['name']}: **{quantity(r['value'], r['unit'])}**, needs "
                           f"{_threshold(r)}" for r in deciding)
        error = "; ".join(_error(r) for r in deciding)
        lines.append(_row(i, c["claim"], _verdict(c, s), number, error,
                          _links(i, s["figures"])))
    t2, t3 = s["phases_s"]["II"]
    return lines + [
        "", f"Claim 1 is judged on {_span((t2 - 0.3, t3))}: from 0.3 s before the "
        "acceleration ends to the lane change, the stretch in which the rods return after the "
        "speed-up (in the paper, all but set 3's). The paper counts that return to its phase "
        "I; the figures here start phase II where the speed-up ends.", ""]


def _numbers_table(s):
    lines = ["## Every number behind a verdict, with its numerical error", "",
             "Rows marked *context* do not decide the verdict; they say how near it is or why. "
             "The values at each step are those of the run (or pair) the number comes from.",
             "", _row("claim", "number", "threshold", "value", "error", "values at each step",
                      "margin to the threshold", "decides"),
             "|---|---|---|---|---|---|---|---|"]
    for i, rows in enumerate(s["deciding_numbers"], start=1):
        for r in rows:
            threshold = _threshold(r) if r["relation"] is not None else "-"
            axis = " (solver)" if r.get("limited_by") == "solver" else ""
            error = ("-" if r["error"] is None else
                     quantity(r["error"], r["unit"], True) + axis if r["converged"] else
                     f"not converged (span {quantity(r['error'], r['unit'])})")
            margin = "-" if r["margin"] is None else \
                f"{quantity(r['margin'], r['unit'])} = {_flip(r)}"
            lines.append(_row(
                i, f"{r['name']} ({', '.join(r['runs'])})", threshold,
                quantity(r["value"], r["unit"]), error, _by_step(r), margin,
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


def _split_cell(row, scale, digits, unit=""):
    text = f"{_signed(scale * row['value'], digits)}{unit}"
    if row["converged"] is False:
        return text + " (not converged: " + ", ".join(
            f"{_signed(scale * v, digits)}" for v in row["values"]) + ")"
    if row["error"] is not None:
        return text + f" ±{scale * row['error']:.{digits}f}"
    return text


def _why_three(s):
    return ("after the lane change the dry struts stick at different extensions left and "
            "right, and the coil springs carry the difference into the wheel loads (steady "
            "changes from place a to place b, window averages, at the finest step each run "
            "tried): "
            + "; ".join(f"{n}: Δd_L-Δd_R {_split_cell(d['lr_change_m'], 1e3, 2, ' mm')}, "
                        f"load split {_split_cell(d['split_change'], 100, 2, ' %')} of the "
                        "corner load" for n, d in sorted(s["split_changes"].items())))


def _disagreements(s):
    bad = [(i, c) for i, c in enumerate(s["claims"], start=1)
           if not c["reproduced"] or c.get("decided") is False]
    if not bad:
        return []
    lines = ["## Where the model disagrees with the paper, and why", ""]
    for i, c in bad:
        why = _why_one(s) if i == 1 else _why_three(s) if i == 3 else c.get("why", "")
        if c.get("decided") is False:
            open_ = [r for r in s["deciding_numbers"][i - 1] if r["decides"] and not r["decided"]]
            why = "undecided: " + "; ".join(f"{r['name']}: {_by_step(r)} ({_flip(r)})"
                                            for r in open_) + ("; " + why if why else "")
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
    lines += ["", "## Front left-right split from place a to place b (steady: window "
              "averages; each run at the finest step it tried, ± its converged error)", "",
              "| run | change of Δd_left - Δd_right [mm] | change of Fz_fl - Fz_fr, of the "
              "corner load [%] | steps tried [ms] |", "|---|---|---|---|"]
    for name, d in sorted(s["split_changes"].items()):
        lines.append(_row(name, _split_cell(d["lr_change_m"], 1e3, 3),
                          _split_cell(d["split_change"], 100, 2),
                          ", ".join(f"{1e3 * h:g}" for h in d["split_change"]["steps_s"])))
    return lines + [""]


def _runs_and_files(s):
    lines = ["## Runs", "", "| run | case | set | wall [s] | real-time factor | "
             "frozen SAP steps | scene hash |", "|---|---|---|---|---|---|---|"]
    for name, info in sorted(s["runs"].items()):
        lines.append(f"| {name} | {info['case']} | {info['friction_set']} | "
                     f"{info['wall_s']:.1f} | {info['real_time_factor']:.2f} | "
                     f"{info['frozen_sap_steps']} | `{info['scene_hash']}` |")
    lines += ["", "Each run's scene, as it ran, is `<run>/scene.yaml` (rerun it with "
              "`drake-car-run --scene <run>/scene.yaml --out DIR`). Frozen SAP steps: "
              "steps in which Drake's solver returned its initial guess (`drake_car/systems/"
              "sap_pacer.py`); the pacer keeps them at 0.", "",
              "## Files", ""]
    figures = s["figures"]
    items = figures.items() if isinstance(figures, dict) else ((f, "") for f in figures)
    for name, what in items:
        lines.append(f"- [{name}]({name})" + (f": {what}" if what else ""))
    lines += ["- [diagram_overview.svg](diagram_overview.svg): the Diagram at a glance (each "
              "system once, the plant's connected ports only, the loggers as one box); "
              "[diagram.svg](diagram.svg): every port", ""]
    if s.get("replay"):
        page = f"{s['replay']}/replay.html"
        lines[-1:] = [f"- [{page}]({page}): the Meshcat replay of run {s['replay']} (open it "
                      "in a browser, no network needed; Meshcat's controls play, pause and "
                      "scrub it)", ""]
    return lines
