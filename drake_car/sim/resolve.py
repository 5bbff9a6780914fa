"""Stick-slip events resolved locally: a run goes at its scene's step and resolves, at halved
steps, only the windows around its friction pairs' slips (``scene.simulator.resolve_events``).

Why: a dry strut's lasting state is decided at its slips (DESIGN.md §9-§10), and a step costs
the same at any size: halving the whole run pays for every step of it.

What opens a window (``is_trigger``; events from ``law.friction.events``, which the runner reads
after every chunk of the monitor's period), for a selected pair (``pairs``: the struts'
translation pairs by default), by ``events``:

- "all" (the default): **every break-away**, and every **full creep** it did not break away
  from within the chunk (|Δ| reached Δmax: the static friction is fully mobilised). Every slip
  of a selected pair is then run in a window, so the run's rest positions carry an error from
  its windows throughout: between windows every selected pair is static.
- "near": only the events whose outcome looks step-dependent at the run's step: a full creep,
  and a break-away that crossed the static band in more than one step (a load barely above
  capacity). Cheaper, but blind where the step cannot see the margin: at 1 ms the fast scheme
  throws every strut break-away of the paper's study through the band in one step, while at
  0.25 ms a_2's return break-aways creep through it over 45-50 steps, and that return takes
  another branch from 0.125 ms on (12.22 instead of 11.72 mm).

Where a window starts (``window_start``): at a saved state (a checkpoint: a chunk start at
which every selected pair is static) ``lead_s`` before the event, and before every slip of a
selected pair that was going on within ``lookback_s`` before it (those slips set the loads the
event is decided by), never before the previous window's end (a resolved state; but see
``merged`` below).

How it is resolved (``_resolve``, ``judge``): the window is run from that state at level 0 (the
scene's step), 1, 2, ... (step / 2^k), each level in its own Diagram of the scene at that step
(built once per run, fed by values: ``sim.transfer``), all to one end: the first chunk end after
the event at which every selected pair has been static and short of its full creep for
``hold_s``. The last three levels resolve the window when, for every selected pair, they agree
on how many times it slipped and stuck, each kept a settled reserve where it ends at full
creep (the capacity its force left unused, moving by at most ``SETTLED`` of itself under the
last halving), and its rest position has converged by the rule the global route uses on a
whole run's outcomes (``sim.convergence.classify``, to ``position_tolerance_m`` or
``angle_tolerance_rad``: the differences shrink at first order, or are within
``window.agreement_band``, a tenth of the tolerance and no more than a tenth of the default's). Three levels, not two, and convergence, not mere agreement: two and three levels
agreed on a wrong branch (b_3 from a window started at 7.75 s did not break away at 1, 0.5 and
0.25 ms and did at 0.125 ms and below, its reserve shrinking 9.5e-4, 6.7e-4, 5.0e-4; a_2's
rods after its return rest 6.4769, 6.4736, 6.4791 mm at 1, 0.5, 0.25 ms, then 5.9707 mm at
0.125 ms). Slip times are recorded, not judged: the outcome is where the rods rest. Else the next level, down to ``finest_step_s``; a window that does not
resolve there takes the finest level and says so. The run goes on at its step from the finest
level's end state; its history and events in the window are that level's.

What a window inherits (``_inherited``, ``_gap``): it starts from the last window's finest
level's end state, whose own error (every state, not only the rods') the next coarser level's
end state stands for at first order: the window's level 0 is run again from that one, and how
far each rest position moves is what it inherits. Where that exceeds the tolerance and the last
window ended within ``lookback_s`` before, the two are resolved as one window (``merged``: b_3's
left strut at 7.86 s broke away or not by what a 0.25 ms window before it left, 1.55 mm apart,
until the windows from 7.10 s were resolved as one, down to 0.0625 ms). The gap before the
window went at the run's step: gap and window are run again at level 1 from the gap's start,
and twice the move against the window's level 1 is the gap's error (first order). Both twins
also judge the branch (``sim.twins._branches``): where a twin's level took the branch of the
level the window hands back and the twin changes it (another count of slips, or a reserve at
full creep moved by more than ``SETTLED`` of itself), a rest position's move is no measure of
the error: the pair's error is unknown (infinite, ``branch_changed`` in the record); where
the inheritance twin finds that, the window is merged with the last one as above (a_3 with a
tolerance of 2e-4 m: its right strut kept 3.9e-4, 3.7e-4, 3.8e-4 of its capacity at 7.85 s at
1, 0.5, 0.25 ms from a 0.25 ms window's end and did not break away, 3.5 mm from where the
default's run rests, with a stated error of 37 µm); where the gap's twin does (its reserve move
doubled as its position's), the window is run again from the gap's start (``merged["gaps"]``:
the design study's --quick sobol_0000, its gap 0.39-1.07 s; ``lookback_s`` still bounds a
merge from the window's own start, so a gap taken in costs one window's length more). A window's error (per pair) is its rest position's (the convergence rule's;
the span of its last three levels where it did not converge, unknown where they leave a strut
at full creep with a reserve not settled: ``window.unsettled``) plus both; a run's, their sum
over its windows. Each level records the extremes of the rods' positions and rotations and
of μ1 in the window (``extrema``): a peak's error. The solver axis (``_solver``, with
``solver_twin``): the run again with SAP's tolerance loosened twice along its own windows (each gap at the run's step, each window at its resolving level,
from where the last window's twin ended); how far each rest position at a window's end lies
from the run's is recorded apart (``solver_errors``: the whole run's solver error up to there,
not a window's share).

The cost: a window of length W costs W/h·(1 + 2 + ... + 2^k) steps for its levels, and its
twins: W/h (what it inherits), 2·(G + W)/h (the gap G before it) and G/h + 2^k·W/h (the
solver's); the run's record (``Run.resolution``) gives every window, its levels (each level's
steps and CPU with the twins counted to it: the resolving level's hold the solver twin's, its
gap at the run's step included), what each found, and the solver twin's own steps and CPU.
"""

