"""The design study's accuracy on demand, local route (``--refine local``; the default,
``--refine global``, refines the jam cases by halving their whole step,
``study.design.jam_cases``): every run with dry
friction, in every part (maps, lines, Sobol's sample, the Monte Carlo, the mitigations, the
noise sample), resolves its near-threshold stick-slip events locally (``sim.resolve``, its
scene's ``simulator.resolve_events``: windows at halved steps down to the spec's
``accuracy.finest_step_s``), in the study's one sweep.

Each row's lasting split then carries the windows' error (``apply_local``): the rods' rest
positions' error (per strut, the largest change of a window's rest position under its last
halving) carried to the split as in the paper's study (``study.paper.local_route``): the left-right
change of the rods' rest positions (place b less place a) errs by twice the sum of both
struts' errors, the lasting split by that times the row's own split per left-right change. The
pull (hands off, after the release) and the rows without a window keep the half-step noise
sample's level (``tables.noise_levels``)."""

import dataclasses
import math

from drake_car.model.geometry import SIDES
from drake_car.scene.scene import ResolveEvents
from drake_car.study.design.jam_cases import DECIDING, YES_NO, tolerances

# What the table gets of a run's resolution (``resolution_fields``).
FIELDS = ("windows", "windows_resolved", "window_finest_step_s", "resolution_cpu_s",
          "run_cpu_s", *(f"rest_error_{s}_m" for s in SIDES))


def resolving(study, scene):
    """``scene`` resolving its events locally (see the module), if it has dry friction."""
    if scene.friction is None or scene.friction.law.mu_s == 0:
        return scene
    return dataclasses.replace(scene, simulator=dataclasses.replace(
        scene.simulator,
        resolve_events=ResolveEvents(finest_step_s=study.accuracy.finest_step_s)))


def resolution_fields(run):
    """The table's columns (``FIELDS``) of a run's resolution (NaN where it has none)."""
    r = (run.resolution or {}) if run is not None else {}
    errors = r.get("position_errors") or {}
    windows = r.get("windows") or []
    return {"windows": len(windows), "windows_resolved": sum(w["resolved"] for w in windows),
            "window_finest_step_s": r.get("finest_step_s") or math.nan,
            "resolution_cpu_s": r.get("cpu_s", math.nan) if r else math.nan,
            "run_cpu_s": run.cpu_s if run is not None else math.nan,
            **{f"rest_error_{s}_m": errors.get(f"{s}_translation", math.nan) if windows
               else math.nan for s in SIDES}}


def apply_local(rows, study, noise):
    """Each row's deciding outcomes with their errors (see the module), in place; the same
    columns as ``jam_cases.apply``'s."""
    tolerance = tolerances(study)
    for row in rows:
        for key in DECIDING:
            level = noise.get(key, math.nan) if math.isfinite(row[key]) else math.nan
            fields = {f"{key}_error": level, f"{key}_error_from": "noise sample",
                      f"{key}_converged": "-", f"{key}_step_s": row.get("step_s", math.nan),
                      f"{key}_values": ""}
            error = _split_error(row) if key == "split_change_rel" else None
            if error is not None and row["status"] == "ok":
                converged = error <= tolerance[key] and row["windows_resolved"] == row["windows"]
                fields |= {f"{key}_error": error, f"{key}_error_from": "windows",
                           f"{key}_converged": YES_NO[converged],
                           f"{key}_step_s": row["window_finest_step_s"],
                           f"{key}_values": repr(float(row[key]))}
            row |= fields
        row["refine_wall_s"] = math.nan
    return rows


def _split_error(row):
    """The lasting split's error from the rods' rest positions' (see the module), or None."""
    errors = [row.get(f"rest_error_{s}_m", math.nan) for s in SIDES]
    if not row.get("windows") or not all(math.isfinite(e) for e in errors):
        return None
    change = ((row["dd_left_b_m"] - row["dd_right_b_m"])
              - (row["dd_left_a_m"] - row["dd_right_a_m"]))
    if not (math.isfinite(change) and change != 0.0):
        return None
    return abs(row["split_change_rel"] / change) * 2.0 * sum(errors)


def summary(rows, study):
    """What the local route did and cost, for the report: per part, the runs with dry friction,
    those with windows, windows (resolved), the finest step a window used, the windows' CPU
    time; the rows whose split did not converge."""
    by_part = {}
    for row in rows:
        if row["status"] != "ok" or not math.isfinite(row.get("run_cpu_s", math.nan)):
            continue
        part = by_part.setdefault(row["role"], {"runs": 0, "with_windows": 0, "windows": 0,
                                                "resolved": 0, "finest_step_s": math.inf,
                                                "resolution_cpu_s": 0.0, "run_cpu_s": 0.0})
        part["runs"] += 1
        part["with_windows"] += row["windows"] > 0
        part["windows"] += row["windows"]
        part["resolved"] += row["windows_resolved"]
        if row["windows"]:
            part["finest_step_s"] = min(part["finest_step_s"], row["window_finest_step_s"])
            part["resolution_cpu_s"] += row["resolution_cpu_s"]
        part["run_cpu_s"] += row["run_cpu_s"]
    unconverged = [{"name": r["name"], "role": r["role"], "value": r["split_change_rel"],
                    "error": r["split_change_rel_error"]} for r in rows
                   if r.get("split_change_rel_converged") == "no"]
    return {"route": "local", "finest_step_s": study.accuracy.finest_step_s,
            "tolerances": tolerances(study), "by_part": by_part, "not_converged": unconverged}


def report_lines(acc):
    """The report's section on the local route."""
    lines = ["## Accuracy where the struts jam", "",
             "Every run with dry friction resolved its near-threshold stick-slip events "
             "locally: windows re-run at halved steps, down to "
             f"{1e3 * acc['finest_step_s']:g} ms, until their outcome no longer changed "
             "(`sim.resolve`); the lasting split's error is the windows' (the rods' rest "
             "positions' error carried to the split), the pull's and a run without a window's "
             "the half-step noise sample's (`table.csv`: `*_error`, `*_error_from`, `windows`, "
             "`rest_error_*_m`, `resolution_cpu_s`).", "",
             "| part | runs | with windows | windows (resolved) | finest step | CPU of the runs "
             "(of it, windows) |", "|---|---|---|---|---|---|"]
    for role, p in acc["by_part"].items():
        finest = "-" if not math.isfinite(p["finest_step_s"]) else \
            f"{1e3 * p['finest_step_s']:g} ms"
        lines.append(f"| {role} | {p['runs']} | {p['with_windows']} | {p['windows']} "
                     f"({p['resolved']}) | {finest} | {p['run_cpu_s']:.0f} s "
                     f"({p['resolution_cpu_s']:.0f} s) |")
    lines.append("")
    if acc["not_converged"]:
        lines += [f"The lasting split did not converge within "
                  f"{100 * acc['tolerances']['split_change_rel']:g} % in "
                  f"{len(acc['not_converged'])} runs: "
                  + ", ".join(f"{u['name']} ({100 * u['value']:+.2f} ± "
                              f"{100 * u['error']:.2f} %)" for u in acc["not_converged"]), ""]
    return lines
