"""Accuracy on demand: runs refined by halving their time step until each outcome they decide
with has converged within its tolerance, on the sweep runner (all the runs of a halving in one
sweep, in parallel).

Generic: the runs are scenes, the outcomes any numbers a caller computes from the runs made at
one step (``outcomes_of``), keyed (subject, outcome): a subject is a run's name, or names joined
by "|" for an outcome of several runs (it is computed only where all of them ran at that step).

Convergence (``classify``, ``sim.convergence``: the rule the local route's windows use too):
on the values at the last three steps, the error of the finest is max(d2, 2^-p · d1), and it
has converged when that is within the tolerance and the differences shrink at first order (or
are below a tenth of the tolerance, or within the solver's error); otherwise its error is the
span of the last three, and the values at every step are kept.

The solver axis (``solver_twin``): SAP's Newton iterations stop at a relative tolerance εr
(1e-6) of the system's momentum that no step removes (``systems.sap_ballast``). Once the steps
are done, a twin of each run at εr loosened twice (``loosened``), at the finest step each of its
outcomes reached, in one more sweep, gives each outcome's solver error there to first order in
εr: |x(2 εr) - x(εr)|. It is the floor below which the step's differences need not shrink: an
outcome whose last two differences are within it has converged as far as the step can take it
(``classify``'s floor), and its budget is its step error plus its solver error; ``limited_by``
names the larger. Measured where the value is reported: on b_3's claim-2 value the
twin moved it by 0.3, 8.2 and 0.2 µm at 1, 0.5 and 0.25 ms, so a coarser step's would not do.

The loop (``refine``): the first round runs every scene at h, h/2 and h/4 (one sweep); each
further round halves the step of the runs an unconverged outcome needs, until every outcome
has converged, the next step would be finer than ``finest_step_s``, or ``budget_s`` of wall
time is spent. Each round's wall time and each run's simulation wall time are recorded.
Refining starts each run from its start, not from a coarser run's saved state (branching
within one step is the sweep runner's: ``sim.branch``): a state saved at another step would
carry that step's error into the finer run.
"""

import dataclasses
import math
import time

from drake_car.law.checks import ParameterError
from drake_car.sim.convergence import classify
from drake_car.systems.sap_ballast import MAX_FACTOR


def halved(scene, halvings=1):
    """``scene`` with its plant's time step divided by 2**halvings (the rest as it is)."""
    from drake_car.scene.scene import at_time_step
    return at_time_step(scene, scene.plant.time_step / 2 ** halvings)




def check_twin(scene, factor=2.0):
    """Refuses (``ParameterError``) a scene whose solver twin, at ``factor`` times its SAP
    tolerance factor, would run beyond the ballast's ``MAX_FACTOR``."""
    value = scene.simulator.sap_tolerance_factor
    if value * factor > MAX_FACTOR:
        raise ParameterError("simulator.sap_tolerance_factor", value,
                             f"must be <= {MAX_FACTOR / factor:g} for the error budget's "
                             f"solver twin (it runs at {factor:g} times it; the SAP ballast is "
                             f"sized for {MAX_FACTOR:g}), or leave the solver axis out")


def loosened(scene, factor=2.0):
    """``scene`` with SAP's relative tolerance loosened by ``factor`` (the solver axis' twin;
    ``scene.simulator.Simulator.sap_tolerance_factor``); refused beyond the ballast's range."""
    check_twin(scene, factor)
    simulator = dataclasses.replace(
        scene.simulator, sap_tolerance_factor=scene.simulator.sap_tolerance_factor * factor)
    return dataclasses.replace(scene, simulator=simulator)


