"""A car from its hard points (issue 31): the car file's points placed exactly, the same car
given by today's parameters builds the same model and settles the same, the engineer's car both
ways is one car, a saved scene of a car file reruns bit for bit, the file lies beneath the
scene's car: values, and values an engineer would not enter are refused with the reason."""

import dataclasses
import re

import numpy as np
import pytest
from numpy.testing import assert_allclose
from pydrake.common.yaml import yaml_dump_typed
from pydrake.multibody.plant import MultibodyPlant

from drake_car.model.car import model_source
from drake_car.model.geometry import SIDES, centre_of_mass, front_corner_points
from drake_car.model.hard_point_table import hard_point_table
from drake_car.model.hard_points import (
    FRONT_POINTS, HardPointCar, frame_shift_m, from_parameters, to_parameters,
    whole_car_inertia_kgm2)
from drake_car.model.loading import data_path, load_car
from drake_car.model.parameters import CarParameters
from drake_car.model.seat import ESCORT_SEAT_POINT_M, estimated_seat_point_m
from drake_car.model.sdformat import generate_sdformat
from drake_car.scene.car_file import read_car_file
from drake_car.scene.load import SceneError, dump_scene, dump_scene_file, load_scene
from drake_car.sim.simulate import simulate

ENGINEER = "cars/engineers_car.yaml"
ENGINEER_SCENES = "scenes/engineers_car.yaml"
SETTLE = "{manoeuvre: !Settle {duration_s: 1.5}, tyres: !VerticalOnly {}, simulator: {start: design}}"
# What a point of the file and the generator's may differ by: the angles' round trip
# (atan, then tan) and the model file's 15 significant digits, of points within 2 m.
POINT_TOLERANCE_M = 1e-13


def _write_car(path, car: HardPointCar):
    path.write_text(yaml_dump_typed(car, schema=HardPointCar))
    return str(path)


def _numbers(sdformat):
    """The numbers of a model file's model (its header comment names the car)."""
    model = sdformat[sdformat.index("<model"):]
    return np.array([float(x) for x in re.findall(r"-?\d+\.?\d*(?:e-?\d+)?", model)])


def test_the_generator_places_every_hard_point_where_the_file_puts_it():
    """A car whose strut axis leans back unlike its steering axis and whose spring seats sit
    off the strut axis both ways (what today's angles could not say before): every point of the
    generated model is the file's, moved into V, to round-off; both sides."""
    car = from_parameters(CarParameters())
    f = car.front
    f.strut_lower_mount_m = [0.040, 0.600, 0.300]
    f.spring_lower_seat_m = [0.030, 0.560, 0.520]
    f.spring_upper_seat_m = [-0.010, 0.520, 0.760]
    f.wheel_centre_m = [0.35, 0.695, 0.300]  # another x origin, drawn at ride height
    for name in FRONT_POINTS:
        if name != "wheel_centre_m":
            setattr(f, name, list(np.array(getattr(f, name)) + [0.35, 0.0, -0.013]))
    car.check()
    params = to_parameters(car)
    shift = frame_shift_m(car)
    assert_allclose(shift, [-0.35, 0.0, 0.013], atol=1e-15)
    names = {"wheel_centre_m": "wheel_centre", "lower_arm_front_pivot_m": "arm_front_pivot",
             "lower_arm_rear_pivot_m": "arm_rear_pivot", "ball_joint_m": "ball_joint",
             "strut_top_mount_m": "top_mount", "strut_lower_mount_m": "strut_lower_mount",
             "spring_upper_seat_m": "spring_upper_seat",
             "spring_lower_seat_m": "spring_lower_seat", "tie_rod_inner_m": "tie_rod_inner",
             "tie_rod_outer_m": "tie_rod_outer"}
    for side, s in SIDES.items():
        placed = front_corner_points(params, s)
        for name, attribute in names.items():
            given = (np.array(getattr(f, name)) + shift) * [1.0, s, 1.0]
            assert_allclose(getattr(placed, attribute), given, rtol=0, atol=POINT_TOLERANCE_M,
                            err_msg=f"{side} {name}")
    assert params.front.strut_caster_deg != pytest.approx(params.front.caster_deg, abs=0.1)
    assert abs(params.front.spring_offset_fore_aft_m) > 0.005


