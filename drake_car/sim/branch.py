"""Runs that share a prefix simulate it once: the paper's lane changes a and b (and any scenes
that differ only in the lane change's case) agree until the lane change starts, so the first
run's whole Diagram context is saved there (plant, friction creep and phases, tyre relaxation,
the pacer's time) and each other run continues from a copy of it in its own Diagram.

How (Drake 1.51): the family's Diagram is built branchable (``build_diagram(branchable=True)``:
both cases' rack commands behind a switch whose selection is a value fixed in the context), the
root context is cloned at the branch time, and each other run continues a clone with its own
case selected, in a new Simulator that does not re-run the initialization events (they would
reset the friction's memory). The strut friction first writes the PD gains of the cloned state
into its actuators (they live in the plant model, not the context). Copying a context into
another, alike-built Diagram does not work: the plant's sampled step memory and SceneGraph's
state carry identifiers of their own Diagram ("map::at" at the next step).
``tests/test_branch.py`` shows a branched run equals the run from scratch bit for bit.
"""

import copy
import dataclasses

from pydrake.systems.analysis import InitializeParams

from drake_car.scene.load import scene_hash
from drake_car.scene.manoeuvres import LaneChange
from drake_car.scene.scene import NoVisualization, Scene
from drake_car.sim.simulate import SceneRunner, simulate
from drake_car.systems.gain_schedule import GainSchedule
from drake_car.systems.strut_friction import StrutFriction


def branch_point(scene: Scene):
    """(the prefix's content hash, the branch time) of a scene whose start it can share with
    others, or None. Scenes with the same prefix hash agree up to the branch time."""
    m = scene.manoeuvre
    if not isinstance(m, LaneChange) or not isinstance(scene.visualization, NoVisualization):
        return None
    t_branch = m.timeline.boundaries()[1]  # the lane change starts: the rack is zero before
    if not 0 < t_branch < scene.end_time_s:
        return None
    prefix = dataclasses.replace(scene, name="", manoeuvre=dataclasses.replace(m, case="a"))
    return scene_hash(prefix), t_branch


def _write_model_values(built, root):
    """The PD gains and effort limits that the friction and the hands-off schedule keep in the
    plant's model (not its context) written again from ``root``'s context: the family's earlier
    run left them as they were at its end (a released rack, a sliding pair)."""
    for system in built.diagram.GetSystems():
        if isinstance(system, (GainSchedule, StrutFriction)):
            system.ForcedPublish(system.GetMyContextFromRoot(root))


def families(scenes: dict):
    """Groups of scene names that share a prefix (each name once; singletons included)."""
    groups = {}
    for name, scene in scenes.items():
        point = branch_point(scene)
        groups.setdefault(point if point is not None else ("alone", name), []).append(name)
    return list(groups.values())


def simulate_family(scenes: list, *, progress=False):
    """Runs scenes that share a prefix (``branch_point``), the prefix once; returns their Runs
    in order. A single scene is simply run."""
    points = {branch_point(s) for s in scenes}
    if len(scenes) > 1 and (len(points) != 1 or None in points):
        raise ValueError("simulate_family: the scenes do not share a prefix: "
                         + ", ".join(s.name for s in scenes))
    if len(scenes) == 1:
        return [simulate(scenes[0], progress=progress)]
    (_, t_branch), = points
    first = SceneRunner(scenes[0], progress=progress, branchable=True)
    first.start()
    first.advance_to(t_branch)
    saved = first.root.Clone()
    prefix_stats, prefix_last_v = copy.copy(first.monitor.stats), first.monitor.last_velocities
    prefix_wall, prefix_cpu = first.wall_s, first.cpu_s
    first.advance_to(scenes[0].end_time_s)
    runs = [first.finish()]
    for scene in scenes[1:]:
        runner = SceneRunner(scene, progress=progress, built=first.built, context=saved.Clone())
        _write_model_values(runner.built, runner.root)
        runner.simulator.Initialize(InitializeParams(suppress_initialization_events=True))
        # Starting at the branch time, the loggers sample that time again: the channels' logs
        # keep it once (sim.simulation.logged_history), the every-step log is not a new step.
        runner.built.velocity_logger.FindMutableLog(runner.root).Clear()
        runner.monitor.resume(prefix_stats, prefix_last_v)
        runner.wall_s, runner.cpu_s = prefix_wall, prefix_cpu
        runner.advance_to(scene.end_time_s)
        runs.append(runner.finish())
    return runs