@dataclasses.dataclass
class Refined:
    """What ``refine`` found. ``outcomes``: (subject, outcome) -> {"unit", "tolerance",
    "steps_s" and "values" (at each step tried), "converged", "value", "error",
    "observed_order", "step_s" (the finest tried), "solver_error" (None without a solver
    twin), "limited_by" ("step" or "solver")}; ``runs``: level -> name -> Run (level k:
    the scene's step / 2**k); ``steps_s``: name -> the steps it ran at; ``needed_step_s``:
    name -> the finest step it ran at (None if a budget stopped it unconverged there: see
    ``converged_runs``); ``rounds``: [{"step_s": steps, "runs": count, "wall_s"}];
    ``wall_s``: the whole refinement's wall time; ``stopped``: why it stopped; ``failed``: the
    runs whose simulation failed at some step (``simulate`` left them out): not refined
    further, their outcomes classified on the steps they ran at."""
    outcomes: dict
    runs: dict
    steps_s: dict
    rounds: list
    wall_s: float
    stopped: str
    failed: list = dataclasses.field(default_factory=list)

    def run_wall_s(self, name):
        """The simulation wall time of run ``name`` at every step it ran at (s)."""
        return sum(level[name].wall_s for level in self.runs.values() if name in level)

    def finest_step_s(self):
        return min(min(steps) for steps in self.steps_s.values())


def subjects_runs(subject):
    return subject.split("|")


def refine(scenes: dict, outcomes_of, tolerances: dict, simulate, *, order=1,
           finest_step_s=None, budget_s=None, drives=None, first_extra=None, halve=halved,
           solver_twin=None):
    """Refines ``scenes`` (name -> Scene) until the outcomes converge (see the module).

    ``outcomes_of(runs)``: runs (name -> Run, all at one halving) -> {(subject, outcome):
    (value, unit)} for the subjects whose runs are all there. ``tolerances``: outcome ->
    absolute tolerance (in its unit). ``simulate(scenes)``: name -> Run for name -> Scene (e.g.
    ``sweep.runner.run_scenes``; called once per round); a name it leaves out failed. ``drives``: the outcomes whose
    convergence is refined for (default: every outcome with a tolerance); the others are
    classified on the steps their runs ran at. ``first_extra``: scenes run in the first round's
    sweep too, not refined (returned as level "extra"). ``halve(scene, k)``: the scene at
    its step / 2**k (default ``halved``). ``solver_twin(scene)``: the scene with SAP's
    tolerance loosened (``loosened``), run at each outcome's finest step after the loop (runs
    level "solver k"): the solver axis (see the module); None: no solver axis."""
    began = time.perf_counter()
    drives = set(tolerances) if drives is None else set(drives)
    runs, steps, rounds, values, failed = {}, {n: [] for n in scenes}, [], {}, set()
    todo = {0: list(scenes), 1: list(scenes), 2: list(scenes)}
    stopped = "every outcome converged"
    while True:
        batch = {}
        for level, names in todo.items():
            for name in names:
                batch[_key(name, level)] = halve(scenes[name], level) if level else scenes[name]
        extra = dict(first_extra or {}) if not rounds else {}
        round_began = time.perf_counter()
        done = simulate(batch | extra)
        rounds.append({"step_s": sorted({s.plant.time_step for s in batch.values()}),
                       "runs": len(batch), "wall_s": time.perf_counter() - round_began})
        if extra:
            runs["extra"] = {n: done[n] for n in extra}
        for level, names in todo.items():
            lost = [n for n in names if _key(n, level) not in done]
            failed.update(lost)  # a run that failed is refined no further
            names = [n for n in names if n not in lost]
            runs.setdefault(level, {}).update({n: done[_key(n, level)] for n in names})
            for name in names:
                steps[name].append(batch[_key(name, level)].plant.time_step)
            for key, (value, unit) in outcomes_of(runs[level]).items():
                values.setdefault(key, {"unit": unit, "by_level": {}})["by_level"][level] = value
        found = _classified(values, tolerances, order, scenes)
        open_ = {k for k, o in found.items() if k[1] in drives and not o["converged"]
                 and not failed.intersection(subjects_runs(k[0]))}
        if not open_:
            if failed:
                stopped = (f"every outcome converged but those of {len(failed)} run(s) that "
                           "failed")
            break
        need = sorted({n for subject, _ in open_ for n in subjects_runs(subject)})
        level = max(len(steps[n]) for n in need)
        step = min(scenes[n].plant.time_step / 2 ** level for n in need)
        if finest_step_s is not None and step < finest_step_s * (1 - 1e-9):
            stopped = f"the next step ({step:g} s) would be finer than the finest allowed"
            break
        if budget_s is not None and time.perf_counter() - began >= budget_s:
            stopped = f"the wall-time budget ({budget_s:g} s) is spent"
            break
        todo = {}
        for name in need:  # each needed run one halving further than it went
            todo.setdefault(len(steps[name]), []).append(name)
        # A subject's runs must all reach the new level, or its outcome is not computed there.
        for subject, _ in open_:
            names = subjects_runs(subject)
            top = max(len(steps[n]) for n in names)
            for n in names:
                for lv in range(len(steps[n]), top + 1):
                    if n not in todo.get(lv, []):
                        todo.setdefault(lv, []).append(n)
    solver = None
    if solver_twin is not None:
        solver = _solver_axis(runs, values, outcomes_of, rounds, failed, scenes, halve,
                              solver_twin, simulate)
    return Refined(_classified(values, tolerances, order, scenes, solver), runs, steps, rounds,
                   time.perf_counter() - began, stopped, sorted(failed))


