"""Running many scenes (serially for now; the Dask runner replaces this)."""

from drake_car.sim.simulate import simulate


def run_scenes(scenes: dict, *, progress=True):
    """name -> Run for name -> Scene."""
    return {name: simulate(scene, progress=progress) for name, scene in scenes.items()}
