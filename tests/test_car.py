"""The car model: files, loop closure, kinematics, settling, strut friction on the car."""


import numpy as np
import pytest
from numpy.testing import assert_allclose
from pydrake.multibody.plant import MultibodyPlant
from pydrake.systems.analysis import Simulator

from conftest import car_scene
from drake_car.law.checks import ParameterError
from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.model.car import model_source
from drake_car.model.geometry import SIDES
from drake_car.model.kinematics import KinematicsError, SuspensionKinematics
from drake_car.model.kinematics_sweep import run_kinematics_sweep
from drake_car.model.loading import ModelFileError, ModelSource, load_car
from drake_car.model.parameters import CarParameters
from drake_car.model.sdformat import DEFAULT_MODEL_PATH, generate_sdformat
from drake_car.scene.load import SceneError, check_scene
from drake_car.scene.manoeuvres import Settle
from drake_car.scene.scene import Scene
from drake_car.sim.build import build_diagram
from drake_car.sim.simulate import simulate

DMAX = StrutFrictionParameters().dmax_translation_m


def test_committed_model_file_is_the_generators_output():
    assert DEFAULT_MODEL_PATH.read_text() == generate_sdformat(CarParameters()), (
        "urdf/car.sdf is stale: run python -m drake_car.model.sdformat")


@pytest.fixture(scope="module")
def sweep():
    return run_kinematics_sweep(CarParameters(), travel_m=0.08, points=17)


def test_each_front_corner_has_one_degree_of_freedom():
    params = CarParameters()
    kin = SuspensionKinematics(model_source(params), params.front.guide_length_l_m)
    for side in SIDES:
        for travel in (-0.08, 0.0, 0.08):
            kin.solve("front", side, travel)
            jacobian = kin.closure_jacobian(side)
            # 6 closure equations (ball joint 3, tie rod 3) on the corner's 7 coordinates
            # (top mount 2, strut revolute 1, strut prismatic 1, lower arm 1, tie rod 2).
            singular = np.linalg.svd(jacobian, compute_uv=False)
            assert jacobian.shape == (6, 7)
            assert singular[-1] > 1e-3 * singular[0], f"{side} {travel}: loops degenerate"
            assert 7 - np.linalg.matrix_rank(jacobian, tol=1e-6 * singular[0]) == 1


def test_loop_closure_over_travel_and_steering(sweep):
    assert max(sweep.kinematics["closure_error_m"]) < 1e-6
    assert max(sweep.steering["closure_error_m"]) < 1e-6


def test_kinematics_signs_and_ranges(sweep):
    k = sweep.kinematics
    side = np.array(k["side"])
    for s in SIDES:
        mask = side == s
        travel = np.array(k["wheel_travel_m"])[mask]
        assert_allclose(travel[[0, -1]], [-0.08, 0.08])
        strut = np.array(k["strut_length_m"])[mask]
        overlap = np.array(k["overlap_m"])[mask]
        assert np.all(np.diff(strut) < 0), f"{s}: bump must shorten the strut"
        assert np.all(np.diff(overlap) > 0), f"{s}: overlap must grow in bump"
        assert np.all(overlap > 0), f"{s}: the rod must stay in the cylinder"
        design = np.argmin(np.abs(travel))
        assert_allclose(np.array(k["caster_deg"])[mask][design], 2.3, atol=1e-4)
        assert_allclose(np.array(k["kingpin_deg"])[mask][design], 12.0, atol=1e-4)
        assert np.all(np.abs(np.array(k["camber_deg"])[mask]) < 5)
    # Left and right are mirror images.
    for name in ("camber_deg", "toe_deg", "strut_length_m", "overlap_m"):
        values = np.array(k[name])
        assert_allclose(values[side == "left"], values[side == "right"], atol=1e-9)
    st = sweep.steering
    rack = np.array(st["rack_m"])
    left, right = np.array(st["steer_left_deg"]), np.array(st["steer_right_deg"])
    to_left = rack > 0
    assert np.all(left[to_left] > 0) and np.all(right[to_left] > 0), "rack left steers left"
    assert np.all(left[rack < 0] < 0) and np.all(right[rack < 0] < 0)


