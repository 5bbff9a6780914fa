"""The paper's manoeuvre as it ran on the study's car: the launch (how long, what the car's drive
allows, when the car reached its speed), the lane change's rack (calibrated for the car: where
the calibration came from, its residual and cost), and each run's check of what its manoeuvre
says it does (speed at place a, lateral shift, heading at the end of the lane change:
``scene.manoeuvre_targets``). A run that is off is flagged at the top of the report and on
stderr (a logging warning): it is never reported silently as the paper's manoeuvre."""

import dataclasses
import logging

import numpy as np

from drake_car.scene.borrowed import drive_limit, drive_limit_words
from drake_car.scene.launch import launch_description
from drake_car.scene.manoeuvre_targets import (
    SHIFT_TOLERANCE_M, SPEED_TOLERANCE_KPH, dry_friction, heading_tolerance_rad,
    lane_change_metrics, manoeuvre_measures)
from drake_car.scene.manoeuvres import PAPER_SHIFT_M, PAPER_SPEED_UP_S, LaneChange
from drake_car.sim.lane_change_calibration import adapted

log = logging.getLogger(__name__)


def prepare(scenes: dict, *, run):
    """(name -> the scene as it runs, the lane change's calibration or None): each scene's
    launch resolved and its rack's profile found or calibrated for the car (once for the
    study: its runs share their inputs), a calibration's runs made by ``run``."""
    out, calibration = {}, None
    for name, scene in scenes.items():
        out[name], found = adapted(scene, run=run)
        calibration = calibration or found
    return out, calibration


def reached_s(history, timeline):
    """When the car's speed first came within ``SPEED_TOLERANCE_KPH`` of the timeline's, after
    the launch began (s; None: never)."""
    t, v = np.asarray(history["t"]), 3.6 * np.asarray(history["speed_mps"])
    near = np.flatnonzero((t >= timeline.settle_s)
                          & (np.abs(v - timeline.speed_kph) <= SPEED_TOLERANCE_KPH))
    return float(t[near[0]] - timeline.settle_s) if near.size else None


def manoeuvre_summary(runs: dict, calibration):
    """The manoeuvre's part of the study's summary (JSON-ready) from ``runs`` (name -> sim
    Run): the launch, the calibration, each run's measures and the runs that are off; warns
    on stderr for each run that is off."""
    first = next(iter(runs.values()))
    checks, off = {}, {}
    for name, r in runs.items():
        measures = manoeuvre_measures(r.history, r.scene.manoeuvre, dry_friction(r.scene))
        checks[name] = [dataclasses.asdict(m) | {"ok": m.ok, "within": m.within}
                        for m in measures]
        bad = [m.describe() for m in measures if not m.ok]
        if bad:
            off[name] = bad
            log.warning("run %s does not do the paper's manoeuvre: %s", name, "; ".join(bad))
    m = first.scene.manoeuvre
    cal = None
    if calibration is not None:
        cal = {k: calibration.get(k) for k in ("profile", "residual", "cost", "source",
                                                 "content_sha256")}
    return {"launch": launch_description(first.scene) | {"drive_limit": drive_limit(first.scene)} | {
                "reached_within_tolerance_after_s": reached_s(first.history, m.timeline),
                "reached_run": first.scene.name},
            "shift_m": m.shift_m, "steer_s": m.timeline.steer_s,
            "profile": {"amplitude_m": m.amplitude_m, "second_lobe": m.second_lobe},
            "calibration": cal, "checks": checks, "off": off, "run_ends": run_ends(runs)}


def run_ends(runs):
    """Where each lane-change run ends (its last sample): the heading and the track's shift
    from the start of phase III, the shift signed to the case's side; with the tolerances the
    lane change's end is judged with (not judged here: the paper's lane change is defined at
    the end of phase III, but a car still turning then keeps going)."""
    out = {}
    for name, r in runs.items():
        m = r.scene.manoeuvre
        if not isinstance(m, LaneChange) or not all(k in r.history for k in ("y_m", "yaw_rad")):
            continue
        lc = lane_change_metrics(r.history, m.timeline)
        if lc is None:
            continue
        sign = 1.0 if m.case == "a" else -1.0
        out[name] = {"t_s": float(r.history["t"][-1]), "heading_deg": lc["final_heading_deg"],
                     "shift_m": sign * lc["final_shift_m"], "asked_shift_m": m.shift_m,
                     "heading_tolerance_deg": float(np.degrees(heading_tolerance_rad(
                         m.timeline))), "dry": dry_friction(r.scene)}
    return out


