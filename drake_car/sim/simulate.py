"""``simulate(scene) -> Run``: the one runner. It builds the scene's Diagram, sets the initial
state the scene asks for, runs under the divergence monitor with an optional progress bar,
and returns the logged history with the scene that ran, the Diagram's picture (Graphviz) and
the replay page when the scene asks for one."""

import contextlib
import dataclasses
import functools
import logging
import math
import signal
import sys
import time

import numpy as np
from pydrake.systems.analysis import Simulator

from drake_car.model.car import loop_closure_error, strut_overlap
from drake_car.model.geometry import SIDES, design_axle_loads_N
from pydrake.common.yaml import yaml_load_typed

from drake_car.scene.load import (
    WALL_PER_STEP_S, dump_scene, dump_scene_file, scene_hash)
from drake_car.scene.scene import MeshcatLive, MeshcatReplay, Scene
from drake_car.sim.build import build_diagram
from drake_car.sim.driver_wiring import manoeuvre_outcome
from drake_car.sim import equilibrium_cache
from drake_car.sim.equilibrium import Equilibrium, equilibrium_from_run, equilibrium_scene
from drake_car.sim.lane_change_calibration import adapted
from drake_car.sim.monitor import Monitor, Road
from drake_car.systems.tyre import WHEELS

log = logging.getLogger(__name__)

# Runs whose estimate exceeds this print it first.
ANNOUNCE_WALL_S = 60.0


@dataclasses.dataclass
class Run:
    """What a run made. ``history``: "t", "phase" and the logged channel groups' columns
    (numpy arrays; "phase" a list of str). ``final``: the state at the end (corner loads,
    ride heights, strut overlaps, loop-closure error, the car's positions). ``diagram_dot``:
    the Diagram as Graphviz text. ``replay_html``: the Meshcat replay page, when asked for."""

    scene: Scene
    history: dict
    wall_s: float
    frozen_sap_steps: int
    first_frozen_sap_step_s: float | None
    steps: int
    final: dict
    diagram_dot: str
    replay_html: str | None = None
    cpu_s: float = math.nan  # CPU seconds of the simulation loop (this process, all threads)

    def __getstate__(self):
        # Drake's configs do not pickle: a Run travels (to and from sweep workers) with its
        # scene as YAML, which loads back to the same scene.
        state = dict(self.__dict__)
        state["scene"] = dump_scene(self.scene)
        return state

    def __setstate__(self, state):
        state = dict(state)
        state["scene"] = yaml_load_typed(schema=Scene, data=state["scene"])
        self.__dict__.update(state)

    @property
    def scene_hash(self):
        return scene_hash(self.scene)

    @property
    def scene_yaml(self):
        return dump_scene(self.scene)

    @property
    def scene_file_text(self):
        """The scene as a scene file (one entry): what ``write_run`` saves as scene.yaml."""
        return dump_scene_file(self.scene)

    def record(self):
        """What a run says about itself (JSON-ready)."""
        return {"scene": self.scene.name, "scene_hash": self.scene_hash,
                "wall_s": self.wall_s, "cpu_s": self.cpu_s,
                "simulated_s": float(self.history["t"][-1]),
                "real_time_factor": float(self.history["t"][-1]) / max(self.wall_s, 1e-9),
                "steps": self.steps, "frozen_sap_steps": self.frozen_sap_steps,
                "first_frozen_sap_step_s": self.first_frozen_sap_step_s,
                "final": {k: v for k, v in self.final.items() if k != "positions"}}


def estimate_wall_s(scene: Scene):
    return scene.end_time_s / scene.time_step_s * WALL_PER_STEP_S


def simulate(scene: Scene, *, progress=False, meshcat=None) -> Run:
    """Runs ``scene``; ``progress`` shows a bar of the simulated time on stderr. A scene with
    ``MeshcatLive`` or ``MeshcatReplay`` visualisation starts a Meshcat server on localhost
    unless ``meshcat`` is given."""
    runner = Runner(scene, progress=progress, meshcat=meshcat)
    runner.start()
    runner.advance_to(runner.scene.end_time_s)
    return runner.finish()


