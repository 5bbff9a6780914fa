"""Wiring the car instance's actuators: the plant wants one desired-state vector [q_d of every
actuator...; v_d of every actuator...] and one feed-forward vector, both in actuator order,
while each source gives [q_d (n); v_d (n)] or a feed-forward for its own n actuators."""

import dataclasses

import numpy as np
from pydrake.systems.primitives import ConstantVectorSource, MatrixGain, Multiplexer


@dataclasses.dataclass
class _Group:
    name: str
    size: int
    pd: bool
    rest_at_zero: bool = False  # a PD group held at q = 0, v = 0 (no desired-state source)
    desired: object = None
    feedforward: object = None


class ActuationWiring:
    """Groups of the instance's actuators, added in the order the actuators were added."""

    def __init__(self, plant, instance):
        self._plant, self._instance = plant, instance
        self._groups = []

    def add(self, name, size, *, pd, rest_at_zero=False):
        self._groups.append(_Group(name, size, pd, rest_at_zero))

    def connect(self, name, *, desired=None, feedforward=None):
        group = next(g for g in self._groups if g.name == name)
        group.desired, group.feedforward = desired, feedforward

    def finish(self, builder):
        plant, instance = self._plant, self._instance
        sizes = [g.size for g in self._groups]
        total = sum(sizes)
        if plant.num_actuated_dofs(instance) != total:
            raise RuntimeError(f"the car has {plant.num_actuated_dofs(instance)} actuators, the "
                               f"wiring knows {total}")
        for group in self._groups:
            if group.pd and group.desired is None and not group.rest_at_zero:
                raise RuntimeError(f"actuators '{group.name}' are PD-controlled but have no "
                                   "desired state")
        port = plant.get_desired_state_input_port(instance)
        desired = [g.desired for g in self._groups]
        if len(desired) == 1:
            builder.Connect(desired[0], port)
        else:
            mux = _mux(builder, "desired_state_mux", desired, [2 * n for n in sizes])
            gain = builder.AddSystem(MatrixGain(_desired_state_order(sizes)))
            gain.set_name("desired_state_order")
            builder.Connect(mux.get_output_port(0), gain.get_input_port())
            builder.Connect(gain.get_output_port(), port)
        feedforward = [g.feedforward for g in self._groups]
        if any(p is not None for p in feedforward):
            mux = _mux(builder, "actuation_mux", feedforward, sizes)
            builder.Connect(mux.get_output_port(0), plant.get_actuation_input_port(instance))


def _desired_state_order(sizes):
    """Permutation from [q_d (n1), v_d (n1), q_d (n2), v_d (n2), ...] to [q_d...; v_d...]."""
    total = sum(sizes)
    permutation = np.zeros((2 * total, 2 * total))
    offset, row = 0, 0
    for n in sizes:
        for k in range(n):
            permutation[row + k, offset + k] = 1.0
            permutation[total + row + k, offset + n + k] = 1.0
        offset += 2 * n
        row += n
    return permutation


def _mux(builder, name, ports, widths):
    """Stacks ``ports`` (None: zeros of that width) into one vector."""
    mux = builder.AddSystem(Multiplexer(widths))
    mux.set_name(name)
    for i, (port, width) in enumerate(zip(ports, widths)):
        if port is None:
            zeros = builder.AddSystem(ConstantVectorSource(np.zeros(width)))
            zeros.set_name(f"{name}_zeros_{i}")
            port = zeros.get_output_port(0)
        builder.Connect(port, mux.get_input_port(i))
    return mux
