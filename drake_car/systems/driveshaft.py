"""Where the drive torque is reacted: through the driveshafts into the body, not the knuckle."""

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix


class Driveshafts:
    """The driveshafts of servo- or torque-driven wheels, as the tyre system applies them
    (``systems.tyre.TyreSystem(driveshafts=...)``, which has the wheels' spin axes every step
    already: one Python call per step serves the tyres and the driveshafts).

    The driven wheels are driven by actuators on their spin joints, which react their torque T
    on the body the wheel turns on, its "knuckle" here (the front's knuckle, the rear's trailing
    arm), as a motion on the joint does in Adams. In a car the torque comes through the
    driveshaft from the body-mounted engine: +T·a is applied to each
    knuckle (cancelling the joint's reaction) and -ΣT·a to the chassis, a the wheel's spin axis
    in world. T is read from the plant's ``net_actuation`` output of ``instance`` (entries
    ``actuation_indices``), a sampled output: the transfer lags the actuator's torque by one
    step. ``knuckle_frames``: per driven wheel, a frame P on its knuckle whose z axis is the
    spin joint's axis (a moment T about it is +T·a).
    """

    def __init__(self, plant, instance, drive_actuators, knuckles, chassis):
        order = [int(i) for i in plant.GetJointActuatorIndices(instance)]
        self.instance = instance
        self.actuation_size = len(order)
        self.actuation_indices = [order.index(int(a.index())) for a in drive_actuators]
        self.wheels = [int(a.joint().child_body().index()) for a in drive_actuators]
        self.knuckles = [int(k.index()) for k in knuckles]
        self.body = int(chassis.index())
        self.knuckle_frames = []
        for actuator, knuckle in zip(drive_actuators, self.knuckles):
            joint = actuator.joint()
            axis_child = (joint.frame_on_child().GetFixedPoseInBodyFrame().rotation()
                          .multiply(joint.revolute_axis()))
            if int(joint.parent_body().index()) != knuckle or not np.allclose(
                    axis_child, [0.0, 1.0, 0.0], atol=1e-12):
                raise ValueError(f"Driveshafts: joint '{joint.name()}' must turn its wheel "
                                 "about the wheel's y axis, on the given knuckle")
            axis = (joint.frame_on_parent().GetFixedPoseInBodyFrame().rotation()
                    .multiply(joint.revolute_axis()))
            self.knuckle_frames.append(RigidTransform(RotationMatrix.MakeFromOneVector(axis, 2),
                                                      np.zeros(3)))
