"""``car_file``: a car given by its hard points (``model.hard_points``), read where the scene is
loaded and turned into the scene's ``car`` (``CarParameters``, the one type everything
downstream reads).

The file's car lies beneath every ``car:`` value a scene's layers give, as the Escort's defaults
do without a car file: ``car: {front: {strut_damping_Nspm: 0.0}}`` (the paper's dry strut) or a
design study's ``car.front.ball_joint_offset_b_m`` act on it as on any car, in the parameters'
terms (b moves the ball joint, and the top mount with it). The saved scene holds ``car_file``
and every value of ``car`` as it ran, the values derived from the hard points included
(kingpin, caster, b, the strut's and the spring's inclinations and offsets, the sprung mass's
centre of gravity and inertia): it reruns bit for bit, and loading it reads the car file again,
beneath the saved values.

A car file states every value (a key left out is refused: no Escort value slips into another
car unseen) but the driver's seat point (``seat_point_m``), which, left out, is estimated from
the car's size [EST] and said so (``scene.borrowed``); the values are checked one by one and
the points as a McPherson corner (``HardPointCar.check``); the car they make is checked with
the scene (``CarParameters.check``, ``scene.car_limits``), a refusal naming the hard points it
was derived from.
"""

import copy
import dataclasses
import functools
import typing
from pathlib import Path

from pydrake.common.yaml import yaml_load

from drake_car.law.checks import ParameterError, checked, excerpt, one_line
from drake_car.model.hard_points import HardPointCar, to_parameters
from drake_car.model.loading import DataFileError, data_path, file_version, where_data_is
from drake_car.model.parameters import CarParameters
from drake_car.scene.guard import check_yaml, read_yaml_file
from drake_car.scene.raw import SceneError, check_raw, guarded, typed


def read_car_file(name) -> HardPointCar:
    """The car file ``name`` (a path, or a name in the package's ``urdf/`` data such as
    ``cars/bmw_320i.yaml``), checked; SceneError naming the file and the key."""
    where = f"car_file {name}"
    path = _car_path(name)
    if not path.exists():
        raise SceneError(f"{where}: car file not found"
                         + ("" if Path(name).is_absolute() else f" ({where_data_is(name)})"))
    try:
        text = guarded(read_yaml_file, path, "car file")
    except SceneError as e:  # a folder, a device, too big: said of the car_file named
        raise SceneError(f"{where}: {e}") from None
    guarded(check_yaml, text, where)
    try:
        raw = yaml_load(data=text) if text.strip() else None  # Drake's reads "" as no data
    except Exception as e:
        raise SceneError(f"{where}: not YAML: {one_line(e)}") from None
    if not isinstance(raw, dict):
        raise SceneError(f"{where}: must map the car's sections (mass, wheelbase_m, "
                         "driven_axle, front, rear, tyre) to their values")
    check_raw(raw, HardPointCar, where, "")
    _every_key_given(raw, HardPointCar, where, "")
    car = typed(where, schema=HardPointCar, data=text)
    try:
        return checked(car, "")
    except ParameterError as e:
        raise SceneError(f"{where}: {e}") from None


def _car_path(name):
    try:
        return data_path(name)
    except DataFileError as e:
        raise SceneError(f"car_file {e}") from None


def _every_key_given(raw, schema, where, key):
    for field in dataclasses.fields(schema):
        name = f"{key}.{field.name}" if key else field.name
        if field.name not in raw and not _optional(schema, field.name):
            raise SceneError(f"{where}: {name} is not given; a car file states every value "
                             "(none is taken from the shipped car)")
        hint = typing.get_type_hints(schema)[field.name]
        if dataclasses.is_dataclass(hint):
            _every_key_given(raw[field.name] or {}, hint, where, name)


def _optional(schema, name):
    """Whether a car file may leave ``name`` out (the seat point: ``model.hard_points``)."""
    return (schema, name) in _OPTIONAL


_OPTIONAL = {(HardPointCar, "seat_point_m")}


def car_of_file(name) -> CarParameters:
    """The car of the car file ``name`` (a fresh copy), read once per process for each version
    of the file (its path, size and modification time)."""
    path = _car_path(name)
    return copy.deepcopy(_car_of_file(str(name), str(path), file_version(path)))


