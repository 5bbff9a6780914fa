"""The static equilibrium cached on disk (``sim.equilibrium_cache``): what comes back is
bit-identical to what was settled; a damaged or foreign entry is ignored and recomputed."""

import dataclasses
import json
import logging

import pytest

from drake_car.sim import equilibrium_cache
from drake_car.sim.simulate import _settled, static_equilibrium
from drake_car.scene.load import dump_scene
from drake_car.sim.equilibrium import equilibrium_scene
from conftest import car_scene


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(equilibrium_cache.ENVIRONMENT_VARIABLE, str(tmp_path))
    _settled.cache_clear()
    yield tmp_path / "equilibrium"
    _settled.cache_clear()


def _scene():
    # A short settling: the cache's behaviour does not depend on how settled the car is.
    return car_scene("straight", "simulator: {equilibrium_settle_s: 0.1}")


def test_the_cached_equilibrium_is_bit_identical(cache):
    scene = _scene()
    settled = static_equilibrium(scene)
    entries = list(cache.glob("*.json"))
    assert len(entries) == 1, entries
    _settled.cache_clear()
    loaded = equilibrium_cache.load(dump_scene(equilibrium_scene(scene)))
    assert loaded is not None
    assert dataclasses.asdict(loaded) == dataclasses.asdict(settled)
    assert dataclasses.asdict(static_equilibrium(scene)) == dataclasses.asdict(settled)


@pytest.mark.parametrize("damage", ["cut short", "another key", "not a number", "empty"])
def test_a_damaged_entry_is_recomputed(cache, damage):
    scene = _scene()
    settled = static_equilibrium(scene)
    (entry,) = cache.glob("*.json")
    data = json.loads(entry.read_text())
    if damage == "cut short":
        entry.write_text(entry.read_text()[: len(entry.read_text()) // 2])
    elif damage == "another key":
        data["key"] = "0" * 64
        entry.write_text(json.dumps(data))
    elif damage == "not a number":
        data["equilibrium"]["positions"][3] = "NaN"
        entry.write_text(json.dumps(data))
    else:
        entry.write_text("")
    settle_yaml = dump_scene(equilibrium_scene(scene))
    assert equilibrium_cache.load(settle_yaml) is None, damage
    _settled.cache_clear()
    assert dataclasses.asdict(static_equilibrium(scene)) == dataclasses.asdict(settled)
    assert equilibrium_cache.load(settle_yaml) is not None, "the recomputed entry is written"


@pytest.mark.parametrize("damage", ["overlap a list", "positions cut to 5", "positions a dict",
                                    "no equilibrium", "a list"])
def test_a_malformed_entry_is_ignored_with_a_warning(cache, damage):
    """Valid JSON with its own key but a value of the wrong shape (review rv44: a list for
    overlap_m raised AttributeError; 5 positions stopped the run in Drake's SetPositions): the
    entry is ignored, one warning names its file, the car is settled again and runs."""
    from drake_car.sim.simulate import simulate
    scene = _scene()
    settled = static_equilibrium(scene)
    (entry,) = cache.glob("*.json")
    data = json.loads(entry.read_text())
    e = data["equilibrium"]
    if damage == "overlap a list":
        e["overlap_m"] = list(e["overlap_m"].values())
    elif damage == "positions cut to 5":
        e["positions"] = e["positions"][:5]
    elif damage == "positions a dict":
        e["positions"] = {"q": 1.0}
    elif damage == "no equilibrium":
        data["equilibrium"] = 3
    else:
        data = [data]
    entry.write_text(json.dumps(data))
    _settled.cache_clear()
    records = []
    handler = logging.Handler(logging.WARNING)
    handler.emit = records.append  # the module's own logger: the commands' set-up stops propagation
    logger = logging.getLogger(equilibrium_cache.__name__)
    logger.addHandler(handler)
    try:
        run = simulate(car_scene("straight", "simulator: {equilibrium_settle_s: 0.1, "
                                             "start: static_equilibrium, end_time_s: 0.01}"))
    finally:
        logger.removeHandler(handler)
    assert len(run.history["t"]) > 0
    messages = [r.getMessage() for r in records]
    assert len(messages) == 1 and str(entry) in messages[0], messages
    assert "damaged equilibrium cache entry" in messages[0]
    _settled.cache_clear()
    assert dataclasses.asdict(static_equilibrium(scene)) == dataclasses.asdict(settled)


def test_the_key_names_the_code_and_the_scene(cache):
    settle = dump_scene(equilibrium_scene(_scene()))
    other = dump_scene(equilibrium_scene(car_scene("straight",
                                                   "simulator: {equilibrium_settle_s: 0.2}")))
    assert equilibrium_cache.entry_key(settle) != equilibrium_cache.entry_key(other)
    assert len(equilibrium_cache.code_fingerprint()) == 64
