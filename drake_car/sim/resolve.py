"""Stick-slip events resolved locally: a run goes at its scene's step and resolves, at halved
steps, only the windows where a friction pair's event is near its threshold
(``scene.simulator.resolve_events``, a ``ResolveEvents``).

Why: a dry strut's lasting state is decided at a few events (DESIGN.md §9-§10), and a step
costs the same at any size; halving the whole run to resolve them pays for every step of it.

What opens a window (``is_trigger``; events from ``law.friction.events``, which the runner reads
after every chunk of the monitor's period), for a selected pair (``pairs``: the struts'
translation pairs by default): a **full creep** it did not break away from within the chunk
(|Δ| reached Δmax: the static friction is fully mobilised, and its fate is decided by the
load's excess over capacity, a fraction 1e-4..1e-3 of it), or a **break-away that crossed the
static band in more than one step** (its velocity change in that step < Δv: a load barely above
capacity, held back by the fast scheme's implicit damping, Kd·dt of added inertia at low
velocity, so whether and when it breaks depends on the step). A break-away thrown through the
band in one step, and a stick, are decided by any step.

Where a window starts (``window_start``): at a saved state (a checkpoint: every chunk start at
which every selected pair is static) ``lead_s`` before the event, and before every slip of a
selected pair that was going on within ``lookback_s`` before it (those slips set the loads the
event is decided by; measured on b_3: a window from the state at 7.75 s, after the other
strut's last slip, keeps one branch at every step down to 0.03 ms; one from 7.2 s, before that
slip, takes the globally converged branch from 0.125 ms), never before the previous window's
end (a resolved state).

How it is resolved (``_resolve``, ``judge``): the window is run from that state at level 0 (the
scene's step), 1, 2, ... (step / 2^k), each level in its own Diagram of the scene at that step
(built once per run, fed by values: ``sim.transfer``), all to one end: the first chunk end after
the event at which every selected pair has been static and short of its full creep for
``hold_s``. A level resolves the window when it agrees with the level before: every selected
pair slipped and stuck as many times and rests at the end within ``position_tolerance_m`` (or
``angle_tolerance_rad``) of it; and a pair that is at full creep at the end kept a settled
reserve (the capacity its force left unused: ``SETTLED``). A window that held a full creep
must agree so over three levels (two halvings): there the outcome is decided by a margin of a
fraction of a percent, and two levels agreed on the wrong branch in both jammed runs (b_3 did
not break away at 1, 0.5 and 0.25 ms and did at 0.125 ms and below; a_3 broke 18 ms earlier
from 0.125 ms on, and rests 0.07 mm elsewhere). Else the next level, down to
``finest_step_s``; a window that does not resolve there takes the finest level and says so.
The run goes on at its step from the resolving level's end state; its history and events in
the window are that level's. A window's error (per pair) is the change of its rest position
under the last halving (first-order's estimate of the finer level's error).

The cost: a window of length W costs W/h·(1 + 2 + ... + 2^k) steps; the run's record
(``Run.resolution``, ``record``) gives every window, its levels, what each found, the steps
and CPU time they took.
"""

import dataclasses
import math
import time

import numpy as np

from drake_car.law.friction.events import BREAK_AWAY, SATURATION, STICK
from drake_car.model.geometry import SIDES
from drake_car.scene.scene import NoVisualization, at_time_step
from drake_car.sim.simulation import logged_history
from drake_car.sim.transfer import set_state, state_values

_EPS = 1e-9
# A pair at full creep that did not break away: its reserve (the capacity its force left
# unused, the smallest while at full creep) is settled when a halving moves it by at most
# this fraction of itself: a factor of ten between the reserve and what a halving changes it
# by (b_3's pair at 7.87 s kept 9.5e-4, 6.7e-4, 5.0e-4 of its capacity at 1, 0.5, 0.25 ms and
# broke away at 0.125 ms).
SETTLED = 0.1


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
    history: dict = None
    end_state: object = None
    monitor: tuple = None
    steps: int = 0
    cpu_s: float = 0.0


