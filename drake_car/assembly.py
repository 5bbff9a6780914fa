"""Assembles the car's Diagram: plant, tyres, steering and drive commands, strut friction.

The diagram holds only the systems asked for: no friction system unless ``friction`` is given,
no Magic Formula unless the tyre setup asks for it, no drive servo unless a drive trajectory is
given, no visualiser unless ``meshcat`` is given, no logger for a channel group not asked for.
"""

import dataclasses
from pathlib import Path

import numpy as np
from pydrake.multibody.plant import (
    AddMultibodyPlant, ExternallyAppliedSpatialForceMultiplexer, MultibodyPlantConfig)
from pydrake.multibody.tree import PdControllerGains
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import (
    ConstantVectorSource, LogVectorOutput, MatrixGain, Multiplexer, TrajectorySource)

from drake_car.law.magic_formula import MagicFormulaTyre
from drake_car.law.road import flat
from drake_car.law.tyre_contact import RadialTyre
from drake_car.law.tyre_slip import SlipOptions
from drake_car.model.car import add_car
from drake_car.model.geometry import SIDES
from drake_car.systems.channels import CAR_CHANNELS, CarChannels
from drake_car.systems.sap_pacer import add_sap_pacer, connect_sap_pacer
from drake_car.model.parameters import CarParameters
from drake_car.systems.driveshaft import DriveshaftReaction
from drake_car.systems.tyre import TyreSystem

DEFAULT_TIME_STEP_S = 1e-3
DEFAULT_TIR = Path(__file__).resolve().parents[1] / "urdf" / "tyres" / "pacejka2006_205_60R15.tir"
# Prescribed front-wheel rotation (paper section 4): a stiff SAP servo on each wheel's spin
# joint; 1e5 N m/rad keeps the wheel within ~0.01 rad of its command at the ~1 kN m drive torque
# of the speed-up, and 2e3 N m s/rad over-damps the wheel's 0.6 kg m².
DRIVE_SERVO_GAINS = PdControllerGains(p=1.0e5, d=2.0e3)
# Channel groups a run can log: the car's (systems/channels.py), the tyres' diagnostics and the
# strut friction's diagnostics.
LOG_CHANNELS = tuple(CAR_CHANNELS) + ("tyres", "friction")


@dataclasses.dataclass
class TyreSetup:
    """Which tyre model: ``magic_formula`` False gives the vertical part only; ``linear`` uses
    the Magic Formula tyre linearised about zero slip (``law.magic_formula.linear_tyre``)."""

    magic_formula: bool = True
    tir_path: Path = DEFAULT_TIR
    combined: bool = True
    slip: SlipOptions = dataclasses.field(default_factory=SlipOptions)
    linear: bool = False


@dataclasses.dataclass
class CarDiagram:
    diagram: object
    plant: object
    scene_graph: object
    car: object
    tyre: object
    friction: object  # the StrutFriction of both struts, or None (friction off)
    rack_command: object  # system whose output is [rack_m, rack_mps]
    drive_actuators: list
    time_step_s: float
    loggers: dict = dataclasses.field(default_factory=dict)  # group -> VectorLogSink
    log_columns: dict = dataclasses.field(default_factory=dict)  # group -> column names

    def plant_context(self, root_context):
        return self.plant.GetMyContextFromRoot(root_context)


