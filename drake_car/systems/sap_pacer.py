"""A pacer that makes Drake's SAP solver take at least one Newton iteration every step.

Why. SAP warm-starts each step with the previous step's velocities and tests its stopping
criterion, ‖D ∇ℓ(v)‖ ≤ εa + εr·max(‖D p‖, ‖D j‖) with εr = 1e-6, *before* iterating. The
right-hand side scales with the whole system's momentum p (for the car at 60 km/h,
‖D p‖ ≈ √(2·kinetic energy) ≈ 645 √J), the left-hand side at the guess with the net impulse of
one step. When the car is near a balance (cruising, settling slowly) and the step is small, the
whole step's impulse falls below the threshold, SAP returns the guess, and every force and
constraint impulse of that step is dropped while the positions still advance ("frozen" steps).
Measured on the lane change a_1 (10 s): 0 frozen steps at 5 ms, 295 at 1 ms (from t = 9.2 s),
32 162 at 50 µs (from 4.85 s), 82 438 at 25 µs (from 4.40 s). Smaller steps are then *less*
accurate: at 25 µs the car's 0.1 m/s² rolling deceleration was dropped on half of the steps and
the slowly returning lubricated struts stopped millimetres short. pydrake 1.51 does not expose
SAP's tolerances (SapSolverParameters), so the fix cannot be a tighter εr.

What. A 1 kg body on a prismatic joint to the world, decoupled from the car, with a SAP PD
actuator (damping only) whose target velocity alternates ±V at every step (a Sine at the
Nyquist frequency π/dt, sampled at the step times). At every step's guess its impulse,
about 2·Kd·dt·V = 20·m·V, is far above any threshold the car sets, so SAP iterates; the Newton
step is taken for all velocities at once, so the car's step is solved to the same tolerance as
any other step. The pacer's momentum (m·V = 0.1 N s) and impulses are negligible beside the
car's, so the threshold is unchanged, and the car does not feel it (no coupling).
"""

import math

import numpy as np
from pydrake.multibody.tree import PdControllerGains, PrismaticJoint, SpatialInertia, UnitInertia
from pydrake.systems.primitives import Multiplexer, Sine

PACER_MASS_KG = 1.0
PACER_SPEED_MPS = 0.1


def add_sap_pacer(plant):
    """Adds the pacer's body, joint and PD actuator to ``plant`` (before Finalize); returns its
    model instance."""
    instance = plant.AddModelInstance("sap_pacer")
    body = plant.AddRigidBody("sap_pacer", instance, SpatialInertia(
        PACER_MASS_KG, np.zeros(3), UnitInertia(1.0, 1.0, 1.0)))
    joint = plant.AddJoint(PrismaticJoint(
        "sap_pacer", plant.world_frame(), body.body_frame(), [1.0, 0.0, 0.0]))
    actuator = plant.AddJointActuator("sap_pacer", joint)
    # Damping 10 m/dt: the velocity follows its target within a step (SAP's near-rigid regime).
    actuator.set_controller_gains(PdControllerGains(p=1e-9, d=10.0 * PACER_MASS_KG
                                                    / plant.time_step()))
    return instance


def connect_sap_pacer(builder, plant, instance):
    """The pacer's target [q_d, v_d] = [V dt/π sin(πt/dt), V cos(πt/dt)]: ±V at the steps."""
    dt = plant.time_step()
    frequency = math.pi / dt
    sine = builder.AddSystem(Sine(PACER_SPEED_MPS / frequency, frequency, 0.0, 1))
    sine.set_name("sap_pacer_target")
    mux = builder.AddSystem(Multiplexer([1, 1]))
    mux.set_name("sap_pacer_desired_state")
    builder.Connect(sine.get_output_port(0), mux.get_input_port(0))
    builder.Connect(sine.get_output_port(1), mux.get_input_port(1))
    builder.Connect(mux.get_output_port(0), plant.get_desired_state_input_port(instance))


def pacer_kinetic_energy(plant, plant_context):
    """The pacer's kinetic energy (J), to take out of plant-wide energies (0 without one)."""
    if not plant.HasModelInstanceNamed("sap_pacer"):
        return 0.0
    v = plant.GetVelocities(plant_context, plant.GetModelInstanceByName("sap_pacer"))
    return 0.5 * PACER_MASS_KG * float(v @ v)
