"""The car settling under gravity from its design position (paper phase I, first 0.8 s)."""

import dataclasses
import time

import numpy as np
from pydrake.systems.analysis import Simulator

from drake_car.assembly import DEFAULT_TIME_STEP_S, build_car_diagram
from drake_car.model.car import loop_closure_error, strut_overlap
from drake_car.model.geometry import SIDES
from drake_car.model.parameters import CarParameters
from drake_car.monitor import attach_monitor, run_checked
from drake_car.systems.tyre import WHEELS


@dataclasses.dataclass
class SettleResult:
    corner_loads_N: dict
    ride_height_m: dict
    strut_overlap_m: dict
    design_axle_loads_N: dict
    total_mass_kg: float
    loop_closure_error_m: float
    max_abs_generalized_velocity_last_half_s: float
    duration_s: float
    time_step_s: float
    wall_s: float
    history: dict  # t, Fz_*, d_*, z_chassis

    def summary(self):
        data = dataclasses.asdict(self)
        data.pop("history")
        data.pop("html")
        data.pop("positions")
        return data

    html: str | None = None  # the Meshcat replay, when the scene asked for one
    # The car's generalized positions at the end (the settled state, to start drives from).
    positions: object = None


def ride_heights(car, plant_context):
    """Height above the road (m) of the chassis points above the axle centres at the design
    wheel-centre height: (0, 0, R0) and (-L, 0, R0) in the chassis frame. Design: R0."""
    chassis = car.body("chassis").EvalPoseInWorld(plant_context)
    r0 = car.params.tyre.unloaded_radius_m
    front = chassis.multiply(np.array([0.0, 0.0, r0]))[2]
    rear = chassis.multiply(np.array([-car.params.wheelbase_m, 0.0, r0]))[2]
    return {"front": float(front), "rear": float(rear)}


def run_settle(params: CarParameters | None = None, *, friction=None, duration_s=5.0,
               time_step_s=DEFAULT_TIME_STEP_S, record_period_s=0.01, tyres=None,
               road_height=None, meshcat=None, realtime_rate=0.0,
               sap_pacer=True) -> SettleResult:
    """Lets the car settle from its design position; returns loads, heights, overlaps."""
    params = params or CarParameters()
    kwargs = {} if road_height is None else {"road_height": road_height}
    built = build_car_diagram(params, time_step_s=time_step_s, friction=friction, tyres=tyres,
                              meshcat=meshcat, sap_pacer=sap_pacer, **kwargs)
    plant, car = built.plant, built.car
    simulator = Simulator(built.diagram)
    simulator.set_target_realtime_rate(realtime_rate)
    root = simulator.get_mutable_context()
    pc = plant.GetMyContextFromRoot(root)
    tyre_context = built.tyre.GetMyContextFromRoot(root)
    attach_monitor(simulator, built)
    simulator.Initialize()
    history = {"t": [], "z_chassis_m": [], "max_abs_generalized_velocity": []}
    history.update({f"Fz_{w}_N": [] for w in WHEELS})
    history.update({f"d_{s}_m": [] for s in SIDES})
    start = time.perf_counter()
    n = int(round(duration_s / record_period_s))
    for k in range(n + 1):
        run_checked(simulator, k * record_period_s)
        loads = built.tyre.GetOutputPort("tyre_loads").Eval(tyre_context)
        history["t"].append(root.get_time())
        for i, w in enumerate(WHEELS):
            history[f"Fz_{w}_N"].append(loads[i])
        for s in SIDES:
            history[f"d_{s}_m"].append(strut_overlap(car, pc, s))
        history["z_chassis_m"].append(car.body("chassis").EvalPoseInWorld(pc).translation()[2])
        history["max_abs_generalized_velocity"].append(
            float(np.max(np.abs(plant.GetVelocities(pc, car.instance)))))
    wall = time.perf_counter() - start
    history = {k: np.asarray(v) for k, v in history.items()}
    last = history["t"] >= duration_s - 0.5
    loads = built.tyre.GetOutputPort("tyre_loads").Eval(tyre_context)
    return SettleResult(
        corner_loads_N={w: float(loads[i]) for i, w in enumerate(WHEELS)},
        ride_height_m=ride_heights(car, pc),
        strut_overlap_m={s: float(strut_overlap(car, pc, s)) for s in SIDES},
        design_axle_loads_N=params.design_axle_loads_N(),
        total_mass_kg=float(plant.CalcTotalMass(pc, [car.instance])),
        loop_closure_error_m=loop_closure_error(car, pc),
        max_abs_generalized_velocity_last_half_s=float(
            np.max(history["max_abs_generalized_velocity"][last])),
        duration_s=duration_s, time_step_s=time_step_s, wall_s=wall, history=history,
        positions=plant.GetPositions(pc, car.instance).copy())
