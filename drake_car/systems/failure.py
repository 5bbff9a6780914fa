"""A run that cannot go on for a physical reason (the rod has left its guide, the state has
diverged): raised from inside a simulation, reported by the scripts as one line (exit 2)."""

from drake_car.law.errors import RunFailed


class SimulationFailure(RunFailed):
    """The simulation cannot continue; the message names the time, the quantity and why."""
