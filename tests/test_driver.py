"""The driver connected from outside: the path-following LeafSystem alone, the car's Diagram
with its driver inputs exported (port names), and a closed loop built in an outer
DiagramBuilder that holds the lane and the speed (a physical outcome, bounds derived below)."""

import math

import numpy as np
import pytest
from pydrake.math import RigidTransform
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder

from drake_car.law.errors import InputError
from drake_car.law.road.centre_line import CentreLine
from drake_car.scene.load import load_scene
from drake_car.scene.paths import PathFollower
from drake_car.sim.build import build_diagram
from drake_car.sim.driver_wiring import (
    CHASSIS_COLUMNS, rack_per_steer_m_per_rad, speed_law, steering_law)
from drake_car.sim.simulate import static_equilibrium
from drake_car.sim.simulation import logged_history
from drake_car.systems.path_driver import (
    PathDriver, SpeedLaw, SteeringLaw, preview_gain_rad_per_m)

def _update(system, context):
    values = system.AllocateDiscreteVariables()
    system.CalcForcedDiscreteVariableUpdate(context, values)
    return values


STRAIGHT = CentreLine([-50.0, 500.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0])


def test_path_driver_alone_steers_back_to_the_line_and_holds_speed():
    law = SteeringLaw(preview_m=10.0, gain_rad_per_m=0.1, wheelbase_m=2.5,
                      rack_per_steer_m_per_rad=0.12, rack_limit_m=0.07)
    speed = SpeedLaw(target_mps=10.0, gain_Nm_per_mps=400.0, integral_time_s=2.0,
                     max_torque_Nm=1000.0)
    columns = ("x_m", "y_m", "yaw_rad", "speed_mps", "sideslip_rad")
    driver = PathDriver(STRAIGHT, law, motion_columns=columns, period_s=0.01, speed=speed)
    assert [driver.get_input_port(i).get_name() for i in range(driver.num_input_ports())] == [
        "chassis_motion"]
    assert [driver.get_output_port(i).get_name() for i in range(driver.num_output_ports())] == [
        "rack_position_m", "drive_torque_Nm", "tracking"]
    context = driver.CreateDefaultContext()
    # 0.5 m left of the line, heading 0.02 rad left of it, travelling 0.01 rad further left.
    driver.chassis_motion_input_port().FixValue(context, [20.0, 0.5, 0.02, 9.0, 0.01])
    context.SetDiscreteState(1, [70.0, 0.0, 0.0])  # the last station: it searches near it
    update = _update(driver, context)
    rack = update.get_vector(0).get_value()[0]
    e_preview = 0.5 + 10.0 * math.sin(0.03)
    assert rack == pytest.approx(0.12 * (-0.1 * e_preview)), "δ = -k (e + L sin e_ψ), rack = c δ"
    station, offset, heading_error = update.get_vector(1).get_value()
    np.testing.assert_allclose([station, offset, heading_error], [70.0, 0.5, 0.03], atol=1e-12)
    torque = update.get_vector(3).get_value()[0]
    assert torque == pytest.approx(400.0 * 1.0), "K_v e_v with no integral yet"
    driver.chassis_motion_input_port().FixValue(context, [20.0, 0.0, 0.0, 0.0, 0.0])
    clamped = _update(driver, context)
    assert clamped.get_vector(3).get_value()[0] == pytest.approx(1000.0), "clamped"
    assert clamped.get_vector(2).get_value()[0] == 0.0, "no integral wind-up while clamped"


def test_path_driver_holds_a_circle_with_its_feed_forward():
    """On the circle, travelling along it, the rack is the curvature feed-forward alone."""
    from drake_car.law.road.centre_line import circle_line
    line = circle_line(0.0, 40.0, True, 200.0)
    law = SteeringLaw(preview_m=10.0, gain_rad_per_m=0.1, wheelbase_m=2.5,
                      rack_per_steer_m_per_rad=0.12, rack_limit_m=0.07)
    driver = PathDriver(line, law, motion_columns=("x_m", "y_m", "yaw_rad", "speed_mps",
                                                   "sideslip_rad"))
    context = driver.CreateDefaultContext()
    angle = 0.7  # on the circle, heading along its tangent
    driver.chassis_motion_input_port().FixValue(
        context, [40.0 * math.sin(angle), 40.0 * (1 - math.cos(angle)), angle, 10.0, 0.0])
    context.SetDiscreteState(1, [50.0 + 40.0 * angle, 0.0, 0.0])
    rack = _update(driver, context).get_vector(0).get_value()[0]
    assert rack == pytest.approx(0.12 * 2.5 / 40.0, rel=1e-3)


