"""The paper's study as a summary (JSON-ready) and a report (Markdown), from the study's runs
and claims (pure: no simulation, no files).

The report is written for a reader of the paper: it defines its terms first (sets, cases,
phases, places, thresholds, peak and steady), gives every verdict beside its threshold, links
each claim to the figure that shows it, and gives every deciding number from ``outcomes.csv``
(``sweep.refine``) with its numerical error (the step's plus the solver's) or "not converged"
with the values at each step; a verdict whose margin does not exceed its error is "undecided
at the finest step tried"."""

import dataclasses

from drake_car.model.loading import working_folder_names
from drake_car.scene.car_file import car_of_file
from drake_car.study.car.describe import car_facts, car_lines, own_strut_damping
from drake_car.study.paper import manoeuvre
from drake_car.study.paper import report_sections as sections
from drake_car.study.paper.local_route import error_method, resolution_section
from drake_car.study.paper.measures import claim_measures, verdict
from drake_car.study.paper.claims import (
    DISPLACEMENT_THRESHOLD_M, SYMMETRY_TOLERANCE, FrictionSet, numbers_text, place_values,
    run_of, set_roles)
from drake_car.study.paper.previous_car import applies, previous_car_section
from drake_car.study.paper.report_format import (  # noqa: F401 (the report's formatting)
    CLAIM_FIGURES, flip, quantity, span)

