"""A window's levels (``sim.resolve``): the state a window starts from (``Checkpoint``), what a
level found (``Outcome``: each selected pair's slips and sticks, where it rests, its reserve at
full creep, the extremes of the watched channels), and whether the last three levels resolve
the window (``judge``)."""

import dataclasses

import numpy as np

from drake_car.law.friction.events import BREAK_AWAY, SATURATION, STICK
from drake_car.sim.convergence import NOISE, classify
from drake_car.sim.simulation import logged_history
from drake_car.sim.transfer import set_state

EPS = 1e-9  # times within this (s) are one (a window's, a level's, a chunk's)
# A pair at full creep that did not break away: its reserve (the capacity its force left
# unused, the smallest while at full creep) is settled when a halving moves it by at most
# this fraction of itself: a factor of ten between the reserve and what a halving changes it
# by (b_3's pair at 7.87 s kept 9.5e-4, 6.7e-4, 5.0e-4 of its capacity at 1, 0.5, 0.25 ms and
# broke away at 0.125 ms).
SETTLED = 0.1
# The logged channels whose extremes in a window each level records (``extrema``): the rods'
# positions and rotations in their cylinders, and each pair's μ1.
WATCHED = ("d_left_m", "d_right_m", "rot_left_rad", "rot_right_rad")


@dataclasses.dataclass
class Checkpoint:
    time_s: float
    values: object  # sim.transfer.StateValues
    monitor: tuple  # sim.monitor.Monitor.snapshot()
    event_count: int  # how many of the runner's events are at or before it


@dataclasses.dataclass
class Outcome:
    """What one level of a window found: per selected pair the break-aways and sticks, the
    position at the end, the margin to breaking away; the level's events, history, end state
    and cost."""
    level: int
    step_s: float
    end_s: float
    counts: dict
    positions: dict
    margins: dict
    events: list
    times: dict = dataclasses.field(default_factory=dict)
    extrema: dict = dataclasses.field(default_factory=dict)
    history: dict = None
    end_state: object = None
    monitor: tuple = None
    steps: int = 0
    cpu_s: float = 0.0


def summarise(runner, outcome, selected):
    """``outcome`` filled from ``runner`` at a level's end: per selected pair its break-aways
    and sticks, their times, its position and its reserve at full creep."""
    friction = runner.built.friction
    context = friction.GetMyContextFromRoot(runner.root)
    q = runner.built.plant.GetPositions(runner.built.plant.GetMyContextFromRoot(runner.root))
    peaks, phase = friction.peaks(context)[1], friction.phases(context)
    positions = q[friction.position_indices()]
    outcome.events = list(runner.events)
    for i in selected:
        rows = [row for row, _, _ in runner.events if int(row[1]) == i]
        breaks = sum(row[2] == BREAK_AWAY for row in rows)
        sticks = sum(row[2] == STICK for row in rows)
        outcome.counts[i] = (int(breaks), int(sticks))
        outcome.times[i] = [float(row[0]) for row in rows if row[2] != SATURATION]
        outcome.positions[i] = float(positions[i])
        # How close the phase the pair is static in at the end came to breaking away:
        # its smallest reserve at full creep (None: it did not reach full creep).
        outcome.margins[i] = (float(peaks[i]) if phase[i] == 0.0 and peaks[i] >= 0
                              else None)


def start_level(runner, checkpoint):
    """``runner`` (a level's) set to ``checkpoint``'s state, its logs and events emptied."""
    set_state(runner.built, runner.simulator, checkpoint.values)
    runner.root = runner.simulator.get_mutable_context()
    velocity_logger = getattr(runner.built, "velocity_logger", None)
    if velocity_logger is not None:
        velocity_logger.FindMutableLog(runner.root).Clear()
    for logger in runner.built.loggers.values():
        logger.FindMutableLog(runner.root).Clear()
    runner.monitor.restore(checkpoint.monitor)
    friction = runner.built.friction
    context = friction.GetMyMutableContextFromRoot(runner.root)
    friction.reset_peaks(context)
    runner.events, runner.event_count = [], friction.event_count(context)


