"""Accuracy on demand, local route: the study's runs with dry friction resolve their near-
threshold stick-slip events locally (``sim.resolve``: the scene's ``simulator.resolve_events``,
saved with each run), the others (no dry friction: no events) are refined by halving their
whole step (``sweep.refine``, the global route, which remains reachable for every run with
``--refine global``).

A locally resolved run's outcomes are its own values at its step, with the windows' finer
steps where its events were. Their error is what the windows say (``position_errors``: per
strut, the largest change of a window's rest position under its last halving, first-order's
estimate of the finer level's error), carried to each outcome by how it is made of the rods'
positions (``ERROR_OF``): a rod's position at a place carries its strut's error; a shift (place b
less place a) twice that; the left-right change twice the sum of both struts'; a mirror pair
the sum of both runs'; the lasting split (a fraction of the corner load) the left-right
change's error times the run's own ratio of split to left-right change (the jammed struts'
preload is what both measure). Outcomes that are not made of rest positions (the rods'
rotation, μ1's counts, the forces at rest) get no error here ("-": not judged). Between
windows every strut is static: its rod moves by its creep only (|Δ| ≤ Δmax), at the run's
step; the step's error on the rest of the car there is not estimated by this route.
"""

import dataclasses
import math

from drake_car.model.geometry import SIDES
from drake_car.scene.scene import ResolveEvents
from drake_car.study.paper.claims import study_columns
from drake_car.study.paper.outcomes import (
    DRIVES, TOLERANCES, outcomes_of_runs, study_outcomes, tolerances)
from drake_car.sweep.refine import refine

# outcome -> (sides' errors used, factor): see the module.
ERROR_OF = {
    **{f"dd_{s}_{p}_m": ((s,), 1.0) for s in SIDES for p in "ab"},
    **{f"shift_{s}_m": ((s,), 2.0) for s in SIDES},
    "lr_change_m": (SIDES, 2.0),
    "return_m": (SIDES, 2.0),
    "peak_dd_m": (SIDES, 1.0),
}


@dataclasses.dataclass
class Accurate:
    """What ``accurate_runs`` made: the study's runs (name -> Run, the values' runs), the
    extra runs, the outcome rows, each run's simulation wall and CPU time over every step
    tried, and the summary's ``refinement`` record."""
    runs: dict
    extra: dict
    outcomes: dict
    run_wall_s: dict
    run_cpu_s: dict
    refinement: dict


def accurate_runs(scenes, roles, timeline, simulate, *, route, extra, halve, finest_step_s,
                  budget_s, solver_twin=None) -> Accurate:
    """The study's runs made accurate by ``route`` (see the module): "local" resolves the dry
    runs' events and refines the others globally, "global" refines every run
    (``sweep.refine``, down to ``finest_step_s`` or ``budget_s``). ``extra``: scenes run in
    the first round too, at their step; ``simulate``: a round's scenes to Runs;
    ``solver_twin``: the globally refined runs' solver axis (``sweep.refine``; the locally
    resolved runs have none)."""
    resolved = resolved_scenes(scenes) if route == "local" else scenes
    local = [n for n in scenes if resolved[n] is not scenes[n]]
    refined = refine({n: s for n, s in scenes.items() if n not in local},
                     outcomes_of_runs(roles, timeline), tolerances(), simulate,
                     finest_step_s=finest_step_s, budget_s=budget_s, drives=DRIVES,
                     first_extra=extra | {n: resolved[n] for n in local}, halve=halve,
                     solver_twin=solver_twin)
    done = refined.runs.pop("extra")
    runs = {n: done[n] if n in local else refined.runs[0][n] for n in scenes}
    table = refined.outcomes | local_rows(study_outcomes(
        {n: study_columns(runs[n].history) for n in local}, roles, timeline),
        {n: runs[n] for n in local})
    made = {n: ("local", [runs[n]]) if n in local else
            ("global", [level[n] for level in refined.runs.values() if n in level])
            for n in scenes}
    summaries = run_summaries(made)
    refinement = {"route": route, "rounds": refined.rounds, "wall_s": refined.wall_s,
                  "stopped": refined.stopped, "steps_s": refined.steps_s, "runs": summaries,
                  "finest_step_s": min(r["finest_step_s"] or math.inf
                                       for r in summaries.values())}
    return Accurate(runs, done, table, {n: sum(r.wall_s for r in made[n][1]) for n in scenes},
                    {n: sum(r.cpu_s for r in made[n][1]) for n in scenes}, refinement)