_span = span


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
    roles_ = set_roles(r.friction for r in study.values())
    sets = {n: dataclasses.asdict(run_of(study, "a", n).friction) for n in roles_.numbers}
    scenes = [run.scene for run in runs.values()]
    t = next(iter(study.values())).columns["t"]
    t2, t3, t4, _ = timeline.boundaries()
    made = {
        "claims": claims,
        "deciding_numbers": measures,
        "friction_sets": sets,
        "set_roles": {"high": roles_.high, "others": list(roles_.others),
                      "fig16": roles_.fig16},
        "car": car_facts(scenes[0], strut_damping=own_strut_damping(scenes)),
        "car_file_strut_damping_Nspm": (car_of_file(scenes[0].car_file).front.strut_damping_Nspm
                                        if scenes[0].car_file else None),
        "paper_car": applies(scenes),
        "sap_pacer": all(sc.simulator.sap_pacer for sc in scenes),
        "cases": {"a": "lane change starting with a left turn (to the left lane and back "
                       "straight)",
                  "b": "lane change starting with a right turn (the mirror image of a)"},
        "phases_s": {"I": [0.0, t2], "II": [t2, t3], "III": [t3, t4],
                     "IV": [t4, float(t[-1])]},
        "places_s": {"a": [t3 - 0.3, t3], "b": [float(t[-1]) - 0.5, float(t[-1])]},
        "rod_positions": rod_positions,
        "speed_at_place_a_kph": {name: 3.6 * place_values(r.columns, timeline, "speed_mps")[0]
                                 for name, r in study.items()},
        "rod_shift_b_minus_a_m": shifts,
        # At the scenes' own step (the curves'): a symmetric car holds 0 at place a.
        "wheel_torque_at_places_Nm": {
            name: list(place_values(r.columns, timeline, "steering_wheel_torque_Nm"))
            for name, r in study.items()},
        "split_changes": {name: {k: outcomes[(name, k)] for k in (
            "lr_change_m", "split_change", "split_change_N", "wheel_torque_change_Nm")}
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
        # the runs' car and tyre files found in the working folder: a rerun starts there
        "working_folder_files": sorted({n for sc in scenes for n in working_folder_names(
            [sc.car_file, getattr(sc.tyres, "tir_file", None)])}),
    }
    for i, c in enumerate(claims, start=1):  # the why the report gives, not the runs' step's
        c["why"] = sections.claim_why(made, i)
    return made


def verdict_line(claims, *, verified, steps_s):
    """The command's last line: how many claims were reproduced and how they were judged
    (``verified``: against their numerical errors at the finest step tried; else at the runs'
    steps ``steps_s``, no error estimated: --no_verify)."""
    judged = [c for c in claims if c["reproduced"] is not None]
    reproduced = sum(bool(c["reproduced"]) for c in judged)
    left_out = len(claims) - len(judged)
    if verified:
        undecided = sum(c.get("decided") is False for c in claims)
        how = f", {undecided} undecided at the finest step tried"
    else:
        how = (f" at the runs' step ({', '.join(f'{1e3 * t:g}' for t in steps_s)} ms), no "
               "numerical error estimated (--no_verify)")
    return (f"{reproduced} of {len(judged)} claims reproduced{how}"
            + (f", {left_out} not applicable to these friction sets" if left_out else ""))


# -- the report ------------------------------------------------------------------------------

def report(s):
    """The Markdown report of a ``summary``."""
    prov = s["provenance"]
    lines = ["# The paper's study: lane change with strut friction", "",
             f"Made by `{prov['command']}`, commit {(prov['git_commit'] or 'unknown')[:10]}, drake "
             f"{prov['drake']}, {prov['created_utc']}; {s['wall_s']:.0f} s wall in all.", ""]
    lines += manoeuvre.manoeuvre_flag(s) + _terms(s) + manoeuvre.manoeuvre_section(s)
    lines += sections.claims_table(s)
    lines += sections.numbers_table(s)
    lines += sections.disagreements(s)
    lines += sections.paper_drive(s)
    lines += resolution_section(s.get("refinement"))
    lines += previous_car_section(s)
    lines += sections.places_tables(s)
    lines += sections.runs_and_files(s)
    return "\n".join(lines)


def _car_section(s):
    """The car that ran, from its scene (the friction sets' damping is said per set)."""
    return ["## The car that ran", "", *car_lines(s["car"], damping=False), ""]


def _set_lines(s):
    """The study's runs, each set from its scenes' values, and the sets each claim judges."""
    # int keys: a summary read back from summary.json has them as strings
    sets = {int(n): FrictionSet(**f) for n, f in sorted(s["friction_sets"].items(),
                                                           key=lambda item: int(item[0]))}
    roles = s["set_roles"]
    example = next(name for name, r in sorted(s["runs"].items())
                   if r["case"] == "a" and r["friction_set"] == max(sets))
    count = len(sets)
    lines = [f"{len(s['runs'])} runs: two cases (a, b) × {count} friction "
             f"set{'s' if count > 1 else ''} ({', '.join(str(n) for n in sets)}); run "
             f"`{example}` is case a with set {max(sets)}. The friction is in the front struts' "
             "cylindrical joints (the rod sliding and turning in the cylinder); the rear has "
             "none.", ""]
    for n, f in sets.items():
        lines.append(f"- **set {n}**: {f.describe()}")
    if any(f.dry and f.damping_Nspm for f in sets.values()):
        lines.append("  (the paper's dry struts are undamped; these ran with the viscous damping "
                     "their scenes give)")
    own = s.get("car_file_strut_damping_Nspm")
    if own is not None and any(f.damping_Nspm != own for f in sets.values()):
        lines.append(f"  (the car file gives {own:g} N s/m of viscous damping in the strut; "
                     "each set ran with its own damping, as listed: to run the car's damper, "
                     "give friction sets of your own with `--scene`, docs/studies.md)")
    if roles["high"] is None:
        lines.append("- **the sets the claims judge**: no set is dry, so the claims about dry "
                     "friction (1, 2, 6) are not applicable")
    else:
        lines.append(
            f"- **the sets the claims judge**: claims 1 and 2 the highest friction, set "
            f"{roles['high']} (the paper's set 3); claim 1 compares it with "
            f"{numbers_text(roles['others'])}; claim 6 (Fig. 16) set {roles['fig16']}, the dry "
            "set nearest the paper's μs = 0.2")
    return lines


def _terms(s):
    lines = _car_section(s) + ["## Sets and cases, and the terms used", ""] + _set_lines(s)
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
