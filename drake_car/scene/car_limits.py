"""What a road car is: the scene's car against the ranges an engineer's car lies in, asked once
where the scene is loaded (``scene.load.check_scene``), after each value's own check
(``CarParameters.check``: the masses, the inertia's triangle inequality, the geometry). These
need the car's geometry (the parts where the model puts them), so they live here:

- the whole car's centre of gravity inside the wheelbase (else an axle load is negative);
- its height between ``COG_HEIGHT_MIN_M`` and half the mean track (a static stability factor
  T / (2 h) of at least 1);
- each axle's ride frequency, from its wheel rate, the tyre's radial stiffness and the corner's
  sprung mass (``model.corners``), in ``RIDE_FREQUENCY_HZ`` (a wheel rate of 28 N/m, a kN/m typo, is refused with
  the range of wheel rates that would do).

Each refusal is a ``ParameterError`` naming the car's key (``check_scene`` prefixes ``car.``
and says which hard points a car file derived it from).
"""

from drake_car.law.checks import ParameterError
from drake_car.model.corners import (
    COG_HEIGHT_MIN_M, RIDE_FREQUENCY_HZ, corner_sprung_mass_kg,
    highest_cog_m, ride_frequency_hz, wheel_rate_range_Npm)
from drake_car.model.geometry import centre_of_mass
from drake_car.model.parameters import CarParameters

def check_car(car: CarParameters):
    """Raises ParameterError (key relative to the car) where the car is no road car."""
    whole = centre_of_mass(car)
    behind, wheelbase = float(-whole[0]), car.wheelbase_m
    if not 0.0 < behind < wheelbase:
        raise ParameterError(
            "mass.cog_to_front_axle_m", car.mass.cog_to_front_axle_m,
            f"puts the whole car's centre of gravity {behind:.3f} m behind the front axle (the "
            f"sprung mass's with the parts where they are): outside the wheelbase (0, "
            f"{wheelbase:.3f}) m, an axle load would be negative")
    height = float(whole[2])
    highest = highest_cog_m(car.front.track_m, car.rear.track_m)
    if not COG_HEIGHT_MIN_M <= height <= highest:
        raise ParameterError(
            "mass.sprung_cog_height_m", car.mass.sprung_cog_height_m,
            f"puts the whole car's centre of gravity {height:.3f} m high: a road car's lies in "
            f"[{COG_HEIGHT_MIN_M:g}, {highest:.3f}] m (at most half its mean track, a static "
            "stability factor T/(2h) >= 1: full-size vans average 1.12, passenger cars 1.41, "
            "NHTSA DOT HS 809 868)")
    for axle in ("front", "rear"):
        mass = corner_sprung_mass_kg(car, axle)
        if not mass > 0:
            raise ParameterError(f"{axle}.wheel_rate_Npm", getattr(car, axle).wheel_rate_Npm,
                                 f"carries no sprung mass ({mass:.1f} kg per corner)")
        frequency = ride_frequency_hz(car, axle)
        low, high = RIDE_FREQUENCY_HZ
        if not low <= frequency <= high:
            lowest, highest_rate = wheel_rate_range_Npm(car, axle, RIDE_FREQUENCY_HZ)
            raise ParameterError(
                f"{axle}.wheel_rate_Npm", getattr(car, axle).wheel_rate_Npm,
                f"gives the body a ride frequency of {frequency:.3g} Hz over the {axle} axle "
                f"({mass:.0f} kg sprung per corner, tyre {car.tyre.radial_stiffness_Npm:g} "
                f"N/m): a passenger car's lies in {low:g}..{high:g} Hz, a wheel rate of "
                f"{lowest:.0f}..{highest_rate:.0f} N/m here (N/m, not kN/m)")