def resolved_scenes(scenes: dict):
    """name -> scene, those with dry friction resolving their events (``ResolveEvents()``'s
    defaults); the others as they are."""
    return {name: dataclasses.replace(s, simulator=dataclasses.replace(
        s.simulator, resolve_events=ResolveEvents())) if _dry(s) else s
        for name, s in scenes.items()}


def _dry(scene):
    return scene.friction is not None and scene.friction.law.mu_s > 0


def side_errors(run):
    """side -> the error of the strut's rest positions (m) from ``run``'s windows; None when
    the run resolved no window."""
    resolution = run.resolution or {}
    errors = resolution.get("position_errors") or {}
    if not resolution.get("window_count"):
        return None
    return {side: float(errors.get(f"{side}_translation", 0.0)) for side in SIDES}


def local_rows(values: dict, runs: dict):
    """Outcome rows (as ``sweep.refine`` gives them) of ``values`` ({(subject, outcome):
    (value, unit)}, ``outcomes.study_outcomes`` of locally resolved ``runs``): each with its
    error from the windows (see the module), converged (error within the tolerance and every
    window resolved; None where not judged), and how it was resolved."""
    rows = {}
    for (subject, outcome), (value, unit) in values.items():
        names = subject.split("|")
        errors = [side_errors(runs[n]) for n in names]
        error = None
        if outcome in ERROR_OF and None not in errors:
            sides, factor = ERROR_OF[outcome]
            error = sum(factor * sum(e[s] for s in sides) for e in errors)
        elif outcome == "mirror_residual_m" and None not in errors:
            error = sum(max(e.values()) for e in errors)
        elif outcome == "split_change" and None not in errors:
            lr = values.get((subject, "lr_change_m"), (0.0, ""))[0]
            lr_error = 2.0 * sum(errors[0].values())
            error = abs(value / lr) * lr_error if lr else None
        tolerance = TOLERANCES[outcome][0]
        all_resolved = all(w["resolved"] for n in names
                           for w in (runs[n].resolution or {}).get("windows") or [])
        rows[(subject, outcome)] = {
            "unit": unit, "tolerance": tolerance, "steps_s": [_step(runs[names[0]])],
            "values": [value], "value": value, "error": error,
            "converged": None if error is None else (error <= tolerance and all_resolved),
            "observed_order": None, "step_s": _step(runs[names[0]]), "route": "local",
            **resolution_fields(runs[n] for n in names)}
    return rows


def _step(run):
    return run.scene.time_step_s


def resolution_fields(runs):
    """How the runs of an outcome were resolved: windows, events in them (the transitions of
    the resolving level), the finest step a window used, the windows' CPU time."""
    found = [(run, run.resolution or {}) for run in runs]
    windows = [w for _, r in found for w in (r.get("windows") or [])]
    steps = [w["step_s"] for w in windows]
    return {"windows": len(windows),
            "events_resolved": sum(sum(sum(c) for c in w["levels"][-1]["counts"].values())
                                   for w in windows),
            "finest_step_s": min(steps) if steps else None,
            "resolution_cpu_s": sum(r.get("cpu_s", 0.0) for _, r in found),
            "run_cpu_s": sum(run.cpu_s for run, _ in found if math.isfinite(run.cpu_s))}


