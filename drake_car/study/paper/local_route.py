"""Accuracy on demand, local route: the study's runs with dry friction resolve every slip of
their struts locally (``sim.resolve``: the scene's ``simulator.resolve_events``, saved with each
run), the others (no dry friction: no slips) are refined by halving their whole step
(``sweep.refine``, the global route, which remains reachable for every run with ``--refine
global``).

A locally resolved run's outcomes are its own values at its step, with the windows' finer
steps where its struts slipped. Each window says the error of the rods' rest positions at its
end (per strut: its convergence error, plus what it inherits from the last window and from the
gap before it: ``sim.resolve``); a rest position carries the errors of every window before it
(their sum, ``errors_between``; on the solver axis the largest of the windows' solver errors,
each the whole run's up to its end). Carried to each outcome by when it is taken and how it is made
of the rods' positions (``local_rows``): a rod's position at place a takes the windows before
the lane change, at place b all of them; a shift (b less a) and the left-right change (its
two shifts) take both; the return (a rod's travel from the end of the speed-up to the lane
change) twice the windows in that time, or, where none is, the creep band 2·Δmax it can move
in while static; a mirror pair both runs'; the lasting split the left-right change's error
times the run's own ratio of split to left-right change (the jammed struts' preload is what
both measure); a peak (the largest Δd, rotation or μ1) the convergence of its window's
levels' extremes (``peak_error``). The forces at rest get no error here ("-": not judged).
"""

import dataclasses
import math

import numpy as np

from drake_car.model.geometry import SIDES
from drake_car.scene.scene import ResolveEvents
from drake_car.sim.convergence import classify
from drake_car.study.paper.claims import RETURN_BLEND_S, study_columns
from drake_car.study.paper.outcomes import (
    DRIVES, TOLERANCES, outcomes_of_runs, study_outcomes, tolerances)
