"""Hard cases at the default settings (fast friction scheme, 1 ms unless stated): each ends with
finite histories and bounded energy, with the physical outcome it expects stated."""

import math

import numpy as np
import pytest
from pydrake.trajectories import PiecewisePolynomial

from drake_car.drive import lane_change_metrics, run_drive
from drake_car.law.frd_friction import StrutFrictionParameters
from drake_car.law.road import CosineBump
from drake_car.manoeuvre import Timeline
from drake_car.model.geometry import SIDES
from drake_car.model.parameters import CarParameters
from drake_car.monitor import DivergenceError
from drake_car.settle import run_settle
from drake_car.systems.sap_pacer import pacer_kinetic_energy
from drake_car.systems.strut_friction import StrutFrictionSetup

DMAX = StrutFrictionParameters().dmax_translation_m
TIMELINE = Timeline()
MASS_KG = CarParameters().mass.total_mass_kg
# Bound on the car's mechanical energy in a drive (gravity measured from the road): kinetic
# energy at 60 km/h plus the potential energy of the car's mass at its CoG height, with a
# factor 2 of margin. It catches an energy gain; a blow-up is the monitor's job.
DRIVE_ENERGY_BOUND_J = 2 * (0.5 * MASS_KG * (60 / 3.6) ** 2
                            + MASS_KG * 9.81 * CarParameters().mass.sprung_cog_height_m)


def dry(mu_s=0.4, mu_d=0.3, **law):
    params = CarParameters()
    params.front.strut_damping_Nspm = 0.0
    return params, StrutFrictionSetup(StrutFrictionParameters(mu_s=mu_s, mu_d=mu_d, **law))


def energy_channel(built, root):
    """Kinetic + gravity + coil springs (the plant's) + the tyres' radial springs; the SAP
    pacer's kinetic energy (a body decoupled from the car) is not the car's."""
    pc = built.plant.GetMyContextFromRoot(root)
    loads = built.tyre.GetOutputPort("tyre_loads").Eval(built.tyre.GetMyContextFromRoot(root))
    stiffness = built.car.params.tyre.radial_stiffness_Npm
    tyres = 0.5 * stiffness * float(np.sum(loads[4:] ** 2))
    return {"energy_J": built.plant.EvalKineticEnergy(pc) + built.plant.EvalPotentialEnergy(pc)
            + tyres - pacer_kinetic_energy(built.plant, pc)}


def assert_finite(history):
    for name, values in history.items():
        if name != "phase":
            assert np.all(np.isfinite(values)), name


def test_jammed_strut_holds_for_a_minute():
    """μs = 0.4 at rest for 60 s: once jammed (by 1 s) the rod moves by less than its creep
    bound Δmax; nothing drifts."""
    params, friction = dry()
    result = run_settle(params, friction=friction, duration_s=60.0, record_period_s=0.05)
    h = result.history
    assert_finite(h)
    after = h["t"] >= 1.0
    for side in SIDES:
        assert np.ptp(h[f"d_{side}_m"][after]) <= DMAX, side
    # The body's bounce on the tyres (2 % damped) has died out by 30 s; then nothing moves.
    assert np.ptp(h["z_chassis_m"][h["t"] >= 30.0]) < 1e-6


@pytest.mark.parametrize("label, law", [
    ("mu_s equals mu_d", dict(mu_s=0.3, mu_d=0.3)),
    ("tiny threshold velocity", dict(dv_translation_mps=1e-6, dv_rotation_radps=1e-6)),
    ("tiny creep", dict(dmax_translation_m=1e-7, dmax_rotation_rad=1e-7)),
    ("zero friction", dict(mu_s=0.0, mu_d=0.0)),
])
def test_friction_extremes_settle(label, law):
    """Each settles with finite states. With friction the rods stop within 2 s and then move by
    at most their creep bound; without friction (and without damping) they keep oscillating."""
    mu_s, mu_d = law.pop("mu_s", 0.4), law.pop("mu_d", 0.3)
    params, friction = dry(mu_s, mu_d, **law)
    h = run_settle(params, friction=friction, duration_s=4.0).history
    assert_finite(h)
    late = h["t"] >= 2.0
    dmax = law.get("dmax_translation_m", DMAX)
    for side in SIDES:
        motion = np.ptp(h[f"d_{side}_m"][late])
        if mu_s > 0:
            assert motion <= max(dmax, 1e-9) + 1e-9, (label, side, motion)
        else:
            assert motion > 1e-3, (label, side, motion)


@pytest.mark.parametrize("height", [0.05, -0.04])
def test_bump_and_pothole_at_60_kph(height):
    """A 5 cm bump / 4 cm pothole, 1.5 m long (slope at most 6 deg, within the tyre model's
    flat-normal assumption), across the road at x = 40 m, hit at 60 km/h with the jammed
    struts: the car passes it with finite states, keeps its line within 0.1 m and its energy
    bounded."""
    params, friction = dry()
    road = CosineBump(start_x_m=40.0, length_m=1.5, height_m=height)
    end = TIMELINE.boundaries()[1] + 0.5
    run = run_drive("straight", params, friction=friction, road_height=road, end_time_s=end,
                    record_period_s=0.01, extra_channels=energy_channel)
    h = run.history
    assert_finite(h)
    assert h["x_m"][-1] > 45.0, "the car must have passed the bump"
    over = (h["x_m"] > 39.0) & (h["x_m"] < 43.0)
    assert np.ptp(h["Fz_fl_N"][over]) > 500.0, "the wheel must feel the bump"
    assert np.max(np.abs(h["y_m"])) < 0.1
    assert np.max(h["energy_J"]) < DRIVE_ENERGY_BOUND_J


