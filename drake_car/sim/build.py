"""``build_diagram(scene)``: the car's Diagram, a straight line of stages, each adding only what
the scene calls for (build order as Drake's hardware_sim: plant and parser, actuators, Finalize,
systems and wiring, loggers, visualiser, Build). The scene is trusted: its values and limits
were checked once, where it was loaded (``scene.load.check_scene``, ``scene.limits``)."""

import dataclasses
import logging

import numpy as np
from pydrake.multibody.plant import AddMultibodyPlant, ExternallyAppliedSpatialForceMultiplexer
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import (
    LogVectorOutput, MatrixGain, PortSwitch, TrajectorySource)

from drake_car.law.tyre.magic_formula import relaxation_lengths_m
from drake_car.law.tyre.contact import RadialTyre
from drake_car.law.tyre.plausibility import wheel_load_note
from drake_car.model.anti_roll_bar import anti_roll_bar_gain
from drake_car.model.car import add_car, forward_speed_index, rolling_momentum_scale
from drake_car.model.channels import CAR_CHANNELS, CarChannels
from drake_car.model.drive import add_drive_actuators
from drake_car.model.geometry import design_axle_loads_N, steering_sign
from drake_car.model.loading import read_tyre
from drake_car.model.steering import add_steering_column, column_strut, release_schedule
from drake_car.model.struts import declare_strut_friction, make_strut_friction
from drake_car.scene.load import channels_of, hands_off_release_s
from drake_car.scene.manoeuvres import LaneChange
from drake_car.scene.raw import SceneError
from drake_car.scene.scene import (
    HandsOff, HeldRack, LinearTyre, MagicFormula, PathFollower, PrescribedRotation, Scene)
from drake_car.sim.actuation import ActuationWiring
from drake_car.sim.drive_wiring import add_drive, driveshafts
from drake_car.sim.driver_wiring import (
    add_path_driver, drive_torque_input, external_outputs, rack_command)
from drake_car.sim.car_diagram import CASES, CarDiagram
from drake_car.systems.gain_schedule import GainSchedule
from drake_car.systems.strut_friction import StrutFriction
from drake_car.systems.sap_ballast import add_sap_ballast, connect_sap_ballast
from drake_car.systems.sap_pacer import add_sap_pacer, connect_sap_pacer
from drake_car.systems.tyre import TyreSystem


log = logging.getLogger(__name__)
_NOTED = set()  # tyre files whose load note was logged (once per file and car per process)


