"""The twins of a resolved window (``sim.resolve``): the re-runs that measure what its levels
alone do not: what it inherits from the last window (``_inherited``), the gap before it, run at
the run's step (``_gap``), and SAP's tolerance (``_solver``, the solver axis). A mixin of
``sim.resolve.Resolver``, whose state (levels, checkpoints, the last window's end) they use."""

import math

from drake_car.sim.transfer import state_values
from drake_car.sim.window import (
    EPS, Checkpoint, Outcome, extrema, one_branch, same_branch, start_level)


class Twins:
    """The twins' methods of a ``sim.resolve.Resolver`` (see the module)."""

    def _inherited(self, outcomes, checkpoint, end_s):
        """{pair: the error this window inherits from the last one}: the window's start state
        is the last window's finest level's end state, whose own error the next coarser level's
        end state stands for (first order: their difference); the window's level 0 is run
        again from that one, from the last window's end, and each pair's rest position moves
        by what the inherited error does to it. Empty for the run's first window (its state
        comes from the run's own step, every strut static since the start)."""
        if self.alternative is None:
            return {}
        moved, twin = self._twin(outcomes[0], self.alternative, end_s, since_s=checkpoint.time_s)
        return self._branches(moved, outcomes[0], twin, outcomes[-1], gain=1.0)

    def _gap(self, outcomes, checkpoint, end_s):
        """{pair: the error of the gap before this window}: the run went from the last window's
        end (or its first static moment) to this window's start at its own step; the gap and
        the window are run again at level 1 (half the step) from there, and each pair's rest
        position's move against the window's level 1 is the gap's step error (infinite where
        the twin changed a branch: ``sim.resolve`` then runs the window from the gap's start).
        Empty where the window starts where the last one ended, or has fewer than three
        levels."""
        start = self.after_last
        if (start is None or checkpoint.time_s <= start.time_s + EPS
                or len(outcomes) < 3):
            return {}
        # The gap ran at h, the twin at h/2: at first order the gap's error at h is twice
        # their difference.
        moved, twin = self._twin(outcomes[1], start, end_s, since_s=checkpoint.time_s)
        return self._branches({i: 2.0 * e for i, e in moved.items()}, outcomes[1], twin,
                              outcomes[-1], gain=2.0)

    def _branches(self, moved, level, twin, chosen, gain):
        """``moved`` with an infinite error for each pair whose branch ``twin`` changed
        (``sim.window.same_branch``: its slips, or its reserve at full creep beyond
        ``SETTLED``): the window then depends on the error the twin stands for by more than a
        rest position's move shows (a_3 with ``position_tolerance_m`` 2e-4: its 7.81 s window
        kept a reserve of 3.9e-4, 3.7e-4, 3.8e-4 at 1, 0.5 and 0.25 ms from the 7.10 s window's
        end and did not break away, where the run resolved as one window from 7.10 s does, 3.5
        mm apart). Only where ``level`` (the twin's) took the branch of ``chosen`` (the level
        the window hands back): a coarser level on another branch says nothing of how the
        chosen one's depends on its start (a_3's lane-change window slips and sticks otherwise
        at 1 ms than at 0.0625 ms, where it resolves: its 1 ms twin's branch is not the run's).
        The pairs are kept in ``self.branch_pairs`` for the window's record."""
        for i in self.selected:
            if not one_branch(chosen, level, i):
                continue  # the twin's level is not on the chosen branch
            if not same_branch(level, twin, i, gain):
                moved[i] = math.inf
                self.branch_pairs.add(i)
        return moved

    def _solver(self, chosen, checkpoint, end_s):
        """The solver axis (with ``solver_twin``): the run again with SAP's tolerance loosened
        twice (``systems.sap_ballast``) along the run's own windows, from where the last
        window's twin ended (before the first window: the run's first static moment), the gap
        at the run's step and this window at its resolving level, so that it carries what the
        solver did before the window as the global route's twin of a whole run does: ({pair:
        how far its rest position at the window's end lies from the run's}, {channel: the
        twin's extremes in the window}, the twin's steps and CPU, also counted to
        ``chosen``)."""
        if not self.settings.solver_twin:
            return {}, {}, None
        steps, cpu_s = chosen.steps, chosen.cpu_s
        start = self.solver_after if self.solver_after is not None else self.after_last
        if start.time_s < checkpoint.time_s - EPS:  # the gap, at the run's step
            runner = self._solver_level(0)
            start_level(runner, start)
            gap = Outcome(0, self.step_s, start.time_s, {}, {}, {}, [])
            self._advance(runner, gap, checkpoint.time_s, until_quiet=False,
                          to_s=checkpoint.time_s)
            chosen.steps, chosen.cpu_s = chosen.steps + gap.steps, chosen.cpu_s + gap.cpu_s
            start = Checkpoint(checkpoint.time_s, state_values(runner.built, runner.root),
                               runner.monitor.snapshot(), 0)
        runner = self._solver_level(chosen.level)
        moved = self._twin(chosen, start, end_s, runner)
        self.solver_after = Checkpoint(runner.root.get_time(),
                                       state_values(runner.built, runner.root),
                                       runner.monitor.snapshot(), 0)
        cost = {"steps": chosen.steps - steps, "cpu_s": chosen.cpu_s - cpu_s}
        return moved, extrema(runner, checkpoint.time_s), cost

    def _solver_level(self, level):
        if level not in self.solver_levels:
            self.solver_levels[level] = self._make_level(self.step_s / 2 ** level,
                                                         solver_factor=2.0)
        return self.solver_levels[level]

    def _twin(self, level, start, end_s, runner=None, since_s=None):
        """{pair: how far its rest position at ``level``'s end moves} when ``level`` (an
        outcome) is run again from ``start`` (a Checkpoint) in its own Diagram (``runner``;
        default: its level's); the twin's steps and CPU are counted to it. With ``since_s`` (the
        window's start): (that, the twin's Outcome, its slips and sticks counted from then on,
        as the level's are)."""
        twin = Outcome(level.level, level.step_s, start.time_s, {}, {}, {}, [])
        runner = runner or self._level_runner(level.level)
        start_level(runner, start)
        if since_s is not None and start.time_s < since_s - EPS:
            # Through the gap to the window's start, where the level's slips and reserve were
            # first taken too: the gap's are not the window's.
            self._advance(runner, twin, end_s, until_quiet=False, to_s=since_s)
            friction = runner.built.friction
            friction.reset_peaks(friction.GetMyMutableContextFromRoot(runner.root))
            runner.events = []
        self._advance(runner, twin, end_s, until_quiet=False, to_s=level.end_s)
        level.cpu_s += twin.cpu_s
        level.steps += twin.steps
        moved = {i: abs(twin.positions[i] - level.positions[i]) for i in self.selected}
        return moved if since_s is None else (moved, twin)

