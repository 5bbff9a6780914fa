"""The one runner of every simulation: the car of a scene (``sim.simulate``) and the rigs
(``sim.rigs``) run through ``Runner``, so each gets the same divergence monitor, progress bar,
deferred Ctrl-C/SIGTERM, wall and CPU time, and history from its loggers.

What a runner needs of a built Diagram is ``Simulation`` (a protocol): the Diagram and its
plant, its loggers and their column names, the monitor's checks it can have, its initial state
and the columns its history derives from what was logged. The car's
``sim.car_diagram.CarDiagram`` is one implementation, each rig (``sim.rigs.friction.Rig``,
``sim.rigs.strut.StrutRig``) another.

The run advances in chunks of ``monitor_period_s``; after each chunk the monitor checks the
state (and the car's runner adds its replay frame). The loggers (Drake's VectorLogSink, C++)
record at their own periods; no Python runs per step to record.
"""

import contextlib
import dataclasses
import signal
import sys
import time
import typing

import numpy as np
from pydrake.systems.analysis import Simulator


class Simulation(typing.Protocol):
    """What the runner needs of a built Diagram."""

    name: str  # what the progress bar shows
    diagram: object
    plant: object  # the MultibodyPlant (the monitor's checks)
    loggers: dict  # group -> VectorLogSink
    log_columns: dict  # group -> the logger's column names
    monitor_period_s: float  # how often the monitor checks the state
    time_step_s: float  # the plant's step

    def monitor(self):
        """The divergence monitor (``sim.monitor.Monitor``) with the checks this simulation
        can have."""

    def set_initial_state(self, root_context):
        """Writes the initial state into the root context, before initialization."""

    def history(self, logged: dict) -> dict:
        """The run's columns from what the loggers recorded (``logged_history``)."""


@dataclasses.dataclass
class RunResult:
    """What a run of any simulation made: its columns and how the run went (wall and CPU
    seconds of the simulation loop, its steps and frozen SAP steps, the Diagram as Graphviz
    text)."""

    history: dict
    wall_s: float
    cpu_s: float
    steps: int
    frozen_sap_steps: int | None
    first_frozen_sap_step_s: float | None
    diagram_dot: str
    events: dict | None = None  # the friction's stick-slip events (``sim.slips``), if kept
    resolution: dict | None = None  # what the local resolution did (``sim.resolve``), if any

    def record(self):
        """What a run says about itself (JSON-ready), as a car's run does."""
        simulated = float(self.history["t"][-1]) if len(self.history["t"]) else 0.0
        record = {"wall_s": self.wall_s, "cpu_s": self.cpu_s, "simulated_s": simulated,
                  "real_time_factor": simulated / max(self.wall_s, 1e-9), "steps": self.steps,
                  "frozen_sap_steps": self.frozen_sap_steps,
                  "first_frozen_sap_step_s": self.first_frozen_sap_step_s}
        if self.events is not None:
            record["events"] = self.events
        if self.resolution is not None:
            record["resolution"] = self.resolution
        return record


class Runner:
    """One simulation, advanced in the monitor's chunks: ``start()`` sets the initial state
    and initializes, ``advance_to(t)`` runs (any number of times), ``result()`` returns the
    history and how the run went. ``end_time_s``: where ``run()`` stops and the progress bar
    ends. ``context``: continue a saved context of ``built``'s Diagram (``sim.branch``)
    instead of a new one. ``realtime_rate``: Drake's target real-time rate (0: as fast as it
    can). ``recorder``: an object whose ``frame(root_context)`` runs after each chunk (the
    car's replay)."""

    def __init__(self, built: Simulation, *, end_time_s, progress=False, context=None,
                 realtime_rate=0.0, recorder=None):
        self.built = built
        self.end_time_s = end_time_s
        if context is None:
            self.simulator = Simulator(built.diagram)
        else:
            self.simulator = Simulator(built.diagram, context)
        self.simulator.set_target_realtime_rate(realtime_rate)
        self.root = self.simulator.get_mutable_context()
        self.recorder = recorder
        self.monitor = built.monitor()
        self.progress = progress
        self.wall_s = 0.0
        self.cpu_s = 0.0
        self.start_time_s = self.root.get_time()

    def start(self):
        """The initial state, then Drake's initialization events; a Ctrl-C or SIGTERM meanwhile
        is deferred to their end (``deferred_signals``: Initialize calls the Python systems
        back from C++, where a SystemExit raised by the signal could be lost and the run go on
        to exit 0: seen once in CI's killed-run test)."""
        with deferred_signals():
            self.built.set_initial_state(self.root)
            self.simulator.Initialize()

    def run(self):
        """``start()`` and ``advance_to(end_time_s)``; returns the runner."""
        self.start()
        self.advance_to(self.end_time_s)
        return self

    def advance_to(self, end):
        """Runs to ``end`` in the monitor's chunks; ``before_chunk`` and ``after_chunk`` (no-ops
        here) act between chunks (``sim.slips``: the friction's events, ``sim.resolve``)."""
        period = self.built.monitor_period_s
        now = self.root.get_time()
        bar = progress_bar(self.built.name, self.end_time_s, now) if self.progress else None
        began, cpu_began = time.perf_counter(), time.process_time()
        try:
            with deferred_signals() as caught:
                while True:
                    target = min((np.floor(now / period + 1e-9) + 1) * period, end)
                    self.before_chunk()
                    self.simulator.AdvanceTo(target)
                    if caught:
                        break
                    self.checked()
                    self.after_chunk(end)
                    now = self.root.get_time()
                    if bar is not None:
                        bar.update(now - bar.n)
                    if now >= end - 1e-12:
                        break
        finally:
            self.wall_s += time.perf_counter() - began
            self.cpu_s += time.process_time() - cpu_began
            if bar is not None:
                bar.close()

    def step_chunk(self, target):
        """Advances to ``target`` and checks there (one chunk, without the hooks)."""
        self.simulator.AdvanceTo(target)
        self.checked()

    def checked(self):
        """After a chunk: the monitor's checks, the recorder's frame."""
        self.monitor.check(self.root)
        if self.recorder is not None:
            self.recorder.frame(self.root)

    def before_chunk(self):
        pass

    def after_chunk(self, end):
        pass

    def history(self):
        """The run's columns (the simulation's own, from its loggers)."""
        return self.built.history(logged_history(self.built, self.root))

    def steps(self):
        """The plant's steps so far: counted by the monitor where it counts them (the car by
        its state logger, the friction rig by time), else the simulated time over the step."""
        if self.monitor.counts_steps or self.monitor.counts_by_time:
            return self.monitor.stats.steps
        return int(round((self.root.get_time() - self.start_time_s) / self.built.time_step_s))

    def diagram_dot(self):
        return self.built.diagram.GetGraphvizString(max_depth=1, options={"plant/split": "I/O"})

    def result(self) -> RunResult:
        stats = self.monitor.stats
        counts = self.monitor.counts_steps
        return RunResult(history=self.history(), wall_s=self.wall_s, cpu_s=self.cpu_s,
                         steps=self.steps(),
                         frozen_sap_steps=stats.frozen_steps if counts else None,
                         first_frozen_sap_step_s=stats.first_frozen_time_s,
                         diagram_dot=self.diagram_dot())


