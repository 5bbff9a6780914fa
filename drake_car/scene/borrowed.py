"""Values a car runs with that are the shipped car's unless its scene states its own, each said
with its source so that no report calls the shipped car's value "this car's":

- the drive's torque limit (``drive_limit``): ``OpenDifferential.max_wheel_torque_Nm``, by
  default the shipped Escort's estimate (1740 N m at the wheels [EST], ``scene.scene``). A car
  file holds the car's geometry, masses and rates, not its drive: the drive is the scene's
  ``drive`` section, set with ``SET_DRIVE``;
- the tyres' relaxation lengths (``relaxation``): ``tyres.slip``'s, by default the shipped
  tyre's estimates (σκ 0.15 m, σα 0.45 m [EST], ``law.tyre.slip``), or the tyre file's own
  (PAC2002 PTX*/PTY*, MF 6.x carcass stiffnesses) at the car's wheel load at rest with
  ``tyres.slip.relaxation_lengths_from_file: true``;
- the driver's seat point (``seat_point``), where the ride study measures comfort: a car file
  that states no ``seat_point_m`` runs with an estimate from the car's size [EST]
  (``model.seat.estimated_seat_point_m``), the Escort's without a car file.

Every report that states the drive's limit or describes the tyres gives these facts (the value
that ran, where it came from, how to set one's own). Where the scene is loaded (``scene.load.
check_scene``), ``say_borrowed`` warns on stderr, once per process and value, where the value
runs: a car file run with the default drive torque in a scene that launches, and a tyre file
with relaxation data of its own that is not used, a car file without its seat point in a scene
that logs the ride; not where only the scene's car is used (the
strut rig, the kinematics: ``load_scene(..., runs=False)``)."""

import logging

from drake_car.law.tyre.magic_formula import relaxation_lengths_m, relaxation_source
from drake_car.law.tyre.slip import SlipOptions
from drake_car.model.loading import read_tyre
from drake_car.model.seat import ESCORT_SEAT_POINT_M, STATE_SEAT
from drake_car.scene.car_file import car_of_file, states_seat_point
from drake_car.scene.launch import TRACTION_MARGIN, drive_torque_limit_Nm
from drake_car.scene.limits import wheel_load_at_rest_N
from drake_car.scene.scene import LinearTyre, MagicFormula, OpenDifferential

log = logging.getLogger(__name__)
_SAID = set()  # the warnings already given in this process

SET_DRIVE = '--scene_text "drive: !OpenDifferential {max_wheel_torque_Nm: ...}"'
USE_FILE_RELAXATION = ("tyres.slip.relaxation_lengths_from_file: true (e.g. --scene_text "
                       '"tyres: {slip: {relaxation_lengths_from_file: true}}")')
_FILE_SOURCE = {"PTX/PTY": "PTX*/PTY*", "carcass": "its carcass stiffnesses"}


def drive_limit(scene):
    """{"max_wheel_torque_Nm", "source": "shipped" (the default, the Escort's estimate) or
    "scene"} of the scene's open differential; None for a drive without a torque limit (the
    paper's prescribed rotation)."""
    drive = scene.drive
    if not isinstance(drive, OpenDifferential):
        return None
    return {"max_wheel_torque_Nm": drive.max_wheel_torque_Nm, "source": _source(drive),
            "runs_Nm": drive_torque_limit_Nm(scene)}


def _source(drive):
    """Where an open differential's torque limit comes from: "shipped" (the default, the
    Escort's estimate) or "scene"."""
    shipped = drive.max_wheel_torque_Nm == OpenDifferential().max_wheel_torque_Nm
    return "shipped" if shipped else "scene"