def test_the_escort_by_its_points_builds_the_same_model_and_settles_the_same(tmp_path):
    """The shipped car given by today's parameters and the same car given by its hard points
    (its car file, ``from_parameters``) make the same model file to its 15 digits and settle
    to the same state."""
    path = _write_car(tmp_path / "escort.yaml", from_parameters(CarParameters()))
    by_parameters = load_scene(scene_text=SETTLE)
    by_points = load_scene(scene_text=SETTLE[:-1] + f", car_file: {path}}}")
    assert by_points.car != by_parameters.car, "the angles come back from the points"
    numbers = [_numbers(generate_sdformat(s.car)) for s in (by_parameters, by_points)]
    assert_allclose(numbers[1], numbers[0], rtol=1e-14, atol=POINT_TOLERANCE_M)
    runs = [simulate(s) for s in (by_parameters, by_points)]
    assert_allclose(runs[1].final["positions"], runs[0].final["positions"], rtol=0, atol=1e-12)
    for name in ("z_m", "pitch_rad", "d_left_m", "d_right_m"):
        assert_allclose(runs[1].history[name], runs[0].history[name], rtol=0, atol=1e-12,
                        err_msg=name)


def test_the_whole_car_is_what_its_file_says():
    """The plant built from the engineer's car file has the file's mass, the whole car's
    centre of gravity and its moments of inertia about it (the body takes the remainder)."""
    given = read_car_file(ENGINEER)
    scene = load_scene(ENGINEER_SCENES, child="points")
    plant = MultibodyPlant(1e-3)
    instance = load_car(plant, model_source(scene.car))
    plant.Finalize()
    context = plant.CreateDefaultContext()
    bodies = list(plant.GetBodyIndices(instance))
    shift = frame_shift_m(given)
    centre = np.array([-given.mass.cog_behind_front_axle_m, 0.0, given.mass.cog_height_m]) + shift
    assert plant.CalcTotalMass(context, [instance]) == pytest.approx(1500.0, rel=1e-6)
    assert_allclose(plant.CalcCenterOfMassPositionInWorld(context, [instance]), centre,
                    atol=1e-6, err_msg="the model file's masses have 6 digits")
    inertia = plant.CalcSpatialInertia(context, plant.world_frame(), bodies).Shift(
        centre).CalcRotationalInertia().CopyToFullMatrix3()
    # 6 significant digits in the model file's inertias; the parts' products of inertia stay.
    assert_allclose(np.diag(inertia), given.mass.inertia_kgm2, rtol=1e-5)
    assert_allclose(whole_car_inertia_kgm2(scene.car), given.mass.inertia_kgm2, rtol=1e-12)


def test_the_engineers_car_both_ways_is_one_car():
    points = load_scene(ENGINEER_SCENES, child="points")
    parameters = load_scene(ENGINEER_SCENES, child="parameters")
    assert points.car == parameters.car
    car = points.car
    assert car.front.ball_joint_offset_b_m == pytest.approx(0.06, abs=1e-15)
    assert car.front.guide_length_l_m == 0.18 and car.front.wheel_rate_Npm == 28000.0
    assert car.mass.total_mass_kg == 1500.0
    cog = centre_of_mass(car) - frame_shift_m(read_car_file(ENGINEER))
    assert_allclose([-cog[0], cog[2]], [1.05, 0.55], atol=1e-12)
    # Not the sprung mass's: the body's own centre lies elsewhere.
    assert abs(car.mass.cog_to_front_axle_m - 1.05) > 1e-3