@contextlib.contextmanager
def deferred_signals():
    """Ctrl-C and SIGTERM while the simulator steps are noted, not raised: raised inside one of
    the Python systems Drake calls back from C++ (most land in the tyre system's update), a
    KeyboardInterrupt crosses C++ as an exception where it can be lost (a run once finished
    and exited 0 after SIGINT). The runner stops after the chunk it is in; the signal is then
    raised again with the handlers that were there before (KeyboardInterrupt, or
    ``results.signals.terminate_as_exit``'s SystemExit)."""
    caught = []
    # A signal the process ignores stays ignored: noted, it would stop the run early and, its
    # handler restored, be raised into nothing, leaving a run cut short that looks finished
    # (a static equilibrium settled for less than its time, then cached: CI started in the
    # background, SIGINT ignored, once cached one).
    signals = [s for s in (signal.SIGINT, signal.SIGTERM)
               if signal.getsignal(s) is not signal.SIG_IGN]
    try:
        previous = {s: signal.signal(s, lambda signum, frame: caught.append(signum))
                    for s in signals}
    except ValueError:  # not the main thread: leave the signals alone
        yield caught
        return
    try:
        yield caught
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        if caught:
            signal.raise_signal(caught[0])


def progress_bar(name, end, now=0.0):
    from tqdm import tqdm
    return tqdm(total=end, initial=now, desc=name, unit="s sim", file=sys.stderr,
                leave=False, disable=None, mininterval=0.5,
                bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.2f}/{total:.2f} s "
                           "[{elapsed}<{remaining}]")


def logged_history(built, root_context):
    """Columns of every logger of ``built``, with their sample times "t" (no "t" when there is
    no logger). A sample repeated at the same time (a branched run's loggers sample again when
    its simulator starts at the branch time, ``sim.branch``) is kept once."""
    history = {}
    for group, logger in built.loggers.items():
        log = logger.FindLog(root_context)
        times = np.array(log.sample_times())
        keep = np.concatenate([[True], np.diff(times) > 0]) if times.size else times > 0
        if "t" in history and not np.array_equal(history["t"], times[keep]):
            raise RuntimeError(f"logger of {group} sampled at other times than the others")
        history["t"] = times[keep]
        data = log.data()
        for row, name in enumerate(built.log_columns[group]):
            history[name] = np.array(data[row])[keep]
    return history


def state_columns(plant, prefix=""):
    """Names of the plant's state [q; v] entries: ``q_<joint>``, ``v_<joint>`` (an index
    appended for a joint of more than one), for a logger of ``get_state_output_port()``."""
    names = [""] * plant.num_multibody_states()
    nq = plant.num_positions()
    for index in plant.GetJointIndices():
        joint = plant.get_joint(index)
        for kind, start, count, offset in (
                ("q", joint.position_start(), joint.num_positions(), 0),
                ("v", joint.velocity_start(), joint.num_velocities(), nq)):
            for k in range(count):
                suffix = f"_{k}" if count > 1 else ""
                names[offset + start + k] = f"{prefix}{kind}_{joint.name()}{suffix}"
    return names
