"""A value is checked once, where it enters (issue 29): the friction law's parameters (μs ≥ μd,
...), the car's parameters and the time step against every explicit part's stability limit are
each asked once per run, by ``scene.load.check_scene`` when the scene is loaded; building,
simulating, a sweep's worker and a sweep's read-back trust the checked scene. Counted by
wrapping each check."""

import collections

import pytest

from conftest import paper_scene
from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.law.tyre import slip as tyre_slip
from drake_car.model import anti_roll_bar, struts
from drake_car.model.parameters import CarParameters
from drake_car.results.files import run_texts
from drake_car.results.record import run_from_texts
from drake_car.scene import car_limits, limits
from drake_car.scene import load as scene_load
from drake_car.sim.simulate import simulate
from drake_car.sweep import runner as sweep_runner
from drake_car.sweep.store import commit_run, key_parts, load_run, run_key

# Each check, by the name the counts use: (module, attribute) of every place it can be called
# through (the module that defines it, and the modules that imported its name).
CHECKS = {
    "friction law (StrutFrictionParameters.check)": [(StrutFrictionParameters, "check")],
    "car (CarParameters.check)": [(CarParameters, "check")],
    "limits (scene.limits.check_limits)": [(limits, "check_limits"),
                                           (scene_load, "check_limits")],
    "road car (scene.car_limits.check_car)": [(car_limits, "check_car"),
                                              (scene_load, "check_car")],
    "anti-roll bars' step limit": [(anti_roll_bar, "time_step_limit_s"),
                                   (limits, "bar_time_step_limit_s")],
    "reference friction's step limit": [(struts, "reference_time_step_limit_s"),
                                        (limits, "reference_time_step_limit_s")],
    "tyres' step limit": [(tyre_slip, "explicit_time_step_limit_s"),
                          (limits, "tyre_time_step_limit_s")],
}


@pytest.fixture
def counts(monkeypatch):
    counted = collections.Counter()
    for name, places in CHECKS.items():
        original = getattr(*places[0])

        def wrapped(*args, _original=original, _name=name, **kwargs):
            counted[_name] += 1
            return _original(*args, **kwargs)
        for owner, attribute in places:
            monkeypatch.setattr(owner, attribute, wrapped)
    return counted


def test_a_run_checks_each_value_once_where_the_scene_is_loaded(counts, tmp_path):
    # The jammed set with the explicit scheme's step limit asked too: a_3 at a step the
    # reference scheme takes, run briefly.
    scene = paper_scene("a_3", "{simulator: {end_time_s: 0.05}, plant: {time_step: 5.0e-6}, "
                               "friction: {scheme: reference}}")
    once = {name: 1 for name in CHECKS}
    assert dict(counts) == once, "loading the scene"
    counts.clear()
    run = simulate(scene)
    assert dict(counts) == {}, "building and simulating a checked scene"
    # A sweep: the worker gets the scene's YAML and its key, the parent commits the files and
    # reads them back by their checksums; neither checks the scene again.
    parts = key_parts(scene)
    sent = sweep_runner._scene_of(scene_load.dump_scene(scene), parts)
    assert scene_load.dump_scene(sent) == scene_load.dump_scene(scene)
    texts = run_texts(run)
    run_from_texts(texts, trusted=True)
    job = sweep_runner.Job(run_key(parts), [scene.name], scene, parts)
    record, result = sweep_runner._record(job, {"run": texts, "wall_s": run.wall_s,
                                                "worker": "here"})
    (tmp_path / "runs").mkdir()
    commit_run(tmp_path / "runs", job, record, result)
    _, back = load_run(tmp_path, job.hash)
    assert dict(counts) == {}, "a sweep's worker and read-back"
    assert back.history["t"].tolist() == run.history["t"].tolist()


def test_a_results_folder_from_elsewhere_is_checked(counts):
    """Without checksums (a folder a user hands in), the scene read back is checked."""
    run = simulate(paper_scene("a_1", "simulator: {end_time_s: 0.02}"))
    counts.clear()
    run_from_texts(run_texts(run))
    assert counts["car (CarParameters.check)"] == 1