def error_method(refinement):
    """The report's sentence on how the numerical errors were made (``refinement``: the
    summary's, None at one step)."""
    if refinement is None:
        return "- **numerical error**: not estimated (one step only, --no_verify)."
    local = refinement.get("route") == "local"
    text = ("- **numerical error** (accuracy on demand): " + (
        "the runs with dry friction resolve their stick-slip events locally: where an event is "
        "near its threshold (a strut at its full static friction, or creeping through the "
        "static band), the run re-runs that window at halved steps until its outcome (each "
        "strut's slips and sticks, where it rests, how close it came to breaking away) no "
        "longer changes with a halving, and goes on at its own step (`sim.resolve`; each "
        "run's `resolution` in run.json, its events in events.csv). Their error is the "
        "windows' last change of the rods' rest positions, carried to each outcome (a "
        "place's position: once, a shift: twice, the left-right change: both struts', the "
        "lasting split: the left-right change's times the run's split per millimetre); "
        "outcomes not made of rest positions get none (\"-\"). The runs without dry friction "
        "are repeated at half and a quarter of their step, " if local else
        "every run is repeated at half and a quarter of its step, ") + (
        "and the runs an outcome has not "
        "converged for are halved again, until each deciding outcome converges within its "
        "tolerance (`outcomes.csv`: one row per run and outcome) or the finest step "
        f"({1e3 * refinement['finest_step_s']:g} ms tried) or the budget is reached "
        f"({refinement['stopped']}). Converged: the last two differences are within the "
        "tolerance and shrink as a first-order scheme's do; the error is then the last "
        "difference, plus the solver's: each such run's twin at its finest step with SAP's "
        "tolerance loosened twice moves it by that much (\"solver\" where that is the larger "
        "part)" + ("; the locally resolved runs have no solver twin" if local else "") + ". A "
        "maximum over runs is taken over each run's own value, its error the largest of "
        "theirs: a run is only ever compared with itself. A verdict is decided only where its "
        "margin exceeds that error; \"n × the error\" says by how much."))
    return text


def local_error(row, shown):
    """A locally resolved measure's error as the report writes it (``shown``: the error as a
    quantity)."""
    finest = row.get("finest_step_s")
    where = f"events resolved down to {1e3 * finest:g} ms" if finest else "no window"
    if row["error"] is None:
        return f"not estimated by the local route ({where}; not made of rest positions)"
    if not row["converged"]:
        return f"±{shown} from the windows, not converged ({where})"
    return f"±{shown} ({where})"


def resolution_section(refinement):
    """The report's table of how each run was made accurate and what that cost."""
    runs = (refinement or {}).get("runs")
    if not runs:
        return []
    lines = ["## How each run was made accurate, and what it cost", "",
             "| run | route | windows (resolved) | events in them | finest step | rest "
             "positions' error (left / right) | CPU of the run (of it, windows) |",
             "|---|---|---|---|---|---|---|"]
    for name, r in runs.items():
        errors = r.get("position_errors") or {}
        shown = " / ".join(f"{1e3 * errors[f'{s}_translation']:.4f} mm"
                           for s in SIDES if f"{s}_translation" in errors) or "-"
        finest = r.get("finest_step_s")
        lines.append(f"| {name} | {r['route']} | {r.get('windows', 0)} "
                     f"({r.get('resolved', 0)}) | {r.get('events_resolved', 0)} | "
                     f"{'-' if finest is None else f'{1e3 * finest:g} ms'} | {shown} | "
                     f"{r['cpu_s']:.1f} s ({r.get('resolution_cpu_s', 0.0):.1f} s) |")
    return lines + ["", "Global: the whole run repeated at halved steps (the CPU of every step "
                    "tried); local: its events' windows resolved at halved steps; the job's "
                    f"CPU time in all: {refinement.get('job_cpu_s', math.nan):.0f} s "
                    "(summary.json's cpu_s).", ""]


def run_summaries(runs_by_route):
    """name -> {route, windows, resolved, events_resolved, finest_step_s, position_errors,
    cpu_s, resolution_cpu_s} for the summary's ``refinement.runs``; ``runs_by_route``:
    name -> (route, [the Runs made of it at every step tried])."""
    out = {}
    for name, (route, made) in runs_by_route.items():
        final = made[-1]
        r = final.resolution or {}
        fields = resolution_fields([final])
        out[name] = {"route": route, "windows": r.get("window_count", 0),
                     "resolved": r.get("resolved", 0),
                     "events_resolved": fields["events_resolved"],
                     "finest_step_s": (fields["finest_step_s"] or final.scene.time_step_s
                                       if route == "local"
                                       else min(m.scene.time_step_s for m in made)),
                     "position_errors": r.get("position_errors") or {},
                     "cpu_s": sum(m.cpu_s for m in made if math.isfinite(m.cpu_s)),
                     "resolution_cpu_s": r.get("cpu_s", 0.0)}
    return out
