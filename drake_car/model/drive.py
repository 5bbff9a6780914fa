"""The car's drive: actuators on the driven axle's wheel spin joints (``CarParameters.
driven_axle``: the front for a front-drive car, the rear for a rear-drive one), the paper's
prescribed rotation (stiff servos) or an open differential (one torque, split equally)."""

import numpy as np
from pydrake.multibody.tree import PdControllerGains

from drake_car.model.geometry import SIDES, design_axle_loads_N

# Prescribed front-wheel rotation (paper section 4): a stiff SAP servo on each wheel's spin
# joint; 1e5 N m/rad keeps the wheel within ~0.01 rad of its command at the ~1 kN m drive torque
# of the speed-up, and 2e3 N m s/rad over-damps the wheel's 0.6 kg m².
DRIVE_SERVO_GAINS = PdControllerGains(p=1.0e5, d=2.0e3)


def rolling_radius(params, axle="front"):
    """Effective rolling radius of a tyre at its design load: R0 - δ/3."""
    load = design_axle_loads_N(params)[axle] / 2
    return params.tyre.unloaded_radius_m - load / params.tyre.radial_stiffness_Npm / 3


def driven_axle(params):
    """(the driven axle, the other axle): ("front", "rear") or ("rear", "front")."""
    axle = params.driven_axle
    return axle, "rear" if axle == "front" else "front"


def driven_wheel_carriers(car):
    """The bodies the driven wheels turn on (their knuckles, or the rear's trailing arms)."""
    axle, _ = driven_axle(car.params)
    return [car.body(f"knuckle_{side}" if axle == "front" else f"trailing_arm_{side}")
            for side in SIDES]


def add_drive_actuators(plant, car, *, pd):
    """One actuator per driven wheel's spin joint (before Finalize), PD-controlled (prescribed
    rotation) or torque-driven (open differential); kept in ``car.drive_actuators``."""
    car.drive_actuators = []
    axle, _ = driven_axle(car.params)
    for side in SIDES:
        actuator = plant.AddJointActuator(f"drive_{side}", car.joint(f"wheel_{axle}_{side}_spin"))
        if pd:
            actuator.set_controller_gains(DRIVE_SERVO_GAINS)
        car.drive_actuators.append(actuator)
    return car.drive_actuators


def open_differential_gain(plant, car, *, speed_gain_Nm_per_mps):
    """The open differential's speed controller as one matrix D: [T_left, T_right] =
    D [x; v_ref; a_ref], x the plant's state. The total torque is
    T = (m + ΣI_w / R²) R a_ref + K (v_ref - v) with v = R_o (ω_ol + ω_or) / 2 the speed the
    free-rolling wheels of the other axle measure (as a car's wheel-speed sensors do), split
    equally: an open differential gives both wheels the same torque."""
    params = car.params
    axle, other = driven_axle(params)
    radius, rear_radius = rolling_radius(params, axle), rolling_radius(params, other)
    inertia = 4 * params.mass.wheel_spin_inertia_kgm2
    mass = params.mass.total_mass_kg + inertia / radius ** 2
    nx = plant.num_multibody_states()
    row = np.zeros(nx + 2)
    for side in SIDES:
        v_index = plant.num_positions() + car.joint(f"wheel_{other}_{side}_spin").velocity_start()
        row[v_index] = -speed_gain_Nm_per_mps * rear_radius / 2
    row[nx] = speed_gain_Nm_per_mps
    row[nx + 1] = mass * radius
    return np.vstack([0.5 * row, 0.5 * row])


def differential_speed_gain(plant, car):
    """The row vector giving the differential's mean speed (rad/s): the driven wheels'
    (ω_l + ω_r) / 2 from the plant's state."""
    row = np.zeros((1, plant.num_multibody_states()))
    axle, _ = driven_axle(car.params)
    for side in SIDES:
        v_index = plant.num_positions() + car.joint(f"wheel_{axle}_{side}_spin").velocity_start()
        row[0, v_index] = 0.5
    return row


def explicit_time_step_limit_s(params, gain_Nm_per_radps):
    """The largest step at which a torque of -K/2 per driven wheel on the differential's
    mean speed (ω_l + ω_r) / 2, applied explicitly (the rev limit), is stable: its modes are
    0 (the wheels turning apart) and -K / (2 I) (alike), I a wheel's spin inertia, so explicit
    Euler is stable for steps below 4 I / K."""
    return 4.0 * params.mass.wheel_spin_inertia_kgm2 / gain_Nm_per_radps