def quiet(runner, selected, dmax, hold_s):
    """Whether every ``selected`` pair of ``runner`` is static, short of its full creep
    (``dmax``: pair -> Δmax), and without an event for ``hold_s``."""
    friction = runner.built.friction
    context = friction.GetMyContextFromRoot(runner.root)
    phase, creep = friction.phases(context), friction.creeps(context)
    now = runner.root.get_time()
    for i in selected:
        if phase[i] != 0.0 or abs(creep[i]) >= dmax[i] * (1 - EPS):
            return False
    return not any(int(row[1]) in selected and row[0] > now - hold_s
                   for row, _, _ in runner.events)


def settled(before, after):
    """Whether a pair's reserve at full creep moved from ``before`` to ``after`` (each None
    where the pair did not reach full creep) by at most ``SETTLED`` of itself: both None, or a
    positive ``after`` that ``before`` lies within ``SETTLED`` of."""
    if (before is None) != (after is None):
        return False
    return after is None or (after > 0 and abs(before - after) <= SETTLED * after)


def one_branch(a, b, i):
    """Whether Outcomes ``a`` and ``b`` took one branch for pair ``i``: the same slips and
    sticks, and both or neither reached full creep in the phase they end static in (a reserve
    in ``Outcome.margins``, or None)."""
    return a.counts[i] == b.counts[i] and (a.margins[i] is None) == (b.margins[i] is None)


def same_branch(level, twin, i, gain=1.0):
    """Whether ``twin`` (an Outcome: ``level`` run again from a perturbed start) took pair
    ``i``'s branch: the same slips and sticks, and its reserve at full creep settled against
    the perturbation (its move times ``gain``: what the perturbation stands for, at first
    order). A window whose branch a twin changes depends on an error the twin stands for: a
    rest position near it is no measure of that error (``sim.twins``)."""
    if not one_branch(level, twin, i):
        return False
    a, b = twin.margins[i], level.margins[i]
    if a == b:  # neither reached full creep, or the twin moved nothing (a reserve 0 too)
        return True
    return settled(b + gain * (a - b), b)


def unsettled(outcomes, i):
    """Whether a window that did not resolve ends with pair ``i`` undecided by its last
    levels with the same slips and sticks: a reserve at full creep that is not settled (gone,
    still moving, or reached at one level and not at the next). Its rest position's span then
    says nothing of the other branch (``sim.resolve``); where their slips and sticks differ,
    the span covers both branches."""
    last = outcomes[-3:]
    if len({o.counts[i] for o in last}) != 1:
        return False  # the span covers both branches
    return len(last) > 1 and not settled(last[-2].margins[i], last[-1].margins[i])


def agreement_band(tolerance, default):
    """How closely a window's last three levels' rest positions may agree without shrinking
    (``sim.convergence``'s quiet clause): a tenth of the ``tolerance``, but no more than a tenth
    of the ``default`` one. A looser tolerance loosens the error a rest position may carry, not
    what counts as agreeing: a_2 at 2e-4 m rests at 6.4769 / 6.4736 / 6.4791 mm at 1 / 0.5 /
    0.25 ms (3.3 and 5.5 µm apart, within a tenth of 2e-4 m, not of the default 2e-5 m) and at
    5.971-5.979 mm from 0.125 ms on, one stop fewer."""
    return NOISE * min(tolerance, default)


def judge(outcomes, selected, tolerance, band=None):
    """Whether the last three levels of a window resolve it (``sim.resolve``): {pair: the
    error of its rest position}, or None; ``selected``: the pairs judged, ``tolerance``: pair ->
    the tolerance of its rest position, ``band``: pair -> its ``agreement_band`` (None: a tenth
    of the tolerance)."""
    if len(outcomes) < 3:
        return None
    last = outcomes[-3:]
    errors = {}
    for i in selected:
        if len({o.counts[i] for o in last}) != 1:
            return None
        if len({o.margins[i] is None for o in last}) != 1:
            return None
        if not settled(last[-2].margins[i], last[-1].margins[i]):
            return None
        found = classify([o.positions[i] for o in last], tolerance[i],
                         noise=None if band is None else band[i])
        if not found["converged"]:
            return None
        errors[i] = found["error"]
    return errors