import math
import time

import numpy as np

from drake_car.law.friction.events import BREAK_AWAY, SATURATION, STICK
from drake_car.sim.window import (
    EPS, Checkpoint, Outcome, agreement_band, extrema, judge, quiet, record, span,
    spliced_history, start_level, summarise, unsettled, window_record)
from drake_car.sim.simulation import logged_history
from drake_car.sim.transfer import set_state, state_values
from drake_car.sim.twins import Twins

class Resolver(Twins):
    """The windows of one ``sim.simulate.Runner`` (see the module); its twins
    (``sim.twins``)."""

    def __init__(self, runner, *, settings, step_s, make_level, selects):
        """``settings``: a ``scene.simulator.ResolveEvents``; ``step_s``: the run's step;
        ``make_level(step_s, solver_factor=1.0)``: a runner of the same simulation at another
        step (its events read after each chunk, as ``runner``'s are: ``events``,
        ``event_count``), SAP's tolerance loosened by ``solver_factor`` (the solver twin);
        ``selects(name)``: whether a friction pair (by name) is resolved (with
        ``settings.pairs``)."""
        self.runner = runner
        self._make_level = make_level
        self.settings = settings
        self.step_s = step_s
        friction = runner.built.friction
        self.friction = friction
        self.names = friction.pair_names()
        kinds = friction.pair_kinds()
        self.selected = [i for i, name in enumerate(self.names) if selects(name)
                         and (self.settings.pairs == "all" or kinds[i] == "translation")]

        def tolerance(s, kind):
            return s.position_tolerance_m if kind == "translation" else s.angle_tolerance_rad

        self.tolerance = {i: tolerance(settings, kinds[i]) for i in self.selected}
        default = type(settings)()  # the default tolerances bound what counts as agreeing
        self.band = {i: agreement_band(self.tolerance[i], tolerance(default, kinds[i]))
                     for i in self.selected}
        self.dv = friction.threshold_velocities()
        self.dmax = friction.maximum_creeps()
        self.levels = {}  # level -> Runner of the scene at that step (built when first needed)
        self.solver_levels = {}  # level -> its Runner with SAP's tolerance loosened twice
        self.checkpoints = []
        self.windows = []  # the record of each window
        self.spliced = []  # (start, end, history) of each window's resolving level
        self.floor_s = -math.inf  # no window starts before this (the last window's end)
        # The last window's next coarser level at its end (``_inherited``), None before one.
        self.alternative = None
        # The state the gap before the next window starts from: the last window's end, or the
        # run's first static moment (``_gap``).
        self.after_last = None
        self.chain = []  # per window: its start checkpoint, the alternative before it, its end
        # Where the last window's solver twin ended (``_solver``), None before one.
        self.solver_after = None
        self.branch_pairs = set()  # the current window's pairs whose branch a twin changed

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
        self.checkpoints = [c for c in self.checkpoints if c.time_s >= now - keep - EPS]
        self.checkpoints.append(Checkpoint(now, state_values(self.runner.built, root),
                                           self.runner.monitor.snapshot(),
                                           len(self.runner.events)))
        if self.after_last is None:  # the first gap starts at the run's first static moment
            self.after_last = self.checkpoints[-1]

    def after_chunk(self, rows, end_s):
        """Resolves a window if the chunk's events (``rows``) hold a trigger."""
        triggers = [row for k, row in enumerate(rows) if self.is_trigger(row, rows[k + 1:])]
        if triggers:
            self._resolve(triggers[0], end_s)

    def is_trigger(self, row, later=()):
        """Whether event ``row`` opens a window (see the module: ``events``); ``later``: the
        chunk's events after it (a full creep the pair broke away from within the chunk is
        judged by that break-away)."""
        pair = int(row[1])
        if pair not in self.selected:
            return False
        if row[2] == SATURATION:
            return not any(int(r[1]) == pair and r[2] == BREAK_AWAY for r in later)
        if row[2] != BREAK_AWAY:
            return False
        return self.settings.events == "all" or abs(row[4]) < self.dv[pair]

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
        usable = [c for c in self.checkpoints if c.time_s <= start + EPS
                  and c.time_s >= self.floor_s - EPS]
        if usable:
            return usable[-1]
        later = [c for c in self.checkpoints if c.time_s >= self.floor_s - EPS]
        return later[0] if later else None

    def _resolve(self, trigger, end_s):
        checkpoint = self.window_start(trigger[0])
        if checkpoint is None:  # no static moment since the last window: go on as it is
            return
        began_cpu = time.process_time()
        s = self.settings
        merged = {"windows": 0, "gaps": 0, "cpu_s": 0.0, "steps": 0, "solver_cpu_s": 0.0}
        own_start_s = checkpoint.time_s  # before a gap is taken in: what lookback_s bounds
        while True:
            outcomes, errors = self._levels(checkpoint, trigger, end_s)
            for o in outcomes:  # before the twins below reuse levels 0 and 1
                o.extrema = extrema(self.levels[o.level], checkpoint.time_s)
            coarser = None  # the next coarser level's end state, for the next window
            if len(outcomes) > 1:
                level = self.levels[outcomes[-2].level]
                coarser = Checkpoint(outcomes[-1].end_s, state_values(level.built, level.root),
                                     level.monitor.snapshot(), 0)
            self.branch_pairs = set()  # pairs whose branch a twin changed (``sim.twins``)
            inherited = self._inherited(outcomes, checkpoint, end_s)
            previous = self.chain[-1] if self.chain else None
            if (previous is not None
                    and any(e > self.tolerance[i] for i, e in inherited.items())
                    and own_start_s - previous["end_s"] <= s.lookback_s + EPS):
                # What this window inherits from the last one exceeds the tolerance: the two
                # are resolved as one window, from the last one's start.
                self.chain.pop()
                gone = self.windows.pop()
                self.spliced.pop()
                merged["windows"] += 1 + gone["merged"]["windows"]
                merged["gaps"] += gone["merged"].get("gaps", 0)
                merged["cpu_s"] += gone["cpu_s"]
                merged["solver_cpu_s"] += ((gone["solver_twin"] or {}).get("cpu_s", 0.0)
                                           + gone["merged"]["solver_cpu_s"])
                merged["steps"] += (sum(lv["steps"] for lv in gone["levels"])
                                    + gone["merged"]["steps"] + sum(o.steps for o in outcomes))
                checkpoint, self.alternative = previous["checkpoint"], previous["alternative"]
                own_start_s = checkpoint.time_s
                self.after_last = previous["after_last"]
                self.solver_after = previous["solver_after"]
                continue
            gap = self._gap(outcomes, checkpoint, end_s)
            if any(math.isinf(e) for e in gap.values()):
                # The gap's twin took another branch: the window depends on the gap's step by
                # more than a rest position shows, so the gap is resolved with it, from the
                # gap's start (the last window's end: every strut static).
                merged["gaps"] += 1
                merged["steps"] += sum(o.steps for o in outcomes)
                checkpoint = self.after_last
                continue
            break
        resolved = errors is not None
        if not resolved:  # the span of the last three levels' rest positions: the error where
            # they do not converge, unknown where they leave a strut undecided (``unsettled``)
            errors = {i: span([o.positions[i] for o in outcomes[-3:]])
                      if len(outcomes) > 1 and not unsettled(outcomes, i) else math.inf
                      for i in self.selected}
        chosen = outcomes[-1]
        self.chain.append({"checkpoint": checkpoint, "alternative": self.alternative,
                           "after_last": self.after_last, "solver_after": self.solver_after,
                           "end_s": chosen.end_s})
        self.alternative = coarser
        for i in errors:
            errors[i] += inherited.get(i, 0.0) + gap.get(i, 0.0)
        self._hand_back(checkpoint, chosen)
        solver, solver_extrema, solver_cost = self._solver(chosen, checkpoint, end_s)
        self.after_last = Checkpoint(chosen.end_s, state_values(self.runner.built,
                                                                 self.runner.root),
                                     self.runner.monitor.snapshot(), len(self.runner.events))
        self.windows.append(window_record(
            self.names, checkpoint, chosen, trigger, outcomes, resolved=resolved, errors=errors,
            inherited=inherited, gap=gap, merged=merged, solver=solver,
            solver_extrema=solver_extrema, solver_cost=solver_cost,
            branch_changed=sorted(self.branch_pairs),
            cpu_s=time.process_time() - began_cpu + merged["cpu_s"]))

    def _levels(self, checkpoint, trigger, end_s):
        """The window from ``checkpoint`` run at level 0, 1, ... until ``judge`` resolves it
        or the finest step: (the levels' outcomes, their errors or None)."""
        s = self.settings
        outcomes, level = [], 0
        reach_s = min(trigger[0] + s.hold_s, end_s)  # every level runs past the event
        while True:
            outcomes.append(self._run_level(level, checkpoint, end_s, reach_s))
            self._common_end(outcomes, end_s)
            errors = judge(outcomes, self.selected, self.tolerance, self.band)
            if errors is not None:
                return outcomes, errors
            if self.step_s / 2 ** (level + 1) < s.finest_step_s * (1 - EPS):
                return outcomes, None
            level += 1

    def _level_runner(self, level):
        if level not in self.levels:
            self.levels[level] = self._make_level(self.step_s / 2 ** level)
        return self.levels[level]

    def _run_level(self, level, checkpoint, end_s, reach_s):
        runner = self._level_runner(level)
        start_level(runner, checkpoint)
        outcome = Outcome(level, self.step_s / 2 ** level, checkpoint.time_s, {}, {}, {}, [])
        self._advance(runner, outcome, end_s, until_quiet=True, to_s=reach_s)
        return outcome

    def _advance(self, runner, outcome, end_s, until_quiet, to_s=None):
        """Runs ``runner`` chunk by chunk until it is quiet (and at least at ``to_s``), or
        ``end_s``; fills ``outcome``."""
        began, steps0 = time.process_time(), runner.monitor.stats.steps
        period = runner.built.monitor_period_s
        while runner.root.get_time() < end_s - EPS:
            now = runner.root.get_time()
            if (to_s is None or now >= to_s - EPS) and now > outcome.end_s + EPS and (
                    not until_quiet
                    or quiet(runner, self.selected, self.dmax, self.settings.hold_s)):
                break
            runner.step_chunk(min((math.floor(now / period + EPS) + 1) * period, end_s))
        outcome.end_s = runner.root.get_time()
        outcome.steps += runner.monitor.stats.steps - steps0
        outcome.cpu_s += time.process_time() - began
        summarise(runner, outcome, self.selected)

    def _common_end(self, outcomes, end_s):
        """All levels run to one end: the latest, where each of them is quiet."""
        while True:
            last = max(o.end_s for o in outcomes)
            behind = [o for o in outcomes if o.end_s < last - EPS]
            if not behind:
                return
            for o in behind:
                self._advance(self.levels[o.level], o, end_s, until_quiet=True, to_s=last)

    def _hand_back(self, checkpoint, chosen):
        """The resolving level's end state into the runner, its history and events kept."""
        runner, fine = self.runner, self.levels[chosen.level]
        history = logged_history(fine.built, fine.root)
        keep = history["t"] > checkpoint.time_s + EPS
        self.spliced.append((checkpoint.time_s, chosen.end_s,
                             {k: v[keep] for k, v in history.items()}))
        set_state(runner.built, runner.simulator, state_values(fine.built, fine.root))
        runner.root = runner.simulator.get_mutable_context()
        velocity_logger = getattr(runner.built, "velocity_logger", None)  # the car's
        if velocity_logger is not None:
            velocity_logger.FindMutableLog(runner.root).Clear()
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
        return spliced_history(history, self.spliced)

    def record(self):
        """What the resolution did and cost (JSON-ready)."""
        return record(self.settings, self.windows)

    def export(self):
        """What a branched run continues with (``sim.branch``)."""
        return (list(self.checkpoints), [dict(w) for w in self.windows], list(self.spliced),
                self.floor_s, self.alternative, self.after_last, list(self.chain),
                self.solver_after)

    def adopt(self, exported):
        (checkpoints, windows, spliced, floor, alternative, after_last, chain,
         self.solver_after) = exported
        self.checkpoints, self.windows, self.spliced, self.floor_s, self.alternative = (
            list(checkpoints), [dict(w) for w in windows], list(spliced), floor, alternative)
        self.after_last, self.chain = after_last, list(chain)
