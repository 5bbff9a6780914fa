"""The driver's seat point: where the ride study measures comfort (ISO 2631-1's Wk-weighted
vertical acceleration a_w, ``model.channels``' ``ride`` group), a car parameter
(``CarParameters.seat_point_m``) because it is the car's: a forward-control van's driver sits
over the front axle, a saloon's near mid-wheelbase, and the body's pitch moves the two points
very differently.

Frame: the vehicle frame V of ``model.parameters`` (the chassis body's frame: origin on the
ground midway between the front contact points at the design position, x forward, y left,
z up), in m. A car file states it in its own frame (``seat_point_m``, moved into V with its
other points: ``model.hard_points``); one that does not gets ``estimated_seat_point_m`` [EST],
named wherever it runs (``scene.borrowed``)."""

import math

from drake_car.law.checks import ParameterError

# The shipped Escort's seat point in V: [EST] the floor under the driver's seat pan (ISO
# 2631-1 measures at the seat surface under the ischial tuberosities; the seat's own cushion
# is not modelled, so this is the seat's mounting point): 1.25 m behind the front axle (a
# C-segment car's front-seat H-point sits about mid-wheelbase, here 2.39 m), 0.37 m left of
# the centre line (a left-hand-drive car, half a front-seat spacing), 0.50 m above the ground.
ESCORT_SEAT_POINT_M = (-1.25, 0.37, 0.50)
# [EST] How far a seat may lie ahead of the front axle or behind the rear one (m): a road
# car's overhangs; the seat lies between its bumpers (a forward-control van's driver sits at
# most some tenths of a metre ahead of the front axle).
MAX_SEAT_OVERHANG_M = 1.0
# [EST] The highest seat point above the ground (m): below a tall van's roof.
MAX_SEAT_HEIGHT_M = 2.0
# How a car file states its own (the hint every estimate's warning gives).
STATE_SEAT = ("seat_point_m: [x, y, z] in the car file (m, its frame: the floor under the "
              "driver's seat)")


def estimated_seat_point_m(car, shipped):
    """[EST] A seat point from the car's own size, for a car file that states none: the
    Escort's point (``ESCORT_SEAT_POINT_M``) scaled by the car's wheelbase (x), front track (y)
    and body's centre-of-gravity height (z; the floor rises with the body) over the Escort's:
    a conventional car's driver, engine ahead, at the same share of the wheelbase. The car's
    layout is not in its geometry: for a forward-control van (the driver over the front axle)
    or a mid-engined car it is wrong, and a_w with it; such a car states its own. The
    Escort's own size gives the Escort's point exactly. ``shipped``: the Escort
    (``CarParameters()``; passed in: the parameters import this module)."""
    x, y, z = ESCORT_SEAT_POINT_M
    return [x * (car.wheelbase_m / shipped.wheelbase_m),
            y * (car.front.track_m / shipped.front.track_m),
            z * (car.mass.sprung_cog_height_m / shipped.mass.sprung_cog_height_m)]


def check_seat_point(car, name="seat_point_m", given=None):
    """Refuses (ParameterError naming ``name``, the value ``given``: the car file's, else the
    point itself) a seat point that is no three finite numbers or lies outside the car: more
    than ``MAX_SEAT_OVERHANG_M`` ahead of the front axle or behind the rear one, outside the
    wider track, not above the ground or above ``MAX_SEAT_HEIGHT_M``."""
    point = car.seat_point_m
    given = point if given is None else given
    if not isinstance(point, (list, tuple)) or len(point) != 3:
        raise ParameterError(name, given, "must be given as [x, y, z] (m)")
    for i, value in enumerate(point):
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value):
            raise ParameterError(f"{name}[{i}]", given[i], "must be a finite number")
    x, y, z = point
    wheelbase = car.wheelbase_m
    half_track = max(car.front.track_m, car.rear.track_m) / 2
    if not -wheelbase - MAX_SEAT_OVERHANG_M <= x <= MAX_SEAT_OVERHANG_M:
        place = f"{abs(x):.3f} m {'behind' if x <= 0 else 'ahead of'} the front axle"
        raise ParameterError(name, given, f"lies {place}: a seat lies at most "
                             f"{MAX_SEAT_OVERHANG_M:g} m ahead of the front axle or behind the "
                             f"rear one ({wheelbase:.3f} m behind it)")
    if not abs(y) <= half_track:
        raise ParameterError(name, given, f"lies {abs(y):.3f} m off the centre line: a seat "
                             f"lies between the wheels (half the track {half_track:.3f} m)")
    if not 0.0 < z <= MAX_SEAT_HEIGHT_M:
        raise ParameterError(name, given, f"lies {z:.3f} m above the ground: a seat lies above "
                             f"it and at most {MAX_SEAT_HEIGHT_M:g} m high")
