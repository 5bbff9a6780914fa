"""``CarDiagram``: the car's Diagram (``sim.build.build_diagram``) with its handles, and what
the one runner needs of it (``sim.simulation.Simulation``)."""

import dataclasses

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.systems.framework import InputPortIndex

from drake_car.scene.scene import Scene
from drake_car.sim.monitor import Monitor, Road
from drake_car.systems.tyre import WHEELS

CASES = ("a", "b")  # a lane change's cases, in the order of a branchable Diagram's switch


@dataclasses.dataclass
class CarDiagram:
    """The car's Diagram with its handles; what the runner needs of it (``sim.simulation.
    Simulation``): its loggers, the monitor's checks (every one: the state, the road, the
    energy; the frozen-step count), the initial state (``initial_positions``, which the
    scene's runner sets to the static equilibrium, ``sim.simulate``) and the history's
    columns (the loggers' and the manoeuvre's phase)."""

    scene: Scene
    diagram: object
    plant: object
    scene_graph: object
    car: object  # model.car.CarModel
    tyre: object  # the TyreSystem
    friction: object  # the StrutFriction of both struts, or None
    pacer: object  # the SAP pacer's model instance, or None
    loggers: dict = dataclasses.field(default_factory=dict)  # group -> VectorLogSink
    log_columns: dict = dataclasses.field(default_factory=dict)  # group -> column names
    velocity_logger: object = None  # the car's state every step (frozen-step count)
    case_port: object = None  # the Diagram's input selecting the lane change's case, or None
    # An external-driver Diagram's exported ports (sim.driver_wiring): name -> port.
    inputs: dict = dataclasses.field(default_factory=dict)
    outputs: dict = dataclasses.field(default_factory=dict)
    driver: object = None  # a !PathFollower scene's PathDriver, or None
    initial_positions: list | None = None  # the car's positions at the start (None: design)

    @property
    def name(self):
        return self.scene.name

    @property
    def monitor_period_s(self):
        return self.scene.simulator.monitor_period_s

    @property
    def time_step_s(self):
        return self.scene.time_step_s

    def monitor(self):
        scene, car = self.scene, self.car
        return Monitor(self.plant, self.diagram, state_logger=self.velocity_logger,
                       instance=car.instance, road=Road(
                           self.tyre, scene.car.tyre.radial_stiffness_Npm,
                           scene.road.flat_up_to_m(), car.body("chassis"),
                           scene.simulator.airborne_limit_s,
                           tuple(car.wheel_bodies()[w] for w in WHEELS)))

    def set_initial_state(self, root_context):
        """The car's positions set to ``initial_positions`` where the runner gave them (None
        after ``build_diagram`` alone: the model's design position stays; for the car at rest
        on its tyres set ``sim.simulate.static_equilibrium(scene).positions``, docs/driver.md)."""
        if self.initial_positions is not None:
            self.plant.SetPositions(self.plant.GetMyMutableContextFromRoot(root_context),
                                    self.car.instance, np.asarray(self.initial_positions))

    def history(self, logged):
        """The loggers' columns (the record period's times when nothing is logged), then the
        manoeuvre's phase at each time."""
        history = dict(logged)
        if "t" not in history:
            period = self.scene.logging.record_period_s
            history["t"] = np.arange(int(round(self.scene.end_time_s / period)) + 1) * period
        history["phase"] = [self.scene.manoeuvre.phase(t) for t in history["t"]]
        return history

    def plant_context(self, root_context):
        return self.plant.GetMyContextFromRoot(root_context)

    def select_case(self, root_context, case):
        """A branchable Diagram's lane-change case (a value fixed in the context)."""
        # The switch's input 0 is its selector; the cases' commands are its inputs 1 and 2.
        self.case_port.FixValue(root_context,
                                AbstractValue.Make(InputPortIndex(1 + CASES.index(case))))
