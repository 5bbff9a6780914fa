"""The paper study's report, its sections after the terms: the claims with their deciding numbers
and errors, every number behind a verdict, where the model disagrees and why, the paper's own
drive, the rods at the places and the lasting split (in N, in % of the corner load, and the
steering-wheel torque the driver holds), the runs and the files. Every sentence about the car or
its drive comes from the summary, which the scenes that ran made."""

import math

from drake_car.results.numbers import signed
from drake_car.study.paper.report_format import (
    by_step, error_text, flip, links, quantity, table_row, threshold_text, verdict_text)


def paper_drive(s):
    """The verdicts with the paper's own drive (its driven wheels' rotation prescribed: a
    locked driven axle) beside the car's own drive."""
    locked = s.get("paper_drive")
    if not locked:
        return []
    axle = s["car"].get("driven_axle", "front")
    effect = ("about 2.5 deg/g more understeer on this car (drake-car-handling)"
              if s.get("paper_car") else
              "a locked axle resists the turn, more understeer (drake-car-handling measures "
              "how much on this car)")
    lines = ["## The paper's own drive, for comparison", "",
             f"The runs above are driven by {s['car']['drive']}. The paper prescribes the "
             f"driven wheels' rotation (here both {axle} wheels'), which locks the {axle} "
             f"axle: {effect}, and the launch follows the prescribed speed even beyond the "
             f"tyres' grip. The same {len(s['runs'])} runs, the same rack input, with the "
             "paper's drive (its struts see other loads):", "",
             "| # | the car's drive | the paper's drive | deciding number with the paper's "
             "drive |", "|---|---|---|---|"]
    words = {True: "yes", False: "no", None: "not applicable"}
    for i, (claim, locked_verdict, number) in enumerate(zip(s["claims"], locked["verdicts"],
                                                           locked["numbers"]), start=1):
        ours, theirs = words[claim["reproduced"]], words[locked_verdict]
        if locked_verdict != claim["reproduced"]:
            theirs = f"**{theirs}** (changes)"
        lines.append(table_row(i, ours, theirs, number))
    return lines + [""]


def claims_table(s):
    lines = ["## The paper's claims", "",
             table_row("#", "claim", "reproduced", "deciding number vs threshold",
                       "numerical error", "figure"), "|---|---|---|---|---|---|"]
    for i, (c, rows) in enumerate(zip(s["claims"], s["deciding_numbers"]), start=1):
        deciding = [r for r in rows if r["decides"]]
        number = ("; ".join(f"{r['name']}: **{quantity(r['value'], r['unit'])}**, needs "
                            f"{threshold_text(r)}" for r in deciding) or "-") + not_friction(rows)
        error = "; ".join(error_text(r) for r in deciding) or "-"
        lines.append(table_row(i, c["claim"], verdict_text(c, s), number, error,
                               links(i, s["figures"]) if deciding else "-"))
    t2, t3 = s["phases_s"]["II"]
    return lines + [
        "", f"Claim 1 is judged on {t2 - 0.3:.3g} s to {t3:.3g} s: from 0.3 s before the "
        "acceleration ends to the lane change, the stretch in which the rods return after the "
        "speed-up (in the paper, all but set 3's). The paper counts that return to its phase "
        "I; the figures here start phase II where the speed-up ends.", ""]


WITHOUT_DRY = "the same without dry friction"  # claim 2's context row (study.paper.measures)


def not_friction(rows):
    """Claim 2's "new position" is friction's only where the car without dry friction does not
    move as much between the same places (a car still surging from its launch at place a moves
    its rods there by itself): a warning, with both numbers, where it does; else ""."""
    deciding = next((r for r in rows if r["decides"]), None)
    alone = next((r for r in rows if r["name"].startswith(WITHOUT_DRY)), None)
    if deciding is None or alone is None or deciding["threshold"] is None:
        return ""
    if deciding["holds"] is not True or alone["value"] <= deciding["threshold"]:
        return ""  # no new position to attribute, or the car alone keeps its rods in place
    budget = (deciding["error"] or 0.0) + (alone["error"] or 0.0)
    if deciding["value"] - alone["value"] > deciding["threshold"] + budget:
        return ""
    return (f" — **not friction's doing**: {alone['name'][len('the same '):]} the rods move "
            f"{quantity(alone['value'], alone['unit'])} between the same places (the car is "
            "not yet at rest at place a), within the threshold and the errors of this number")


