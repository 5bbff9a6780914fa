"""``sim.resolve.Resolver._resolve``'s control flow with its simulations stubbed: what it does
when a twin says a branch changed, independent of whether a real (chaotic) run happens to
produce one (tests/test_resolve_branches.py runs the real case, slow)."""

import math
import types

import pytest

from drake_car.sim import resolve
from drake_car.sim.window import Checkpoint

TOLERANCE_M = 2e-5  # the default position tolerance (scene.ResolveEvents)


class Stub(resolve.Resolver):
    """A Resolver whose levels and twins are scripted: ``gaps`` and ``inherits`` are the
    successive answers of ``_gap`` and ``_inherited``; every call's start is recorded."""

    def __init__(self, gaps, inherits, after_last, chain=()):
        self.settings = types.SimpleNamespace(lookback_s=1.0)
        self.selected, self.tolerance, self.names = [0], {0: TOLERANCE_M}, ["left"]
        level = types.SimpleNamespace(built=None, root=None,
                                      monitor=types.SimpleNamespace(snapshot=tuple))
        self.levels = {0: level, 1: level, 2: level}
        self.alternative, self.solver_after, self.branch_pairs = None, None, set()
        self.after_last = after_last
        self.chain = [dict(c) for c in chain]
        self.windows = [{"merged": {"windows": 0, "gaps": 0, "solver_cpu_s": 0.0, "steps": 0},
                         "cpu_s": 0.0, "levels": [], "solver_twin": None} for _ in chain]
        self.spliced = [None for _ in chain]
        self.runner = types.SimpleNamespace(built=None, root=None, events=[],
                                            monitor=types.SimpleNamespace(snapshot=tuple))
        self.gaps, self.inherits, self.starts, self.start_at = list(gaps), list(inherits), [], None

    def window_start(self, event_s):
        return self.start_at

    def _levels(self, checkpoint, trigger, end_s):
        self.starts.append(checkpoint.time_s)
        outcomes = [types.SimpleNamespace(level=k, end_s=end_s, steps=10, positions={0: 1e-3})
                    for k in range(3)]
        return outcomes, {0: 1e-6}

    def _inherited(self, outcomes, checkpoint, end_s):
        return self.inherits.pop(0)

    def _gap(self, outcomes, checkpoint, end_s):
        return self.gaps.pop(0)

    def _hand_back(self, checkpoint, chosen):
        pass

    def _solver(self, chosen, checkpoint, end_s):
        return {}, {}, {}


@pytest.fixture(autouse=True)
def no_state(monkeypatch):
    """The stubs' states are empty; a window's record is its arguments."""
    monkeypatch.setattr(resolve, "state_values", lambda built, root: None)
    monkeypatch.setattr(resolve, "extrema", lambda level, since_s: {})
    monkeypatch.setattr(resolve, "window_record",
                        lambda names, checkpoint, chosen, trigger, outcomes, **kw:
                        {"start_s": checkpoint.time_s, **kw})


def _checkpoint(t):
    return Checkpoint(t, None, (), 0)


def test_a_gap_whose_twin_changed_a_branch_is_run_again_from_the_gaps_start():
    # The window from 1.07 s; the run went at its step since 0.39 s (the last window's end).
    # The gap's twin took another branch (infinite): the window runs again from 0.39 s, and
    # that window's own gap is then none (it starts where the last one ended).
    stub = Stub(gaps=[{0: math.inf}, {}], inherits=[{}, {}], after_last=_checkpoint(0.39))
    stub.start_at = _checkpoint(1.07)
    stub._resolve((1.2, 0), end_s=3.0)
    assert stub.starts == [1.07, 0.39]
    (window,) = stub.windows
    assert window["start_s"] == 0.39 and window["merged"]["gaps"] == 1
    assert window["merged"]["steps"] == 30  # the three levels from 1.07 s, run and replaced
    assert window["errors"] == {0: pytest.approx(1e-6)}  # finite: the gap is in the window


def test_a_finite_gap_error_is_added_and_the_window_kept():
    stub = Stub(gaps=[{0: 3e-6}], inherits=[{}], after_last=_checkpoint(0.39))
    stub.start_at = _checkpoint(1.07)
    stub._resolve((1.2, 0), end_s=3.0)
    assert stub.starts == [1.07]
    (window,) = stub.windows
    assert window["start_s"] == 1.07 and window["merged"]["gaps"] == 0
    assert window["errors"] == {0: pytest.approx(4e-6)}


@pytest.mark.parametrize("last_end_s, merges", [(0.5, True), (0.05, False)])
def test_a_merge_after_a_gap_restart_is_bounded_from_the_windows_own_start(last_end_s, merges):
    # The window's own start is 1.07 s; the last window ended at ``last_end_s``. The gap
    # (from its end) changed a branch, so the window ran again from there; then what it
    # inherits exceeds the tolerance: the two merge only if the last window ended within
    # lookback_s (1 s) of 1.07 s, the window's own start (not of the gap's start, which would
    # let every restart reach one window further back).
    last = {"checkpoint": _checkpoint(0.2), "alternative": None, "after_last": None,
            "solver_after": None, "end_s": last_end_s}
    stub = Stub(gaps=[{0: math.inf}, {}, {}], inherits=[{}, {0: 10 * TOLERANCE_M}, {}],
                after_last=_checkpoint(last_end_s), chain=[last])
    stub.start_at = _checkpoint(1.07)
    stub._resolve((1.2, 0), end_s=3.0)
    if merges:
        assert stub.starts == [1.07, last_end_s, 0.2]
        assert stub.windows[-1]["merged"]["windows"] == 1 and len(stub.windows) == 1
    else:
        assert stub.starts == [1.07, last_end_s]
        assert len(stub.windows) == 2 and stub.windows[-1]["merged"]["windows"] == 0
