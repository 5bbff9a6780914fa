"""The design study's accuracy on demand, local route (``--refine local``; the default,
``--refine global``, halves the jam cases' whole step instead, ``study.design.jam_cases``).

Which runs: the jam cases (``jam_cases.jam_scenes``: the runs of the spec's ``accuracy.parts``
whose μs is at least ``accuracy.jam_mu_s``, and every run of the user's change), the runs whose
lasting state the step can decide (a jammed strut's lasting split takes one of two branches).
Each resolves the stick-slip events of its struts locally (``sim.resolve``: its scene's
``simulator.resolve_events``, ``resolve_events`` here: windows re-run at halved steps, down to
the spec's ``accuracy.finest_step_s``), in the study's one sweep. Every other run is at the
study's step, its errors the half-step noise sample's (drawn from those runs: ``tables.noise_levels``),
as on the global route. ``accuracy.jam_mu_s: 0`` resolves every dry run of the parts.

A resolved run's lasting split carries the windows' error (``apply``), carried as in the
paper's study (``study.paper.local_route``): a strut's rest position at place a carries the
errors of the windows before place a ends (the lane change's start), at place b of those before
place b ends (the driver's release, hands off; else the run's end), each window's its
convergence error plus what it inherits and the gap before it (``sim.resolve``); the left-right
change of the rods' rest positions (place b less place a) errs by the sum of the four, the
lasting split by that times the row's own split per left-right change. Windows after place b
(hands off) do not count.
What the windows do not cover is said, not estimated: a resolved run that opened no window, and
the pull (hands off, after the release; not made of rest positions), keep the noise sample's
level, and ``*_error_from`` says so. Between windows every strut is static (every slip opens
a window: ``resolve_events``), and the gaps' step error is in the windows' errors."""

import dataclasses
import math

from drake_car.model.geometry import SIDES
from drake_car.scene.load import hands_off_release_s
from drake_car.scene.scene import HandsOff, ResolveEvents
from drake_car.study.design.jam_cases import DECIDING, YES_NO, tolerances
from drake_car.study.paper.local_route import errors_between

# What the table gets of a run's resolution (``resolution_fields``).
FIELDS = ("windows", "windows_resolved", "window_finest_step_s", "window_steps",
          "resolution_cpu_s", "run_cpu_s",
          *(f"rest_error_{s}_{p}_m" for s in SIDES for p in "ab"))
# Which slips a run resolves, by ``ResolveEvents.events``: in words.
EVENT_WORDS = {"all": "every slip of their struts", "near": "their near-threshold stick-slip events"}
# How a row's outcomes were resolved (the table's ``resolved_by``).
WINDOWS, HALVING, NONE = "windows", "halving", "-"


def resolve_events(study):
    """The jam cases' ``ResolveEvents``: windows down to the spec's ``accuracy.finest_step_s``,
    one at every break-away of a strut (``events="all"``; "near": only where the run's step
    shows the event near its threshold). Which events open a window is set here, on its one
    line. Measured on --quick (docs/studies.md, 17 jam cases against the global route): "near"
    misses a break-away the step decides in 3 of them (their splits 0.05-0.19 % of the corner
    load from the global route's, beyond their errors: no window opened); "all" agrees in all
    17, the study at 2.41× its unrefined run's CPU rather than 1.80×."""
    # No solver twin: the design study's budget is the step's on both routes (its global
    # route has no solver axis either).
    return ResolveEvents(finest_step_s=study.accuracy.finest_step_s, events="all",
                         solver_twin=False)


def resolving(study, scene):
    """``scene`` resolving its events locally (see the module), if it has dry friction."""
    if scene.friction is None or scene.friction.law.mu_s == 0:
        return scene
    return dataclasses.replace(scene, simulator=dataclasses.replace(
        scene.simulator, resolve_events=resolve_events(study)))


def resolving_parts(study, parts, names):
    """``parts`` ({role: {name: (scene, values)}}) with the runs ``names`` resolving."""
    return {role: {name: ((resolving(study, scene) if name in names else scene), values)
                   for name, (scene, values) in part.items()}
            for role, part in parts.items()}


def announcement(study, count, compare):
    """The line the command prints as the local route starts."""
    a = study.accuracy
    return (f"accuracy on demand: {count} runs (at μs >= {a.jam_mu_s:g} of "
            f"{', '.join(a.parts)}" + (", and --compare's" if compare else "")
            + f") resolve {EVENT_WORDS[resolve_events(study).events]} locally, down to "
            f"{1e3 * a.finest_step_s:g} ms")