def numbers_table(s):
    lines = ["## Every number behind a verdict, with its numerical error", "",
             "Rows marked *context* do not decide the verdict; they say how near it is or why. "
             "The values at each step are those of the run (or pair) the number comes from; "
             "a largest (smallest) over runs carries the largest of those runs' errors "
             "(|max x - max y| <= max |x - y|), not only its own run's.",
             "", table_row("claim", "number", "threshold", "value", "error",
                           "values at each step", "margin to the threshold", "decides"),
             "|---|---|---|---|---|---|---|---|"]
    for i, rows in enumerate(s["deciding_numbers"], start=1):
        for r in rows:
            threshold = threshold_text(r) if r["relation"] is not None else "-"
            axis = " (solver)" if r.get("limited_by") == "solver" else ""
            # Not converged: the spread of the last three steps (global); the windows' budget
            # (local: their step errors summed, whose own spreads are in them, plus the solver's).
            budget = quantity(r["error"], r["unit"]) if r["error"] is not None else ""
            unconverged = (f"±{budget} from the windows" if r.get("route") == "local"
                           else f"span {budget}")
            error = ("-" if r["error"] is None else
                     quantity(r["error"], r["unit"], True) + axis if r["converged"] else
                     f"not converged ({unconverged})")
            margin = "-" if r["margin"] is None else \
                f"{quantity(r['margin'], r['unit'])} = {flip(r)}"
            lines.append(table_row(
                i, f"{r['name']} ({', '.join(r['runs'])})", threshold,
                quantity(r["value"], r["unit"]), error, by_step(r), margin,
                "yes" if r["decides"] else "*context*"))
    return lines + [""]


def _measure(rows, outcome):
    return next(r for r in rows if r["outcomes"] == [outcome])


def _set_holds(number, friction, normal, steady, peak, stuck=False):
    """What static friction does to one set's rod in the speed-up: μs·N at rest against the
    load the speed-up takes off each front wheel (steady and at its peak); ``stuck``: the rod
    was measured not to move as the acceleration ended."""
    mu_s = friction["mu_s"]
    if not mu_s:
        return f"set {number} has no dry friction (μs = 0): nothing holds its rod"
    hold = mu_s * normal
    holds = f"set {number} holds μs·N = {mu_s:g} × {normal:.0f} = {hold:.0f} N"
    then = " and then stuck" if stuck else ""
    if hold >= peak:
        return (f"{holds}, more than the peak {peak:.0f} N: its rod never breaks free"
                + (", so it cannot return" if stuck else ""))
    if hold >= steady:
        return (f"{holds}, less than the peak {peak:.0f} N: its rod broke free as the "
                f"acceleration set in{then}")
    return (f"{holds}, less than the {steady:.0f} N the speed-up takes off each front wheel: "
            f"its rod slipped as the car accelerated{then}")


def _why_one(s):
    """Claim 1's why: the part(s) that decide the verdict first (the set whose rod moved
    against the claim, by how much, and what static friction did to it), then every other set
    the claim speaks of."""
    rows = s["deciding_numbers"][0]
    hold, peak, steady = (_measure(rows, k)["value"]
                          for k in ("hold_N", "unload_peak_N", "unload_steady_N"))
    high = s["set_roles"]["high"]
    sets = {int(k): v for k, v in s["friction_sets"].items()}
    mu_s = sets[high]["mu_s"]
    normal = hold / mu_s if mu_s else 0.0
    target = s["timeline_s"]["speed_kph"]
    speeds = [v for name, v in s.get("speed_at_place_a_kph", {}).items()
              if s["runs"][name]["friction_set"] == high]
    still = min(speeds, default=target)
    accelerating = still < target - 1.0
    first = (f"the car was still accelerating when the lane change began ({still:.1f} of "
             f"{target:g} km/h at place a, set {high}): the acceleration had not ended, so no "
             "rod could return after it, and the claim is not judged on the paper's "
             "manoeuvre; " if accelerating else "")
    moved = [r for r in rows if r["outcomes"] == ["return_m"] and r["decides"]]
    told, parts = [], []
    for r in sorted(moved, key=lambda r: r["holds"] is not False):
        number = s["runs"][r["runs"][0]]["friction_set"]
        value = quantity(r["value"], r["unit"])
        stuck = r["relation"] == ">" and not r["holds"]
        story = _set_holds(number, sets[number], normal, steady, peak, stuck)
        if r["holds"] is False:
            parts.append(f"the verdict turns on set {number} ({', '.join(r['runs'])}): its rod "
                         f"moves {value} as the acceleration ends, where the claim needs "
                         f"{threshold_text(r)}; {story}")
        else:
            parts.append(f"set {number} agrees with the claim ({value}, needs "
                         f"{threshold_text(r)}): " + story.replace(f"set {number} ", "it ", 1))
        told.append(number)
    named = [high] + list(s["set_roles"].get("others", []))
    parts += [_set_holds(k, sets[k], normal, steady, peak) for k in named if k not in told]
    return (first + f"the strut's normal force at rest is N = {normal:.0f} N (eq. 4, from "
            "the strut's bending, which the ball-joint offset b and the spring line set); the "
            f"speed-up unloads each front wheel by {steady:.0f} N steady (at constant "
            f"acceleration) and by {peak:.0f} N at its peak (the body pitching as the "
            "acceleration sets in). " + ". ".join(p[0].upper() + p[1:] for p in parts))


