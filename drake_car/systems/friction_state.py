"""What ``StrutFriction`` holds, read and set by name (a mixin of it): the pairs' names, Δv and
Δmax, their phases, creeps and positions in a context, and the stick-slip event log
(``law.friction.events``) the runner reads after every chunk (``sim.simulate``) and the local
resolution of events works with (``sim.resolve``, ``sim.transfer``). The discrete state groups
are ``StrutFriction``'s: ``_memory`` = [creep..., phase..., position at the last step...],
``_desired`` = [q_d..., v_d...] (fast scheme), ``_events`` the event log."""

from drake_car.law.friction.events import read_log


class FrictionStateAccess:
    """Accessors of ``StrutFriction``'s state (see the module)."""

    def pair_names(self):
        """Each pair's name in the event log: "<strut label>_<kind>" ("left_translation")."""
        return [f"{label}_{p.kind}" if label else p.kind
                for label, p in zip(self._labels, self._pairs)]

    def threshold_velocities(self):
        """Each pair's Δv (m/s or rad/s)."""
        return self._dv.copy()

    def maximum_creeps(self):
        """Each pair's Δmax (m or rad)."""
        return self._dmax.copy()

    def phases(self, context):
        """Each pair's phase in ``context`` (0 static, 1 kinetic)."""
        n = len(self._pairs)
        return context.get_discrete_state(self._memory).get_value()[n:2 * n].copy()

    def creeps(self, context):
        """Each pair's creep Δ in ``context`` (m or rad)."""
        return context.get_discrete_state(self._memory).get_value()[:len(self._pairs)].copy()

    def peaks(self, context):
        """Each pair's largest |v|/Δv in its current phase, and its smallest reserve at full
        creep in it (-1: it has not been at full creep): the event log's running values."""
        n = len(self._pairs)
        log = context.get_discrete_state(self._events).get_value()
        return log[1:1 + n].copy(), log[1 + n:1 + 2 * n].copy()

    def reset_peaks(self, context):
        """Starts each pair's running peaks afresh in ``context`` (a window's start)."""
        n = len(self._pairs)
        log = context.get_discrete_state(self._events).get_value().copy()
        log[1:1 + n] = 0.0
        log[1 + n:1 + 2 * n] = -1.0
        context.SetDiscreteState(int(self._events), log)

    def event_count(self, context):
        """How many events the log has seen in ``context``."""
        return int(context.get_discrete_state(self._events).get_value()[0])

    def position_indices(self):
        """Each pair's joint position's index in the plant's positions."""
        return self._q_index_array.copy()

    def shift_positions(self, context, shift):
        """Moves this system's record of the pairs' positions (the position at the last step,
        the fast scheme's position targets) by ``shift`` (per pair, m or rad) in ``context``:
        for a change of the plant's positions that is no motion of the pairs (``sim.transfer``:
        a constraint's violation set to another step's), which must not count as creep."""
        n = len(self._pairs)
        memory = context.get_discrete_state(self._memory).get_value().copy()
        memory[2 * n:] += shift
        context.SetDiscreteState(int(self._memory), memory)
        if self._desired is not None:
            desired = context.get_discrete_state(self._desired).get_value().copy()
            desired[:n] += shift
            context.SetDiscreteState(int(self._desired), desired)

    def events(self, context, since=0):
        """The stick-slip events numbered ``since``.. in this system's ``context``: (rows,
        the count so far, how many of them the bounded log lost) (``law.friction.events``)."""
        return read_log(context.get_discrete_state(self._events).get_value(), len(self._pairs),
                        since)