class Runner:
    """One simulation of a scene, advanced in the monitor's chunks: ``start()`` sets the
    initial state and initializes, ``advance_to(t)`` runs (any number of times), ``finish()``
    returns the Run. ``sim.branch`` starts a runner from another runner's saved context."""

    def __init__(self, scene: Scene, *, progress=False, meshcat=None, branchable=False,
                 built=None, context=None):
        """``branchable``: build the Diagram so that other cases can continue its context
        (``sim.branch``); ``built`` and ``context``: continue such a Diagram's saved context
        with this scene's case instead of building anew (its scene as it runs already). A
        scene built anew is run as it adapts to its car (``sim.lane_change_calibration``: a
        launch left out, a lane change's rack), which the Run's scene then holds."""
        if built is None:
            scene = adapted(scene, run=simulate)[0]
        self.scene = scene
        visual = scene.visualization
        shows = isinstance(visual, (MeshcatLive, MeshcatReplay))
        if shows and meshcat is None:
            from drake_car.sim.replay import start_meshcat
            meshcat = start_meshcat()
            if isinstance(visual, MeshcatLive):
                log.info("Meshcat: %s", meshcat.web_url())
        self.built = built or build_diagram(scene, meshcat=meshcat if shows else None,
                                            branchable=branchable)
        if context is None:
            self.simulator = Simulator(self.built.diagram)
        else:
            self.simulator = Simulator(self.built.diagram, context)
        if self.built.case_port is not None:
            self.built.select_case(self.simulator.get_mutable_context(), scene.manoeuvre.case)
        self.simulator.set_target_realtime_rate(
            visual.realtime_rate if isinstance(visual, MeshcatLive) else 0.0)
        self.root = self.simulator.get_mutable_context()
        self.recorder = None
        if isinstance(visual, MeshcatReplay):
            from drake_car.sim.replay import ReplayRecorder
            self.recorder = ReplayRecorder(meshcat, self.built, visual)
        self.monitor = Monitor(self.built.plant, self.built.diagram,
                               state_logger=self.built.velocity_logger,
                               instance=self.built.car.instance, road=Road(
                                   self.built.tyre, scene.car.tyre.radial_stiffness_Npm,
                                   scene.road.flat_up_to_m(), self.built.car.body("chassis"),
                                   scene.simulator.airborne_limit_s,
                                   tuple(self.built.car.wheel_bodies()[w] for w in WHEELS)))
        self.progress = progress
        self.wall_s = 0.0
        self.cpu_s = 0.0

    def start(self):
        """The scene's initial state, then Drake's initialization events."""
        _set_initial_state(self.built, self.root, self.scene)
        estimate = estimate_wall_s(self.scene)
        if self.progress and estimate > ANNOUNCE_WALL_S:
            log.info("%s: %g s at %g s steps, about %.0f min of wall time", self.scene.name,
                     self.scene.end_time_s, self.scene.time_step_s, estimate / 60)
        self.simulator.Initialize()

    def advance_to(self, end):
        period = self.scene.simulator.monitor_period_s
        now = self.root.get_time()
        first = int(np.floor(now / period + 1e-9)) + 1
        last = max(first, int(np.ceil(end / period - 1e-9)))
        bar = _progress_bar(self.scene, self.scene.end_time_s, now) if self.progress else None
        began, cpu_began = time.perf_counter(), time.process_time()
        try:
            with _deferred_signals() as caught:
                for k in range(first, last + 1):
                    target = min(k * period, end)
                    self.simulator.AdvanceTo(target)
                    if caught:
                        break
                    self.monitor.check(self.root)
                    if self.recorder is not None:
                        self.recorder.frame(self.root)
                    if bar is not None:
                        bar.update(target - bar.n)
        finally:
            self.wall_s += time.perf_counter() - began
            self.cpu_s += time.process_time() - cpu_began
            if bar is not None:
                bar.close()

    def finish(self) -> Run:
        built, root, scene = self.built, self.root, self.scene
        history = logged_history(built, root)
        history["phase"] = [scene.manoeuvre.phase(t) for t in history["t"]]
        html = self.recorder.finish() if self.recorder is not None else None
        dot = built.diagram.GetGraphvizString(max_depth=1, options={"plant/split": "I/O"})
        stats = self.monitor.stats
        final = final_state(built, root)
        outcome = manoeuvre_outcome(scene, history, log)  # a path manoeuvre's: done as asked?
        if outcome is not None:
            final["manoeuvre_outcome"] = outcome
        return Run(scene=scene, history=history, wall_s=self.wall_s,
                   frozen_sap_steps=stats.frozen_steps,
                   first_frozen_sap_step_s=stats.first_frozen_time_s, steps=stats.steps,
                   final=final, diagram_dot=dot, replay_html=html, cpu_s=self.cpu_s)


