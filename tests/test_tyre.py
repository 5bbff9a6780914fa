"""The tyre system's vertical part, alone and on the car's plant."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.math import SpatialVelocity
from pydrake.multibody.plant import MultibodyPlant

from drake_car.law.road.profiles import Flat
from drake_car.law.tyre.contact import RadialTyre, contact_point, radial_force
from drake_car.model.car import add_car
from drake_car.systems.tyre import WHEELS, TyreSystem

TYRE = RadialTyre(unloaded_radius_m=0.3, radial_stiffness_Npm=2.0e5, radial_damping_Nspm=300.0)


def test_contact_point_of_a_cambered_wheel():
    # Spin axis tilted by 5 deg about x: the lowest point of the circle is R below the centre
    # along the in-plane downward direction, i.e. R cos(5 deg) below it.
    tilt = np.radians(5.0)
    axis = np.array([0.0, np.cos(tilt), np.sin(tilt)])
    point, deflection, _ = contact_point(np.array([1.0, 2.0, 0.29]), axis, 0.3, Flat())
    assert_allclose(deflection, 0.3 * np.cos(tilt) - 0.29, rtol=1e-12)
    assert_allclose(point[2], 0.0)


def test_radial_force_never_pulls():
    assert radial_force(TYRE, 0.0, -1.0) == 0.0
    assert_allclose(radial_force(TYRE, 0.01, 0.0), 2000.0)
    assert radial_force(TYRE, 0.001, -10.0) == 0.0  # damper would pull: clipped
    with pytest.raises(ValueError, match="radial_stiffness_Npm"):
        RadialTyre(0.3, 0.0, 1.0)


def tyres_on_the_car(road=None, kinematics="ports"):
    """The tyre system for the car's wheels, alone, with its default context."""
    plant = MultibodyPlant(time_step=1e-3)
    car = add_car(plant)
    plant.Finalize()
    tyres = TyreSystem(car.wheel_bodies(), TYRE, *([] if road is None else [road]),
                       time_step_s=1e-3, kinematics=kinematics)
    return plant, car, tyres, tyres.CreateDefaultContext()


def test_tyre_system_alone():
    plant, car, tyres, context = tyres_on_the_car()
    assert [tyres.get_input_port(i).get_name() for i in range(2)] == [
        "body_poses", "body_spatial_velocities"]
    assert [tyres.get_output_port(i).get_name() for i in range(3)] == [
        "tyre_wrenches", "tyre_loads", "tyre_diagnostics"]
    poses = [RigidTransform() for _ in range(plant.num_bodies())]
    velocities = [SpatialVelocity.Zero() for _ in range(plant.num_bodies())]
    bodies = car.wheel_bodies()
    for i, w in enumerate(WHEELS):  # wheel centres 1, 2, 3, 4 cm into the road, upright
        poses[int(bodies[w].index())] = RigidTransform(
            RollPitchYaw(0, 0.3 * i, 0), [i, 0.7, 0.3 - 0.01 * (i + 1)])
    velocities[int(bodies["fl"].index())] = SpatialVelocity(np.zeros(3), [0, 0, -0.1])
    tyres.GetInputPort("body_poses").FixValue(context, poses)
    tyres.GetInputPort("body_spatial_velocities").FixValue(context, velocities)
    # The outputs are state: computed by the initialization event, then by each step's update.
    tyres.ExecuteInitializationEvents(context)
    loads = tyres.GetOutputPort("tyre_loads").Eval(context)
    expected = [2.0e5 * 0.01 * (i + 1) for i in range(4)]
    expected[0] += 300.0 * 0.1  # compressing at 0.1 m/s
    assert_allclose(loads[:4], expected, rtol=1e-9)
    assert_allclose(loads[4:], [0.01, 0.02, 0.03, 0.04], rtol=1e-9)
    wrenches = tyres.GetOutputPort("tyre_wrenches").Eval(context)
    assert len(wrenches) == 6 * 4
    for i, (w, fz) in enumerate(zip(WHEELS, expected)):
        # Force and moment about the centre in the wheel's frame: straight up in world, and no
        # moment (the contact point lies right below the centre of an upright wheel).
        rotation = poses[int(bodies[w].index())].rotation()
        assert_allclose(rotation.multiply(wrenches[6 * i:6 * i + 3]), [0, 0, fz], atol=1e-9)
        assert_allclose(wrenches[6 * i + 3:6 * i + 6], 0.0, atol=1e-9)
    # Drake's C++ applies them: per wheel its force and moment along the wheel's axes.
    applier = tyres.make_applier()
    applier_context = applier.CreateDefaultContext()
    applier.get_command_input_port().FixValue(applier_context, wrenches)
    applier.get_body_poses_input_port().FixValue(applier_context, poses)
    forces = applier.get_spatial_forces_output_port().Eval(applier_context)
    assert len(forces) == 6 * 4
    for i, (w, fz) in enumerate(zip(WHEELS, expected)):
        mine = forces[6 * i:6 * i + 6]
        assert all(f.body_index == bodies[w].index() for f in mine)
        total = sum(f.F_Bq_W.get_coeffs() for f in mine)
        assert_allclose(total, [0, 0, 0, 0, 0, fz], atol=1e-9)


