"""The SAP pacer (drake_car/systems/sap_pacer.py): Drake's SAP solver returns its initial guess
when a step's whole impulse is below εr = 1e-6 of the system's momentum; the pacer makes it
iterate every step. The SAP ballast (drake_car/systems/sap_ballast.py) loosens that tolerance by
a given factor: a push just above εr is dropped at twice εr."""

import math

import numpy as np
import pytest
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
from pydrake.multibody.tree import PdControllerGains, PrismaticJoint, SpatialInertia, UnitInertia
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import ConstantVectorSource

from drake_car.systems.sap_ballast import (
    BALLAST_MASS_KG, add_sap_ballast, connect_sap_ballast, sap_momentum_scale)
from drake_car.systems.sap_pacer import add_sap_pacer, connect_sap_pacer, pacer_kinetic_energy

MASS_KG, SPEED_MPS, PUSH_N, DT_S, DURATION_S = 1000.0, 20.0, 1.0, 1e-3, 1.0


def pushed_block(pacer, push_N=PUSH_N, tolerance_factor=None):
    """A 1000 kg block sliding at 20 m/s, pushed by ``push_N`` (1 N) for 1 s; a negligible PD
    damper (1e-9 N s/m) on its joint puts a constraint into SAP's problem; with
    ``tolerance_factor`` a ballast loosens SAP's tolerance by it. Returns its Δv."""
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(
        MultibodyPlantConfig(time_step=DT_S, discrete_contact_approximation="sap"), builder)
    body = plant.AddRigidBody("block", SpatialInertia(MASS_KG, np.zeros(3),
                                                      UnitInertia(1.0, 1.0, 1.0)))
    joint = plant.AddJoint(PrismaticJoint("slide", plant.world_frame(), body.body_frame(),
                                          [1.0, 0.0, 0.0]))
    plant.AddJointActuator("push", joint).set_controller_gains(PdControllerGains(p=0.0, d=1e-9))
    instance = add_sap_pacer(plant) if pacer else None
    ballast = add_sap_ballast(plant) if tolerance_factor else None
    plant.Finalize()
    if instance is not None:
        connect_sap_pacer(builder, plant, instance)
    if ballast is not None:  # the block's own scale per unit speed: √m
        connect_sap_ballast(builder, plant, ballast,
                            speed_index=plant.num_positions() + joint.velocity_start(),
                            scale_per_speed=math.sqrt(MASS_KG), factor=tolerance_factor)
    push = builder.AddSystem(ConstantVectorSource([push_N]))
    builder.Connect(push.get_output_port(), plant.get_actuation_input_port(body.model_instance()))
    target = builder.AddSystem(ConstantVectorSource([0.0, 0.0]))
    builder.Connect(target.get_output_port(),
                    plant.get_desired_state_input_port(body.model_instance()))
    simulator = Simulator(builder.Build())
    context = plant.GetMyContextFromRoot(simulator.get_mutable_context())
    joint.set_translation_rate(context, SPEED_MPS)
    if ballast is not None:  # started at its target: in balance from the first step
        plant.GetJointByName("sap_ballast").set_translation_rate(
            context, math.sqrt(tolerance_factor ** 2 - 1) * math.sqrt(MASS_KG / BALLAST_MASS_KG)
            * SPEED_MPS)
        block_only = plant.CreateDefaultContext()
        joint.set_translation_rate(block_only, SPEED_MPS)
        assert sap_momentum_scale(plant, context) == pytest.approx(
            tolerance_factor * sap_momentum_scale(plant, block_only), rel=1e-12)
    simulator.AdvanceTo(DURATION_S)
    if pacer:  # decoupled, and its kinetic energy is what the helper says
        assert pacer_kinetic_energy(plant, context) == pytest.approx(
            0.5 * plant.GetVelocities(context, instance)[0] ** 2)
    return joint.get_translation_rate(context) - SPEED_MPS


def test_sap_drops_a_small_push_without_the_pacer():
    """Each step's impulse, F dt/√m = 3.2e-5 √(kg) m/s, is below εr √m v = 6.3e-4: SAP keeps
    the guess and the block never speeds up. (If Drake changes this, this test says so.)"""
    assert pushed_block(pacer=False) == 0.0


def test_the_pacer_restores_the_push():
    """With the pacer the block gains F t / m = 1e-3 m/s. The problem is quadratic (linear
    damper, no limits), so SAP's Newton step is exact up to roundoff; 1e-6 m/s (0.1 % of the
    change) bounds the roundoff of 1000 steps with room to spare."""
    assert pushed_block(pacer=True) == pytest.approx(PUSH_N * DURATION_S / MASS_KG, abs=1e-6)


@pytest.mark.parametrize("factor, kept", [(None, True), (1.25, True), (2.0, False)])
def test_the_ballast_loosens_the_tolerance_by_its_factor(factor, kept):
    """A push whose step impulse is 1.5 εr of the block's momentum (F dt/√m = 1.5 εr √m v,
    F = 30 N; the block's momentum grows by 0.15 % in the second): SAP takes it at εr and at
    1.25 εr, and drops it, every step, at 2 εr. The pacer is off (it would make SAP iterate)."""
    push_N = 1.5 * 1e-6 * MASS_KG * SPEED_MPS / DT_S
    dv = pushed_block(pacer=False, push_N=push_N, tolerance_factor=factor)
    if kept:  # as test_the_pacer_restores_the_push: the Newton step is exact up to roundoff
        assert dv == pytest.approx(push_N * DURATION_S / MASS_KG, abs=1e-6)
    else:
        assert dv == 0.0
