"""The friction rig's slips resolved locally (``run_rig(resolve=...)``, ``sim.resolve``) and its
closed-form cases read on the local and the global route (``study.rig.routes``, issue 32 item
3): windows open at the rig's slips and hand back a finer state, a state moves exactly into a
level of the same step, and the two routes' readings agree within their stated errors.

Tolerances from the model (``study.rig.routes``): positions to the law's Δmax (its pre-sliding
range), the belt's times to Δmax / V; a window's position error maps to a slip start's time
as 2 P / V (a stuck block moves with the belt at V)."""

import numpy as np
import pytest

from conftest import assert_same_state
from drake_car.sim import transfer
from drake_car.sim.rigs.friction import RigRunner, build_rig
from drake_car.study.rig.closed_forms import BELT, BELT_LAW
from drake_car.study.rig.routes import (
    case, compare, global_route, local_route, run, settings)

STEP_S = 1e-3


def test_the_rigs_windows_open_at_its_slips_and_hand_back_a_finer_state():
    """The belt at 1 ms, resolved: every break-away of the block is in a window run at finer
    steps, whose samples and events the run keeps; a level's steps are its window's length over
    its step (counted by time: the rig's monitor has no per-step logger)."""
    law = BELT_LAW
    result = run("belt", "fast", STEP_S, settings(law))
    r = result.resolution
    assert r["window_count"] >= 3, r["window_count"]  # the first stick and three cycles
    events = result.events
    slips = [w for kind, w in zip(events["kind"], events["window"]) if kind == "break_away"]
    assert len(slips) >= 3 and min(slips) >= 0, "every slip of the block in a window"
    assert max(s for s, w in zip(events["step_s"], events["window"]) if w >= 0) < STEP_S
    for w in r["windows"]:
        assert w["trigger"]["kind"] == "break_away" and w["step_s"] < STEP_S
        assert w["start_s"] < w["trigger"]["time_s"] < w["end_s"]
    first = r["windows"][0]["levels"][0]  # no twin ran at the first window's level 0
    window = r["windows"][0]
    assert first["steps"] == round((window["end_s"] - window["start_s"]) / STEP_S), first
    t = result.history["t"]
    inside = (t > window["start_s"]) & (t <= window["end_s"])
    assert np.allclose(np.diff(t[inside]), window["step_s"]), "the window's own samples"
    assert np.all(np.diff(t) > 0)
    assert result.record()["resolution"]["window_count"] == r["window_count"]
    again = run("belt", "fast", STEP_S, settings(law))
    for column, values in result.history.items():
        assert np.array_equal(again.history[column], values), column


def test_a_rig_state_moved_to_a_level_of_the_same_step_continues_bit_for_bit():
    """Mid-stick on the belt (0.3 s), the rig's state moved into another Diagram of the same
    step (a window's level 0) continues exactly as the run that never left."""
    options = case("belt").options(STEP_S, "fast")
    a = RigRunner(build_rig(options, BELT_LAW), end_time_s=0.5)
    a.start()
    a.advance_to(0.3)
    b = RigRunner(build_rig(options, BELT_LAW), end_time_s=0.5)
    transfer.set_state(b.built, b.simulator, transfer.state_values(a.built, a.root))
    b.root = b.simulator.get_mutable_context()
    a.advance_to(0.4)
    b.advance_to(0.4)
    assert_same_state(a, b)


@pytest.mark.parametrize("name", ["oscillator", "belt"])
def test_the_local_and_the_global_route_agree_within_their_errors(name):
    """Each reading (the oscillator's turning points and decay per cycle; the belt's periods,
    slip starts x_1 and lags D) of the local route at 1 ms and of the global route (1 ms
    halved until each has converged to the law's tolerance) lie within the sum of their stated
    errors, both find as many, and the global route's converged."""
    local = local_route(name, "fast", STEP_S)
    reference = global_route(name, "fast", STEP_S)
    rows = compare(local, reference)
    assert rows and not [r for r in rows if r[1] == "count"], rows
    assert all(r[7] for r in rows), [r for r in rows if not r[7]]
    assert all(all(c) for c in reference["converged"].values()), reference["converged"]
    # The errors are the routes' own, not zero (nor unknown: a twin that changed a branch,
    # sim.twins): the local one from its windows.
    assert all(np.all(e > 0) and np.all(np.isfinite(e)) for e in local["errors"].values()), \
        local["errors"]
    if name == "belt":
        # A period's error: each slip start's 2 P / V, P the windows' summed position errors
        # before it, each window's of the order of Δmax (measured: 2-6 Δmax / V over the 4
        # windows); 10 Δmax / V says it is a few windows' creep bands, not a vacuous bound.
        assert np.all(local["errors"]["period_s"]
                      < 10 * BELT_LAW.dmax_translation_m / BELT["belt_speed_mps"])
