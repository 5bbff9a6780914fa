"""Where the drive torque is reacted: through the driveshafts into the body, not the knuckle."""

import numpy as np
from pydrake.common.value import Value
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.plant import ExternallyAppliedSpatialForce
from pydrake.systems.framework import LeafSystem


class DriveshaftReaction(LeafSystem):
    """Moves the drive servos' reaction torque from the knuckles to the chassis.

    .. pydrake_system::

        name: DriveshaftReaction
        input_ports:
        - net_actuation
        - body_poses
        output_ports:
        - reaction_forces

    The front wheels' rotation is prescribed by servos on the wheel-knuckle joints, which react
    their torque T on the knuckle (as a motion on the joint does in Adams). In a front-drive car
    the torque comes through the driveshaft from the body-mounted engine: this system applies
    +T·a to each knuckle (cancelling the joint's reaction) and -T·a to the chassis, a the wheel's
    spin axis in world. ``net_actuation``: the car instance's net actuation (N m), of which the
    entries ``actuation_indices`` are the two drive servos; it is the plant's sampled output,
    so the transfer lags the servo torque by one step.
    """

    def __init__(self, plant, instance, drive_actuators, knuckles, chassis):
        super().__init__()
        order = [int(i) for i in plant.GetJointActuatorIndices(instance)]
        self._indices = [order.index(int(a.index())) for a in drive_actuators]
        self._knuckles = [k.index() for k in knuckles]
        self._wheels = [a.joint().child_body().index() for a in drive_actuators]
        self._chassis = chassis.index()
        self._actuation = self.DeclareVectorInputPort("net_actuation", len(order))
        self._poses = self.DeclareAbstractInputPort("body_poses",
                                                    Value[list[RigidTransform]]())
        self.DeclareAbstractOutputPort(
            "reaction_forces", lambda: Value[list[ExternallyAppliedSpatialForce]](),
            self._calc)

    def _calc(self, context, output):
        torque = self._actuation.Eval(context)
        poses = self._poses.Eval(context)
        forces = []
        total = np.zeros(3)
        for index, knuckle, wheel in zip(self._indices, self._knuckles, self._wheels):
            axis = poses[int(wheel)].rotation().matrix()[:, 1]
            moment = torque[index] * axis
            total += moment
            forces.append(_torque(knuckle, moment))
        forces.append(_torque(self._chassis, -total))
        output.set_value(forces)


def _torque(body_index, moment):
    force = ExternallyAppliedSpatialForce()
    force.body_index = body_index
    force.p_BoBq_B = np.zeros(3)
    force.F_Bq_W = SpatialForce(moment, np.zeros(3))
    return force
