"""drake_car: what dry friction in a car's McPherson struts does to the car, on Drake's systems
framework (Harlecki & Kubas' ADAMS study rebuilt). What a user builds with:

    import drake_car
    scene = drake_car.load_scene("scenes/paper_study.yaml", child="a_3")
    run = drake_car.simulate(scene)             # history, final state, the scene that ran
    built = drake_car.build_diagram(drake_car.scene_as_it_runs(scene))  # its Diagram, handles
    built = drake_car.build_diagram(scene, external_driver=True)   # wire your own driver

The names load lazily (PEP 562): importing one room (``drake_car.law.friction.frd``) loads
neither Drake nor the rest of the package.
"""

import importlib

# name -> the module that defines it
_EXPORTS = {
    # scenes: load, check, the one scene type
    "load_scene": "drake_car.scene.load",
    "Scene": "drake_car.scene.scene",
    "SceneError": "drake_car.scene.load",
    # the one build function and the one runner
    "build_diagram": "drake_car.sim.build",
    "CarDiagram": "drake_car.sim.car_diagram",
    "simulate": "drake_car.sim.simulate",
    "scene_as_it_runs": "drake_car.sim.simulate",
    "Run": "drake_car.sim.simulate",
    # the car's systems
    "StrutFriction": "drake_car.systems.strut_friction",
    "TyreSystem": "drake_car.systems.tyre",
    "PathDriver": "drake_car.systems.path_driver",
    # the laws' parameter types
    "StrutFrictionParameters": "drake_car.law.friction.frd",
    "FrictionPairLaw": "drake_car.law.friction.frd",
    "SlipOptions": "drake_car.law.tyre.slip",
    "MagicFormulaTyre": "drake_car.law.tyre.magic_formula",
    "RadialTyre": "drake_car.law.tyre.contact",
    "SteeringLaw": "drake_car.systems.path_driver",
    "SpeedLaw": "drake_car.systems.path_driver",
    "CentreLine": "drake_car.law.road.centre_line",
    "CarParameters": "drake_car.model.parameters",
    # the path follower's laws on a given car
    "steering_law": "drake_car.sim.driver_wiring",
    "speed_law": "drake_car.sim.driver_wiring",
    # errors by kind
    "InputError": "drake_car.law.errors",
    "RunFailed": "drake_car.law.errors",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'drake_car' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # once loaded, found without this hook
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