@pytest.fixture(scope="module")
def settled():
    return simulate(car_scene("settle", "manoeuvre: !Settle {duration_s: 4.0}")).final


def test_settled_corner_loads_match_design_axle_loads(settled):
    loads, design = settled["corner_loads_N"], settled["design_axle_loads_N"]
    assert_allclose(loads["fl"] + loads["fr"], design["front"], rtol=0.02)
    assert_allclose(loads["rl"] + loads["rr"], design["rear"], rtol=0.02)
    assert_allclose(loads["fl"], loads["fr"], rtol=1e-6)
    assert_allclose(settled["total_mass_kg"], CarParameters().mass.total_mass_kg, rtol=1e-12)
    # SAP's regularised constraints: closure well inside the 1e-6 m requirement.
    assert settled["loop_closure_error_m"] < 1e-6
    # Sagged from the design height by tyre deflection plus spring travel, not more than 5 cm.
    r0 = CarParameters().tyre.unloaded_radius_m
    for where, height in settled["ride_height_m"].items():
        assert r0 - 0.05 < height < r0, where


def test_jammed_rods_do_not_return(settled):
    """Paper Fig. 14, curve 3, phase I: with μs = 0.4 the rods stop where they jam."""
    jammed = simulate(car_scene("settle_jammed"))
    t = jammed.history["t"]
    for side in SIDES:
        d = jammed.history[f"d_{side}_m"]
        after = t >= 0.8
        # Stuck: from 0.8 s on the rod moves by its creep at most.
        assert np.ptp(d[after]) <= 2 * DMAX, side
        # ...and away from where a lubricated rod settles (by far more than the creep).
        assert abs(d[-1] - settled["strut_overlap_m"][side]) > 200 * DMAX, side


def test_normal_force_matches_reaction():
    """N of eq. (4) from the system equals N computed here from the strut joint's reaction,
    with the overlap and the mid-point taken from the bodies' world positions; the right strut's
    in the left's reflected frame (its moment, an axial vector, with the opposite sign:
    ``model.struts.make_strut_friction``)."""
    scene = car_scene("settle_jammed", "friction: {law: {mu_s: 0.2, mu_d: 0.15}}")
    built = build_diagram(scene)
    simulator = Simulator(built.diagram)
    simulator.AdvanceTo(1.0)
    root = simulator.get_context()
    plant, car = built.plant, built.car
    pc = plant.GetMyContextFromRoot(root)
    reactions = plant.get_reaction_forces_output_port().Eval(pc)
    world = plant.world_frame()
    system = built.friction
    for side in SIDES:
        prismatic = car.joint(f"strut_prismatic_{side}")
        reaction = reactions[int(prismatic.index())]
        X_WJc = prismatic.frame_on_child().CalcPoseInWorld(pc)
        force_W = X_WJc.rotation().multiply(reaction.translational())
        moment_W = X_WJc.rotation().multiply(reaction.rotational())

        def point(name):
            return plant.CalcPointsPositions(pc, plant.GetFrameByName(name, car.instance),
                                             np.zeros(3), world).ravel()
        guide, piston = point(f"guide_{side}"), point(f"piston_{side}")
        overlap = np.linalg.norm(guide - piston)
        axis = (guide - piston) / overlap
        middle = (guide + piston) / 2
        moment_mid = moment_W + np.cross(X_WJc.translation() - middle, force_W)
        f_perp = force_W - force_W.dot(axis) * axis
        m_perp = moment_mid - moment_mid.dot(axis) * axis
        expected = np.linalg.norm(SIDES[side] * m_perp / overlap + f_perp)
        diagnostics = system.GetOutputPort("diagnostics").Eval(system.GetMyContextFromRoot(root))
        names = system.diagnostic_names()
        assert expected > 100.0, f"{side}: the strut should carry a transverse load"
        assert_allclose(diagnostics[names.index(f"{side}_translation_N")], expected, rtol=1e-9,
                        err_msg=side)
        # The settled car's rotation pair is stuck: static phase, |ω| within the threshold.
        assert diagnostics[names.index(f"{side}_rotation_phase")] == 0.0, side
        assert abs(diagnostics[names.index(f"{side}_rotation_v")]) <= \
            scene.friction.law.dv_rotation_radps


# -- bad input ------------------------------------------------------------------------------