@contextlib.contextmanager
def _deferred_signals():
    """Ctrl-C and SIGTERM while the simulator steps are noted, not raised: raised inside one of
    the Python systems Drake calls back from C++ (most land in the tyre system's update), a
    KeyboardInterrupt crosses C++ as an exception where it can be lost (a run once finished
    and exited 0 after SIGINT). The runner stops after the chunk it is in; the signal is then
    raised again with the handlers that were there before (KeyboardInterrupt, or
    ``results.folder.terminate_as_exit``'s SystemExit)."""
    caught = []
    signals = (signal.SIGINT, signal.SIGTERM)
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


def static_equilibrium(scene: Scene) -> Equilibrium:
    """Where ``scene``'s car rests (``sim.equilibrium``), cached by the settling scene's
    content."""
    return _settled(dump_scene(equilibrium_scene(scene)))


@functools.lru_cache(maxsize=64)
def _settled(settle_yaml) -> Equilibrium:
    # In memory for this process, on disk between processes (sim.equilibrium_cache).
    cached = equilibrium_cache.load(settle_yaml)
    if cached is not None:
        return cached
    equilibrium = equilibrium_from_run(simulate(yaml_load_typed(schema=Scene, data=settle_yaml)))
    equilibrium_cache.store(settle_yaml, equilibrium)
    return equilibrium


def _set_initial_state(built, root, scene):
    if scene.simulator.start != "static_equilibrium":
        return
    start = static_equilibrium(scene)
    plant = built.plant
    plant.SetPositions(plant.GetMyMutableContextFromRoot(root), built.car.instance,
                       np.asarray(start.positions))


def _progress_bar(scene, end, now=0.0):
    from tqdm import tqdm
    return tqdm(total=end, initial=now, desc=scene.name, unit="s sim", file=sys.stderr,
                leave=False, disable=None, mininterval=0.5,
                bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.2f}/{total:.2f} s "
                           "[{elapsed}<{remaining}]")


def logged_history(built, root_context):
    """Columns of every logger of ``built``, with their sample times "t". A sample repeated at
    the same time (a branched run's loggers sample again when its simulator starts at the
    branch time, ``sim.branch``) is kept once."""
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
    if "t" not in history:
        period = built.scene.logging.record_period_s
        history["t"] = np.arange(int(round(built.scene.end_time_s / period)) + 1) * period
    return history


def final_state(built, root):
    """The car at the end of a run: what a settled car is judged by."""
    plant, car = built.plant, built.car
    pc = plant.GetMyContextFromRoot(root)
    tyre_context = built.tyre.GetMyContextFromRoot(root)
    loads = built.tyre.GetOutputPort("tyre_loads").Eval(tyre_context)
    chassis = car.body("chassis").EvalPoseInWorld(pc)
    r0 = car.params.tyre.unloaded_radius_m
    # Height above the road of the chassis points above the axle centres at the design
    # wheel-centre height: (0, 0, R0) and (-L, 0, R0) in the chassis frame (design: R0).
    ride = {"front": float(chassis.multiply(np.array([0.0, 0.0, r0]))[2]),
            "rear": float(chassis.multiply(np.array([-car.params.wheelbase_m, 0.0, r0]))[2])}
    return {
        "corner_loads_N": {w: float(loads[i]) for i, w in enumerate(WHEELS)},
        "design_axle_loads_N": design_axle_loads_N(car.params),
        "ride_height_m": ride,
        "strut_overlap_m": {s: float(strut_overlap(car, pc, s)) for s in SIDES},
        "loop_closure_error_m": loop_closure_error(car, pc),
        "total_mass_kg": float(plant.CalcTotalMass(pc, [car.instance])),
        "max_abs_generalized_velocity": float(
            np.max(np.abs(plant.GetVelocities(pc, car.instance)))),
        "positions": plant.GetPositions(pc, car.instance).tolist(),
    }

