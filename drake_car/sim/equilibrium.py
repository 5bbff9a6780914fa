"""The static equilibrium every drive starts from: the lubricated car settled at rest on its
tyres (as a multibody code's static analysis precedes its dynamic run). Δd is measured from it
(the paper's "increments from static equilibrium").

``equilibrium_scene(scene)`` derives, from any scene, the settling scene whose end state is that
equilibrium: the same car, road and plant, the struts lubricated (no friction, the paper's
1250 N s/m, which settles fast; neither changes where the car comes to rest), vertical tyres
only, at rest for ``simulator.equilibrium_settle_s`` at ``simulator.equilibrium_time_step_s``
(default 1 ms). The runner (``sim.simulate``) runs it and
caches the result by that scene's content. The car at rest touches the road only under its
tyres: a road that is flat there (z = 0 up to ``FLAT_AHEAD_M`` ahead of the front contact
patches) gives the flat road's equilibrium bit for bit, so the settling scene takes the flat
road, and every scene on such a road shares one cached equilibrium.
"""

import dataclasses

from pydrake.multibody.plant import MultibodyPlantConfig

from drake_car.law.road.profiles import Flat
from drake_car.scene.manoeuvres import Settle
from drake_car.scene.scene import (
    Logging, NoVisualization, Scene, Simulator, VerticalOnly)

LUBRICATED_DAMPING_NSPM = 1250.0  # paper section 4
# The car starts with its front contact patches at x = 0 (the vehicle frame's origin): the
# patches' half length (~0.1 m) and their creep while settling (millimetres) lie well inside 1 m.
FLAT_AHEAD_M = 1.0


@dataclasses.dataclass
class Equilibrium:
    positions: list  # the car's generalized positions
    overlap_m: dict  # d per side
    corner_loads_N: dict
    max_abs_velocity: float  # of the car's generalized velocities at the end
    settle_s: float
    time_step_s: float


def equilibrium_scene(scene: Scene) -> Scene:
    car = dataclasses.replace(scene.car, front=dataclasses.replace(
        scene.car.front, strut_damping_Nspm=LUBRICATED_DAMPING_NSPM))
    sim = scene.simulator
    plant = scene.plant
    if sim.equilibrium_time_step_s is not None:
        plant = MultibodyPlantConfig(**{f.name: getattr(plant, f.name)
                                        for f in MultibodyPlantConfig.__fields__})
        plant.time_step = sim.equilibrium_time_step_s
    return Scene(
        name="static equilibrium", car=car, friction=None,
        tyres=VerticalOnly(), road=_road_at_rest(scene.road),
        manoeuvre=Settle(duration_s=scene.simulator.equilibrium_settle_s),
        plant=plant,
        simulator=Simulator(start="design", sap_pacer=sim.sap_pacer),
        logging=Logging(channels=["struts"], record_period_s=0.1),
        visualization=NoVisualization())


def _road_at_rest(road):
    return Flat() if road.flat_up_to_m() >= FLAT_AHEAD_M else road


def equilibrium_from_run(run) -> Equilibrium:
    final = run.final
    return Equilibrium(positions=final["positions"], overlap_m=final["strut_overlap_m"],
                       corner_loads_N=final["corner_loads_N"],
                       max_abs_velocity=final["max_abs_generalized_velocity"],
                       settle_s=run.scene.manoeuvre.duration_s,
                       time_step_s=run.scene.time_step_s)