def test_a_saved_scene_of_a_car_file_reruns_bit_for_bit(tmp_path):
    scene = load_scene(ENGINEER_SCENES, child="points", scene_text="simulator: {end_time_s: 0.2}")
    run = simulate(scene)
    saved = tmp_path / "scene.yaml"
    text = dump_scene_file(run.scene)
    saved.write_text(text)
    assert "car_file: cars/engineers_car.yaml" in text
    assert "kingpin_inclination_deg: 12.00048697617058" in text, "the derived values are saved"
    again = load_scene(saved)
    assert dump_scene(again) == dump_scene(run.scene) and again.car == run.scene.car
    rerun = simulate(again)
    for name in run.history:
        if name != "phase":
            assert np.array_equal(rerun.history[name], run.history[name]), name


def test_the_car_file_lies_beneath_the_scene_s_car_values():
    """The paper's dry strut (car.front.strut_damping_Nspm: 0) and a design factor (b) lay over
    the file's car, in a file's entry, a --scene_text and a base scene alike."""
    text = f"{{car_file: {ENGINEER}, car: {{front: {{strut_damping_Nspm: 0.0}}}}}}"
    scene = load_scene(scene_text=text)
    assert scene.car.front.strut_damping_Nspm == 0.0
    assert scene.car.mass.total_mass_kg == 1500.0
    # The car file given after the scene's own car values (a study's base, then the user's
    # --scene_text): the base's values stay laid over the new car.
    base = load_scene(scene_text="car: {front: {strut_damping_Nspm: 0.0, guide_length_l_m: 0.15}}")
    rebased = load_scene(base=base, scene_text=f"car_file: {ENGINEER}")
    assert rebased.car.front.strut_damping_Nspm == 0.0
    assert rebased.car.front.guide_length_l_m == 0.15
    assert rebased.car.mass.total_mass_kg == 1500.0
    back = load_scene(base=rebased, scene_text="car_file: null")
    assert back.car.mass.total_mass_kg == CarParameters().mass.total_mass_kg
    assert back.car.front.strut_damping_Nspm == 0.0
    moved = load_scene(scene_text=f"{{car_file: {ENGINEER}, "
                                  "car: {front: {ball_joint_offset_b_m: 0.08}}}")
    assert moved.car.front.ball_joint_offset_b_m == 0.08


def test_the_hard_point_table_says_what_was_entered_and_what_derived():
    escort = {r.quantity: r for r in hard_point_table(CarParameters())}
    assert escort["kingpin inclination"].kind == "input"
    assert escort["ball joint"].kind == "derived"
    assert escort["kingpin inclination"].value == (12.0,)
    # The ground intercept of the steering axis lies inboard of the contact centre (positive
    # scrub) and ahead of it (positive trail) on the shipped car.
    assert escort["scrub radius"].value[0] > 0 and escort["caster trail"].value[0] > 0
    given = read_car_file(ENGINEER)
    scene = load_scene(ENGINEER_SCENES, child="points")
    rows = {r.quantity: r for r in hard_point_table(scene.car, given)}
    assert rows["ball joint"].kind == "input" and rows["kingpin inclination"].kind == "derived"
    assert_allclose(rows["ball joint"].value, given.front.ball_joint_m, atol=1e-15)
    assert_allclose(rows["whole car's CoG behind the front axle, height"].value, (1.05, 0.55),
                    atol=1e-12)
    assert rows["ball-joint offset b"].value[0] == pytest.approx(0.06)
    assert 0.8 < rows["front ride frequency"].value[0] < 2.0


def _engineer(tmp_path, change):
    car = read_car_file(ENGINEER)
    change(car)
    return _write_car(tmp_path / "car.yaml", car)


def _set(group, name, value):
    def change(car):
        setattr(getattr(car, group) if group else car, name, value)
    return change


