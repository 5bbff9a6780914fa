"""A corner's share of the car at rest: its unsprung and sprung masses, its ride rate and the
body's ride frequency over an axle, and the ranges a road car's lie in (pure numpy;
``scene.car_limits`` and ``model.hard_points`` check them, the hard-point table reports
them)."""

import math

from drake_car.model.geometry import design_axle_loads_N
from drake_car.model.parameters import GRAVITY_MPS2, CarParameters

# A passenger car's ride frequency (Hz): [EST] 0.8-2 Hz, around the body's 1-1.5 Hz that
# production cars are tuned to (below 1 Hz can cause nausea, above 1.5 Hz impairs comfort:
# Audi self-study programme 242, "Audi A6 '98 running gear", p. 9), with room for soft
# luxury cars and firm sporting ones.
RIDE_FREQUENCY_HZ = (0.8, 2.0)
# [EST] The lowest road car's centre of gravity (m): sports cars have theirs at ~0.40-0.45 m.
COG_HEIGHT_MIN_M = 0.3
# The least static stability factor T / (2 h) of a road vehicle: NHTSA report DOT HS 809 868
# (2005), sales-weighted averages of model year 2003: passenger cars 1.41, SUVs 1.17, pickups
# 1.18, minivans 1.24, full-size vans 1.12; below 1 a vehicle on a dry road tips before it
# slides.
MIN_STATIC_STABILITY = 1.0


def highest_cog_m(front_track_m, rear_track_m):
    """The highest centre of gravity of a road car of these tracks (m): T / (2 SSF_min)."""
    return (front_track_m + rear_track_m) / 2 / (2 * MIN_STATIC_STABILITY)


def unsprung_corner_mass_kg(car: CarParameters, axle):
    """A corner's unsprung mass (kg): the wheel and what moves with it, the arms' mass shared
    half with the body (they pivot on it)."""
    m = car.mass
    if axle == "front":
        return (m.front_wheel_kg + m.front_knuckle_kg + m.strut_slider_kg
                + (m.front_lower_arm_kg + m.tie_rod_kg) / 2)
    return m.rear_wheel_kg + m.rear_carrier_kg / 2


def corner_sprung_mass_kg(car: CarParameters, axle):
    """The sprung mass a corner carries at rest (kg): half the axle load over g less its
    unsprung mass."""
    return design_axle_loads_N(car)[axle] / 2 / GRAVITY_MPS2 - unsprung_corner_mass_kg(car, axle)


def ride_rate_Npm(car: CarParameters, axle):
    """The wheel rate in series with the tyre's radial stiffness (N/m):
    K_R = K_w K_t / (K_w + K_t)."""
    wheel = getattr(car, axle).wheel_rate_Npm
    tyre = car.tyre.radial_stiffness_Npm
    return wheel * tyre / (wheel + tyre)


def ride_frequency_hz(car: CarParameters, axle):
    """The body's bounce frequency over an axle (Hz): sqrt(K_R / m_corner) / 2π."""
    return math.sqrt(ride_rate_Npm(car, axle) / corner_sprung_mass_kg(car, axle)) / (2 * math.pi)


def wheel_rate_range_Npm(car: CarParameters, axle, frequencies_hz):
    """The wheel rates (N/m) whose ride frequencies are ``frequencies_hz`` on this car's tyre:
    K_w = K_R K_t / (K_t - K_R), K_R = m (2π f)² (infinite where K_R would reach the tyre's
    own stiffness)."""
    mass, tyre = corner_sprung_mass_kg(car, axle), car.tyre.radial_stiffness_Npm
    bounds = []
    for frequency in frequencies_hz:
        ride = mass * (2 * math.pi * frequency) ** 2
        bounds.append(ride * tyre / (tyre - ride) if ride < tyre else math.inf)
    return tuple(bounds)
