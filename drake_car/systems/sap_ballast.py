"""A ballast that loosens Drake's SAP solver's stopping tolerance by a known factor: the only
handle on the solver's accuracy that Python has, and with it the solver axis of the error
budget (``sweep.refine``).

Why. SAP stops its Newton iterations when ‖∇ℓ‖ ≤ εa + εr·max(‖p̃‖, ‖j̃c‖) (Drake's
``SapSolver::CalcStoppingCriteriaResidual``: the momentum-balance residual ∇ℓ, the momentum
p = A·v and the constraint impulses jc, each scaled by diag(A)^(-1/2); εr = 1e-6, εa = 1e-14
√J). pydrake (1.51 to 1.58) binds no ``SapSolverParameters``; of SAP's settings only
``sap_near_rigid_threshold`` is reachable (``MultibodyPlantConfig``), which is not a tolerance.
At 60 km/h the car's ‖p̃‖ is 643 √J, so a step may end with a velocity error up to about
εr·‖p̃‖/√m: 1.2e-4 m/s on a strut's sliding pair (m ≈ 30 kg), more than the friction law's
threshold velocity Δv = 1e-4 m/s. No step size removes that floor.

What. A body on a prismatic joint to the world, decoupled from everything else, whose velocity
follows the car's speed u through a damping-only SAP PD actuator (``connect_sap_ballast``):
its scaled momentum is √(F² - 1)·k·u, k the car's ‖p̃‖ per unit speed, so SAP's momentum scale
becomes √(‖p̃_car‖² + (F² - 1)·k²u²) = F·‖p̃_car‖ wherever the car's motion sets the scale: the
relative tolerance is F·εr. At rest (u = 0) the ballast is still and the tolerance εr. Nothing
of the car feels it: its block of A is its own, its PD target is reached within the step (its
quadratic cost is solved exactly by the Newton step the car's problem takes anyway). A run at
F = 2 beside the run at F = 1 gives the solver's share of an outcome's error to first order in
εr (``sweep.refine``'s solver twin), as a run at half the step gives the step's.
"""

import math

import numpy as np
from pydrake.multibody.tree import PdControllerGains, PrismaticJoint, SpatialInertia, UnitInertia
from pydrake.systems.primitives import MatrixGain

# The ballast's mass (kg): large enough to keep its speed below the divergence monitor's limit
# (sim.monitor: 500 m/s) up to the scene's largest factor, 100, at 100 km/h (340 m/s; at F = 2
# and 60 km/h, 3.5 m/s).
BALLAST_MASS_KG = 1.0e5
# The largest factor it is sized for (a scene's, and a solver twin's at twice a scene's).
MAX_FACTOR = 100.0


def add_sap_ballast(plant):
    """Adds the ballast's body, joint and damping-only PD actuator to ``plant`` (before
    Finalize); returns its model instance."""
    instance = plant.AddModelInstance("sap_ballast")
    body = plant.AddRigidBody("sap_ballast", instance, SpatialInertia(
        BALLAST_MASS_KG, np.zeros(3), UnitInertia(1.0, 1.0, 1.0)))
    joint = plant.AddJoint(PrismaticJoint(
        "sap_ballast", plant.world_frame(), body.body_frame(), [1.0, 0.0, 0.0]))
    actuator = plant.AddJointActuator("sap_ballast", joint)
    # Damping 10 m/dt: the velocity follows its target within a step (as the SAP pacer's).
    actuator.set_controller_gains(PdControllerGains(p=1e-9, d=10.0 * BALLAST_MASS_KG
                                                    / plant.time_step()))
    return instance


def sap_momentum_scale(plant, plant_context):
    """SAP's momentum scale ‖p̃‖ = ‖diag(M)^(-1/2)·M·v‖ (√J) of the velocities in
    ``plant_context`` (M the mass matrix, for SAP's A: the two differ by the step's implicit
    joint damping, dt·D)."""
    mass = plant.CalcMassMatrix(plant_context)
    momentum = mass @ plant.GetVelocities(plant_context)
    return float(np.linalg.norm(momentum / np.sqrt(np.diag(mass))))


def connect_sap_ballast(builder, plant, instance, *, speed_index, scale_per_speed, factor):
    """The ballast's target velocity √(factor² - 1)·``scale_per_speed``/√m times the plant
    state's entry ``speed_index`` (a speed, m/s), through a matrix from the plant's state (no
    Python per step). ``scale_per_speed``: the rest of the plant's ``sap_momentum_scale`` per
    unit of that speed (√kg)."""
    if not (math.isfinite(factor) and factor >= 1.0):
        raise ValueError(f"SAP ballast: factor {factor} must be a finite number >= 1")
    gain = np.zeros((2, plant.num_multibody_states()))
    gain[1, speed_index] = math.sqrt(factor ** 2 - 1.0) * scale_per_speed / math.sqrt(
        BALLAST_MASS_KG)
    target = builder.AddSystem(MatrixGain(gain))
    target.set_name("sap_ballast_target")
    builder.Connect(plant.get_state_output_port(), target.get_input_port())
    builder.Connect(target.get_output_port(), plant.get_desired_state_input_port(instance))