@pytest.mark.parametrize("label, change, key, reason", [
    ("a wheel rate in kN/m", _set("front", "wheel_rate_Npm", 28.0), "car.front.wheel_rate_Npm",
     r"ride frequency of 0.0\d+ Hz .* 0.8..2 Hz, a wheel rate of \d+..\d+ N/m"),
    ("a CoG behind the rear axle", _set("mass", "cog_behind_front_axle_m", 2.6),
     "mass.cog_behind_front_axle_m", r"inside the wheelbase"),
    ("a CoG 1.2 m high", _set("mass", "cog_height_m", 1.2), "mass.cog_height_m",
     r"static stability factor"),
    ("a ball joint above the top mount", _set("front", "ball_joint_m", [0.026, 0.635, 0.9]),
     "front.ball_joint_m", r"below strut_top_mount_m"),
    ("an arm of zero length", _set("front", "lower_arm_rear_pivot_m", [0.251, 0.320, 0.196]),
     "front.lower_arm_rear_pivot_m", r"bushes at least"),
    ("an arm that does not reach", _set("front", "ball_joint_m", [0.1, 0.33, 0.1955]),
     "front.ball_joint_m", r"from the lower arm's pivot axis"),
    ("a strut longer than its travel", _set("front", "guide_length_l_m", 0.5),
     "car.front.guide_length_l_m", r"too long"),
    ("no rebound travel", _set("front", "guide_length_l_m", 0.02),
     "car.front.guide_length_l_m", r"rebound travel"),
    ("an impossible inertia", _set("mass", "inertia_kgm2", [382.0, 1885.0, 2500.0]),
     "mass.inertia_kgm2", r"triangle inequality"),
    ("an inertia too small for the parts", _set("mass", "inertia_kgm2", [20.0, 1885.0, 1890.0]),
     "mass.inertia_kgm2", r"too small for its parts"),
    ("a truck's mass", _set("mass", "total_mass_kg", 7500.0), "mass.total_mass_kg",
     r"3500 kg"),
    ("a quadricycle's mass", _set("mass", "total_mass_kg", 400.0), "mass.total_mass_kg",
     r"450"),
    ("the right corner's points", _set("front", "wheel_centre_m", [0.0, -0.695, 0.330]),
     "front.wheel_centre_m", r"left corner"),
    ("a point in mm (a newcomer's: it was read as an impossible inertia)",
     _set("front", "wheel_centre_m", [0.0, 787.1, 330.0]), "front.wheel_centre_m[1]",
     r"787.1 .*more than 10 m from the car file's origin.*in mm\?"),
])
def test_what_an_engineer_would_not_enter_is_refused_with_the_reason(tmp_path, label, change,
                                                                      key, reason):
    path = _engineer(tmp_path, change)
    with pytest.raises(SceneError) as refused:
        load_scene(scene_text=f"car_file: {path}")
    message = str(refused.value)
    assert key in message and re.search(reason, message), (label, message)
    assert "\n" not in message


@pytest.mark.parametrize("text, key, reason", [
    ("car: {front: {wheel_rate_Npm: 28.0}}", "car.front.wheel_rate_Npm", "kN/m"),
    ("car: {mass: {sprung_cog_height_m: 1.3}}", "car.mass.sprung_cog_height_m",
     "static stability factor"),
    ("car: {mass: {cog_to_front_axle_m: 2.3, cog_to_rear_axle_m: 0.1}}",
     "car.front.wheel_rate_Npm", r"kg sprung per corner"),
    ("car: {mass: {sprung_inertia_kgm2: [244.0, 1342.0, 1700.0]}}",
     "car.mass.sprung_inertia_kgm2", "triangle inequality"),
    ("car: {mass: {total_mass_kg: 5000.0}}", "car.mass.total_mass_kg", "3500"),
    ("car: {front: {guide_length_l_m: 0.4}}", "car.front.guide_length_l_m", "too long"),
    ("car: {seat_point_m: [-1.25, 3.0, 0.5]}", "car.seat_point_m", "between the wheels"),
    ("car: {seat_point_m: [-1.25, 0.37]}", "car.seat_point_m", r"\[x, y, z\]"),
])
def test_today_s_parameters_are_refused_alike(text, key, reason):
    with pytest.raises(SceneError, match=re.escape(key) + ".*" + reason):
        load_scene(scene_text=text)