def _ends_lines(man):
    """The runs without dry friction where they end: a car that had not finished turning when
    the lane change ended is said so, with how far it went on."""
    ends = {n: e for n, e in (man.get("run_ends") or {}).items() if not e["dry"]}
    if not ends:
        return []
    # Said when the path after the lane change leaves the shift's own tolerance: a heading a
    # little off parallel (the shipped Escort's 0.11 deg) moves the track by millimetres.
    name, e = max(ends.items(), key=lambda item: abs(item[1]["shift_m"]
                                                       - item[1]["asked_shift_m"]))
    drifted = abs(e["shift_m"] - e["asked_shift_m"])
    still = drifted > SHIFT_TOLERANCE_M
    text = (f"Where the runs without dry friction end ({e['t_s']:g} s; not judged: the lane "
            "change is defined at the end of phase III): heading "
            + ", ".join(f"{n} {_number(x['heading_deg'], 'deg')}°" for n, x in sorted(
                ends.items()))
            + "; track " + ", ".join(f"{n} {_number(x['shift_m'], 'm')} m" for n, x in sorted(
                ends.items())) + " from where the lane change began.")
    if still:
        text += (f" The car went on turning after the lane change: run {name} ends "
                 f"{_number(e['heading_deg'], 'deg')}° off parallel (the lane change's end is "
                 f"judged within {e['heading_tolerance_deg']:.2g}°), its track "
                 f"{_number(drifted, 'm')} m off the asked {e['asked_shift_m']:g} m, beyond "
                 f"the shift's tolerance of {SHIFT_TOLERANCE_M:g} m; place b sees that car.")
    return ["", text]


def launch_words(s):
    """" in 3 s" after "the speed-up to 60 km/h" in the report's phases."""
    man, launch = s.get("manoeuvre"), s["timeline_s"]["speed_up_s"]
    return f" in {PAPER_SPEED_UP_S if launch is None else launch:g} s" + (
        "" if man is None else " (the launch: see *The manoeuvre as it ran*)")


def shift_words(s):
    man = s.get("manoeuvre")
    shift = PAPER_SHIFT_M if man is None else man["shift_m"]
    return f"{shift:g} m sideways asked"


def manoeuvre_flag(s):
    """The report's warning lines at its top when a run did not do its manoeuvre."""
    man = s.get("manoeuvre")
    if not man or not man["off"]:
        return []
    runs = "; ".join(f"{n}: {', '.join(lines)}" for n, lines in sorted(man["off"].items()))
    return [f"**Warning: not the paper's manoeuvre.** {runs}. The verdicts below are about "
            "these runs as they ran, not about the paper's lane change (see *The manoeuvre as "
            "it ran*).", ""]