def split_cell(row, scale, digits, unit=""):
    """A steady change as the report writes it: its value, ± its converged error; not converged,
    the spread that makes it so: the values at the steps tried (each step's, in ms), or a
    locally resolved run's windows' summed error against their tolerance."""
    text = f"{signed(scale * row['value'], digits)}{unit}"
    if row["converged"] is False:
        if len(row["values"]) > 1 or row["error"] is None:
            return text + " (not converged: " + ", ".join(
                f"{signed(scale * v, digits)} at {1e3 * h:g} ms"
                for h, v in zip(row["steps_s"], row["values"])) + ")"
        if not math.isfinite(row["error"]):
            return text + " (not converged: a window's branch its twins found unsettled)"
        tolerance = (f", above their tolerance {scale * row['tolerance']:.{digits}f}"
                     if row.get("tolerance") is not None else "")
        finest = row.get("finest_step_s")
        down = f" resolved down to {1e3 * finest:g} ms" if finest else ""
        return text + (f" (not converged: ±{scale * row['error']:.{digits}f} from the "
                       f"windows{down}{tolerance})")
    if row["error"] is not None:
        return text + f" ±{scale * row['error']:.{digits}f}"
    return text


def _why_three(s):
    return ("after the lane change the dry struts stick at different extensions left and "
            "right, and the coil springs carry the difference into the wheel loads (steady "
            "changes from place a to place b, window averages, at the finest step each run "
            "tried): "
            + "; ".join(f"{n}: Δd_L-Δd_R {split_cell(d['lr_change_m'], 1e3, 2, ' mm')}, "
                        f"load split {split_cell(d['split_change_N'], 1, 0, ' N')} = "
                        f"{split_cell(d['split_change'], 100, 2, ' %')} of the corner load"
                        for n, d in sorted(s["split_changes"].items())))


def claim_why(s, i):
    """Why claim ``i`` (from 1) came out as it did, as the report says it: claims 1 and 3 from
    the deciding numbers (the converged ones where accuracy on demand ran), the others as their
    claim has it."""
    c = s["claims"][i - 1]
    if c.get("applicable") is False:
        return c.get("why", "")
    return _why_one(s) if i == 1 else _why_three(s) if i == 3 else c.get("why", "")


def disagreements(s):
    bad = [(i, c) for i, c in enumerate(s["claims"], start=1)
           if c["reproduced"] is False or c.get("decided") is False]
    if not bad:
        return []
    lines = ["## Where the model disagrees with the paper, and why", ""]
    for i, c in bad:
        why = claim_why(s, i)
        if c.get("decided") is False:
            open_ = [r for r in s["deciding_numbers"][i - 1] if r["decides"] and not r["decided"]]
            why = "undecided: " + "; ".join(f"{r['name']}: {by_step(r)} ({flip(r)})"
                                            for r in open_) + ("; " + why if why else "")
        lines.append(f"- **{i}. {c['claim']}** ({links(i, s['figures'])}): "
                     f"{why.rstrip('.')}.")
    return lines + [""]