def drive_limit_words(limit):
    """The drive's torque limit with its source, in words (``limit``: ``drive_limit``'s)."""
    if limit is None:
        return "no torque limit (the paper's prescribed rotation: stiff servos)"
    text = f"{limit['max_wheel_torque_Nm']:g} N m at the driven wheels"
    if limit["source"] == "scene":
        text += " (the scene's `drive.max_wheel_torque_Nm`)"
    else:
        text += (" (`drive.max_wheel_torque_Nm`'s default: the shipped Escort's estimate [EST], "
                 "its 1.9 l engine's ~150 N m through first gear and final drive; another "
                 f"car's: {SET_DRIVE})")
    runs = limit.get("runs_Nm", limit["max_wheel_torque_Nm"])
    if runs < limit["max_wheel_torque_Nm"]:
        text += (f", clamped to {runs:.0f} N m: what the driven tyres transmit in the launch "
                 f"(`drive.torque_within_grip`: {TRACTION_MARGIN:g} of their peak grip [EST]; a "
                 "clamp above it spins the wheels past the peak)")
    return text


def relaxation(scene):
    """The tyres' relaxation as it runs (JSON-ready), None for tyres without slip:
    {"used_m": [σκ, σα] or None (steady-state slips), "source": "file", "shipped" (the
    defaults of ``SlipOptions``) or "scene" (``tyres.slip``'s own), "wheel_load_N",
    "file_source": the file's relaxation data (``relaxation_source``) or None, "file_m": its
    lengths at the wheel load at rest or None}."""
    tyres = scene.tyres
    if not isinstance(tyres, (MagicFormula, LinearTyre)):
        return None
    tyre = read_tyre(tyres.tir_file)
    load = wheel_load_at_rest_N(scene.car)
    file_source = relaxation_source(tyre)
    file_m = None if file_source is None else list(relaxation_lengths_m(tyre, load))
    slip, default = tyres.slip, SlipOptions()
    lengths = [slip.relaxation_length_long_m, slip.relaxation_length_lat_m]
    if not slip.relaxation:
        used, source = None, "none"
    elif slip.relaxation_lengths_from_file:
        used, source = file_m, "file"
    else:
        shipped = lengths == [default.relaxation_length_long_m,
                              default.relaxation_length_lat_m]
        used, source = lengths, "shipped" if shipped else "scene"
    return {"used_m": used, "source": source, "wheel_load_N": load,
            "file": tyres.tir_file, "file_source": file_source, "file_m": file_m}


def file_relaxation_unused(r):
    """Whether the tyre file has relaxation data that the runs do not use."""
    return r is not None and r["file_m"] is not None and r["source"] in ("shipped", "scene")


def relaxation_words(r):
    """The relaxation lengths that ran and their source, in words (``r``: ``relaxation``'s);
    where the file's own are not used, says so and how to use them."""
    if r is None:
        return "no slip (no relaxation)"
    if r["source"] == "none":
        text = "no relaxation (tyres.slip.relaxation: false: steady-state slips)"
    else:
        sk, sa = r["used_m"]
        text = f"relaxation lengths σκ {sk:.3g} m, σα {sa:.3g} m: " + (
            f"the tyre file's ({_FILE_SOURCE[r['file_source']]}) at the wheel load at rest, "
            f"{r['wheel_load_N']:.0f} N" if r["source"] == "file" else
            "the shipped tyre's estimates [EST] (`tyres.slip`, `drake_car/law/tyre/slip.py`)"
            if r["source"] == "shipped" else "the scene's `tyres.slip`")
    if file_relaxation_unused(r):
        sk, sa = r["file_m"]
        text += (f"; **the tyre file has its own, not used** ({_FILE_SOURCE[r['file_source']]}: "
                 f"σκ {sk:.3g} m, σα {sa:.3g} m at {r['wheel_load_N']:.0f} N): use them with "
                 f"{USE_FILE_RELAXATION}")
    return text


