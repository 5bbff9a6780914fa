"""``tyres.vertical_from_file``: the tyre file's vertical stiffness and damping set into the
scene's ``car.tyre`` where the scene is loaded, so that everything built from the scene (the
tyres' radial spring, the static equilibrium and its cache key, the drive's rolling radius, the
divergence monitor's energy, the handling analysis) uses the same numbers and the saved scene
shows them. Loading the saved scene again sets the same values."""

import dataclasses
import math

from drake_car.law.checks import ParameterError
from drake_car.law.tyre.contact import vertical_from_file
from drake_car.law.tyre.magic_formula import MagicFormulaTyre
from drake_car.model.loading import tir_path
from drake_car.model.parameters import TyreVerticalParameters


def resolve_vertical(scene):
    """The scene with car.tyre's radial stiffness and damping from its tyre file when
    ``tyres.vertical_from_file`` (else unchanged). A car.tyre value that is neither the
    default nor the file's is refused: it would have no effect."""
    tyres = scene.tyres
    if not getattr(tyres, "vertical_from_file", False):
        return scene
    tyre = MagicFormulaTyre.from_file(tir_path(tyres.tir_file))
    try:
        stiffness, damping = vertical_from_file(tyre)
    except ValueError as e:
        raise ParameterError("tyres.vertical_from_file", True, f"needs them: {e}") from None
    default, given = TyreVerticalParameters(), scene.car.tyre
    for name, value in (("radial_stiffness_Npm", stiffness), ("radial_damping_Nspm", damping)):
        mine = getattr(given, name)
        if mine != getattr(default, name) and not math.isclose(mine, value, rel_tol=1e-12):
            raise ParameterError(f"car.tyre.{name}", mine,
                                 f"has no effect with tyres.vertical_from_file (the file "
                                 f"gives {value:g}); leave it out (a scene saved on another "
                                 "tyre file holds that file's value: lay the new file over "
                                 "the scene file it was made from)")
    car = dataclasses.replace(scene.car, tyre=dataclasses.replace(
        given, radial_stiffness_Npm=stiffness, radial_damping_Nspm=damping))
    return dataclasses.replace(scene, car=car)