class Resolver:
    """The windows of one ``sim.simulate.Runner`` (see the module)."""

    def __init__(self, runner, *, make_runner):
        """``make_runner(scene, branchable=...)``: a runner of another scene (the levels')."""
        self.runner = runner
        self._make_runner = make_runner
        self.settings = runner.scene.simulator.resolve_events
        friction = runner.built.friction
        self.friction = friction
        self.names = friction.pair_names()
        kinds = friction.pair_kinds()
        self.selected = [i for i, name in enumerate(self.names)
                         if name.split("_")[0] in SIDES
                         and (self.settings.pairs == "all" or kinds[i] == "translation")]
        self.tolerance = {i: (self.settings.position_tolerance_m if kinds[i] == "translation"
                              else self.settings.angle_tolerance_rad) for i in self.selected}
        self.dv = friction.threshold_velocities()
        self.dmax = friction.maximum_creeps()
        self.levels = {}  # level -> Runner of the scene at that step (built when first needed)
        self.checkpoints = []
        self.windows = []  # the record of each window
        self.spliced = []  # (start, end, history) of each window's resolving level
        self.floor_s = -math.inf  # no window starts before this (the last window's end)

    # -- called by the runner --------------------------------------------------------------
    def before_chunk(self):
        """A checkpoint where every selected pair is static (windows start at one)."""
        root = self.runner.root
        phase = self.friction.phases(self.friction.GetMyContextFromRoot(root))
        if np.any(phase[self.selected] != 0.0):
            return
        now = root.get_time()
        # A window may start before a slip that was going on ``lookback_s`` before its event:
        # the checkpoints of twice that are kept.
        s = self.settings
        keep = 2 * s.lookback_s + s.lead_s + self.runner.built.monitor_period_s
        self.checkpoints = [c for c in self.checkpoints if c.time_s >= now - keep - _EPS]
        self.checkpoints.append(Checkpoint(now, state_values(self.runner.built, root),
                                           self.runner.monitor.snapshot(),
                                           len(self.runner.events)))

    def after_chunk(self, rows, end_s):
        """Resolves a window if the chunk's events (``rows``) hold a trigger."""
        triggers = [row for k, row in enumerate(rows) if self.is_trigger(row, rows[k + 1:])]
        if triggers:
            self._resolve(triggers[0], end_s)

    def is_trigger(self, row, later=()):
        """Whether event ``row`` opens a window (see the module); ``later``: the chunk's
        events after it (a full creep the pair broke away from within the chunk is judged by
        that break-away)."""
        pair = int(row[1])
        if pair not in self.selected:
            return False
        if row[2] == SATURATION:
            return not any(int(r[1]) == pair and r[2] == BREAK_AWAY for r in later)
        return row[2] == BREAK_AWAY and abs(row[4]) < self.dv[pair]

    # -- a window ----------------------------------------------------------------------------
    def window_start(self, event_s):
        """The checkpoint a window for an event at ``event_s`` starts from (see the module)."""
        s = self.settings
        start = event_s - s.lead_s
        open_since = {}
        for row, _, _ in self.runner.events:
            pair, t = int(row[1]), row[0]
            if pair not in self.selected or t > event_s:
                continue
            if row[2] == BREAK_AWAY:
                open_since[pair] = t
            elif row[2] == STICK and pair in open_since:
                began = open_since.pop(pair)
                if t >= event_s - s.lookback_s:
                    start = min(start, began)
        start = max(min([start] + list(open_since.values())), self.floor_s)
        usable = [c for c in self.checkpoints if c.time_s <= start + _EPS
                  and c.time_s >= self.floor_s - _EPS]
        if usable:
            return usable[-1]
        later = [c for c in self.checkpoints if c.time_s >= self.floor_s - _EPS]
        return later[0] if later else None

    def _resolve(self, trigger, end_s):
        checkpoint = self.window_start(trigger[0])
        if checkpoint is None:  # no static moment since the last window: go on as it is
            return
        began_cpu = time.process_time()
        s = self.settings
        outcomes, level = [], 0
        reach_s = min(trigger[0] + s.hold_s, end_s)  # every level runs past the event
        while True:
            outcomes.append(self._run_level(level, checkpoint, end_s, reach_s))
            self._common_end(outcomes, end_s)
            errors = self.judge(outcomes)
            if errors is not None:
                break
            if self.runner.scene.time_step_s / 2 ** (level + 1) < s.finest_step_s * (1 - _EPS):
                break
            level += 1
        resolved = errors is not None
        if not resolved:  # the change of the rest positions under the last halving
            errors = {i: abs(outcomes[-1].positions[i] - outcomes[-2].positions[i])
                      if len(outcomes) > 1 else math.inf for i in self.selected}
        chosen = outcomes[-1]
        self._hand_back(checkpoint, chosen)
        self.windows.append({
            "start_s": checkpoint.time_s, "end_s": chosen.end_s,
            "trigger": {"time_s": float(trigger[0]), "pair": self.names[int(trigger[1])],
                        "kind": "saturation" if trigger[2] == SATURATION else "break_away"},
            "resolved": resolved, "step_s": chosen.step_s,
            "position_errors": {self.names[i]: e for i, e in errors.items()},
            "levels": [{"step_s": o.step_s, "steps": o.steps, "cpu_s": o.cpu_s,
                        "counts": {self.names[i]: list(c) for i, c in o.counts.items()},
                        "times": {self.names[i]: t for i, t in o.times.items()},
                        "positions": {self.names[i]: p for i, p in o.positions.items()},
                        "margins": {self.names[i]: m for i, m in o.margins.items()}}
                       for o in outcomes],
            "cpu_s": time.process_time() - began_cpu})

    def _level_runner(self, level):
        if level not in self.levels:
            base = self.runner.scene
            scene = dataclasses.replace(
                at_time_step(base, base.time_step_s / 2 ** level), visualization=NoVisualization(),
                simulator=dataclasses.replace(base.simulator, resolve_events=None))
            self.levels[level] = self._make_runner(
                scene, branchable=self.runner.built.case_port is not None)
        return self.levels[level]

    def _run_level(self, level, checkpoint, end_s, reach_s):
        runner = self._level_runner(level)
        set_state(runner.built, runner.simulator, checkpoint.values)
        runner.root = runner.simulator.get_mutable_context()
        runner.built.velocity_logger.FindMutableLog(runner.root).Clear()
        for logger in runner.built.loggers.values():
            logger.FindMutableLog(runner.root).Clear()
        runner.monitor.restore(checkpoint.monitor)
        friction = runner.built.friction
        context = friction.GetMyMutableContextFromRoot(runner.root)
        friction.reset_peaks(context)
        runner.events, runner.event_count = [], friction.event_count(context)
        outcome = Outcome(level, runner.scene.time_step_s, checkpoint.time_s, {}, {}, {}, [])
        self._advance(runner, outcome, end_s, until_quiet=True, to_s=reach_s)
        return outcome

    def _advance(self, runner, outcome, end_s, until_quiet, to_s=None):
        """Runs ``runner`` chunk by chunk until it is quiet (and at least at ``to_s``), or
        ``end_s``; fills ``outcome``."""
        began, steps0 = time.process_time(), runner.monitor.stats.steps
        period = runner.built.monitor_period_s
        while runner.root.get_time() < end_s - _EPS:
            now = runner.root.get_time()
            if (to_s is None or now >= to_s - _EPS) and now > outcome.end_s + _EPS and (
                    not until_quiet or self._quiet(runner)):
                break
            runner.step_chunk(min((math.floor(now / period + _EPS) + 1) * period, end_s))
        outcome.end_s = runner.root.get_time()
        outcome.steps += runner.monitor.stats.steps - steps0
        outcome.cpu_s += time.process_time() - began
        self._summarise(runner, outcome)

    def _quiet(self, runner):
        """Every selected pair static, short of its full creep, and without an event for
        ``hold_s``."""
        friction = runner.built.friction
        context = friction.GetMyContextFromRoot(runner.root)
        phase, creep = friction.phases(context), friction.creeps(context)
        now = runner.root.get_time()
        for i in self.selected:
            if phase[i] != 0.0 or abs(creep[i]) >= self.dmax[i] * (1 - _EPS):
                return False
        return not any(int(row[1]) in self.selected and row[0] > now - self.settings.hold_s
                       for row, _, _ in runner.events)

    def _common_end(self, outcomes, end_s):
        """All levels run to one end: the latest, where each of them is quiet."""
        while True:
            last = max(o.end_s for o in outcomes)
            behind = [o for o in outcomes if o.end_s < last - _EPS]
            if not behind:
                return
            for o in behind:
                self._advance(self.levels[o.level], o, end_s, until_quiet=True, to_s=last)

    def _summarise(self, runner, outcome):
        friction = runner.built.friction
        context = friction.GetMyContextFromRoot(runner.root)
        q = runner.built.plant.GetPositions(runner.built.plant.GetMyContextFromRoot(runner.root))
        peaks, phase = friction.peaks(context)[1], friction.phases(context)
        positions = q[friction.position_indices()]
        outcome.events = list(runner.events)
        for i in self.selected:
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

    def judge(self, outcomes):
        """Whether the last level resolves the window (see the module): {pair: the error of
        its rest position (its change under the last halving)}, or None."""
        saturated = any(row[2] == SATURATION and int(row[1]) in self.selected
                        for o in outcomes for row, _, _ in o.events)
        agreeing = 3 if saturated else 2
        if len(outcomes) < agreeing:
            return None
        last = outcomes[-agreeing:]
        errors = {}
        for i in self.selected:
            if len({o.counts[i] for o in last}) != 1:
                return None
            for x, y in zip(last, last[1:]):  # each slip and stick within two of x's steps
                if any(abs(p - q) > 2 * x.step_s + _EPS for p, q in zip(x.times[i], y.times[i])):
                    return None
            if len({o.margins[i] is None for o in last}) != 1:
                return None
            a, b = last[-2].margins[i], last[-1].margins[i]
            if b is not None and not (b > 0 and abs(a - b) <= SETTLED * b):
                return None
            changes = [abs(x.positions[i] - y.positions[i]) for x, y in zip(last, last[1:])]
            if max(changes) > self.tolerance[i]:
                return None
            errors[i] = changes[-1]
        return errors

    def _hand_back(self, checkpoint, chosen):
        """The resolving level's end state into the runner, its history and events kept."""
        runner, fine = self.runner, self.levels[chosen.level]
        history = logged_history(fine.built, fine.root)
        keep = history["t"] > checkpoint.time_s + _EPS
        self.spliced.append((checkpoint.time_s, chosen.end_s,
                             {k: v[keep] for k, v in history.items()}))
        set_state(runner.built, runner.simulator, state_values(fine.built, fine.root))
        runner.root = runner.simulator.get_mutable_context()
        runner.built.velocity_logger.FindMutableLog(runner.root).Clear()
        runner.monitor.restore(fine.monitor.snapshot())
        window = len(self.windows)
        runner.events = (runner.events[:checkpoint.event_count]
                         + [(row, step, window) for row, step, _ in chosen.events])
        friction = runner.built.friction
        runner.event_count = friction.event_count(friction.GetMyContextFromRoot(runner.root))
        self.checkpoints = []
        self.floor_s = chosen.end_s

    # -- the run's record ------------------------------------------------------------------
    def spliced_history(self, history):
        """``history`` (the runner's loggers) with each window's samples replaced by its
        resolving level's."""
        if not self.spliced:
            return history
        t = history["t"]
        keep = np.ones(t.size, dtype=bool)
        for start, end, _ in self.spliced:
            keep &= ~((t > start + _EPS) & (t <= end + _EPS))
        parts = [{k: v[keep] for k, v in history.items()}] + [h for _, _, h in self.spliced]
        times = np.concatenate([p["t"] for p in parts])
        order = np.argsort(times, kind="stable")
        return {k: np.concatenate([p[k] for p in parts])[order] for k in history}

    def record(self):
        """What the resolution did and cost (JSON-ready)."""
        standing = self.windows
        errors = {}
        for w in standing:
            for pair, error in w["position_errors"].items():
                errors[pair] = max(errors.get(pair, 0.0), error)
        return {"settings": dataclasses.asdict(self.settings), "windows": self.windows,
                "window_count": len(standing),
                "resolved": sum(w["resolved"] for w in standing),
                "finest_step_s": min((w["step_s"] for w in standing), default=None),
                "position_errors": errors,
                "window_steps": sum(lv["steps"] for w in self.windows for lv in w["levels"]),
                "cpu_s": sum(w["cpu_s"] for w in self.windows)}

    def export(self):
        """What a branched run continues with (``sim.branch``)."""
        return (list(self.checkpoints), [dict(w) for w in self.windows], list(self.spliced),
                self.floor_s)

    def adopt(self, exported):
        checkpoints, windows, spliced, floor = exported
        self.checkpoints, self.windows, self.spliced, self.floor_s = (
            list(checkpoints), [dict(w) for w in windows], list(spliced), floor)