def test_stiff_top_mount_over_the_bump():
    """Elastomer top mounts of 1e9 N/m (the strut's ~40 kg on them rings at ω ≈ 5000 rad/s,
    ω·dt = 5 at 1 ms: an explicit spring would diverge; the mount is SAP's implicit PD) with
    jammed struts over the 5 cm bump at 60 km/h: finite, energy bounded, and the mounts deflect
    as springs do, |δ| ≤ F/k with F below 5 times the static front corner load (~19 kN)."""
    params, friction = dry()
    params.front.top_mount_stiffness_Npm = 1e9
    road = CosineBump(start_x_m=40.0, length_m=1.5, height_m=0.05)
    end = TIMELINE.boundaries()[1] + 0.5

    def mounts(built, root):
        energy = energy_channel(built, root)
        pc = built.plant.GetMyContextFromRoot(root)
        deflection = max(abs(built.car.joint(f"top_mount_{a}_{s}").get_translation(pc))
                         for a in "xyz" for s in SIDES)
        return energy | {"mount_deflection_m": deflection}

    run = run_drive("straight", params, friction=friction, road_height=road, end_time_s=end,
                    record_period_s=0.01, extra_channels=mounts)
    h = run.history
    assert_finite(h)
    assert h["x_m"][-1] > 45.0, "the car must have passed the bump"
    assert np.max(h["energy_J"]) < DRIVE_ENERGY_BOUND_J
    bound = 5 * params.design_axle_loads_N()["front"] / 2 / 1e9
    assert 0.0 < np.max(h["mount_deflection_m"]) < bound


def test_full_steering_lock_at_speed():
    """The rack goes to its full stroke in 0.5 s at 60 km/h: the car spins out or ploughs on;
    either way the simulation stays finite and the energy below its bound."""
    params, friction = dry()
    t2 = TIMELINE.boundaries()[0]
    stroke = params.front.rack_stroke_m
    rack = PiecewisePolynomial.FirstOrderHold([0.0, t2 + 0.2, t2 + 0.7],
                                              np.array([[0.0, 0.0, stroke]]))
    run = run_drive("straight", params, friction=friction, rack=rack, end_time_s=t2 + 3.0,
                    record_period_s=0.01, extra_channels=energy_channel)
    h = run.history
    assert_finite(h)
    assert abs(math.degrees(h["yaw_rad"][-1])) > 20.0, "the car must turn"
    assert np.max(h["energy_J"]) < DRIVE_ENERGY_BOUND_J


def test_standing_still_for_a_minute():
    """Parked on Magic Formula tyres (transient slip: the contact patch acts as a spring) for
    60 s: no drift and no energy gain once settled."""
    from drake_car.assembly import TyreSetup
    timeline = Timeline(settle_s=60.0)
    run = run_drive("straight", timeline=timeline, tyres=TyreSetup(), end_time_s=60.0,
                    record_period_s=0.05, extra_channels=energy_channel)
    h = run.history
    assert_finite(h)
    settled = h["t"] >= 10.0  # the settling bounce (2 % damped on the tyres) has died out
    assert np.ptp(h["x_m"][settled]) < 1e-4 and np.ptp(h["y_m"][settled]) < 1e-4
    energy = h["energy_J"][settled]
    # Kinetic + gravity + coil and tyre springs of ~7 kJ: 1e-5 J (1e-9) covers round-off and
    # the servos' PD springs, which this sum leaves out.
    assert np.max(energy) <= energy[0] + 1e-5, "a parked car must not gain energy"


def test_five_millisecond_step():
    """The lane change with jammed struts at 5 ms: finite, and the track still shifts within
    0.1 m of the 1 ms result (3.55 m with this friction set)."""
    params, friction = dry()
    end = TIMELINE.boundaries()[2] + 0.2
    coarse = run_drive("a", params, friction=friction, time_step_s=5e-3, end_time_s=end,
                       record_period_s=0.05)
    assert_finite(coarse.history)
    fine = run_drive("a", params, friction=friction, end_time_s=end, record_period_s=0.05)
    shift = lane_change_metrics(coarse.history, TIMELINE)["shift_m"]
    assert shift == pytest.approx(lane_change_metrics(fine.history, TIMELINE)["shift_m"],
                                  abs=0.1)


def test_divergence_stops_with_a_clear_error():
    """An explicitly applied tyre spring of 5e7 N/m on ~15 kg wheels is unstable at 5 ms
    (ω·dt ≈ 9 > 2): the monitor stops the run and names the time."""
    params = CarParameters()
    params.tyre.radial_stiffness_Npm = 5e7
    with pytest.raises(DivergenceError, match=r"diverged at t = \d+\.\d+ s"):
        run_drive("straight", params, time_step_s=5e-3, end_time_s=2.0)


def test_same_scene_twice_gives_identical_histories():
    params, friction = dry()
    runs = [run_drive("a", params, friction=friction, end_time_s=1.5, record_period_s=0.01)
            for _ in range(2)]
    for name, values in runs[0].history.items():
        assert np.array_equal(values, runs[1].history[name]), name