def test_preview_gain_gives_the_damping_ratio():
    """k = 4 ζ² l / L²: the kinematic car's closed loop s² + (u k L / l) s + u² k / l."""
    l, preview, u = 2.4, 10.0, 15.0
    for zeta in (0.7, 1.0, 1.5):
        k = preview_gain_rad_per_m(preview, l, zeta)
        wn = u * math.sqrt(k / l)
        assert (u * k * preview / l) / (2 * wn) == pytest.approx(zeta)


def _external(scene_text):
    return build_diagram(load_scene(scene_text=scene_text), external_driver=True)


def test_external_driver_ports():
    built = _external("manoeuvre: !Straight {}\nfriction: {law: {mu_s: 0.2, mu_d: 0.15}}\n"
                      "car: {front: {strut_damping_Nspm: 0.0}}")
    diagram = built.diagram
    assert [diagram.get_input_port(i).get_name() for i in range(diagram.num_input_ports())] \
        == ["drive_torque_Nm", "rack_position_m"]
    assert [diagram.get_output_port(i).get_name() for i in range(diagram.num_output_ports())] \
        == ["car_state", "chassis_motion", "body_poses", "body_spatial_velocities",
            "tyre_loads_N", "tyre_diagnostics", "strut_friction_diagnostics"]
    assert set(built.inputs) == {"drive_torque_Nm", "rack_position_m"}
    assert built.outputs["chassis_motion"].size() == len(CHASSIS_COLUMNS)
    plant, instance = built.plant, built.car.instance
    assert built.outputs["car_state"].size() == (plant.num_positions(instance)
                                                 + plant.num_velocities(instance))
    assert built.outputs["strut_friction_diagnostics"].size() == len(
        built.friction.diagnostic_names())
    # The loads alone (the tyre system's own port holds the radial deflections after them).
    assert built.outputs["tyre_loads_N"].size() == 4
    assert built.outputs["tyre_diagnostics"].size() == len(built.tyre.diagnostic_names())
    # No friction: no diagnostics port; a manoeuvre that does not drive: no torque input.
    settle = _external("manoeuvre: !Settle {}")
    assert set(settle.inputs) == {"rack_position_m"}
    assert "strut_friction_diagnostics" not in settle.outputs


def test_external_driver_refused_where_it_cannot_be():
    scene = load_scene(scene_text="drive: !PrescribedRotation {}")
    with pytest.raises(InputError, match="OpenDifferential"):
        build_diagram(scene, external_driver=True)
    with pytest.raises(InputError, match="HeldRack"):
        build_diagram(load_scene(scene_text="steering: !HandsOff {}"), external_driver=True)


def test_the_linkage_ratio_steers_left_with_the_rack_left():
    """Rack travel per road-wheel angle: positive (rack left + turns left +) and of a car's
    size (0.07 m of stroke over 25-45 degrees of lock)."""
    ratio = rack_per_steer_m_per_rad(load_scene().car)
    assert 0.07 / math.radians(45) < ratio < 0.07 / math.radians(25)


# A strongly understeering passenger car [EST]: 0.1 rad of road-wheel angle per g (5.7 deg/g;
# cars of this class run 1-4 deg/g). It bounds how slowly the lane offset decays (below).
MAX_UNDERSTEER_RAD_PER_G = 0.1