def test_missing_model_file(tmp_path):
    with pytest.raises(ModelFileError, match="nowhere.sdf.*not found"):
        load_car(MultibodyPlant(1e-3), ModelSource(path=tmp_path / "nowhere.sdf"))


def test_malformed_model_file_names_file(tmp_path):
    path = tmp_path / "broken.sdf"
    path.write_text(generate_sdformat(CarParameters()).replace("</model>", "</mod>"))
    with pytest.raises(ModelFileError, match="broken.sdf"):
        load_car(MultibodyPlant(1e-3), ModelSource(path=path))


def test_model_file_missing_a_part(tmp_path):
    path = tmp_path / "no_rack.sdf"
    text = generate_sdformat(CarParameters()).replace('frame name="top_mount_left"',
                                                      'frame name="top_mount_l"')
    path.write_text(text)
    with pytest.raises(ModelFileError, match="no_rack.sdf.*top_mount_left"):
        load_car(MultibodyPlant(1e-3), ModelSource(path=path))


def test_model_file_whose_loop_cannot_close(tmp_path):
    path = tmp_path / "open_loop.sdf"
    params = CarParameters()
    text = generate_sdformat(params)
    # Move the arm's end of the left ball joint 2 cm up: the knuckle cannot reach it.
    start = text.index('<frame name="ball_joint_arm_left"')
    start = text.index("<pose", start)
    end = text.index("</pose>", start)
    x, y, z, *rpy = text[text.index(">", start) + 1:end].split()
    text = (text[:text.index(">", start) + 1]
            + " ".join([x, y, str(float(z) + 0.02)] + rpy) + text[end:])
    path.write_text(text)
    with pytest.raises(ModelFileError, match="open_loop.sdf.*do not close"):
        SuspensionKinematics(ModelSource(path=path), params.front.guide_length_l_m)


def test_travel_out_of_reach():
    with pytest.raises(KinematicsError, match="front left corner"):
        run_kinematics_sweep(CarParameters(), travel_m=0.6, points=5)


@pytest.mark.parametrize("group, name, value", [
    ("mass", "total_mass_kg", 0.0),
    ("mass", "front_wheel_kg", -1.0),
    ("front", "wheel_rate_Npm", 0.0),
    ("rear", "wheel_rate_Npm", -5.0),
    ("front", "rod_radius_r_m", 0.0),
    ("front", "guide_length_l_m", float("nan")),
    ("front", "ball_joint_offset_b_m", 0.9),
    ("tyre", "radial_stiffness_Npm", 0.0),
])
def test_parameter_out_of_range_names_it(group, name, value):
    params = CarParameters()
    setattr(getattr(params, group), name, value)
    with pytest.raises(ParameterError, match=f"{group}.{name}"):
        params.check()
    # A scene is checked once, where it enters (scene.load.check_scene); the build trusts it.
    with pytest.raises(SceneError, match=f"car.{group}.{name}"):
        check_scene(Scene(car=params, manoeuvre=Settle()))


def test_compliant_top_mount_adds_three_joints_per_side_and_keeps_the_mass():
    """A compliant mount is three prismatic joints (x, y, z) per side between the body and the
    strut's universal joint, each held by a SAP spring-damper actuator; the chassis gives up
    the mount's mass so the car's mass is unchanged."""
    rigid, compliant = CarParameters(), CarParameters()
    compliant.front.top_mount_stiffness_Npm = 2e6
    built = {name: build_diagram(Scene(car=p, manoeuvre=Settle()))
             for name, p in (("rigid", rigid), ("compliant", compliant))}
    plants = {name: b.plant for name, b in built.items()}
    assert (plants["compliant"].num_velocities()
            == plants["rigid"].num_velocities() + 6)
    actuators = built["compliant"].car.top_mount_actuators
    assert [a.name() for a in actuators] == [f"top_mount_{a}_{s}" for s in SIDES for a in "xyz"]
    assert all(a.get_controller_gains().p == 2e6 for a in actuators)
    masses = {name: plant.CalcTotalMass(plant.CreateDefaultContext(), [b.car.instance])
              for (name, plant), b in zip(plants.items(), built.values())}
    assert masses["compliant"] == pytest.approx(masses["rigid"], rel=1e-12)