def test_a_car_file_s_seat_point_is_its_own_else_estimated_from_its_size():
    """The one key a car file may leave out: stated, it is moved into V with the file's other
    points; left out, the Escort's point scaled by the car's wheelbase, front track and body
    height [EST], which gives the Escort its own point exactly."""
    escort = CarParameters()
    assert estimated_seat_point_m(escort, escort) == list(ESCORT_SEAT_POINT_M) \
        == escort.seat_point_m
    car = read_car_file(ENGINEER)
    assert car.seat_point_m == []  # left out
    params = to_parameters(car)
    assert params.seat_point_m == estimated_seat_point_m(params, CarParameters())
    longer = dataclasses.replace(car, wheelbase_m=1.2 * car.wheelbase_m)
    assert to_parameters(longer).seat_point_m[0] == pytest.approx(1.2 * params.seat_point_m[0],
                                                                  rel=1e-12)
    car.seat_point_m = [-0.10, 0.40, 0.90]  # a forward-control van's driver
    car.check()
    assert_allclose(to_parameters(car).seat_point_m,
                    np.array([-0.10, 0.40, 0.90]) + frame_shift_m(car), rtol=0, atol=1e-15)


@pytest.mark.parametrize("point, key, reason", [
    ([-1.25, 0.37], "seat_point_m", r"must be given as \[x, y, z\]"),
    ([-1.25, float("nan"), 0.5], "seat_point_m[1]", "must be a finite number"),
    ([-1250.0, 370.0, 500.0], "seat_point_m[0]", r"more than 10 m .*in mm\?"),
    ([2.5, 0.37, 0.5], "seat_point_m", r"2.500 m ahead of the front axle: a seat lies at most 1 m"),
    ([-1.25, 0.37, -0.2], "seat_point_m", r"above the ground: a seat lies above it"),
])
def test_a_bad_seat_point_is_refused_naming_the_key_and_the_file(tmp_path, point, key, reason):
    path = _engineer(tmp_path, _set("", "seat_point_m", point))
    with pytest.raises(SceneError) as refused:
        load_scene(scene_text=f"car_file: {path}")
    message = str(refused.value)
    assert f"car_file {path}: {key} = " in message and re.search(reason, message), message
    assert "\n" not in message


def test_a_car_file_states_every_value(tmp_path):
    full = data_path(ENGINEER).read_text()
    cut = re.sub(r"\n  rack_stroke_m: .*", "", full)
    (tmp_path / "cut.yaml").write_text(cut)
    with pytest.raises(SceneError, match="front.rack_stroke_m is not given"):
        load_scene(scene_text=f"car_file: {tmp_path / 'cut.yaml'}")
    (tmp_path / "typo.yaml").write_text(full.replace("ball_joint_m", "bal_joint_m"))
    with pytest.raises(SceneError, match="unknown key 'front.bal_joint_m'"):
        load_scene(scene_text=f"car_file: {tmp_path / 'typo.yaml'}")
    with pytest.raises(SceneError, match="nowhere.yaml"):
        load_scene(scene_text="car_file: nowhere.yaml")


def test_round_trip_of_today_s_parameters_is_round_off():
    params = CarParameters()
    back = to_parameters(from_parameters(params))
    for group in ("front", "mass"):
        for field in dataclasses.fields(getattr(params, group)):
            mine, theirs = getattr(getattr(params, group), field.name), getattr(
                getattr(back, group), field.name)
            if mine is None:
                mine = params.front.caster_deg
            assert_allclose(theirs, mine, rtol=1e-12, atol=1e-12, err_msg=field.name)