def test_state_kinematics_equal_the_plant_s():
    """The wheels' motion from the plant's state (compiled kinematics) gives the same forces as
    from the plant's pose and velocity lists, at a state with every coordinate moved."""
    from drake_car.law.tyre.magic_formula import MagicFormulaTyre
    from drake_car.data import resource
    magic = MagicFormulaTyre.from_file(str(resource("urdf/tyres/pacejka2006_205_60R15.tir")))
    plant = MultibodyPlant(time_step=1e-3)
    car = add_car(plant)
    plant.Finalize()
    plant_context = plant.CreateDefaultContext()
    rng = np.random.default_rng(1)
    q = plant.GetPositions(plant_context) + rng.uniform(-0.02, 0.02, plant.num_positions())
    q[car.body("chassis").floating_positions_start() + 6] -= 0.02  # the body 2 cm lower
    plant.SetPositions(plant_context, q)
    plant.SetVelocities(plant_context, rng.uniform(-3, 3, plant.num_velocities()))
    outputs = {}
    for kinematics in ("state", "ports"):
        tyres = TyreSystem(car.wheel_bodies(), TYRE, magic_formula_tyre=magic, time_step_s=1e-3,
                           kinematics=kinematics)
        context = tyres.CreateDefaultContext()
        if kinematics == "state":
            tyres.GetInputPort("plant_state").FixValue(
                context, plant.GetPositionsAndVelocities(plant_context))
        else:
            tyres.GetInputPort("body_poses").FixValue(
                context, plant.get_body_poses_output_port().Eval(plant_context))
            tyres.GetInputPort("body_spatial_velocities").FixValue(
                context, plant.get_body_spatial_velocities_output_port().Eval(plant_context))
        tyres.ExecuteInitializationEvents(context)
        outputs[kinematics] = [tyres.GetOutputPort(name).Eval(context).copy()
                               for name in ("tyre_wrenches", "tyre_loads", "tyre_diagnostics")]
    assert np.max(outputs["state"][1][:4]) > 100.0, "the wheels touch the road"
    for state, ports in zip(outputs["state"], outputs["ports"]):
        assert_allclose(state, ports, rtol=1e-9, atol=1e-9)


def test_road_profiles():
    from drake_car.law.checks import ParameterError
    from drake_car.law.road.profiles import CosineBump, SampledProfile
    bump = CosineBump(start_x_m=10.0, length_m=0.5, height_m=0.04).check()
    assert bump(9.9, 0.0) == 0.0 and bump(10.5, 1.0) == 0.0
    assert bump(10.25, -0.7) == pytest.approx(0.04)
    pothole = CosineBump(10.0, 0.5, -0.03)
    assert pothole(10.25, 0.0) == pytest.approx(-0.03)
    samples = SampledProfile([0.0, 1.0, 3.0], [0.0, 0.01, -0.01]).check()
    assert samples(0.5, 0.0) == pytest.approx(0.005) and samples(5.0, 0.0) == -0.01
    assert samples(0.5, -0.7) == samples(0.5, 0.7)  # one profile across the road
    tracks = SampledProfile([0.0, 1.0, 3.0], [0.0, 0.01, -0.01], [0.0, -0.02, 0.0]).check()
    assert tracks(0.5, 0.7) == pytest.approx(0.005) and tracks(0.5, -0.7) == pytest.approx(-0.01)
    assert tracks.flat_up_to_m() == 0.0 and samples.flat_up_to_m() == 0.0
    assert SampledProfile([0.0, 1.0, 3.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.01]).flat_up_to_m() == 1.0
    assert SampledProfile([0.0, 1.0], [0.01, 0.0]).flat_up_to_m() == -math.inf
    assert bump.flat_up_to_m() == 10.0 and Flat().flat_up_to_m() == math.inf
    with pytest.raises(ParameterError, match=r"z_right_m \(1 samples\)"):
        SampledProfile([0.0, 1.0], [0.0, 0.0], [0.0]).check()
    with pytest.raises(ParameterError, match=r"z_right_m\[1\] = 1.0 makes a slope"):
        SampledProfile([0.0, 1.0], [0.0, 0.0], [0.0, 1.0]).check()
    with pytest.raises(ParameterError, match=r"x_m\[2\] = 1.0 must be > x_m\[1\]"):
        SampledProfile([0.0, 1.0, 1.0], [0, 0, 0]).check()
    with pytest.raises(ParameterError, match=r"x_m\[1\] = nan must be a finite number"):
        SampledProfile([0.0, float("nan")], [0, 0]).check()
    with pytest.raises(ParameterError, match="length_m = 0.0 must be > 0"):
        CosineBump(0.0, 0.0, 0.1).check()
    with pytest.raises(ParameterError, match="slope"):  # 0.2 m over 0.5 m: 1.26 > 0.3
        CosineBump(0.0, 0.5, 0.2).check()


def test_tyre_load_on_a_bump():
    """A wheel 2 cm above the flat road touches a 4 cm bump by 2 cm: Fz = k·0.02."""
    from drake_car.law.road.profiles import CosineBump
    plant, car, tyres, context = tyres_on_the_car(
        CosineBump(start_x_m=-0.25, length_m=0.5, height_m=0.04))
    poses = [RigidTransform() for _ in range(plant.num_bodies())]
    for w, body in car.wheel_bodies().items():
        x = 0.0 if w == "fl" else 5.0
        poses[int(body.index())] = RigidTransform([x, 0.7, 0.32])
    tyres.GetInputPort("body_poses").FixValue(context, poses)
    tyres.GetInputPort("body_spatial_velocities").FixValue(
        context, [SpatialVelocity.Zero()] * plant.num_bodies())
    tyres.ExecuteInitializationEvents(context)
    loads = tyres.GetOutputPort("tyre_loads").Eval(context)
    assert_allclose(loads[:4], [2.0e5 * 0.02, 0, 0, 0], atol=1e-6)
