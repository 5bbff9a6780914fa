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
        self._wheels = [int(a.joint().child_body().index()) for a in drive_actuators]
        # One force object per knuckle and one for the chassis, refilled every step.
        self._applied = [_applied_torque(k.index()) for k in knuckles]
        self._applied.append(_applied_torque(chassis.index()))
        self._actuation = self.DeclareVectorInputPort("net_actuation", len(order))
        self._poses = self.DeclareAbstractInputPort("body_poses",
                                                    Value[list[RigidTransform]]())
        self.DeclareAbstractOutputPort(
            "reaction_forces", lambda: Value[list[ExternallyAppliedSpatialForce]](),
            self._calc)

    def _calc(self, context, output):
        torque = self._actuation.Eval(context).tolist()
        poses = self._poses.Eval(context)
        total = [0.0, 0.0, 0.0]
        for index, wheel, applied in zip(self._indices, self._wheels, self._applied):
            (_, ax, _), (_, ay, _), (_, az, _) = poses[wheel].rotation().matrix().tolist()
            t = torque[index]
            moment = [t * ax, t * ay, t * az]  # T along the wheel's spin axis (its body y)
            total = [total[0] + moment[0], total[1] + moment[1], total[2] + moment[2]]
            applied.F_Bq_W = SpatialForce(moment, _ZERO)
        self._applied[-1].F_Bq_W = SpatialForce([-total[0], -total[1], -total[2]], _ZERO)
        output.set_value(self._applied)  # copied into the port's value


_ZERO = [0.0, 0.0, 0.0]


def _applied_torque(body_index):
    force = ExternallyAppliedSpatialForce()
    force.body_index = body_index
    force.p_BoBq_B = np.zeros(3)
    return force
