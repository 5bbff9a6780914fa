"""A runner that keeps its friction's stick-slip events and may resolve its slips locally: the
event bookkeeping the car's runner (``sim.simulate.SceneRunner``) and the friction rig's
(``sim.rigs.friction.RigRunner``) share.

After every chunk of the monitor's period the friction's event log (``law.friction.events``)
is read into ``events`` as (row, step, window) triples: row in ``EVENT_FIELDS``, step the step
that saw it, window the resolution window that resolved it (-1: none); ``last_rows`` the
chunk's rows. With ``resolve`` (a ``scene.simulator.ResolveEvents``) a ``sim.resolve.Resolver``
acts between chunks (``before_chunk``, ``after_chunk``) and ``logged()`` splices its windows'
histories into the loggers'.
"""

import math

from drake_car.law.friction.events import EVENT_FIELDS, KIND_NAMES
from drake_car.sim.resolve import Resolver
from drake_car.sim.simulation import Runner, logged_history


class SlipRunner(Runner):
    """``sim.simulation.Runner`` with the friction's events read after every chunk and, with
    ``resolve``, its slips resolved locally (see the module)."""

    def __init__(self, built, *, resolve=None, make_level=None, selects=lambda name: True,
                 **runner_options):
        """``resolve``: a ``ResolveEvents`` or None; ``make_level(step_s, solver_factor=1.0)``: a
        runner of the same simulation at another step (a window's level, ``sim.resolve``; SAP's
        tolerance loosened by ``solver_factor`` for the solver twin); ``selects(name)``:
        whether a friction pair (by name) is resolved."""
        super().__init__(built, **runner_options)
        self.events, self.event_count, self.events_lost, self.last_rows = [], 0, 0, []
        self.resolver = None
        if resolve is not None and built.friction is not None:
            self.resolver = Resolver(self, settings=resolve, step_s=built.time_step_s,
                                     make_level=make_level, selects=selects)

    def checked(self):
        """After a chunk: the monitor's checks, the recorder's frame, the chunk's events."""
        super().checked()
        friction = self.built.friction
        if friction is None:
            return
        rows, self.event_count, lost = friction.events(friction.GetMyContextFromRoot(self.root),
                                                       self.event_count)
        self.events_lost += lost
        step = self.built.time_step_s
        self.events.extend((row, step, -1) for row in rows)
        self.last_rows = rows

    def before_chunk(self):
        if self.resolver is not None:
            self.resolver.before_chunk()

    def after_chunk(self, end):
        if self.resolver is not None:
            self.resolver.after_chunk(self.last_rows, end)

    def logged(self):
        """The loggers' columns, each resolved window's from its resolving level."""
        logged = logged_history(self.built, self.root)
        if self.resolver is not None:
            logged = self.resolver.spliced_history(logged)
        return logged

    def history(self):
        return self.built.history(self.logged())

    def event_table(self):
        """The run's events as columns (``event_columns``); None without friction."""
        friction = self.built.friction
        if friction is None:
            return None
        return event_columns(self.events, friction.pair_names(),
                             friction.threshold_velocities(), self.events_lost)

    def resolution(self):
        """What the local resolution did and cost (``Resolver.record``), None without it."""
        return None if self.resolver is None else self.resolver.record()


def event_columns(events, pair_names, dv, lost=0):
    """(row, step, window) triples as JSON-ready columns: ``law.friction.events``'
    EVENT_FIELDS, the pair and kind by name, ``band_steps`` (Δv over the step's velocity
    change: how many steps of that change the static band is wide), the step that saw the
    event, the window that resolved it (-1: none); and ``lost``, the events the bounded log
    lost (a count, not a column)."""
    rows = [row for row, _, _ in events]
    table = {field: [float(row[k]) for row in rows] for k, field in enumerate(EVENT_FIELDS)}
    table["pair"] = [pair_names[int(row[1])] for row in rows]
    table["kind"] = [KIND_NAMES[float(row[2])] for row in rows]
    table["band_steps"] = [float(dv[int(row[1])] / abs(row[4])) if row[4] else math.inf
                           for row in rows]
    table["step_s"] = [float(step) for _, step, _ in events]
    table["window"] = [int(window) for _, _, window in events]
    table["lost"] = int(lost)
    return table