def say_borrowed(scene, where="scene"):
    """Warns on stderr, once per process and value, where a loaded scene's car runs with the
    shipped car's drive torque, leaves its tyre file's relaxation data unused, or logs the
    ride at a seat point its car file does not state (an estimate)."""
    drive = scene.drive  # its source only: the clamp (drive_limit's runs_Nm) is not needed here
    if (scene.car_file and getattr(scene.manoeuvre, "drives", False)
            and isinstance(drive, OpenDifferential)
            and _source(drive) == "shipped"):  # a scene that launches: not a settle
        key = ("drive", drive.max_wheel_torque_Nm)
        if key not in _SAID:
            _SAID.add(key)
            log.warning("%s: car_file %s runs with the drive's torque limit "
                        "drive.max_wheel_torque_Nm = %g N m, the shipped Escort's estimate "
                        "[EST], not this car's: it sets the launch; set your car's with %s",
                        where, scene.car_file, drive.max_wheel_torque_Nm, SET_DRIVE)
    if scene.car_file and "ride" in (scene.logging.channels or ()):
        s = seat_point(scene)
        key = ("seat", scene.car_file, tuple(s["seat_point_m"]))
        if s["source"] == "estimated" and key not in _SAID:
            _SAID.add(key)
            log.warning("%s: car_file %s states no seat_point_m: the ride's comfort (a_w) is "
                        "measured at an estimate [EST], %s (%s); state your car's with %s",
                        where, scene.car_file, seat_place(s["seat_point_m"]), SEAT_ESTIMATE,
                        STATE_SEAT)
    if isinstance(scene.tyres, (MagicFormula, LinearTyre)) and scene.tyres.slip.relaxation \
            and not scene.tyres.slip.relaxation_lengths_from_file:
        r = relaxation(scene)
        key = ("relaxation", r["file"], tuple(r["used_m"]))
        if file_relaxation_unused(r) and key not in _SAID:
            _SAID.add(key)
            log.warning("%s: tyres.tir_file %s has relaxation data of its own (%s: σκ %.3g m, "
                        "σα %.3g m at %.0f N), not used: the runs relax with tyres.slip's σκ "
                        "%g m, σα %g m%s; use the file's with %s", where, r["file"],
                        _FILE_SOURCE[r["file_source"]], *r["file_m"], r["wheel_load_N"],
                        *r["used_m"], " (the shipped tyre's estimates [EST])"
                        if r["source"] == "shipped" else "", USE_FILE_RELAXATION)


def seat_point(scene):
    """{"seat_point_m": [x, y, z] in V, "source": "car_file" (the file states it), "estimated"
    (a car file that states none: ``model.seat.estimated_seat_point_m``), "shipped" (the
    Escort's) or "scene" (the scene's ``car.seat_point_m``), "car_file"} of the scene's car."""
    point, name = [float(v) for v in scene.car.seat_point_m], scene.car_file or None
    if name:
        own = [float(v) for v in car_of_file(name).seat_point_m]
        source = ("scene" if point != own else
                  "car_file" if states_seat_point(name) else "estimated")
    else:
        source = "shipped" if point == list(ESCORT_SEAT_POINT_M) else "scene"
    return {"seat_point_m": point, "source": source, "car_file": name}


# What the estimate is (model.seat.estimated_seat_point_m), for the warning and the reports.
SEAT_ESTIMATE = ("the Escort's point scaled by the car's wheelbase, front track and body height: "
                 "a conventional car's driver, wrong for a forward-control van's over the front "
                 "axle")


def seat_place(point):
    """"1.250 m behind the front axle, 0.370 m left of the centre line, 0.500 m above the
    ground": a point in V, in words."""
    x, y, z = point
    return (f"{abs(x):.3f} m {'behind' if x <= 0 else 'ahead of'} the front axle, {abs(y):.3f} "
            f"m {'left' if y >= 0 else 'right'} of the centre line, {z:.3f} m above the ground")


def seat_point_words(s):
    """Where the seat point lies and where it comes from, in words (``s``: ``seat_point``'s)."""
    source = {
        "car_file": f"the car file's `seat_point_m` (`{s['car_file']}`)",
        "scene": "the scene's `car.seat_point_m`",
        "shipped": "the shipped Escort's [EST], `drake_car/model/seat.py`",
        "estimated": f"**estimated** [EST]: the car file `{s['car_file']}` states none, so "
                     f"{SEAT_ESTIMATE}; state your car's with {STATE_SEAT}"}
    return f"{seat_place(s['seat_point_m'])} ({source[s['source']]})"