from drake_car.sweep.refine import check_twin, refine

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
    ``solver_twin``: the solver axis (``sweep.refine``'s twin of a globally refined run; a
    locally resolved run's windows run theirs when it is given: ``sim.resolve``)."""
    resolved = (resolved_scenes(scenes, finest_step_s, solver_twin=solver_twin is not None)
                if route == "local" else scenes)
    local = [n for n in scenes if resolved[n] is not scenes[n]]
    refined = refine({n: s for n, s in scenes.items() if n not in local},
                     outcomes_of_runs(roles, timeline), tolerances(), simulate,
                     finest_step_s=finest_step_s, budget_s=budget_s, drives=DRIVES,
                     first_extra=extra | {n: resolved[n] for n in local}, halve=halve,
                     solver_twin=solver_twin)
    done = refined.runs.pop("extra")
    runs = {n: done[n] if n in local else finest_run(refined.runs, n) for n in scenes}
    table = refined.outcomes | local_rows(study_outcomes(
        {n: study_columns(runs[n].history) for n in local}, roles, timeline),
        {n: runs[n] for n in local}, timeline)
    made = {n: ("local", [runs[n]]) if n in local else
            ("global", [level[n] for level in refined.runs.values() if n in level])
            for n in scenes}
    summaries = run_summaries(made)
    refinement = {"route": route, "solver_axis": solver_twin is not None,
                  "rounds": refined.rounds, "wall_s": refined.wall_s,
                  "stopped": refined.stopped, "steps_s": refined.steps_s, "runs": summaries,
                  "finest_step_s": min(r["finest_step_s"] or math.inf
                                       for r in summaries.values())}
    return Accurate(runs, done, table, {n: sum(r.wall_s for r in made[n][1]) for n in scenes},
                    {n: sum(r.cpu_s for r in made[n][1]) for n in scenes}, refinement)


def finest_run(levels: dict, name):
    """Run ``name`` at the finest step it was refined to (``sweep.refine``'s runs: level ->
    name -> Run), the study's CSVs and figures drawn from it; the replay page, made at the
    scene's own step only, carried over from there."""
    steps = [k for k in levels if isinstance(k, int) and name in levels[k]]
    finest, first = levels[max(steps)][name], levels[min(steps)][name]
    if finest.replay_html is None and first.replay_html is not None:
        finest = dataclasses.replace(finest, replay_html=first.replay_html)
    return finest


def resolved_scenes(scenes: dict, finest_step_s=ResolveEvents.finest_step_s,
                    solver_twin=True):
    """name -> scene, those with dry friction resolving every slip of their struts
    (``ResolveEvents`` down to ``finest_step_s``, with the solver twin with ``solver_twin``:
    refused where it cannot run, ``sweep.refine.check_twin``); the others as they are."""
    settings = ResolveEvents(finest_step_s=finest_step_s, solver_twin=solver_twin)
    for scene in scenes.values():
        if solver_twin and _dry(scene):
            check_twin(scene)
    return {name: dataclasses.replace(s, simulator=dataclasses.replace(
        s.simulator, resolve_events=settings)) if _dry(s) else s
        for name, s in scenes.items()}


def _dry(scene):
    return scene.friction is not None and scene.friction.law.mu_s > 0


def errors_between(run, start_s=-math.inf, end_s=math.inf, axis="position_errors"):
    """side -> the error of the strut's rest positions (m) from ``run``'s windows that reach
    into (``start_s``, ``end_s``); None when the run resolved no window.
    ``axis``: "position_errors" (the step's: convergence, inheritance, gaps) or
    "solver_errors" (the solver twin's: each window's is the whole run's up to its end, so the
    largest of them)."""
    resolution = run.resolution or {}
    if not resolution.get("window_count"):
        return None
    out = dict.fromkeys(SIDES, 0.0)
    for w in resolution["windows"]:
        if w["end_s"] > start_s and w["start_s"] < end_s:
            for side in SIDES:
                error = float(w.get(axis, {}).get(f"{side}_translation", 0.0))
                out[side] = (out[side] + error if axis == "position_errors"
                             else max(out[side], error))
    return out


# A peak over the run (and both struts): the channel it is taken of (per side), from the run's
# first value (Δd) or from zero.
PEAKS = {"rotation_rad": ("rot_{}_rad", False), "peak_dd_m": ("d_{}_m", True),
         **{f"mu1_peak_{s}": (f"friction_{s}_translation_mu1", False) for s in SIDES}}


def _peak_at(run, outcome):
    """Where ``run`` reaches peak ``outcome``: (its channel's name pattern, the side, the time,
    the value it is taken from, its scale, the windows holding that time)."""
    (channel, from_start), history = PEAKS[outcome], run.history
    sides = [outcome.rsplit("_", 1)[1]] if outcome.startswith("mu1_") else SIDES
    scale = run.scene.friction.law.mu_s if outcome.startswith("mu1_") else 1.0
    best = None
    for side in sides:
        x = np.asarray(history[channel.format(side)], dtype=float)
        ref = x[0] if from_start else 0.0
        k = int(np.argmax(np.abs(x - ref)))
        if best is None or abs(x[k] - ref) > best[0]:
            best = (abs(x[k] - ref), side, float(history["t"][k]), ref)
    _, side, t, ref = best
    windows = [w for w in (run.resolution or {}).get("windows") or []
               if w["start_s"] < t <= w["end_s"] + 1e-9]
    return channel, side, t, ref, scale, windows


def peak_error(run, outcome, tolerance):
    """(error, converged) of peak ``outcome`` of a locally resolved ``run``: where the run
    reaches it inside a window, the convergence of that window's levels' peaks
    (``sim.convergence.classify``, each level's extremes of the channel in the window); a rod's
    position outside every window is a rest position (every strut static there): its windows'
    error. None (not estimated) for a rotation or μ1 peak reached between windows."""
    channel, side, t, ref, scale, windows = _peak_at(run, outcome)
    before = (errors_between(run, end_s=t) or {}).get(side)
    if not windows:
        if outcome == "peak_dd_m" and before is not None:  # a rest position
            return before, before <= tolerance
        return None, None
    w = windows[0]
    if len(w["levels"]) < 3:  # no convergence to judge
        return None, None
    series = [max(abs(lo - ref), abs(hi - ref)) / scale
              for lo, hi in (lv["extrema"][channel.format(side)] for lv in w["levels"])]
    found = classify(series, tolerance)
    error = found["error"]
    if outcome == "peak_dd_m":  # where the rod started the window, and what it inherits
        pair, earlier = f"{side}_translation", errors_between(run, end_s=w["start_s"])[side]
        error += (earlier + w["inherited_errors"].get(pair, 0.0)
                  + w.get("gap_errors", {}).get(pair, 0.0))
    return error, found["converged"] and w["resolved"]


def peak_solver_error(run, outcome):
    """The solver axis of peak ``outcome`` (see ``peak_error``): in a window, how far the
    solver twin's extreme of the channel lies from the run's (the twin carries the run's
    solver error up to there); a rest position between windows: the solver error of the
    windows before it; None where ``peak_error`` gives none or no window ran a twin."""
    channel, side, t, ref, scale, windows = _peak_at(run, outcome)
    before = (errors_between(run, end_s=t, axis="solver_errors") or {}).get(side)
    if not windows:
        return before if outcome == "peak_dd_m" else None
    w, name = windows[0], channel.format(side)
    twin, chosen = w.get("solver_extrema", {}).get(name), w["levels"][-1]["extrema"].get(name)
    if twin is None or chosen is None or len(w["levels"]) < 3:  # as peak_error
        return None
    return abs(max(abs(a - ref) for a in twin) - max(abs(b - ref) for b in chosen)) / scale


def local_rows(values: dict, runs: dict, timeline):
    """Outcome rows (as ``sweep.refine`` gives them) of ``values`` ({(subject, outcome):
    (value, unit)}, ``outcomes.study_outcomes`` of locally resolved ``runs``): each with its
    error from the windows (see the module), converged (error within the tolerance and every
    window resolved; None where not judged), and how it was resolved."""
    t2, t3 = timeline.boundaries()[:2]
    rows = {}
    for (subject, outcome), (value, unit) in values.items():
        names = subject.split("|")
        error = _carried(outcome, subject, value, values, runs, names, (t2, t3),
                         "position_errors")
        solver = _carried(outcome, subject, value, values, runs, names, (t2, t3),
                          "solver_errors")
        tolerance = TOLERANCES[outcome][0]
        peak_converged = None
        if outcome in PEAKS:
            error, peak_converged = peak_error(runs[names[0]], outcome, tolerance)
            solver = peak_solver_error(runs[names[0]], outcome)
        elif outcome.startswith("mu1_reaches_") and value == 0:
            # A count of 0 is exact at every level while its peak stays clear of 1: decided
            # where the peak's margin exceeds the peak's error (``measures.claim_measures``).
            peak = f"mu1_peak_{outcome.rsplit('_', 1)[1]}"
            if (subject, peak) in values:
                peak_err, _ = peak_error(runs[names[0]], peak, TOLERANCES[peak][0])
                error = None if peak_err is None else 0.0
                peak_converged = None if peak_err is None else True
                solver = None if peak_err is None else 0.0
        all_resolved = all(w["resolved"] for n in names
                           for w in (runs[n].resolution or {}).get("windows") or [])
        rows[(subject, outcome)] = {
            "unit": unit, "tolerance": tolerance, "steps_s": [_step(runs[names[0]])],
            "values": [value], "value": value, "error": error,
            "converged": None if error is None else (
                peak_converged if peak_converged is not None
                else error <= tolerance and all_resolved),
            "observed_order": None, "step_s": _step(runs[names[0]]), "route": "local",
            "solver_error": solver if _twinned(runs[n] for n in names) else None,
            "limited_by": (None if error is None else "solver"
                           if solver is not None and solver > error else "step"),
            **resolution_fields(runs[n] for n in names)}
    return rows


def _carried(outcome, subject, value, values, runs, names, boundaries, axis):
    """The windows' errors on ``axis`` (``errors_between``) carried to a non-peak outcome (see
    the module); None where the outcome takes none."""
    t2, t3 = boundaries
    before_a = [errors_between(runs[n], end_s=t3, axis=axis) for n in names]
    at_b = [errors_between(runs[n], axis=axis) for n in names]
    if None in at_b:
        return None
    side = outcome.split("_")[1] if outcome.startswith(("dd_", "shift_")) else None
    if outcome.startswith("dd_"):
        return (before_a if outcome.endswith("_a_m") else at_b)[0][side]
    if outcome.startswith("shift_"):
        return before_a[0][side] + at_b[0][side]
    if outcome in ("lr_change_m", "split_change"):
        error = sum(before_a[0].values()) + sum(at_b[0].values())
        if outcome == "split_change":
            lr = values.get((subject, "lr_change_m"), (0.0, ""))[0]
            return abs(value / lr) * error if lr else None
        return error
    if outcome == "return_m":
        if axis == "solver_errors":  # a difference of the run's solver error up to two times
            return 2.0 * max(errors_between(runs[names[0]], end_s=t3, axis=axis).values())
        during = errors_between(runs[names[0]], t2 - RETURN_BLEND_S, t3, axis=axis)
        if any(during.values()):
            return 2.0 * max(during.values())
        # No window in the return: the creep band it can move in while static.
        return 2.0 * runs[names[0]].scene.friction.law.dmax_translation_m
    if outcome == "mirror_residual_m":
        return sum(max(e.values()) for e in at_b)
    return None


def _twinned(runs):
    """Whether every run's windows ran their solver twin."""
    return all(((r.resolution or {}).get("settings") or {}).get("solver_twin", False)
               for r in runs)


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
        "the runs with dry friction resolve every slip of their struts locally: the run "
        "re-runs each window around a slip at halved steps until where the rods rest has "
        "converged (the same rule as below, on the window's last three levels: each strut's "
        "slips and sticks the same, a strut at full creep settled), and goes on at its own "
        "step from the finest level (`sim.resolve`; each run's `resolution` in run.json, its "
        "events in events.csv). A window's error is its rest positions' plus what it inherits "
        "from the last window (its level 0 run again from the last window's next coarser "
        "end; windows that inherit more than the tolerance are resolved as one) and from the "
        "gap before it (gap and window again at half the step); a rest position carries the "
        "windows' errors before it (their sum), carried to each outcome by when it is taken "
        "and how it is made of the rods' positions; a peak takes its window's levels' "
        "convergence; the forces at rest get none (\"-\"). The runs without dry friction "
        "are repeated at half and a quarter of their step, " if local else
        "every run is repeated at half and a quarter of its step, ") + (
        "and the runs an outcome has not "
        "converged for are halved again, until each deciding outcome converges within its "
        "tolerance (`outcomes.csv`: one row per run and outcome) or the finest step "
        f"({1e3 * refinement['finest_step_s']:g} ms tried) or the budget is reached "
        f"({refinement['stopped']}). Converged: the last two differences are within the "
        "tolerance and shrink as a first-order scheme's do; the error is then the last "
        "difference" + ((", plus the solver's: each such run's twin at its finest step "
                         "with SAP's tolerance loosened twice moves it by that much "
                         "(\"solver\" where that is the larger part)" + (
                             "; on the local route the twin runs along the run's own "
                             "windows (each gap at the run's step, each window at its "
                             "resolving level) with SAP's tolerance loosened twice, and how "
                             "far the rods' rest positions at a window's end lie from the "
                             "run's is the run's solver error up to there (the largest is "
                             "carried)"
                             if local else "")) if refinement.get("solver_axis", True)
                       else " (no solver axis: --no_solver_axis)") + ". A "
        "maximum over runs is taken over each run's own value, its error the largest of "
        "theirs: a run is only ever compared with itself. A verdict is decided only where its "
        "margin exceeds that error (a value that did not converge: the spread of its last "
        "three steps or levels); \"n × the error\" says by how much."))
    return text


def local_error(row, shown):
    """A locally resolved measure's error as the report writes it (``shown``: the error as a
    quantity)."""
    finest = row.get("finest_step_s")
    where = f"slips resolved down to {1e3 * finest:g} ms" if finest else "no window"
    if row["error"] is None:
        return (f"not estimated by the local route ({where}; a force at rest, or a peak "
                "between windows)")
    if not math.isfinite(row["error"]):  # a window's branch its twins found unsettled
        return f"unknown: a window's branch depends on what it cannot bound ({where})"
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
                    "tried); local: its events' windows resolved at halved steps. A b run's row "
                    "has the prefix it takes over from its a run (run once), so the rows sum to "
                    f"more than the job's CPU: {refinement.get('job_cpu_s', math.nan):.0f} s "
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
