"""The package's front door: ``drake_car`` offers what a user builds with, loaded lazily, so
that importing one room (the law) loads neither Drake nor the rest of the package."""

import subprocess
import sys

import drake_car


def test_every_exported_name_resolves():
    for name in drake_car.__all__:
        assert getattr(drake_car, name) is not None, name
    assert set(drake_car.__all__) <= set(dir(drake_car))
    assert {"load_scene", "Scene", "build_diagram", "simulate", "StrutFriction", "TyreSystem",
            "StrutFrictionParameters", "PathDriver"} <= set(drake_car.__all__)


def test_an_unknown_name_is_an_attribute_error():
    try:
        drake_car.no_such_name
    except AttributeError as e:
        assert "no_such_name" in str(e)
    else:
        raise AssertionError("drake_car.no_such_name did not raise")


def test_the_law_loads_without_drake():
    """A fresh process importing the package and the friction law has no pydrake module."""
    code = ("import sys, drake_car, drake_car.law.friction.frd; "
            "print(sorted(m for m in sys.modules if m.startswith(('pydrake', 'drake_car.sim'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]", out


def test_the_package_docstrings_build_works_on_a_lane_change():
    """``drake_car``'s own example: a lane change's Diagram is built from the scene as it runs
    (its rack calibrated for the car: the shipped Escort's profile); the uncalibrated scene is
    refused with an InputError that names the way."""
    import pytest
    from pathlib import Path
    root = Path(__file__).resolve().parents[1]
    scene = drake_car.load_scene(root / "scenes" / "paper_study.yaml", child="a_3")
    with pytest.raises(drake_car.InputError, match=r"drake_car\.scene_as_it_runs\(scene\)"):
        drake_car.build_diagram(scene)
    built = drake_car.build_diagram(drake_car.scene_as_it_runs(scene))
    assert built.scene.manoeuvre.calibrated and built.friction is not None


def test_quiet_quiets_drakes_own_info_messages_too():
    """``--quiet`` is warnings only: Drake's messages (e.g. "Meshcat listening ...", routed to
    the "drake" logger) included; without it Drake's level is left as pydrake sets it."""
    import logging
    from drake_car.commands.cli import configure_logging
    drake = logging.getLogger("drake")
    before = drake.level
    try:
        configure_logging()
        assert drake.level == before
        configure_logging(quiet=True)
        assert not drake.isEnabledFor(logging.INFO) and drake.isEnabledFor(logging.WARNING)
    finally:
        drake.setLevel(before)
        configure_logging()