def place_ends_s(scene):
    """When places a and b end (the outcomes' ``place_values``): the lane change's start; the
    driver's release (hands off), else the run's end (inf)."""
    b = hands_off_release_s(scene) if isinstance(scene.steering, HandsOff) else math.inf
    return scene.manoeuvre.timeline.boundaries()[1], b


def resolution_fields(run):
    """The table's columns (``FIELDS``) of a run's resolution (NaN where it has none)."""
    r = (run.resolution or {}) if run is not None else {}
    windows = r.get("windows") or []
    fields = {"windows": len(windows), "windows_resolved": sum(w["resolved"] for w in windows),
              "window_finest_step_s": r.get("finest_step_s") or math.nan,
              "window_steps": r.get("window_steps", 0) if r else 0,
              "resolution_cpu_s": r.get("cpu_s", math.nan) if r else math.nan,
              "run_cpu_s": run.cpu_s if run is not None else math.nan}
    ends = place_ends_s(run.scene) if windows else (math.nan, math.nan)
    for place, end in zip("ab", ends):
        errors = errors_between(run, end_s=end) if windows else None
        for side in SIDES:
            fields[f"rest_error_{side}_{place}_m"] = (errors or {}).get(side, math.nan)
    return fields


def apply(rows, study, noise, resolved):
    """Each row's deciding outcomes with their errors (see the module), in place; the same
    columns as ``jam_cases.apply``'s, and ``resolved_by``. ``resolved``: the names of the runs
    that resolved their events."""
    tolerance = tolerances(study)
    for row in rows:
        local = row["name"] in resolved and row["status"] == "ok"
        row["resolved_by"] = WINDOWS if local else NONE
        for key in DECIDING:
            level = noise.get(key, math.nan) if math.isfinite(row[key]) else math.nan
            fields = {f"{key}_error": level, f"{key}_error_from": "noise sample",
                      f"{key}_converged": "-", f"{key}_step_s": row.get("step_s", math.nan),
                      f"{key}_values": ""}
            if local and key == "split_change_rel":
                error = _split_error(row)
                if error is not None:
                    converged = (error <= tolerance[key]
                                 and row["windows_resolved"] == row["windows"])
                    fields |= {f"{key}_error": error, f"{key}_error_from": "windows",
                               f"{key}_converged": YES_NO[converged],
                               f"{key}_step_s": row["window_finest_step_s"],
                               f"{key}_values": repr(float(row[key]))}
                elif not row["windows"]:
                    fields[f"{key}_error_from"] = "noise sample (no window opened)"
            elif local:
                fields[f"{key}_error_from"] = "noise sample (not carried from the windows)"
            row |= fields
        row["refine_wall_s"] = math.nan
    return rows


def _error(error):
    """A lasting split's error as the report writes it: unknown where a window's twins found
    its branch unsettled (``sim.twins``; infinite)."""
    return f"± {100 * error:.2f} %" if math.isfinite(error) else "error unknown: a window's branch"


def _split_error(row):
    """The lasting split's error from the rods' rest positions' (see the module), or None."""
    errors = [row.get(f"rest_error_{s}_{p}_m", math.nan) for s in SIDES for p in "ab"]
    if not row.get("windows") or any(math.isnan(e) for e in errors):
        return None  # (an infinite one, a window's branch unknown, is carried)
    change = ((row["dd_left_b_m"] - row["dd_right_b_m"])
              - (row["dd_left_a_m"] - row["dd_right_a_m"]))
    if not (math.isfinite(change) and change != 0.0):
        return None
    return abs(row["split_change_rel"] / change) * sum(errors)


