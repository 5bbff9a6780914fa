"""One runner for every simulation (sim/simulation.py): the car of a scene and both rigs run
through ``Runner``, with its monitor, recording, progress, interrupts and timing."""

import os
import signal
import threading

import numpy as np
import pytest

from conftest import paper_scene
from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.model.parameters import CarParameters
from drake_car.sim.build import build_diagram
from drake_car.sim.monitor import DivergenceError
from drake_car.sim.rigs.friction import RigOptions, build_rig, run_rig
from drake_car.sim.rigs.strut import StrutRigOptions, build_strut_rig, run_strut_rig
from drake_car.sim.simulation import Runner, Simulation

LAW = StrutFrictionParameters(mu_s=0.2, mu_d=0.15)
PROTOCOL = [name for name in dir(Simulation) if not name.startswith("_")] + [
    "name", "diagram", "plant", "loggers", "log_columns", "monitor_period_s", "time_step_s"]


def test_the_car_and_the_rigs_give_the_runner_what_it_needs():
    built = [build_diagram(paper_scene("a_1", "simulator: {end_time_s: 0.1}")),
             build_rig(RigOptions(), LAW),
             build_strut_rig(CarParameters(), StrutRigOptions(), LAW)]
    for simulation in built:
        missing = [name for name in PROTOCOL if not hasattr(simulation, name)]
        assert not missing, (type(simulation).__name__, missing)


def test_a_rig_run_records_how_it_went_and_starts_at_its_initial_state():
    """The friction rig on the runner: its record says what a car's run says (wall and CPU
    time, the steps: the duration over the step), and its first sample is the initial state
    at t = 0 (x0, v0; the hand-rolled loop before it recorded the state after the first step
    there: Simulator.AdvanceTo(0) after Initialize runs the updates due at t = 0)."""
    options = RigOptions(friction=False, x0_m=0.01, v0_mps=0.2, spring_Npm=1000.0)
    run = run_rig(options, LAW, duration_s=0.05)
    record = run.record()
    assert record["steps"] == 50 and record["simulated_s"] == pytest.approx(0.05)
    assert record["wall_s"] > 0 and record["cpu_s"] > 0, record
    h = run.history
    assert (h["t"][0], h["x_m"][0], h["v_mps"][0]) == (0.0, 0.01, 0.2)
    assert h["x_m"][1] != 0.01  # the step moved it
    strut = run_strut_rig(CarParameters(), StrutRigOptions(), LAW, cycles=0.02)
    assert strut.steps == 40 and strut.history["stroke_m"][0] == 0.0


def test_a_diverging_rig_is_stopped_by_the_monitor():
    """A frictionless block pushed by 1 MN (30 kg: 3.3e4 m/s²) passes the monitor's 500 m/s
    within 16 ms: stopped at the next check (every 10 ms), naming the block's joint."""
    with pytest.raises(DivergenceError, match=r"diverged at t = 0\.02\d* s: velocity of joint "
                                              r"'block_joint'"):
        run_rig(RigOptions(friction=False, force_N=1e6), LAW, duration_s=1.0)


def test_an_interrupt_stops_a_rig_between_monitor_chunks():
    """Ctrl-C while a rig steps is raised between the monitor's chunks, as on the car."""
    rig = build_strut_rig(CarParameters(), StrutRigOptions(), LAW)
    runner = Runner(rig, end_time_s=300.0)
    runner.start()
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            runner.advance_to(300.0)
    finally:
        timer.cancel()
    t = runner.root.get_time()
    period = rig.monitor_period_s
    assert 0 < t < 300.0 and abs(t / period - round(t / period)) < 1e-6, t
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    assert runner.wall_s > 0 and np.isfinite(runner.cpu_s)


def test_a_signal_the_process_ignores_does_not_cut_a_run_short():
    """A run whose process ignores SIGINT (started in the background by a shell without job
    control) runs its whole length when one arrives: noted and then raised into nothing, it
    had stopped the run early as if finished (a static equilibrium settled for less than its
    time, then cached)."""
    from drake_car.sim.simulation import deferred_signals
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with deferred_signals() as caught:
            signal.raise_signal(signal.SIGINT)
        assert caught == [], "an ignored signal is not noted"
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)
    with pytest.raises(KeyboardInterrupt):  # not ignored: noted, then raised at the end
        with deferred_signals() as caught:
            signal.raise_signal(signal.SIGINT)
            assert caught == [signal.SIGINT]