def build_diagram(scene: Scene, *, meshcat=None, branchable=False,
                  column_form="reflected", external_driver=False) -> CarDiagram:
    """The scene's Diagram (a lane change's rack must be calibrated for the car: build
    ``drake_car.scene_as_it_runs(scene)``, as ``simulate`` does). ``meshcat``: a
    ``pydrake.geometry.Meshcat`` to draw the car in (a ``MeshcatVisualizer`` is added whatever
    the scene's ``visualization`` says: that section is what ``simulate`` reads; a replay page
    from your own loop: ``sim.replay.ReplayRecorder``). ``branchable`` (lane changes only): both cases' rack commands
    behind a switch whose selection is a value of the context (``select_case``), so runs that
    differ only in the case can continue one saved context (``sim.branch``). ``column_form``:
    how a hands-off scene's steering column is modelled (``model.steering.COLUMN_FORMS``; the
    coupler form is the reference the tests hold the default to).

    ``external_driver``: leave the rack command and the drive torque unconnected and export
    them as the Diagram's inputs ``rack_position_m`` and ``drive_torque_Nm``, with the
    outputs a driver or controller reads (``car_state``, ``chassis_motion``, ``body_poses``,
    ``body_spatial_velocities``, ``tyre_loads_N``, ``tyre_diagnostics``,
    ``strut_friction_diagnostics``; units and
    layouts in ``sim.driver_wiring``), as Drake's ``MakeHardwareStation`` exports every
    unconnected input: the driver is then a system of the caller's own outer Diagram
    (``CarDiagram.inputs`` / ``outputs`` hold the ports). It is an argument of the build, not
    a scene value, because the scene describes a run that is a pure function of it (the car,
    road, tyres, friction and what drives them): a Diagram whose inputs come from outside is
    not such a run until the caller says what feeds them. The scene's manoeuvre still gives
    the run's phases and end and its speed the drive's rev limit; its rack and speed profiles
    are not built. Needs the scene's steering ``!HeldRack`` and drive ``!OpenDifferential``;
    not branchable."""
    if external_driver and (branchable or not isinstance(scene.steering, HeldRack)):
        raise SceneError("build_diagram(external_driver=True): needs steering !HeldRack (the "
                         "driver comes from outside) and is not branchable")
    builder = DiagramBuilder()
    # 1. The plant and the car, then every actuator the scene needs, before Finalize.
    plant, scene_graph = AddMultibodyPlant(scene.plant, builder)
    car = add_car(plant, scene.car)
    wiring = ActuationWiring(plant, car.instance)
    wiring.add("rack", 1, pd=True)
    if car.top_mount_actuators:
        wiring.add("top_mount", len(car.top_mount_actuators), pd=True, rest_at_zero=True)
    drives = scene.manoeuvre.drives
    if drives:
        add_drive_actuators(plant, car, pd=isinstance(scene.drive, PrescribedRotation))
        wiring.add("drive", 2, pd=isinstance(scene.drive, PrescribedRotation))
    declarations = None
    if scene.friction is not None:
        declarations = declare_strut_friction(plant, car, rotation=scene.friction.rotation,
                                              scheme=scene.friction.scheme)
    column = _Column(scene, add_steering_column(plant, car, scene.steering, scheme="fast",
                                                form=column_form)
                     if isinstance(scene.steering, HandsOff) else None, column_form)
    strut_pairs = len(sum(declarations.values(), [])) if declarations else 0
    if strut_pairs or column.merged:
        wiring.add("friction", strut_pairs + (len(column.pairs) if column.merged else 0),
                   pd=scene.friction is None or scene.friction.scheme == "fast")
    if column.own_group:
        wiring.add("steering_column", len(column.pairs), pd=True)
    pacer = add_sap_pacer(plant) if scene.simulator.sap_pacer else None
    factor = scene.simulator.sap_tolerance_factor
    ballast = add_sap_ballast(plant) if factor > 1.0 else None
    plant.Finalize()
    if pacer is not None:
        connect_sap_pacer(builder, plant, pacer)
    if ballast is not None:  # SAP's tolerance loosened by the factor (the solver axis)
        connect_sap_ballast(builder, plant, ballast, speed_index=forward_speed_index(car),
                            scale_per_speed=rolling_momentum_scale(car), factor=factor)
    helpers = [i for i in (pacer, ballast) if i is not None]  # decoupled from the car

    # 2. Anti-roll bars: the arms' angles coupled left to right (a matrix, no Python).
    bars = anti_roll_bar_gain(plant, car, car.arm_rates) if car.arm_rates else None
    if bars is not None:
        bar = builder.AddSystem(MatrixGain(bars))
        bar.set_name("anti_roll_bars")
        builder.Connect(plant.get_state_output_port(), bar.get_input_port())
        builder.Connect(bar.get_output_port(), plant.get_applied_generalized_force_input_port())

    # 3. Tyres: forces on the wheels from their poses and velocities (and the driveshafts'
    # reaction of the drive torque, which needs the wheels' spin axes too).
    tyre = _add_tyres(builder, plant, car, scene, driveshafts(plant, car, scene))
    applier = builder.AddSystem(tyre.make_applier())
    applier.set_name("tyre_forces")
    builder.Connect(tyre.GetOutputPort("tyre_wrenches"), applier.get_command_input_port())
    builder.Connect(plant.get_body_poses_output_port(), applier.get_body_poses_input_port())
    applied = [applier.get_spatial_forces_output_port()]

    # 4. Strut friction (and a hands-off column's, one more pair of the same system where
    # both use the fast scheme): reactions in, PD targets and feed-forward out.
    friction = None
    if strut_pairs or column.merged:
        friction = builder.AddSystem(make_strut_friction(
            plant, car, declarations or {},
            scene.friction.law if scene.friction is not None else column.law,
            scheme=scene.friction.scheme if scene.friction is not None else "fast",
            extra_struts=[column.strut()] if column.merged else []))
        friction.connect(builder, plant)
        wiring.connect("friction", desired=friction.desired_state_output_port(),
                       feedforward=friction.actuation_output_port())

    # 5. Drive: the speed profile through the front wheels, torque reacted by the body (or a
    # torque from outside).
    inputs = {}
    if drives and external_driver:
        inputs["drive_torque_Nm"] = drive_torque_input(builder, plant, car, scene, wiring)
    elif drives:
        add_drive(builder, plant, car, scene, wiring)

    # 6. Steering: the rack servo follows the manoeuvre's rack trajectory (a path follower's
    # command, or a position from outside).
    case_port, driver, channels = None, None, None
    if external_driver or isinstance(scene.steering, PathFollower):
        channels = _car_channels(builder, plant, car, helpers, scene, extra=["chassis"])
    if external_driver:
        inputs["rack_position_m"], rack_port = rack_command(builder)
    elif isinstance(scene.steering, PathFollower):
        driver = add_path_driver(builder, scene, channels.GetOutputPort("chassis"))
        _, rack_port = rack_command(builder, driver.rack_output_port())
    elif branchable:
        if not isinstance(scene.manoeuvre, LaneChange):
            raise SceneError("build_diagram: only lane changes are branchable")
        switch = builder.AddSystem(PortSwitch(2))
        switch.set_name("lane_change_case")
        for case in CASES:
            source = builder.AddSystem(TrajectorySource(
                dataclasses.replace(scene.manoeuvre, case=case).rack(scene.end_time_s), 1))
            source.set_name(f"rack_command_{case}")
            builder.Connect(source.get_output_port(0), switch.DeclareInputPort(f"case_{case}"))
        case_index = builder.ExportInput(switch.get_port_selector_input_port(),
                                         "lane_change_case")
        rack_port = switch.get_output_port(0)
    else:
        m = scene.manoeuvre  # a lane change's profile is needed only if the run reaches it
        rack = builder.AddSystem(TrajectorySource(
            m.rack(scene.end_time_s) if isinstance(m, LaneChange) else m.rack(), 1))
        rack.set_name("rack_command")
        rack_port = rack.get_output_port(0)
    if not (external_driver or isinstance(scene.steering, PathFollower)) and (
            steering_sign(scene.car) < 0):
        # A manoeuvre's rack travel is a front-steer linkage's (left steers left): a rack
        # behind the axle travels the other way (a driver's command is the rack's own).
        mirror = builder.AddSystem(MatrixGain(-np.eye(2)))
        mirror.set_name("rack_behind_the_axle")
        builder.Connect(rack_port, mirror.get_input_port())
        rack_port = mirror.get_output_port()
    wiring.connect("rack", desired=rack_port)
    if column.pairs is not None:
        _let_go(builder, plant, car, scene, column, wiring)

    # 7. Everything into the plant.
    wiring.finish(builder)
    if len(applied) == 1:
        builder.Connect(applied[0], plant.get_applied_spatial_force_input_port())
    else:
        combine = builder.AddSystem(ExternallyAppliedSpatialForceMultiplexer(len(applied)))
        combine.set_name("applied_forces")
        for i, port in enumerate(applied):
            builder.Connect(port, combine.get_input_port(i))
        builder.Connect(combine.get_output_port(0), plant.get_applied_spatial_force_input_port())

    # 8. Loggers: one per channel group asked for; the car's state every step.
    loggers, columns = _add_loggers(builder, plant, car, tyre, friction, helpers, scene,
                                    channels)
    input_index = {name: builder.ExportInput(port, name) for name, port in inputs.items()}
    output_index = {}
    if external_driver:
        output_index = {name: builder.ExportOutput(port, name) for name, port in
                        external_outputs(builder, plant, car, tyre, friction,
                                         channels.GetOutputPort("chassis")).items()}
    velocity_logger = LogVectorOutput(plant.get_state_output_port(car.instance), builder,
                                      scene.time_step_s)
    velocity_logger.set_name("car_state_every_step")

    # 9. Visualiser.
    if meshcat is not None:
        from pydrake.geometry import MeshcatVisualizer, MeshcatVisualizerParams, Role
        period = 1.0 / getattr(scene.visualization, "frames_per_second", 32.0)
        MeshcatVisualizer.AddToBuilder(
            builder, scene_graph, meshcat,
            MeshcatVisualizerParams(role=Role.kIllustration, publish_period=period))
    diagram = builder.Build()
    diagram.set_name("car")
    if branchable:
        case_port = diagram.get_input_port(case_index)
    return CarDiagram(scene=scene, diagram=diagram, plant=plant, scene_graph=scene_graph,
                      car=car, tyre=tyre, friction=friction, pacer=pacer, loggers=loggers,
                      log_columns=columns, velocity_logger=velocity_logger,
                      case_port=case_port, driver=driver,
                      inputs={n: diagram.get_input_port(i) for n, i in input_index.items()},
                      outputs={n: diagram.get_output_port(i) for n, i in output_index.items()})