def manoeuvre_section(s):
    """The report's section on the launch, the rack and each run's check."""
    man = s.get("manoeuvre")
    if not man:
        return []
    la = man["launch"]
    paper = la["speed_up_s"] == la["paper_speed_up_s"]
    follows = la["profile_peak_accel_mps2"] <= la["max_accel_mps2"]
    lines = ["## The manoeuvre as it ran", "",
             f"- **launch**: 0 to {la['speed_kph']:g} km/h in {la['speed_up_s']:g} s"
             + (" (the paper's)" if paper else f" (the paper's {la['paper_speed_up_s']:g} s is "
                "more than the car allows with this drive)")
             + f"; the speed profile asks {la['profile_peak_accel_mps2']:.2f} m/s² at its peak. "
             f"The drive allows {la['drive_accel_mps2']:.2f} m/s² (its torque limit"
             + (f" {drive_limit_words(la['drive_limit'])}," if "drive_limit" in la else "")
             + " through the car's rolling radius and mass with the wheels' spin inertia), "
             f"the car's {la['driven_axle']} tyres' grip {la['traction_accel_mps2']:.2f} m/s² "
             f"(90 % [EST] of what their peak μ {la['peak_mu']:.2f} gives" + _grip_load(la)
             + f"): it is limited by {la['limited_by']}, its shortest "
             f"launch {la['shortest_launch_s']:g} s, its speed controller's lag "
             f"{la['lag_s']:.2f} s" + (". It follows the profile" if follows else
                                       ". It falls behind the profile and catches up")
             + f"; predicted {la['predicted_speed_at_place_a_kph']:.1f} km/h at place a "
             f"(±{la['predicted_speed_error_kph']:g} km/h, the prediction's error measured on "
             f"the shipped Escort; `drake_car/scene/launch.py`). The launch lasted "
             + ("beyond the run" if la["reached_within_tolerance_after_s"] is None else
                f"{la['reached_within_tolerance_after_s']:.2f} s")
             + f" for the car (run {la['reached_run']}: from its start until the car's speed "
             f"came within {SPEED_TOLERANCE_KPH:g} km/h of {la['speed_kph']:g} km/h)."]
    profile, cal = man["profile"], man["calibration"]
    rack = (f"- **rack**: the lane change's profile, {1e3 * (profile['amplitude_m'] or 0):.3f} "
            f"mm with a second lobe of {profile['second_lobe'] or 0:.4f}")
    if profile["amplitude_m"] is None:
        lines.append("- **rack**: none calibrated (the runs stop before the lane change).")
    elif cal is None:
        lines.append(rack + ", as the scenes give it (not calibrated here).")
    else:
        r, cost = cal["residual"] or {}, cal["cost"]
        lines.append(
            rack + f", calibrated for this car: {cal['source']} (its inputs' content "
            f"`{cal['content_sha256'][:16]}`); with lubricated struts, case a, it moved the "
            f"track {r.get('shift_m', float('nan')):.4f} m with a heading change of "
            f"{_number(r.get('heading_change_deg', float('nan')), 'deg')}° at the end of the "
            "lane change"
            + ("" if not cost else f"; the calibration took {cost['runs']} runs, "
               f"{cost['wall_s']:.0f} s wall, {cost['cpu_s']:.0f} s CPU") + ".")
    lines += ["", "Each run against what its manoeuvre says it does "
              "(`drake_car/scene/manoeuvre_targets.py`):", ""]
    names = sorted(man["checks"])
    whats = [m["what"] for m in man["checks"][names[0]]]
    lines.append("| run | " + " | ".join(whats) + " |")
    lines.append("|---" * (len(whats) + 1) + "|")
    first = man["checks"][names[0]]
    lines.append("| asked | " + " | ".join(f"{_number(m['target'], m['unit'])} ± "
                                            f"{m['tolerance']:.2g} {m['unit']}"
                                            for m in first) + " |")
    for name in names:
        cells = [("-" if m["value"] is None else _number(m["value"], m["unit"]))
                 + ("" if m["ok"] else " **OFF**")
                 + (" (the friction's effect)" if m["ok"] and not m.get("within", True) else "")
                 for m in man["checks"][name]]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    dry = sorted(n for n in names if any(m.get("friction_effect") for m in man["checks"][n]))
    if dry:
        judged = [n for n in names if n not in dry]
        lines += ["", (f"The lateral shift and the heading are judged on the runs without dry "
                       f"strut friction ({', '.join(judged)})" if judged else
                       "No run here is without dry strut friction: the lateral shift and the "
                       "heading are judged on none of them (the rack's own check is its "
                       "calibration's, on the car without dry friction, above)")
                  + f": every run gets the same rack input, and in {', '.join(dry)} "
                  "(dry struts) the path it makes is moved by the friction the study measures; "
                  "beyond the tolerance there it is marked as the friction's effect, not as a "
                  "manoeuvre that is off."]
    return lines + _ends_lines(man) + [""]


def _number(value, unit):
    """``value`` to the digits its check needs; no "-0.0000"."""
    shown = f"{value:.{ {'km/h': 2, 'm': 3}.get(unit, 4)}f}"
    return shown.lstrip("-") if float(shown) == 0 else shown


def _grip_load(la):
    """The load the peak μ and the grip were evaluated at: the driven axle's at the grip's
    limit, with its load transfer (not its load during this launch, where the drive limits it);
    a summary made before it was recorded says none."""
    grip = la.get("grip_load_N")
    if grip is None:
        return ""
    during = la["driven_load_N"]
    return (f" at the driven axle's {grip:.0f} N, its load with the transfer at that "
            "acceleration" + (f"; {during:.0f} N during this launch" if abs(grip - during) >= 1
                              else ""))