def test_an_outside_driver_holds_the_lane_and_the_speed():
    """The car's Diagram with its driver inputs exported; a PathDriver on the lane's centre
    line (y = 0) connected in an outer DiagramBuilder; the car starts at rest 0.5 m left of
    the line and speeds up to 60 km/h.

    Lane: the loop has ζ = 1 for a neutral car (k = 4 l / L²); understeer η = 1 + K u²/(g l)
    lowers ζ and ω_n by sqrt(η), so the offset's envelope decays at σ = ζ ω_n = 2 u / (L η)
    at least. From the time the car passes half the target speed, σ >= 2 u_h / (L η(u_t))
    with K at its upper bound; the offset at the end is then at most 0.5 m (1 + σT) e^(-σT)
    (the critically damped envelope), and never more than the 0.5 m it started with (the
    overshoot of ζ >= 0.7 is < 5 %). It never leaves the 3.7 m lane.
    Speed: the PI's clamp lets go at the error e_s = T_max / K_v; from there the critically
    damped loop (ω = 1 / (2τ)) leaves at most e_s (1 + ωT) e^(-ωT) after T."""
    target = 60.0 / 3.6
    scene = load_scene(scene_text="manoeuvre: !Straight {timeline: {settle_s: 0.5, "
                                  "speed_up_s: 3.0, straight_s: 3.0, steer_s: 0.5, "
                                  "calm_s: 0.0}}")
    car = build_diagram(scene, external_driver=True)
    builder = DiagramBuilder()
    builder.AddSystem(car.diagram)
    follower = PathFollower(preview_m=10.0, damping_ratio=1.0)
    law = steering_law(scene.car, follower)
    speed = speed_law(scene.car, target, time_constant_s=0.5)
    driver = builder.AddSystem(PathDriver(STRAIGHT, law, motion_columns=CHASSIS_COLUMNS,
                                          speed=speed))
    builder.Connect(car.outputs["chassis_motion"], driver.chassis_motion_input_port())
    builder.Connect(driver.rack_output_port(), car.inputs["rack_position_m"])
    builder.Connect(driver.drive_torque_output_port(), car.inputs["drive_torque_Nm"])
    simulator = Simulator(builder.Build())
    root = simulator.get_mutable_context()
    plant_context = car.plant.GetMyMutableContextFromRoot(root)
    car.plant.SetPositions(plant_context, car.car.instance,
                           np.asarray(static_equilibrium(scene).positions))
    chassis = car.car.body("chassis")
    pose = car.plant.EvalBodyPoseInWorld(plant_context, chassis)
    start_offset = 0.5
    car.plant.SetFreeBodyPose(plant_context, chassis, RigidTransform(
        pose.rotation(), pose.translation() + [0.0, start_offset, 0.0]))
    simulator.Initialize()
    simulator.AdvanceTo(scene.end_time_s)
    history = logged_history(car, root)
    t, y, v = history["t"], history["y_m"], history["speed_mps"]

    g, l, L = 9.81, scene.car.wheelbase_m, follower.preview_m
    eta = 1 + MAX_UNDERSTEER_RAD_PER_G * target ** 2 / (g * l)
    t_half = t[np.argmax(v >= target / 2)]
    sigma = 2 * (target / 2) / (L * eta)
    T = t[-1] - t_half
    lane_bound = start_offset * (1 + sigma * T) * math.exp(-sigma * T)
    assert abs(y[-1]) <= lane_bound, (y[-1], lane_bound)
    assert np.max(np.abs(y)) <= start_offset * 1.05, np.max(np.abs(y))
    assert np.max(np.abs(y)) + 1.69 / 2 < 3.7 / 2, "inside its lane"

    e_s = speed.max_torque_Nm / speed.gain_Nm_per_mps
    t_free = t[np.argmax(v >= target - e_s)]
    omega = 1 / (2 * 0.5)
    T = t[-1] - t_free
    speed_bound = e_s * (1 + omega * T) * math.exp(-omega * T)
    assert abs(v[-1] - target) <= speed_bound, (v[-1], target, speed_bound)

    # The exported loads are the tyre system's first four values (its deflections left out).
    loads = car.outputs["tyre_loads_N"].Eval(car.diagram.GetMyContextFromRoot(root))
    own = car.tyre.GetOutputPort("tyre_loads").Eval(car.tyre.GetMyContextFromRoot(root))
    np.testing.assert_array_equal(loads, own[:4])
    # They carry the car: it has held its speed on the flat road for over 2 s, long after its
    # heave mode (about 1.5 Hz, damping ratio about 0.3: e-fold in about 0.35 s) settled, so
    # the body's vertical acceleration is below 0.1 % of g.
    assert loads.sum() == pytest.approx(scene.car.mass.total_mass_kg * 9.81, rel=1e-3)
