"""Loads the car's model file into a MultibodyPlant, with clear errors for bad files."""

import dataclasses
import filecmp
import functools
from pathlib import Path

from pydrake.math import RigidTransform
from pydrake.multibody.parsing import Parser

from drake_car.data import resource
from drake_car.model.geometry import SIDES
from drake_car.law.errors import InputError
from drake_car.law.tyre.magic_formula import MagicFormulaTyre
from drake_car.law.tyre.property_file import TirFileError

# Bodies and joints every car model file must declare (the code addresses them by name).
REQUIRED_BODIES = ["chassis", "steering_rack"] + [
    f"{part}_{side}" for side in SIDES for part in (
        "lower_arm", "knuckle", "strut_slider", "piston_rod", "wheel_front", "tie_rod",
        "trailing_arm", "wheel_rear")]
REQUIRED_FRAMES = [
    f"{name}_{side}" for side in SIDES for name in (
        "top_mount", "ball_joint_arm", "ball_joint_knuckle", "spring_upper_seat",
        "spring_lower_seat", "strut_lower_mount", "piston", "guide", "rear_spring_upper_seat",
        "rear_spring_lower_seat", "tie_rod_outer", "tie_rod_end")]


class DataFileError(InputError):
    """A relative name of a car's data file that names two different files."""


class ModelFileError(InputError):
    """A model file is missing, malformed, or lacks a part the car needs; names the file."""


@dataclasses.dataclass
class ModelSource:
    """Either a path to an SDFormat/URDF file or the text of one (``label`` names it)."""

    text: str | None = None
    path: Path | None = None
    label: str = "<generated car model>"


def load_car(plant, source: ModelSource, *, fixed_chassis: bool = False):
    """Adds the car to ``plant`` (not finalized) and returns its model instance."""
    parser = Parser(plant)
    try:
        if source.path is not None:
            path = Path(source.path)
            if not path.is_file():
                raise ModelFileError(f"{path}: model file not found")
            instances = parser.AddModels(str(path))
            where = str(path)
        else:
            instances = parser.AddModelsFromString(source.text, "sdf")
            where = source.label
    except ModelFileError:
        raise
    except Exception as e:  # Drake reports parse errors as RuntimeError with the line
        name = source.path if source.path is not None else source.label
        raise ModelFileError(f"{name}: cannot parse the car model: {e}") from e
    if len(instances) != 1:
        raise ModelFileError(f"{where}: expected one model, found {len(instances)}")
    instance = instances[0]
    for name in REQUIRED_BODIES:
        if not plant.HasBodyNamed(name, instance):
            raise ModelFileError(f"{where}: the car model lacks the body '{name}'")
    for name in REQUIRED_FRAMES:
        if not plant.HasFrameNamed(name, instance):
            raise ModelFileError(f"{where}: the car model lacks the frame '{name}'")
    if fixed_chassis:
        plant.WeldFrames(plant.world_frame(),
                         plant.GetBodyByName("chassis", instance).body_frame(),
                         RigidTransform())
    return instance


def frame_point(plant, name, instance):
    """(body, position of the frame's origin in the body frame) of a named fixed frame."""
    frame = plant.GetFrameByName(name, instance)
    return frame.body(), frame.GetFixedPoseInBodyFrame().translation()


def file_version(path):
    """(size, modification time) of the file at ``path``, what a read-once cache keys a file's
    version by; None where it cannot be read (its reader then names the missing file)."""
    try:
        stat = path.stat()
    except OSError:
        return None
    return stat.st_size, stat.st_mtime_ns


def read_tyre(name):
    """The Magic Formula tyre of property file ``name`` (``tir_path``), read once per process
    for each version of the file (its path, size and modification time)."""
    path = tir_path(name)
    return _read_tyre(str(path), file_version(path))


@functools.lru_cache(maxsize=32)
def _read_tyre(path, version):
    return MagicFormulaTyre.from_file(Path(path))


def tir_path(name, option="tyres.tir_file"):
    """A tyre property file (``data_path``); a ``name`` found nowhere is a TirFileError naming
    ``option`` (the scene's key, or a command's option) and, for a relative name, where it was
    looked for."""
    path = data_path(name)
    if not path.exists():
        raise TirFileError(f"{option} {name}: tyre property file not found" + (
            "" if Path(name).is_absolute() else f" ({where_data_is(name)})"))
    return path


def data_path(name):
    """A file of the car's data (a tyre property file, a car file): an absolute path; or a path
    inside the package's ``urdf/`` data (``tyres/pacejka2006_205_60R15.tir``,
    ``cars/bmw_320i.yaml``); or, when no such data exists, a path relative to the working
    folder (made absolute). A relative name that is both, two different files, is refused
    (DataFileError): which one ran would depend on where the job was started."""
    path = Path(name)
    if path.is_absolute():
        return path
    packaged = Path(str(resource("urdf").joinpath(name)))
    local = path.absolute()
    if packaged.is_file() and local.is_file() and not filecmp.cmp(packaged, local, shallow=False):
        raise DataFileError(
            f"{name}: names both a shipped file ({packaged}) and a different one in the "
            f"working folder ({local}): which ran would depend on where the job starts; give "
            "yours by its absolute path, or move or rename the working folder's copy")
    if packaged.exists() or not path.exists():
        return packaged
    return local


def working_folder_names(names):
    """Those of the data-file ``names`` (None left out) that are found in the working folder,
    not in the shipped data: a scene naming them runs only from this folder."""
    shipped = Path(str(resource("urdf")))
    found = []
    for name in names:
        if not name or Path(name).is_absolute():
            continue
        try:
            path = data_path(name)
        except DataFileError:
            path = Path(name).absolute()
        if path.exists() and not path.is_relative_to(shipped):
            found.append(name)
    return found


def where_data_is(name):
    """Where ``data_path`` looked for a relative ``name`` (for a "not found")."""
    return (f"looked in the working folder ({Path.cwd()}) and the shipped data "
            f"({Path(str(resource('urdf')))})")
