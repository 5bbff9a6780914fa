"""The project's data, shipped with the package: the model folder ``urdf/`` (car model, tyre
property files) and the scenes folder ``scenes/`` at the project's top level, linked here (a
built wheel holds copies). Read through ``resource``, never through a path relative to a
source file."""

import importlib.resources


def resource(relative):
    """A file or folder of the package's data, e.g. ``resource("urdf/tyres/x.tir")``."""
    return importlib.resources.files(__name__).joinpath(relative)