def _solver_axis(runs, values, outcomes_of, rounds, failed, scenes, halve, twin, simulate):
    """The solver twins, one sweep (a round of its own): each run at each level where one of
    its outcomes ends, with SAP's tolerance loosened (``twin``); returns (subject, outcome) ->
    |x(twin) - x| at that level (a twin that failed gives none)."""
    finest = {key: max(v["by_level"]) for key, v in values.items()}
    wanted = {(name, level) for (subject, _), level in finest.items()
              for name in subjects_runs(subject) if name not in failed}
    batch = {f"{_key(n, lv)} (solver twin)": twin(halve(scenes[n], lv) if lv else scenes[n])
             for n, lv in sorted(wanted)}
    began = time.perf_counter()
    done = simulate(batch)
    rounds.append({"step_s": sorted({s.plant.time_step for s in batch.values()}),
                   "runs": len(batch), "wall_s": time.perf_counter() - began,
                   "solver_twins": True})
    for n, lv in wanted:
        if f"{_key(n, lv)} (solver twin)" in done:
            runs.setdefault(f"solver {lv}", {})[n] = done[f"{_key(n, lv)} (solver twin)"]
    solver = {}
    for level in sorted(set(finest.values())):
        for key, (value, _) in outcomes_of(runs.get(f"solver {level}", {})).items():
            if finest.get(key) == level:
                solver[key] = abs(value - values[key]["by_level"][level])
    return solver


def _key(name, level):
    return name if level == 0 else f"{name} at dt/{2 ** level}"


def _classified(values, tolerances, order, scenes, solver=None):
    """Outcome rows (``Refined.outcomes``); ``solver``: (subject, outcome) -> solver error, or
    None without a solver axis."""
    out = {}
    for (subject, outcome), v in values.items():
        levels = sorted(v["by_level"])
        series = [v["by_level"][lv] for lv in levels]
        base = scenes[subjects_runs(subject)[0]].plant.time_step
        tolerance = tolerances.get(outcome)
        floor = None if solver is None else solver.get((subject, outcome))
        found = classify(series, math.inf if tolerance is None else tolerance, order,
                         floor or 0.0)
        out[(subject, outcome)] = {
            "unit": v["unit"], "tolerance": tolerance, "steps_s": [base / 2 ** lv for lv in levels],
            "values": series, "step_s": base / 2 ** levels[-1], **found, "solver_error": floor,
            "limited_by": "solver" if floor is not None and floor > found["error"] else "step"}
        if tolerance is None:
            out[(subject, outcome)]["converged"] = None  # no tolerance: not judged
    return out
