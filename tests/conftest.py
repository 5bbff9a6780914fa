"""Shared helpers: the shipped scenes, short runs, the tiers (``-m "not slow"`` is the quick
tier; the README's command runs everything)."""

import dataclasses

import numpy as np

from drake_car.data import resource
from drake_car.scene.load import load_scene

CAR_SCENES = resource("scenes/car.yaml")
PAPER_SCENES = resource("scenes/paper_study.yaml")


def car_scene(child, text=None):
    return load_scene(CAR_SCENES, child=child, scene_text=text)


def paper_scene(child, text=None):
    return load_scene(PAPER_SCENES, child=child, scene_text=text)


def with_car(scene, **front):
    """``scene`` with front suspension fields replaced."""
    return dataclasses.replace(scene, car=dataclasses.replace(
        scene.car, front=dataclasses.replace(scene.car.front, **front)))


def assert_same_state(a, b):
    """Two runners' Diagrams hold the same discrete state, bit for bit (``sim.transfer``)."""
    from drake_car.sim import transfer
    va, vb = (transfer.state_values(r.built, r.root) for r in (a, b))
    for system, groups in va.groups.items():
        for i, values in enumerate(groups):
            assert np.array_equal(values, vb.groups[system][i]), (system, i)


def assert_finite(history):
    for name, values in history.items():
        if name != "phase":
            assert np.all(np.isfinite(values)), name