@functools.lru_cache(maxsize=16)
def _car_of_file(name, path, version):
    return to_parameters(read_car_file(name))


def states_seat_point(name):
    """Whether the car file ``name`` states its seat point (``seat_point_m``; else the car runs
    with an estimate: ``model.seat``)."""
    path = _car_path(name)
    return _states_seat_point(str(name), str(path), file_version(path))


@functools.lru_cache(maxsize=16)
def _states_seat_point(name, path, version):
    return bool(read_car_file(name).seat_point_m)


def with_car_file(scene, name):
    """``scene`` with ``car_file = name``: the car the file makes (the Escort's defaults for
    None), with every value in which ``scene.car`` differs from the car it was made from (its
    own car file's, or the defaults) laid over it."""
    old = car_of_file(scene.car_file) if scene.car_file else CarParameters()
    new = car_of_file(name) if name else CarParameters()
    return dataclasses.replace(scene, car_file=name, car=_laid_over(new, scene.car, old))


def _laid_over(new, car, old):
    out = copy.deepcopy(new)
    for field in dataclasses.fields(car):
        mine, theirs = getattr(car, field.name), getattr(old, field.name)
        if dataclasses.is_dataclass(mine):
            setattr(out, field.name, _laid_over(getattr(new, field.name), mine, theirs))
        elif mine != theirs:
            setattr(out, field.name, copy.deepcopy(mine))
    return out


def derived_note(scene, key):
    """For a refusal of ``car.<key>`` of a scene with a car file whose value the file gave: what
    the value was derived from ('' otherwise)."""
    if not scene.car_file or not key.startswith("car."):
        return ""
    inner = key[len("car."):]
    group, _, name = inner.partition(".")
    try:
        given = getattr(getattr(car_of_file(scene.car_file), group), name.split("[")[0])
        mine = getattr(getattr(scene.car, group), name.split("[")[0])
    except (AttributeError, SceneError):
        return ""
    if given != mine:
        return ""
    source = DERIVED_FROM.get(inner.split("[")[0], inner.split("[")[0])
    return f" (car_file {excerpt(scene.car_file)} gives it from its {source})"


_SPRING = "front.spring_upper_seat_m and front.spring_lower_seat_m (about the strut axis)"
_STRUT = "front.strut_top_mount_m and front.strut_lower_mount_m"
_STEER = "front.ball_joint_m and front.strut_top_mount_m"
_BODY = ("mass (the whole car's centre of gravity and inertia, less the parts') and "
         "wheelbase_m")
# Where each value of CarParameters comes from in a car file (for a refusal's message).
DERIVED_FROM = {
    "front.track_m": "front.wheel_centre_m (y)",
    "front.ball_joint_offset_b_m": "front.wheel_centre_m and front.ball_joint_m (y)",
    "front.ball_joint_height_m": "front.ball_joint_m", "front.ball_joint_x_m": "front.ball_joint_m",
    "front.kingpin_inclination_deg": _STEER, "front.caster_deg": _STEER,
    "front.top_mount_height_m": "front.strut_top_mount_m",
    "front.strut_inclination_deg": _STRUT, "front.strut_caster_deg": _STRUT,
    "front.strut_lower_mount_below_top_m": _STRUT,
    "front.spring_lower_seat_below_top_m": _SPRING, "front.spring_upper_seat_below_top_m": _SPRING,
    "front.spring_offset_m": _SPRING, "front.spring_inclination_deg": _SPRING,
    "front.spring_offset_fore_aft_m": _SPRING, "front.spring_inclination_fore_aft_deg": _SPRING,
    "front.rack_x_m": "front.tie_rod_inner_m", "front.rack_height_m": "front.tie_rod_inner_m",
    "front.rack_half_length_m": "front.tie_rod_inner_m",
    "mass.cog_to_front_axle_m": _BODY, "mass.cog_to_rear_axle_m": _BODY,
    "mass.sprung_cog_height_m": _BODY, "mass.sprung_inertia_kgm2": _BODY,
    "rear.pivot_height_m": "rear.pivot_height_m (moved with the frame)",
    "rear.spring_lower_height_m": "rear.spring_lower_height_m (moved with the frame)",
    "rear.spring_upper_height_m": "rear.spring_upper_height_m (moved with the frame)",
}
