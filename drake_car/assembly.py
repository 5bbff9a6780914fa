"""Assembles the car's Diagram: plant, tyres, steering command, strut friction, loggers.

The diagram holds only the systems asked for: no friction system unless ``friction`` is given,
no visualiser unless ``meshcat`` is given.
"""

import dataclasses

import numpy as np
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import ConstantVectorSource, Multiplexer, MatrixGain

from drake_car.law.tyre_contact import RadialTyre, flat_road
from drake_car.model.car import add_car
from drake_car.model.geometry import SIDES
from drake_car.model.parameters import CarParameters
from drake_car.systems.tyre import TyreSystem

DEFAULT_TIME_STEP_S = 1e-3


@dataclasses.dataclass
class CarDiagram:
    diagram: object
    plant: object
    scene_graph: object
    car: object
    tyre: object
    friction: dict  # side -> StrutFriction (empty when friction is off)
    rack_command: object  # system whose output is [rack_m, rack_mps]
    time_step_s: float

    def plant_context(self, root_context):
        return self.plant.GetMyContextFromRoot(root_context)


def build_car_diagram(params: CarParameters | None = None, *, time_step_s=DEFAULT_TIME_STEP_S,
                      model_path=None, friction=None, road_height=flat_road, meshcat=None,
                      fixed_chassis=False, rack_command=None):
    """Builds the car's Diagram.

    ``friction``: None (no friction system) or a ``StrutFrictionSetup`` from
    ``drake_car.systems.strut_friction`` (parameters and scheme for both front struts).
    ``rack_command``: a system with one output [rack_m, rack_mps] (default: rack held at 0).
    """
    if not time_step_s > 0:
        raise ValueError(f"time_step_s = {time_step_s} must be > 0 (the plant is discrete)")
    params = params or CarParameters()
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlant(
        MultibodyPlantConfig(time_step=time_step_s, discrete_contact_approximation="sap"),
        builder)
    car = add_car(plant, params, model_path=model_path, fixed_chassis=fixed_chassis)
    friction_declarations = {}
    if friction is not None:
        friction.check_time_step(time_step_s)
        for side in SIDES:
            friction_declarations[side] = friction.declare(plant, car.strut_joints(side), side)
    plant.Finalize()

    tyre = builder.AddSystem(TyreSystem(
        car.wheel_bodies(),
        RadialTyre(params.tyre.unloaded_radius_m, params.tyre.radial_stiffness_Npm,
                   params.tyre.radial_damping_Nspm),
        road_height))
    tyre.set_name("tyres")
    builder.Connect(plant.get_body_poses_output_port(), tyre.GetInputPort("body_poses"))
    builder.Connect(plant.get_body_spatial_velocities_output_port(),
                    tyre.GetInputPort("body_spatial_velocities"))
    builder.Connect(tyre.GetOutputPort("tyre_forces"),
                    plant.get_applied_spatial_force_input_port())

    if rack_command is None:
        rack_command = builder.AddSystem(ConstantVectorSource(np.zeros(2)))
        rack_command.set_name("rack_hold")
    else:
        builder.AddSystem(rack_command)

    friction_systems = {}
    desired_sources = [(rack_command.get_output_port(0), 1)]
    actuation_sources = []
    for side, declaration in friction_declarations.items():
        system = builder.AddSystem(friction.make_system(
            plant, declaration, side, guide_length_l_m=params.front.guide_length_l_m))
        system.set_name(f"strut_friction_{side}")
        system.connect(builder, plant)
        friction_systems[side] = system
        actuation_sources.append(system.actuation_output_port())
        port = system.desired_state_output_port()
        if port is None:  # explicit scheme: its actuators have no PD; their desired state is unused
            zeros = builder.AddSystem(ConstantVectorSource(np.zeros(2 * system.num_pairs())))
            zeros.set_name(f"strut_friction_{side}_no_desired_state")
            port = zeros.get_output_port(0)
        desired_sources.append((port, system.num_pairs()))
    _connect_desired_state(builder, plant, car.instance, desired_sources)
    if actuation_sources:
        # Actuators of the car instance, in order: rack servo (no feed-forward), then the pairs.
        zero = builder.AddSystem(ConstantVectorSource(np.zeros(1)))
        zero.set_name("rack_feedforward")
        mux = builder.AddSystem(Multiplexer(
            [1] + [port.size() for port in actuation_sources]))
        mux.set_name("actuation_mux")
        builder.Connect(zero.get_output_port(0), mux.get_input_port(0))
        for i, port in enumerate(actuation_sources):
            builder.Connect(port, mux.get_input_port(i + 1))
        builder.Connect(mux.get_output_port(0), plant.get_actuation_input_port(car.instance))

    if meshcat is not None:
        from pydrake.geometry import MeshcatVisualizer, MeshcatVisualizerParams, Role
        MeshcatVisualizer.AddToBuilder(
            builder, scene_graph, meshcat,
            MeshcatVisualizerParams(role=Role.kIllustration, publish_period=1 / 32))
    diagram = builder.Build()
    diagram.set_name("car")
    return CarDiagram(diagram=diagram, plant=plant, scene_graph=scene_graph, car=car, tyre=tyre,
                      friction=friction_systems, rack_command=rack_command,
                      time_step_s=time_step_s)


def _connect_desired_state(builder, plant, instance, sources):
    """The plant wants [q_d of each PD actuator..., v_d of each...] in actuator order; each source
    gives [q_d (n), v_d (n)] for its n actuators, added in the same order."""
    sizes = [2 * n for _, n in sources]
    port = plant.get_desired_state_input_port(instance)
    total = sum(n for _, n in sources)
    if port.size() != 2 * total:
        raise RuntimeError(f"desired-state port has size {port.size()}, sources give {2 * total}")
    if len(sources) == 1:
        builder.Connect(sources[0][0], port)
        return
    mux = builder.AddSystem(Multiplexer(sizes))
    mux.set_name("desired_state_mux")
    permutation = np.zeros((2 * total, 2 * total))
    offset, row = 0, 0
    for _, n in sources:
        for k in range(n):
            permutation[row + k, offset + k] = 1.0  # q_d
            permutation[total + row + k, offset + n + k] = 1.0  # v_d
        offset += 2 * n
        row += n
    gain = builder.AddSystem(MatrixGain(permutation))
    gain.set_name("desired_state_order")
    for i, (source, _) in enumerate(sources):
        builder.Connect(source, mux.get_input_port(i))
    builder.Connect(mux.get_output_port(0), gain.get_input_port())
    builder.Connect(gain.get_output_port(), port)