def build_car_diagram(params: CarParameters | None = None, *, time_step_s=DEFAULT_TIME_STEP_S,
                      model_path=None, friction=None, tyres: TyreSetup | None = None,
                      road_height=flat, meshcat=None, fixed_chassis=False,
                      rack_trajectory=None, drive_trajectory=None, drive_reaction="driveshaft",
                      log_channels=(), log_period_s=0.01, sap_pacer=True):
    """Builds the car's Diagram.

    ``friction``: None (no friction system) or a ``StrutFrictionSetup`` (both front struts).
    ``tyres``: a ``TyreSetup``; default: vertical only (the car stands or settles).
    ``rack_trajectory``: a PiecewisePolynomial of the rack position (m), fed to the rack servo
    with its derivative by a TrajectorySource (default: rack held at 0).
    ``drive_trajectory``: a PiecewisePolynomial of the two front wheels' rotation angles (rad);
    adds a servo on each front wheel (default: free-rolling wheels). ``drive_reaction``:
    "driveshaft" (the servo torque is reacted by the body, as in a front-drive car) or
    "knuckle" (reacted where the joint is, as a joint motion in Adams).
    ``log_channels``: groups of ``LOG_CHANNELS`` to log every ``log_period_s`` by VectorLogSinks
    named ``log_<group>`` ("friction" only when there is friction). ``sap_pacer``: add the
    pacer that keeps SAP from returning its initial guess (``systems/sap_pacer.py``; without it
    steps at or below 1 ms drop whole steps' impulses near a balance).
    """
    unknown = [g for g in log_channels if g not in LOG_CHANNELS]
    if unknown:
        raise ValueError(f"log channels {unknown} unknown; choose from {LOG_CHANNELS}")
    if log_channels and not log_period_s > 0:
        raise ValueError(f"log_period_s = {log_period_s} must be > 0")
    if drive_reaction not in ("driveshaft", "knuckle"):
        raise ValueError(f"drive_reaction {drive_reaction!r} must be 'driveshaft' or 'knuckle'")
    if not time_step_s > 0:
        raise ValueError(f"time_step_s = {time_step_s} must be > 0 (the plant is discrete)")
    params = params or CarParameters()
    tyres = tyres or TyreSetup(magic_formula=False)
    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlant(
        MultibodyPlantConfig(time_step=time_step_s, discrete_contact_approximation="sap"),
        builder)
    car = add_car(plant, params, model_path=model_path, fixed_chassis=fixed_chassis)
    # Actuators of the car instance, in the order they are added: the rack servo and the
    # compliant top mounts (add_car), then the drive servos, then the friction pairs. Each entry: (desired-state port or None,
    # feed-forward port or None, number of actuators).
    actuator_groups = [("rack", 1)]
    if car.top_mount_actuators:  # spring-dampers: PD towards zero deflection
        actuator_groups.append(("top_mount", len(car.top_mount_actuators)))
    drive_actuators = []
    if drive_trajectory is not None:
        if drive_trajectory.rows() != 2:
            raise ValueError("drive_trajectory must give the two front wheels' angles")
        for side in SIDES:
            actuator = plant.AddJointActuator(f"drive_{side}",
                                              car.joint(f"wheel_front_{side}_spin"))
            actuator.set_controller_gains(DRIVE_SERVO_GAINS)
            drive_actuators.append(actuator)
        actuator_groups.append(("drive", 2))
    friction_declarations = {}
    if friction is not None:
        friction.check_time_step(time_step_s)
        for side in SIDES:
            friction_declarations[side] = friction.declare(plant, car.strut_joints(side), side)
    pacer = add_sap_pacer(plant) if sap_pacer else None
    plant.Finalize()
    if pacer is not None:
        connect_sap_pacer(builder, plant, pacer)

    magic = MagicFormulaTyre.from_file(tyres.tir_path) if tyres.magic_formula else None
    tyre = builder.AddSystem(TyreSystem(
        car.wheel_bodies(),
        RadialTyre(params.tyre.unloaded_radius_m, params.tyre.radial_stiffness_Npm,
                   params.tyre.radial_damping_Nspm),
        road_height, magic_formula_tyre=magic, slip=tyres.slip, combined=tyres.combined,
        linear=tyres.linear, time_step_s=time_step_s))
    tyre.set_name("tyres")
    tyre.check_time_step(time_step_s, params.mass.wheel_spin_inertia_kgm2)
    builder.Connect(plant.get_body_poses_output_port(), tyre.GetInputPort("body_poses"))
    builder.Connect(plant.get_body_spatial_velocities_output_port(),
                    tyre.GetInputPort("body_spatial_velocities"))
    if drive_trajectory is not None and drive_reaction == "driveshaft":
        shafts = builder.AddSystem(DriveshaftReaction(
            plant, car.instance, drive_actuators,
            [car.body(f"knuckle_{side}") for side in SIDES], car.body("chassis")))
        shafts.set_name("driveshafts")
        builder.Connect(plant.get_net_actuation_output_port(car.instance),
                        shafts.GetInputPort("net_actuation"))
        builder.Connect(plant.get_body_poses_output_port(), shafts.GetInputPort("body_poses"))
        combine = builder.AddSystem(ExternallyAppliedSpatialForceMultiplexer(2))
        combine.set_name("applied_forces")
        builder.Connect(tyre.GetOutputPort("tyre_forces"), combine.get_input_port(0))
        builder.Connect(shafts.GetOutputPort("reaction_forces"), combine.get_input_port(1))
        builder.Connect(combine.get_output_port(0), plant.get_applied_spatial_force_input_port())
    else:
        builder.Connect(tyre.GetOutputPort("tyre_forces"),
                        plant.get_applied_spatial_force_input_port())

    if rack_trajectory is None:
        rack_command = builder.AddSystem(ConstantVectorSource(np.zeros(2)))
        rack_command.set_name("rack_hold")
    else:
        rack_command = builder.AddSystem(TrajectorySource(rack_trajectory, 1))
        rack_command.set_name("rack_command_akima")
    desired = [rack_command.get_output_port(0)]
    feedforward = [None]
    if car.top_mount_actuators:
        desired.append(None)  # zeros: the mount's rest position
        feedforward.append(None)
    if drive_trajectory is not None:
        drive = builder.AddSystem(TrajectorySource(drive_trajectory, 1))
        drive.set_name("drive_command")
        desired.append(drive.get_output_port(0))
        feedforward.append(None)
    friction_system = None
    if friction_declarations:
        friction_system = builder.AddSystem(friction.make_system(
            plant, friction_declarations, guide_length_l_m=params.front.guide_length_l_m))
        friction_system.set_name("strut_friction")
        friction_system.connect(builder, plant)
        actuator_groups.append(("friction", friction_system.num_pairs()))
        # None: the explicit scheme has no PD
        desired.append(friction_system.desired_state_output_port())
        feedforward.append(friction_system.actuation_output_port())
    sizes = [n for _, n in actuator_groups]
    _connect_desired_state(builder, plant, car.instance, desired, sizes)
    if any(port is not None for port in feedforward):
        _connect_actuation(builder, plant, car.instance, feedforward, sizes)

    loggers, columns = _add_loggers(builder, plant, car, params, tyre, friction_system,
                                    log_channels, log_period_s)

    if meshcat is not None:
        from pydrake.geometry import MeshcatVisualizer, MeshcatVisualizerParams, Role
        MeshcatVisualizer.AddToBuilder(
            builder, scene_graph, meshcat,
            MeshcatVisualizerParams(role=Role.kIllustration, publish_period=1 / 32))
    diagram = builder.Build()
    diagram.set_name("car")
    return CarDiagram(diagram=diagram, plant=plant, scene_graph=scene_graph, car=car, tyre=tyre,
                      friction=friction_system, rack_command=rack_command,
                      drive_actuators=drive_actuators, time_step_s=time_step_s,
                      loggers=loggers, log_columns=columns)