def places_tables(s):
    lines = ["## Rod positions at places a and b (window averages)", "",
             "| run | Δd left a [mm] | Δd left b [mm] | Δd right a [mm] | Δd right b [mm] |",
             "|---|---|---|---|---|"]
    for name, pos in sorted(s["rod_positions"].items()):
        lines.append(f"| {name} | {1e3 * pos['dd_left_at_a_m']:.3f} | "
                     f"{1e3 * pos['dd_left_at_b_m']:.3f} | {1e3 * pos['dd_right_at_a_m']:.3f} | "
                     f"{1e3 * pos['dd_right_at_b_m']:.3f} |")
    corner = s["car"]["corner_load_N"]["front"]
    c = s["car"]["rack_gain_m_per_rad"]
    lines += ["", "## The lasting front left-right split, and the steering-wheel torque it "
              "leaves (from place a to place b)", "",
              f"Steady changes (window averages), each run at the finest step it tried, ± its "
              f"converged error where it was refined. The split is Fz_fl - Fz_fr, in newtons "
              f"and in % of the front "
              f"corner load at rest ({corner:.0f} N: half the front axle's); the steering-wheel "
              f"torque is what the driver holds to keep the rack where the manoeuvre puts it "
              f"(straight ahead after the lane change), the rack force times the rack gain c = "
              f"{1e3 * c:g} mm/rad (unassisted steering; + towards a left turn): a lasting change "
              "is a torque the driver must hold to drive straight on.",
              "", "| run | change of Δd_left - Δd_right [mm] | split change [N] | split change "
              "[% of the corner load] | steering-wheel torque change [N m] | steps tried [ms] |",
              "|---|---|---|---|---|---|"]
    for name, d in sorted(s["split_changes"].items()):
        lines.append(table_row(name, split_cell(d["lr_change_m"], 1e3, 3),
                               split_cell(d["split_change_N"], 1, 0),
                               split_cell(d["split_change"], 100, 2),
                               split_cell(d["wheel_torque_change_Nm"], 1, 3),
                               ", ".join(f"{1e3 * h:g}" for h in d["split_change"]["steps_s"])))
    return lines + [""] + _torque_at_places(s)


def _torque_at_places(s):
    """The steering-wheel torque at places a and b: driving straight at place a a symmetric
    car holds none; what a run holds there is its launch's broken mirror, which the change
    carries (docs/accuracy.md "The mirror")."""
    torques = s.get("wheel_torque_at_places_Nm")
    if not torques:
        return []
    cells = ", ".join(f"{n} {signed(a, 3)} / {signed(b, 3)}"
                      for n, (a, b) in sorted(torques.items()))
    return [f"The steering-wheel torque at place a / place b [N m], at each run's own step: "
            f"{cells}. Driving straight at place a the car is symmetric and holds none: a "
            "torque there is the launch's broken mirror (round-off amplified where both "
            "struts' rotation pairs break away together, in the friction law's Stribeck band; "
            "a coarse step's, docs/accuracy.md \"The mirror\"). A case b run continues its "
            "case a's launch, so their changes above differ by twice that torque; the torques "
            "at place b are the ones to compare mirrored.", ""]


def runs_and_files(s):
    lines = ["## Runs", "", "| run | case | set | wall [s] | real-time factor | "
             "frozen SAP steps | scene hash |", "|---|---|---|---|---|---|---|"]
    for name, info in sorted(s["runs"].items()):
        lines.append(f"| {name} | {info['case']} | {info['friction_set']} | "
                     f"{info['wall_s']:.1f} | {info['real_time_factor']:.2f} | "
                     f"{info['frozen_sap_steps']} | `{info['scene_hash']}` |")
    pacer = ("the pacer keeps them at 0" if s.get("sap_pacer", True) else
             "the pacer is off in these scenes (simulator.sap_pacer: false)")
    files, folder = s.get("working_folder_files"), s["provenance"].get("working_folder")
    where = (f"from `{folder}`, where its {', '.join(f'`{n}`' for n in files)} are (the scene "
             "names them relative to that folder): `cd " + folder + " && ") if files and folder \
        else "with `"
    lines += ["", "Each run's scene, as it ran, is `<run>/scene.yaml` (rerun it " + where +
              "drake-car-run --scene <run>/scene.yaml --out DIR`). Frozen SAP steps: "
              "steps in which Drake's solver returned its initial guess "
              f"(`drake_car/systems/sap_pacer.py`); {pacer}.", "",
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
