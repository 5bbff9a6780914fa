"""The tyre system's vertical part, alone and on the car's plant."""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.math import SpatialVelocity
from pydrake.multibody.plant import MultibodyPlant

from drake_car.law.road import Flat
from drake_car.law.tyre_contact import RadialTyre, contact_point, radial_force
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


def tyres_on_the_car(road=None):
    """The tyre system for the car's wheels, alone, with its default context."""
    plant = MultibodyPlant(time_step=1e-3)
    car = add_car(plant)
    plant.Finalize()
    tyres = TyreSystem(car.wheel_bodies(), TYRE, *([] if road is None else [road]))
    return plant, car, tyres, tyres.CreateDefaultContext()


def test_tyre_system_alone():
    plant, car, tyres, context = tyres_on_the_car()
    assert [tyres.get_input_port(i).get_name() for i in range(2)] == [
        "body_poses", "body_spatial_velocities"]
    assert [tyres.get_output_port(i).get_name() for i in range(2)] == [
        "tyre_forces", "tyre_loads"]
    poses = [RigidTransform() for _ in range(plant.num_bodies())]
    velocities = [SpatialVelocity.Zero() for _ in range(plant.num_bodies())]
    bodies = car.wheel_bodies()
    for i, w in enumerate(WHEELS):  # wheel centres 1, 2, 3, 4 cm into the road, upright
        poses[int(bodies[w].index())] = RigidTransform(
            RollPitchYaw(0, 0.3 * i, 0), [i, 0.7, 0.3 - 0.01 * (i + 1)])
    velocities[int(bodies["fl"].index())] = SpatialVelocity(np.zeros(3), [0, 0, -0.1])
    tyres.GetInputPort("body_poses").FixValue(context, poses)
    tyres.GetInputPort("body_spatial_velocities").FixValue(context, velocities)
    loads = tyres.GetOutputPort("tyre_loads").Eval(context)
    expected = [2.0e5 * 0.01 * (i + 1) for i in range(4)]
    expected[0] += 300.0 * 0.1  # compressing at 0.1 m/s
    assert_allclose(loads[:4], expected, rtol=1e-9)
    assert_allclose(loads[4:], [0.01, 0.02, 0.03, 0.04], rtol=1e-9)
    forces = tyres.GetOutputPort("tyre_forces").Eval(context)
    assert len(forces) == 4
    for i, (force, w, fz) in enumerate(zip(forces, WHEELS, expected)):
        assert force.body_index == bodies[w].index()
        assert_allclose(force.F_Bq_W.translational(), [0, 0, fz], rtol=1e-9)
        # Applied at the contact point on the road: R - deflection below the centre.
        assert_allclose(np.linalg.norm(force.p_BoBq_B), 0.3 - 0.01 * (i + 1), rtol=1e-9)


def test_road_profiles():
    from drake_car.law.checks import ParameterError
    from drake_car.law.road import CosineBump, SampledProfile
    bump = CosineBump(start_x_m=10.0, length_m=0.5, height_m=0.04).check()
    assert bump(9.9, 0.0) == 0.0 and bump(10.5, 1.0) == 0.0
    assert bump(10.25, -0.7) == pytest.approx(0.04)
    pothole = CosineBump(10.0, 0.5, -0.03)
    assert pothole(10.25, 0.0) == pytest.approx(-0.03)
    samples = SampledProfile([0.0, 1.0, 3.0], [0.0, 0.01, -0.01]).check()
    assert samples(0.5, 0.0) == pytest.approx(0.005) and samples(5.0, 0.0) == -0.01
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
    from drake_car.law.road import CosineBump
    plant, car, tyres, context = tyres_on_the_car(
        CosineBump(start_x_m=-0.25, length_m=0.5, height_m=0.04))
    poses = [RigidTransform() for _ in range(plant.num_bodies())]
    for w, body in car.wheel_bodies().items():
        x = 0.0 if w == "fl" else 5.0
        poses[int(body.index())] = RigidTransform([x, 0.7, 0.32])
    tyres.GetInputPort("body_poses").FixValue(context, poses)
    tyres.GetInputPort("body_spatial_velocities").FixValue(
        context, [SpatialVelocity.Zero()] * plant.num_bodies())
    loads = tyres.GetOutputPort("tyre_loads").Eval(context)
    assert_allclose(loads[:4], [2.0e5 * 0.02, 0, 0, 0], atol=1e-6)