def test_the_second_car_s_file_is_its_module_s_output():
    """urdf/cars/bmw_320i.yaml is what drake_car/model/cars/bmw_320i.py writes from its
    sources (``python -m drake_car.model.cars.bmw_320i``), every value with its source; the
    car it makes has [CR2]'s mass, tracks, wheelbase and rates, its sprung mass's roll and pitch
    inertia and CoG, and the E90's kingpin geometry."""
    from drake_car.model.cars import bmw_320i
    text = bmw_320i.car_file_text()
    assert data_path("cars/bmw_320i.yaml").read_text() == text
    assert all("  # " in line for line in text.splitlines()
               if line.startswith("  ") or line.startswith(("wheelbase_m", "driven_axle")))
    car = load_scene(scene_text="car_file: cars/bmw_320i.yaml").car
    assert car.driven_axle == "rear"
    assert car.mass.total_mass_kg == bmw_320i.MASS_KG
    assert car.front.track_m == pytest.approx(bmw_320i.FRONT_TRACK_M, abs=1e-15)
    assert car.wheelbase_m == pytest.approx(2.5789128, abs=1e-12)
    assert_allclose(car.mass.sprung_inertia_kgm2[:2], bmw_320i.SPRUNG_ROLL_PITCH_KGM2, rtol=1e-12)
    assert_allclose([car.mass.cog_to_front_axle_m, car.mass.sprung_cog_height_m],
                    [bmw_320i.SPRUNG_TO_FRONT_AXLE_M, bmw_320i.SPRUNG_COG_HEIGHT_M + 0.018],
                    atol=1e-12)
    assert 10.0 < car.front.kingpin_inclination_deg < 12.0
    # Its rack end placed for the least bump steer ([EST], the module): toe within ±0.07 deg
    # over ±75 mm of wheel travel (Chrono's round-number TIEROD_C gave ±2 deg).
    from drake_car.model.kinematics_sweep import run_kinematics_sweep
    toe = run_kinematics_sweep(car, travel_m=0.075, points=7).kinematics["toe_deg"]
    assert np.max(np.abs(toe)) < 0.07


def test_a_rack_behind_the_axle_steers_the_way_the_manoeuvre_says():
    """The BMW's steering arms lie behind its steering axis ([E90]): rack travel to the left
    steers its wheels right (the linkage's ratio by the kinematics has the geometry's sign);
    a manoeuvre's rack command (a front-steer linkage's: positive steers left) reaches its rack
    mirrored, so a left ramp steer turns it left as it turns the Escort."""
    from drake_car.model.geometry import steering_sign
    from drake_car.sim.driver_wiring import rack_per_steer_m_per_rad
    bmw = load_scene(scene_text="car_file: cars/bmw_320i.yaml").car
    assert steering_sign(bmw) == -1.0 and rack_per_steer_m_per_rad(bmw) < 0
    assert steering_sign(CarParameters()) == 1.0 and rack_per_steer_m_per_rad(CarParameters()) > 0
    text = ("{car_file: cars/bmw_320i.yaml, manoeuvre: !StepSteer {rack_m: 0.004, timeline: "
            "{settle_s: 0.2, speed_up_s: 1.0, straight_s: 0.2, steer_s: 1.0, calm_s: 0.0, "
            "speed_kph: 20.0}}, logging: {record_period_s: 0.02}}")
    h = simulate(load_scene(scene_text=text)).history
    assert h["rack_m"][-1] == pytest.approx(-0.004, abs=2e-4), "the rack travels right"
    # Left steer, and a left yaw rate near the kinematic u δ / L (0.041 rad/s at 20 km/h).
    steer = h["steer_fl_rad"][-1]
    assert steer > 0.01
    assert h["yaw_rate_radps"][-1] > 0.5 * h["speed_mps"][-1] * steer / bmw.wheelbase_m