def _note_tyre_load(tyre, car_parameters):
    """A tyre file whose FNOMIN is far from the car's wheel loads (``plausibility.
    wheel_load_note``; the load range itself is checked with the scene): a warning, once per
    file and car in a process."""
    note = wheel_load_note(tyre, {axle: load / 2 for axle, load
                                  in design_axle_loads_N(car_parameters).items()})
    if note and (note not in _NOTED):
        _NOTED.add(note)
        log.warning("tyres.tir_file: %s", note)


def _add_tyres(builder, plant, car, scene, driveshafts):
    tyres = scene.tyres
    magic = None
    slip = getattr(tyres, "slip", None)
    if isinstance(tyres, (MagicFormula, LinearTyre)):
        magic = read_tyre(tyres.tir_file)
        _note_tyre_load(magic, scene.car)
        if slip is not None and slip.relaxation and slip.relaxation_lengths_from_file:
            # at the wheel load at rest: the plant's weight over four wheels
            wheel_N = plant.CalcTotalMass(plant.CreateDefaultContext()) * 9.81 / 4.0
            sigma = relaxation_lengths_m(magic, wheel_N)
            slip = dataclasses.replace(slip, relaxation_length_long_m=sigma[0],
                                       relaxation_length_lat_m=sigma[1])
    v = scene.car.tyre
    kwargs = {} if slip is None else {"slip": slip}
    if magic is not None:  # the file's data are of its TYRESIDE; the other side mirrored
        kwargs["mirror_left"] = ("fr", "rr") if magic.side == "RIGHT" else ("fl", "rl")
    tyre = builder.AddSystem(TyreSystem(
        car.wheel_bodies(),
        RadialTyre(v.unloaded_radius_m, v.radial_stiffness_Npm, v.radial_damping_Nspm),
        scene.road, magic_formula_tyre=magic,
        combined=getattr(tyres, "combined_slip", True),
        linear=isinstance(tyres, LinearTyre), time_step_s=scene.time_step_s,
        driveshafts=driveshafts, **kwargs))
    tyre.set_name("tyres")
    tyre.connect(builder, plant)
    return tyre


