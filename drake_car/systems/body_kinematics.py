"""The poses and spatial velocities of a few bodies of a MultibodyPlant from its state vector:
``law.numerics.tree_kinematics`` (compiled) on the plant's joints between the world and those bodies,
checked against the plant's own kinematics when made."""

import numpy as np
from pydrake.multibody.tree import BodyIndex

from drake_car.law.numerics.tree_kinematics import JOINT_TYPES, pack_joint, tree_kinematics

# Largest difference (m, rad, m/s, rad/s) from the plant's kinematics accepted at the check.
CHECK_TOLERANCE = 1e-9


class BodyKinematics:
    """``bodies``' poses and spatial velocities from the plant's state [q; v] (the plant's
    ``state`` output, one vector: cheaper to read every step than ``body_poses`` and
    ``body_spatial_velocities``, lists of every body's). ``rows[i]`` is the row of ``bodies[i]``
    in what ``__call__`` returns. Raises ValueError when a joint on the way has a type
    ``law.numerics.tree_kinematics`` lacks (``JOINT_TYPES``)."""

    def __init__(self, plant, bodies):
        inboard = {int(plant.get_joint(j).child_body().index()): plant.get_joint(j)
                   for j in plant.GetJointIndices()}
        world = int(plant.world_body().index())
        order = []  # body indices, parents first
        for body in bodies:
            path, index = [], int(body.index())
            while index != world and index not in order:
                if index not in inboard:
                    name = plant.get_body(BodyIndex(index)).name()
                    raise ValueError(f"BodyKinematics: body {name} has no joint to its parent "
                                     "(a free body without a floating joint)")
                path.append(index)
                index = int(inboard[index].parent_body().index())
            order += reversed(path)
        rows = []
        for index in order:
            joint = inboard[index]
            kind = joint.type_name()
            if kind not in JOINT_TYPES:
                raise ValueError(f"BodyKinematics: joint '{joint.name()}' is a {kind} joint; "
                                 f"the compiled kinematics knows {JOINT_TYPES}")
            X_PF = joint.frame_on_parent().GetFixedPoseInBodyFrame()
            if kind == "weld":
                X_PF = X_PF.multiply(joint.X_FM())
            X_MC = joint.frame_on_child().GetFixedPoseInBodyFrame().inverse()
            axis = (joint.revolute_axis() if kind == "revolute" else
                    joint.translation_axis() if kind == "prismatic" else np.zeros(3))
            parent = int(joint.parent_body().index())
            rows.append(pack_joint(order.index(parent) if parent != world else -1, kind,
                                   joint.position_start(), joint.velocity_start(),
                                   X_PF.GetAsMatrix34(), X_MC.GetAsMatrix34(), axis))
        self._tree = np.array(rows)
        self._nq = plant.num_positions()
        self._indices = order
        self.rows = np.array([order.index(int(b.index())) for b in bodies], dtype=np.int64)
        self._check(plant)

    def __call__(self, x):
        """(poses n x 3 x 4, twists n x 6) of the tree's bodies at the plant state ``x``."""
        n = len(self._indices)
        poses, twists = np.empty((n, 3, 4)), np.empty((n, 6))
        tree_kinematics(self._tree, x, self._nq, poses, twists)
        return poses, twists

    def _check(self, plant):
        """Against the plant's kinematics at two states: the default and one with every
        coordinate moved (quaternions kept unit)."""
        context = plant.CreateDefaultContext()
        rng = np.random.default_rng(0)
        for moved in (False, True):
            if moved:
                q = plant.GetPositions(context) + rng.uniform(-0.3, 0.3, plant.num_positions())
                for index in plant.GetFloatingBaseBodies():
                    start = plant.get_body(index).floating_positions_start()
                    q[start:start + 4] /= np.linalg.norm(q[start:start + 4])
                plant.SetPositions(context, q)
                plant.SetVelocities(context, rng.uniform(-2, 2, plant.num_velocities()))
            poses, twists = self(plant.GetPositionsAndVelocities(context))
            for row, index in enumerate(self._indices):
                body = plant.get_body(BodyIndex(index))
                pose = plant.EvalBodyPoseInWorld(context, body).GetAsMatrix34()
                twist = plant.EvalBodySpatialVelocityInWorld(context, body).get_coeffs()
                error = max(np.max(np.abs(pose - poses[row])), np.max(np.abs(twist - twists[row])))
                if not error < CHECK_TOLERANCE:
                    raise ValueError(f"BodyKinematics: the compiled kinematics of body "
                                     f"{body.name()} differs from the plant's by {error:.3g}")