def _add_loggers(builder, plant, car, params, tyre, friction, groups, period):
    loggers, columns = {}, {}
    car_groups = [g for g in groups if g in CAR_CHANNELS]
    if car_groups:
        channels = builder.AddSystem(CarChannels(plant, car, car_groups,
                                                 params.front.guide_length_l_m))
        channels.set_name("car_channels")
        channels.connect(builder, plant)
        for group in car_groups:
            loggers[group] = LogVectorOutput(channels.GetOutputPort(group), builder, period)
            columns[group] = list(CAR_CHANNELS[group])
    if "tyres" in groups:
        loggers["tyres"] = LogVectorOutput(tyre.GetOutputPort("tyre_diagnostics"), builder,
                                           period)
        columns["tyres"] = tyre.diagnostic_names()
    if "friction" in groups and friction is not None:
        loggers["friction"] = LogVectorOutput(friction.GetOutputPort("diagnostics"), builder,
                                              period)
        columns["friction"] = [f"friction_{name}" for name in friction.diagnostic_names()]
    for group, logger in loggers.items():
        logger.set_name(f"log_{group}")
    return loggers, columns


def _mux(builder, name, ports, sizes, width):
    """Stacks ``ports`` (None: zeros of that size) into one vector."""
    mux = builder.AddSystem(Multiplexer([width(n) for n in sizes]))
    mux.set_name(name)
    for i, (port, n) in enumerate(zip(ports, sizes)):
        if port is None:
            zeros = builder.AddSystem(ConstantVectorSource(np.zeros(width(n))))
            zeros.set_name(f"{name}_zeros_{i}")
            port = zeros.get_output_port(0)
        builder.Connect(port, mux.get_input_port(i))
    return mux


def _connect_desired_state(builder, plant, instance, ports, sizes):
    """The plant wants [q_d of every actuator..., v_d of every actuator...] in actuator order;
    each source gives [q_d (n), v_d (n)] for its n actuators (None: not PD-controlled)."""
    port = plant.get_desired_state_input_port(instance)
    total = sum(sizes)
    if port.size() != 2 * total:
        raise RuntimeError(f"desired-state port has size {port.size()}, sources give {2 * total}")
    if len(ports) == 1:
        builder.Connect(ports[0], port)
        return
    mux = _mux(builder, "desired_state_mux", ports, sizes, lambda n: 2 * n)
    permutation = np.zeros((2 * total, 2 * total))
    offset, row = 0, 0
    for n in sizes:
        for k in range(n):
            permutation[row + k, offset + k] = 1.0  # q_d
            permutation[total + row + k, offset + n + k] = 1.0  # v_d
        offset += 2 * n
        row += n
    gain = builder.AddSystem(MatrixGain(permutation))
    gain.set_name("desired_state_order")
    builder.Connect(mux.get_output_port(0), gain.get_input_port())
    builder.Connect(gain.get_output_port(), port)


def _connect_actuation(builder, plant, instance, ports, sizes):
    mux = _mux(builder, "actuation_mux", ports, sizes, lambda n: n)
    builder.Connect(mux.get_output_port(0), plant.get_actuation_input_port(instance))
