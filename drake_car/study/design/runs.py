"""The design study's runs, as named scenes: the maps' points, Sobol's sample, the Monte Carlo
of jam states with the driver letting go after the manoeuvre, each mitigation over the same
Monte-Carlo states, and a sample repeated at half the step (the numerical noise). Pure: scenes
in, scenes out; the sweep runs them. (The smoke test's shortened study: ``smoke.quick``.)"""

import dataclasses

from pydrake.multibody.plant import MultibodyPlantConfig

from drake_car.scene.load import load_scene
from drake_car.scene.scene import HandsOff
from drake_car.study.design.spec import rough_road, with_value
from drake_car.study.design.sensitivity import map_points, sobol_points


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


def line_scenes(study):
    """{name: (scene, values)} of every line's points at each of ``line_mu_s``, hands off."""
    scenes = {}
    for i, line in enumerate(study.lines):
        for j, mu_s in enumerate(study.line_mu_s):
            for k, value in enumerate(line.values):
                name = f"line{i}_mu{j}_{k:02d}"
                values = {"friction.law.mu_s": mu_s, line.key: value}
                scene = hands_off(study, with_value(study, values, name=name))
                scenes[name] = (scene, values | {"line": line.key})
    return scenes


def hands_off(study, scene):
    """``scene`` with the driver letting go where its calm phase ends (so place b, its last
    0.5 s, is the same window with hands on and off), and driving on long enough to cover the
    study's pull distance."""
    m = scene.manoeuvre
    t = m.timeline
    span = study.pull_distance_m / t.speed_mps
    release = t.boundaries()[2] + t.calm_s
    timeline = dataclasses.replace(t, calm_s=t.calm_s + span + 0.2)
    return dataclasses.replace(scene, manoeuvre=dataclasses.replace(m, timeline=timeline),
                               steering=HandsOff(release_s=release))


def monte_carlo_scenes(study, *, samples=None, mu_s=None, scene_text=None, prefix="mc"):
    """Jam states: the base scene on a seeded rough road before the manoeuvre, hands off after
    it; at ``mu_s`` (None: the base scene's), ``scene_text`` (a mitigation) laid over each."""
    scenes = {}
    for k in range(study.monte_carlo.samples if samples is None else samples):
        name = f"{prefix}_{k:04d}"
        scene = dataclasses.replace(hands_off(study, study.base), road=rough_road(study, k))
        if mu_s is not None:
            scene = with_value(study, {"friction.law.mu_s": mu_s}, base=scene)
        if scene_text:
            scene = load_scene(scene_text=scene_text, base=scene)
        scenes[name] = (with_value(study, {}, name=name, base=scene), {"sample": k})
    return scenes


def mitigation_baseline(study):
    """The name of the mitigations' baseline group (the car as it is, at their μs)."""
    mu_s = study.mitigation_mu_s
    return "baseline" + (f" (μs {mu_s:g})" if mu_s is not None else "")


def mitigation_scenes(study):
    """The first ``mitigation_samples`` jam states at ``mitigation_mu_s``: the car as it is
    (``mitigation_baseline``), then with each mitigation. A group equal to the Monte Carlo's
    runs has their hashes, so the sweep runs it once."""
    groups = [(mitigation_baseline(study), "")] + [(m.name, m.scene_text)
                                                    for m in study.mitigations]
    scenes = {}
    for j, (label, scene_text) in enumerate(groups):
        for name, (scene, values) in monte_carlo_scenes(
                study, samples=study.mitigation_samples, mu_s=study.mitigation_mu_s,
                scene_text=scene_text, prefix=f"mitigation{j}").items():
            scenes[name] = (scene, values | {"mitigation": label})
    return scenes


def noise_sample(study, parts):
    """``noise_samples`` names spread evenly over every part's runs (parts: {role: {name:
    ...}}), each part in turn: the runs whose half-step twins measure the numerical noise."""
    pools = [list(part) for part in parts.values() if part]
    picks = {i: [] for i in range(len(pools))}
    for n in range(study.noise_samples):
        picks[n % len(pools)].append(None)
    names = []
    for i, pool in enumerate(pools):
        count = min(len(picks[i]), len(pool))
        names += [pool[int(k * len(pool) / count)] for k in range(count)]
    return names


def noise_scenes(study, scenes, names):
    """``names`` of ``scenes`` (name -> (scene, values)) at half their step:
    {name: (scene, values | {"of": original name})}."""
    out = {}
    for name in names:
        scene, values = scenes[name]
        plant = MultibodyPlantConfig(**{f.name: getattr(scene.plant, f.name)
                                        for f in MultibodyPlantConfig.__fields__})
        plant.time_step = scene.plant.time_step / 2
        half = f"noise_{name}"
        out[half] = (dataclasses.replace(scene, name=half, plant=plant),
                     values | {"of": name})
    return out
