"""Tyre forces on the four wheels as a LeafSystem.

This is the vertical part (radial stiffness and damping at one contact point per wheel on the
road surface). The Magic Formula's horizontal forces are added in this same system by a later
issue; until then the horizontal contact forces are zero.
"""

import numpy as np
from pydrake.common.value import AbstractValue, Value
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialForce, SpatialVelocity
from pydrake.multibody.plant import ExternallyAppliedSpatialForce
from pydrake.systems.framework import BasicVector, LeafSystem, ValueProducer

from drake_car.law.tyre_contact import RadialTyre, contact_point, flat_road, radial_force

WHEELS = ("fl", "fr", "rl", "rr")


class TyreSystem(LeafSystem):
    """Radial tyre forces at one contact point per wheel.

    .. pydrake_system::

        name: TyreSystem
        input_ports:
        - body_poses
        - body_spatial_velocities
        output_ports:
        - tyre_forces
        - tyre_loads

    ``body_poses`` and ``body_spatial_velocities`` are the plant's outputs of the same names.
    ``tyre_forces`` is a list of ExternallyAppliedSpatialForce (one per wheel, applied at the
    contact point, expressed in world) for the plant's ``applied_spatial_force`` input.
    ``tyre_loads`` is the vector of vertical loads Fz (N) in the order fl, fr, rl, rr followed by
    the deflections (m) in the same order.

    Equations: deflection δ = max(0, h(x_c, y_c) - z_c) at the lowest point c of the wheel circle;
    Fz = max(0, k δ + c δ̇), with δ̇ = -v_z of the wheel centre.
    """

    def __init__(self, wheel_bodies: dict, tyre: RadialTyre, road_height=flat_road):
        super().__init__()
        missing = [w for w in WHEELS if w not in wheel_bodies]
        if missing:
            raise ValueError(f"TyreSystem: wheel bodies missing for {missing}")
        self._tyre = tyre
        self._road = road_height
        self._body_indices = [wheel_bodies[w].index() for w in WHEELS]
        self._poses_port = self.DeclareAbstractInputPort(
            "body_poses", Value[list[RigidTransform]]())
        self._velocities_port = self.DeclareAbstractInputPort(
            "body_spatial_velocities", Value[list[SpatialVelocity]]())
        self.DeclareAbstractOutputPort(
            "tyre_forces", lambda: Value[list[ExternallyAppliedSpatialForce]](),
            self._calc_forces)
        self.DeclareVectorOutputPort("tyre_loads", BasicVector(2 * len(WHEELS)), self._calc_loads)
        self._solution_cache = self.DeclareCacheEntry(
            description="contact_solution",
            value_producer=ValueProducer(
                allocate=lambda: AbstractValue.Make(()), calc=self._calc_solution),
            prerequisites_of_calc={self.all_input_ports_ticket()})

    def _calc_solution(self, context, abstract_value):
        poses = self._poses_port.Eval(context)
        velocities = self._velocities_port.Eval(context)
        result = []
        for index in self._body_indices:
            pose = poses[int(index)]
            rotation = pose.rotation().matrix()
            centre = pose.translation()
            point, deflection, _ = contact_point(centre, rotation[:, 1],
                                                 self._tyre.unloaded_radius_m, self._road)
            rate = -velocities[int(index)].translational()[2]
            fz = radial_force(self._tyre, deflection, rate)
            result.append((index, rotation, centre, point, deflection, fz))
        abstract_value.set_value(tuple(result))

    def _calc_forces(self, context, output):
        forces = []
        for index, rotation, centre, point, _, fz in self._solution_cache.Eval(context):
            force = ExternallyAppliedSpatialForce()
            force.body_index = index
            force.p_BoBq_B = rotation.T @ (point - centre)
            force.F_Bq_W = SpatialForce(np.zeros(3), np.array([0.0, 0.0, fz]))
            forces.append(force)
        output.set_value(forces)

    def _calc_loads(self, context, output):
        solution = self._solution_cache.Eval(context)
        output.SetFromVector([s[5] for s in solution] + [s[4] for s in solution])