def summary(rows, study, resolved):
    """What the local route did and cost, for the report: per part, its runs, those resolved,
    with windows, windows (resolved), the finest step a window used, the CPU time of the
    part's runs, of its resolved runs and of their windows; the study's runs' CPU in all and
    the windows' share (what resolving added); the resolved rows whose split did not converge
    and those that opened no window. Rows of equal runs (one hash) count once."""
    by_part, seen = {}, set()
    totals = {"run_cpu_s": 0.0, "resolution_cpu_s": 0.0}
    for row in rows:
        if row["status"] != "ok" or not math.isfinite(row.get("run_cpu_s", math.nan)):
            continue
        part = by_part.setdefault(row["role"], {
            "runs": 0, "resolved": 0, "with_windows": 0, "windows": 0, "windows_resolved": 0,
            "finest_step_s": math.inf, "run_cpu_s": 0.0, "resolved_run_cpu_s": 0.0,
            "resolution_cpu_s": 0.0})
        part["runs"] += 1
        if row["hash"] in seen:
            continue
        seen.add(row["hash"])
        part["run_cpu_s"] += row["run_cpu_s"]
        totals["run_cpu_s"] += row["run_cpu_s"]
        if row["name"] not in resolved:
            continue
        part["resolved"] += 1
        part["resolved_run_cpu_s"] += row["run_cpu_s"]
        part["with_windows"] += row["windows"] > 0
        part["windows"] += row["windows"]
        part["windows_resolved"] += row["windows_resolved"]
        if row["windows"]:
            part["finest_step_s"] = min(part["finest_step_s"], row["window_finest_step_s"])
            part["resolution_cpu_s"] += row["resolution_cpu_s"]
            totals["resolution_cpu_s"] += row["resolution_cpu_s"]
    mine = [r for r in rows if r["name"] in resolved and r["status"] == "ok"]
    unconverged = [{"name": r["name"], "role": r["role"], "value": r["split_change_rel"],
                    "error": r["split_change_rel_error"]} for r in mine
                   if r.get("split_change_rel_converged") == "no"]
    a = study.accuracy
    return {"route": "local", "events": resolve_events(study).events,
            "jam_mu_s": a.jam_mu_s, "parts": list(a.parts),
            "compare": any(r["role"] == "compare" for r in mine),
            "finest_step_s": a.finest_step_s, "tolerances": tolerances(study),
            "runs": len(mine), "by_part": by_part, "totals": totals,
            "not_converged": unconverged,
            "no_window": [r["name"] for r in mine if not r["windows"]]}


def report_lines(acc):
    """The report's section on the local route."""
    t = acc["totals"]
    share = t["resolution_cpu_s"] / t["run_cpu_s"] if t["run_cpu_s"] else math.nan
    lines = ["## Accuracy where the struts jam", "",
             f"The {acc['runs']} runs of {', '.join(acc['parts'])} at μs ≥ "
             f"{acc['jam_mu_s']:g}" + (" and of the user's change (--compare) at any μs"
                                       if acc.get("compare") else "")
             + f" resolved {EVENT_WORDS[acc.get('events', 'all')]} locally: windows re-run at "
             f"halved steps, down to {1e3 * acc['finest_step_s']:g} ms, until their outcome no "
             "longer changed (`sim.resolve`); the rest of each run is at the study's step. "
             "Their lasting split's error is the windows' (the rods' rest positions' error "
             "carried to the split); a run that opened no window, their pull, and every other "
             "run keep the half-step noise sample's (`table.csv`: `resolved_by`, `*_error`, "
             "`*_error_from`, `windows`, `rest_error_*_m`, `resolution_cpu_s`). The windows "
             f"took {t['resolution_cpu_s']:.0f} s of CPU, {100 * share:.0f} % of the "
             f"{t['run_cpu_s']:.0f} s the study's runs took (their simulation loops; equal runs "
             "counted once).", "",
             "| part | runs | resolved | with windows | windows (resolved) | finest step | "
             "CPU of the runs | of the resolved runs (of it, windows) |",
             "|---|---|---|---|---|---|---|---|"]
    for role, p in acc["by_part"].items():
        finest = "-" if not math.isfinite(p["finest_step_s"]) else \
            f"{1e3 * p['finest_step_s']:g} ms"
        lines.append(f"| {role} | {p['runs']} | {p['resolved']} | {p['with_windows']} | "
                     f"{p['windows']} ({p['windows_resolved']}) | {finest} | "
                     f"{p['run_cpu_s']:.0f} s | {p['resolved_run_cpu_s']:.0f} s "
                     f"({p['resolution_cpu_s']:.0f} s) |")
    lines.append("")
    if acc["not_converged"]:
        lines += [f"The lasting split did not converge within "
                  f"{100 * acc['tolerances']['split_change_rel']:g} % in "
                  f"{len(acc['not_converged'])} resolved runs: "
                  + ", ".join(f"{u['name']} ({100 * u['value']:+.2f} %, {_error(u['error'])})"
                              for u in acc["not_converged"]), ""]
    if acc["no_window"]:
        lines += [f"Resolved runs that opened no window (no strut slipped; their "
                  f"error is the noise sample's): {', '.join(acc['no_window'])}.", ""]
    return lines