def extrema(runner, start_s):
    """{channel: [min, max]} of the ``WATCHED`` channels and each pair's μ1 that ``runner``
    logged after ``start_s`` (its window)."""
    history = logged_history(runner.built, runner.root)
    keep = history["t"] > start_s + EPS
    names = [c for c in history if c in WATCHED
             or (c.startswith("friction_") and c.endswith("_mu1"))]
    return {c: [float(np.min(history[c][keep])), float(np.max(history[c][keep]))]
            for c in names if np.any(keep)}


def spliced_history(history, spliced):
    """``history`` (the runner's loggers) with each window's samples replaced by its
    resolving level's."""
    if not spliced:
        return history
    t = history["t"]
    keep = np.ones(t.size, dtype=bool)
    for start, end, _ in spliced:
        keep &= ~((t > start + EPS) & (t <= end + EPS))
    parts = [{k: v[keep] for k, v in history.items()}] + [h for _, _, h in spliced]
    times = np.concatenate([p["t"] for p in parts])
    order = np.argsort(times, kind="stable")
    return {k: np.concatenate([p[k] for p in parts])[order] for k in history}


def window_record(names, checkpoint, chosen, trigger, outcomes, *, resolved, errors, inherited,
                  gap, merged, cpu_s, solver=None, solver_extrema=None, solver_cost=None,
                  branch_changed=()):
    """A window's record (JSON-ready; ``sim.resolve``): ``names`` the friction's pair names,
    ``chosen`` the level it hands back, the errors per pair index."""
    def by_name(values):
        return {names[i]: v for i, v in values.items()}
    return {
        "start_s": checkpoint.time_s, "end_s": chosen.end_s,
        "trigger": {"time_s": float(trigger[0]), "pair": names[int(trigger[1])],
                    "kind": "saturation" if trigger[2] == SATURATION else "break_away"},
        "resolved": resolved, "step_s": chosen.step_s,
        "position_errors": by_name(errors), "inherited_errors": by_name(inherited),
        "gap_errors": by_name(gap), "merged": merged,
        # The pairs whose branch the inherited or the gap's twin changed (their error unknown:
        # infinite in memory, null in run.json; ``sim.twins``).
        "branch_changed": [names[i] for i in branch_changed],
        # The solver axis (``sim.twins``): the whole run's solver error at the window's end,
        # not part of position_errors.
        "solver_errors": by_name(solver or {}), "solver_extrema": solver_extrema or {},
        "solver_twin": solver_cost,  # its steps and CPU (None: no twin)
        "levels": [{"step_s": o.step_s, "steps": o.steps, "cpu_s": o.cpu_s,
                    "counts": {names[i]: list(c) for i, c in o.counts.items()},
                    "times": by_name(o.times), "positions": by_name(o.positions),
                    "margins": by_name(o.margins), "extrema": o.extrema}
                   for o in outcomes],
        "cpu_s": cpu_s}


def span(values):
    """max - min of ``values``."""
    return max(values) - min(values)


def record(settings, windows):
    """What a run's resolution did and cost (JSON-ready): its ``windows``' records."""
    # A rest position carries every window's step error before it (their sum) and the solver
    # error of the last (each the whole run's: the largest).
    errors, solver = {}, {}
    for w in windows:
        for pair, error in w["position_errors"].items():
            errors[pair] = errors.get(pair, 0.0) + error
        for pair, error in w.get("solver_errors", {}).items():  # each the run's up to there
            solver[pair] = max(solver.get(pair, 0.0), error)
    return {"settings": dataclasses.asdict(settings), "windows": windows,
            "window_count": len(windows),
            "resolved": sum(w["resolved"] for w in windows),
            "finest_step_s": min((w["step_s"] for w in windows), default=None),
            "position_errors": errors, "solver_errors": solver,
            "window_steps": sum(sum(lv["steps"] for lv in w["levels"]) + w["merged"]["steps"]
                                for w in windows),
            "cpu_s": sum(w["cpu_s"] for w in windows),
            # of it, the solver twins'
            "solver_cpu_s": sum((w.get("solver_twin") or {}).get("cpu_s", 0.0)
                                + w["merged"].get("solver_cpu_s", 0.0) for w in windows)}
