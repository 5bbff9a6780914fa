"""``simulate(scene) -> Run``: a scene's car on the one runner (``sim.simulation``). It
builds the scene's Diagram, sets the initial state the scene asks for, runs under the
divergence monitor with an optional progress bar, and returns the logged history with the
scene that ran, the Diagram's picture (Graphviz) and the replay page when the scene asks for
one."""

import dataclasses
import functools
import logging
import math

import numpy as np

from drake_car.model.car import loop_closure_error, strut_overlap
from drake_car.model.geometry import SIDES, design_axle_loads_N
from pydrake.common.yaml import yaml_load_typed

from drake_car.scene.load import (
    WALL_PER_STEP_S, dump_scene, dump_scene_file, scene_hash)
from drake_car.scene.scene import (
    MeshcatLive, MeshcatReplay, NoVisualization, Scene, at_time_step)
from drake_car.sim.build import build_diagram
from drake_car.sim.driver_wiring import manoeuvre_outcome
from drake_car.sim import equilibrium_cache
from drake_car.sim.equilibrium import Equilibrium, equilibrium_from_run, equilibrium_scene
from drake_car.sim.lane_change_calibration import adapted
from drake_car.sim.slips import SlipRunner
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
    events: dict | None = None  # the friction pairs' stick-slip events (``event_columns``)
    resolution: dict | None = None  # what the local resolution of events did (``sim.resolve``)

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
                "final": {k: v for k, v in self.final.items() if k != "positions"},
                "events": self.events, "resolution": self.resolution}


def estimate_wall_s(scene: Scene):
    return scene.end_time_s / scene.time_step_s * WALL_PER_STEP_S


def simulate(scene: Scene, *, progress=False, meshcat=None) -> Run:
    """Runs ``scene``; ``progress`` shows a bar of the simulated time on stderr. A scene with
    ``MeshcatLive`` or ``MeshcatReplay`` visualisation starts a Meshcat server on localhost
    unless ``meshcat`` is given."""
    return SceneRunner(scene, progress=progress, meshcat=meshcat).run().finish()


def scene_as_it_runs(scene: Scene) -> Scene:
    """The scene as ``simulate`` runs it, to build its Diagram yourself: a launch left out
    resolved to what the car's drive allows (``scene.launch``), a lane change's rack calibrated
    for the car (``sim.lane_change_calibration``: the shipped Escort's profile, else found in
    the cache by content or calibrated by a few runs). A scene with nothing to adapt comes back
    as it is."""
    return adapted(scene, run=simulate)[0]


class SceneRunner(SlipRunner):
    """The one runner (``sim.simulation.Runner``, with its friction's events and the local
    resolution of its struts' slips: ``sim.slips.SlipRunner``) on a scene's car: builds the
    scene's Diagram, selects its lane-change case, starts from the scene's initial state (the static
    equilibrium by default), shows or records Meshcat when the scene asks, and ``finish()``
    returns the Run.
    ``sim.branch`` starts one from another runner's saved context."""

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
        if built is None:
            built = build_diagram(scene, meshcat=meshcat if shows else None,
                                  branchable=branchable)
        elif built.scene is not scene:  # another case of a branchable Diagram: this scene's
            built = dataclasses.replace(built, scene=scene)
        recorder = None
        if isinstance(visual, MeshcatReplay):
            from drake_car.sim.replay import ReplayRecorder
            recorder = ReplayRecorder(meshcat, built, visual)
        resolve = scene.simulator.resolve_events
        super().__init__(built, end_time_s=scene.end_time_s, progress=progress,
                         context=context, recorder=recorder,
                         realtime_rate=(visual.realtime_rate if isinstance(visual, MeshcatLive)
                                        else 0.0),
                         resolve=resolve,
                         make_level=functools.partial(level_runner, scene,
                                                      built.case_port is not None),
                         selects=lambda name: name.split("_")[0] in SIDES)
        if built.case_port is not None:
            built.select_case(self.root, scene.manoeuvre.case)

    def start(self):
        """The scene's initial state, then Drake's initialization events."""
        if self.scene.simulator.start == "static_equilibrium":
            self.built.initial_positions = static_equilibrium(
                self.scene, self.built.plant.num_positions(self.built.car.instance)).positions
        estimate = estimate_wall_s(self.scene)
        if self.progress and estimate > ANNOUNCE_WALL_S:
            log.info("%s: %g s at %g s steps, about %.0f min of wall time", self.scene.name,
                     self.scene.end_time_s, self.scene.time_step_s, estimate / 60)
        super().start()

    def finish(self) -> Run:
        result = self.result()
        html = self.recorder.finish() if self.recorder is not None else None
        final = final_state(self.built, self.root)
        outcome = manoeuvre_outcome(self.scene, result.history, log)  # a path manoeuvre's
        if outcome is not None:
            final["manoeuvre_outcome"] = outcome
        return Run(scene=self.scene, history=result.history, wall_s=result.wall_s,
                   frozen_sap_steps=result.frozen_sap_steps,
                   first_frozen_sap_step_s=result.first_frozen_sap_step_s, steps=result.steps,
                   final=final, diagram_dot=result.diagram_dot, replay_html=html,
                   cpu_s=result.cpu_s, events=self.event_table(),
                   resolution=self.resolution())


def level_runner(scene, branchable, step_s, solver_factor=1.0):
    """A runner of ``scene`` at ``step_s``, SAP's tolerance loosened by ``solver_factor``,
    without visualisation or resolution: a window's level (``sim.resolve``)."""
    level = dataclasses.replace(
        at_time_step(scene, step_s), visualization=NoVisualization(),
        simulator=dataclasses.replace(
            scene.simulator, resolve_events=None,
            sap_tolerance_factor=scene.simulator.sap_tolerance_factor * solver_factor))
    return SceneRunner(level, branchable=branchable)


def static_equilibrium(scene: Scene, positions=None) -> Equilibrium:
    """Where ``scene``'s car rests (``sim.equilibrium``), cached by the settling scene's
    content. ``positions``: how many the car has, where known (a cached entry with another
    count is damaged: recomputed)."""
    settle_yaml = dump_scene(equilibrium_scene(scene))
    equilibrium = _settled(settle_yaml)
    if positions is not None and len(equilibrium.positions) != positions:
        # only an entry from disk can have another count: damaged; settled again
        equilibrium_cache.discard(settle_yaml, f"positions: {len(equilibrium.positions)} "
                                               f"values, the car has {positions}")
        _settled.cache_clear()
        equilibrium = _settled(settle_yaml)
    return equilibrium


@functools.lru_cache(maxsize=64)
def _settled(settle_yaml) -> Equilibrium:
    # In memory for this process, on disk between processes (sim.equilibrium_cache).
    cached = equilibrium_cache.load(settle_yaml)
    if cached is not None:
        return cached
    equilibrium = equilibrium_from_run(simulate(yaml_load_typed(schema=Scene, data=settle_yaml)))
    equilibrium_cache.store(settle_yaml, equilibrium)
    return equilibrium


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

