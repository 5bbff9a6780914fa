"""PD gains and effort limits of joint actuators changed at given times (Drake keeps them in
the plant model, not the context): a LeafSystem whose publish events write them, at
initialization (the first entry, so a simulation depends only on its context) and at each
entry's time."""

from pydrake.multibody.tree import PdControllerGains
from pydrake.systems.framework import LeafSystem

# Floor on PD gains: Drake removes a controller whose gains are both zero.
MIN_GAIN = 1e-9


class GainSchedule(LeafSystem):
    """Writes ``schedule`` = [(time_s, kp, kd, effort_limit), ...] (times increasing, the first
    at 0) into ``actuators`` (all alike). No ports.

    .. pydrake_system::

        name: GainSchedule
    """

    def __init__(self, actuators, schedule):
        super().__init__()
        if not schedule or schedule[0][0] != 0.0:
            raise ValueError("GainSchedule: the schedule must start at time 0")
        times = [entry[0] for entry in schedule]
        if any(b <= a for a, b in zip(times, times[1:])):
            raise ValueError(f"GainSchedule: times {times} must increase")
        self._actuators = list(actuators)
        self._schedule = [(t, max(kp, MIN_GAIN), max(kd, MIN_GAIN), effort)
                          for t, kp, kd, effort in schedule]
        self.DeclareInitializationPublishEvent(self._write)
        self.DeclareForcedPublishEvent(self._write)
        for t, *_ in self._schedule[1:]:
            self.DeclarePeriodicPublishEvent(period_sec=1e9, offset_sec=t,
                                             publish=self._write)

    def _write(self, context):
        now = context.get_time()
        entry = [e for e in self._schedule if e[0] <= now + 1e-12][-1]
        gains = PdControllerGains(p=entry[1], d=entry[2])
        for actuator in self._actuators:
            actuator.set_controller_gains(gains)
            actuator.set_effort_limit(entry[3])