@dataclasses.dataclass
class _Column:
    """A hands-off scene's steering column: its friction pairs (None: held steering; [] no
    friction) and where they go: ``merged`` into the car's strut-friction system (the
    reflected form's pair is the car's actuator; the struts' scheme is fast or absent),
    ``own_group`` (the car's actuator, but the struts use the reference scheme: a fast system
    of its own), else (the coupler form) a system wired to the column's model instance."""

    scene: Scene
    pairs: list | None
    form: str

    @property
    def merged(self):
        return (bool(self.pairs) and self.form == "reflected"
                and (self.scene.friction is None or self.scene.friction.scheme == "fast"))

    @property
    def own_group(self):
        return bool(self.pairs) and self.form == "reflected" and not self.merged

    @property
    def law(self):
        return self.strut().params

    def strut(self):
        return column_strut(self.pairs, self.scene.steering,
                            self.scene.car.front.rack_gain_m_per_rad)


def _let_go(builder, plant, car, scene, column, wiring):
    """Hands off: the rack servo lets go at the release time; the column's friction where it
    is not one more pair of the car's strut-friction system."""
    release = builder.AddSystem(GainSchedule([car.rack_actuator],
                                             release_schedule(hands_off_release_s(scene))))
    release.set_name("hands_off")
    if not column.pairs or column.merged:
        return
    strut = column.strut()
    system = builder.AddSystem(StrutFriction(plant, [strut], strut.params, scheme="fast",
                                             name="steering_friction"))
    system.connect(builder, plant)
    if column.own_group:
        wiring.connect("steering_column", desired=system.desired_state_output_port(),
                       feedforward=system.actuation_output_port())
        return
    instance = plant.GetModelInstanceByName("steering_column")
    builder.Connect(system.desired_state_output_port(),
                    plant.get_desired_state_input_port(instance))
    builder.Connect(system.actuation_output_port(), plant.get_actuation_input_port(instance))


def _car_channels(builder, plant, car, helpers, scene, extra=()):
    """The car's channels system with the groups the scene logs and ``extra`` ones."""
    groups = [g for g in channels_of(scene) if g in CAR_CHANNELS]
    channels = builder.AddSystem(CarChannels(plant, car, groups + [
        g for g in extra if g not in groups], helper_instances=helpers))
    channels.set_name("car_channels")
    channels.connect(builder, plant)
    return channels


def _add_loggers(builder, plant, car, tyre, friction, helpers, scene, channels=None):
    """One logger per channel group the scene logs; ``channels``: the car's channels system
    when the build made one already (a driver reads it)."""
    groups = channels_of(scene)
    period = scene.logging.record_period_s
    loggers, columns = {}, {}
    car_groups = [g for g in groups if g in CAR_CHANNELS]
    if car_groups:
        if channels is None:
            channels = _car_channels(builder, plant, car, helpers, scene)
        for group in car_groups:
            loggers[group] = LogVectorOutput(channels.GetOutputPort(group), builder, period)
            columns[group] = list(CAR_CHANNELS[group])
    if "tyres" in groups:
        loggers["tyres"] = LogVectorOutput(tyre.GetOutputPort("tyre_diagnostics"), builder,
                                           period)
        columns["tyres"] = tyre.diagnostic_names()
    if "friction" in groups:
        loggers["friction"] = LogVectorOutput(friction.GetOutputPort("diagnostics"), builder,
                                              period)
        columns["friction"] = [f"friction_{name}" for name in friction.diagnostic_names()]
    for group, logger in loggers.items():
        logger.set_name(f"log_{group}")
    return loggers, columns

