"""The design study's runs, as named scenes: the maps' points, Sobol's sample, the Monte Carlo
of jam states with the driver letting go after the manoeuvre, each mitigation over the same
Monte-Carlo states, and a sample repeated at half the step (the numerical noise). Pure: scenes
in, scenes out; the sweep runs them."""

import dataclasses

from pydrake.multibody.plant import MultibodyPlantConfig

from drake_car.law.road import SampledProfile
from drake_car.scene.load import load_scene
from drake_car.scene.scene import HandsOff
from drake_car.study.design import rough_road, with_value
from drake_car.study.sensitivity import map_points, sobol_points

# The driver lets go this long after the lane change ends (the car runs straight again).
RELEASE_AFTER_S = 1.0


def quick(study):
    """A smoke version of ``study`` (``--quick``): every phase shortened, 2 × 2 maps, the
    smallest Sobol sample, 4 Monte-Carlo states, 2 per mitigation, 2 noise runs."""
    t = study.base.manoeuvre.timeline
    timeline = dataclasses.replace(t, settle_s=0.1, speed_up_s=0.6, straight_s=0.3,
                                   steer_s=0.6, calm_s=0.5)
    base = dataclasses.replace(study.base, manoeuvre=dataclasses.replace(
        study.base.manoeuvre, timeline=timeline))
    return dataclasses.replace(
        study, base=base, maps=[dataclasses.replace(m, points=2) for m in study.maps],
        sobol_base_samples=2, monte_carlo=dataclasses.replace(study.monte_carlo, samples=4,
                                                              length_m=8.0),
        mitigation_samples=2, noise_samples=2, pull_distance_m=5.0)


def map_scenes(study):
    """{name: (scene, values)} of every map's points."""
    scenes = {}
    for i, spec in enumerate(study.maps):
        for k, values in enumerate(map_points(study, spec)):
            name = f"map{i}_{k:03d}"
            scenes[name] = (with_value(study, values, name=name), values)
    return scenes


def sobol_scenes(study):
    return {f"sobol_{k:04d}": (with_value(study, values, name=f"sobol_{k:04d}"), values)
            for k, values in enumerate(sobol_points(study))}


def hands_off(study, scene):
    """``scene`` with the driver letting go ``RELEASE_AFTER_S`` after the lane change, and long
    enough after it to drive the study's pull distance."""
    m = scene.manoeuvre
    t = m.timeline
    span = study.pull_distance_m / t.speed_mps
    timeline = dataclasses.replace(t, calm_s=RELEASE_AFTER_S + span + 0.2)
    release = t.settle_s + t.speed_up_s + t.straight_s + t.steer_s + RELEASE_AFTER_S
    return dataclasses.replace(scene, manoeuvre=dataclasses.replace(m, timeline=timeline),
                               steering=HandsOff(release_s=release))


def monte_carlo_scenes(study, *, samples=None, scene_text=None, prefix="mc"):
    """Jam states: the base scene on a seeded rough road before the manoeuvre, hands off after
    it; ``scene_text`` (a mitigation) laid over each."""
    base = study.base
    if scene_text:
        base = load_scene(scene_text=scene_text, base=base)
    scenes = {}
    for k in range(study.monte_carlo.samples if samples is None else samples):
        x, z = rough_road(study, k)
        name = f"{prefix}_{k:04d}"
        scene = dataclasses.replace(hands_off(study, base), name=name,
                                    road=SampledProfile(x_m=x, z_m=z))
        scenes[name] = (with_value(study, {}, name=name, base=scene), {"sample": k})
    return scenes


def mitigation_scenes(study):
    scenes = {}
    for j, mitigation in enumerate(study.mitigations):
        for name, (scene, values) in monte_carlo_scenes(
                study, samples=study.mitigation_samples, scene_text=mitigation.scene_text,
                prefix=f"mitigation{j}").items():
            scenes[name] = (scene, values | {"mitigation": mitigation.name})
    return scenes


def noise_scenes(study, scenes):
    """The first ``noise_samples`` of ``scenes`` (name -> (scene, values)) at half their step:
    {name: (scene, values | {"of": original name})}."""
    out = {}
    for name in list(scenes)[:study.noise_samples]:
        scene, values = scenes[name]
        plant = MultibodyPlantConfig(**{f.name: getattr(scene.plant, f.name)
                                        for f in MultibodyPlantConfig.__fields__})
        plant.time_step = scene.plant.time_step / 2
        half = f"noise_{name}"
        out[half] = (dataclasses.replace(scene, name=half, plant=plant),
                     values | {"of": name})
    return out
