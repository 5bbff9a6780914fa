"""The scene's ``simulator`` section (``scene.scene``): how a run is carried out (its end, its
initial state, the SAP pacer and tolerance, the divergence monitor) and the stick-slip events
it resolves locally (``ResolveEvents``, ``sim.resolve``)."""

import dataclasses
import math
import typing

from drake_car.law.checks import ParameterError, checked, nonnegative, one_of, positive
from drake_car.systems.sap_ballast import MAX_FACTOR


@dataclasses.dataclass
class ResolveEvents:
    """Stick-slip events resolved locally (``sim.resolve``): where a friction pair of the struts
    (``pairs``: translation, the rods' sliding, which decides where they rest; or all, rotation
    too) slips (``events``: "all", every break-away or full creep; "near", only a full creep or
    a break-away that crossed the static band in more than one step), the run resolves a window
    around it at halved steps until the window's outcome (each pair's slips and sticks, where it
    rests: converged within ``position_tolerance_m``, or ``angle_tolerance_rad`` for rotation,
    and how close each came to breaking away) no longer changes with a further halving, down to
    ``finest_step_s``, and goes on at its own step from the finest window's end. A window starts
    ``lead_s`` before its event, and before every slip of the pairs that ended within
    ``lookback_s`` before it; it ends once every pair has been static, short of its full creep,
    for ``hold_s``. ``solver_twin``: the budget's solver axis (``sim.twins``: the run again
    along its windows with SAP's tolerance loosened twice). A looser tolerance loosens the
    error, not what counts as agreeing (``sim.window.agreement_band``; docs/accuracy.md)."""

    pairs: str = "translation"
    events: str = "all"
    finest_step_s: float = 3.125e-5
    position_tolerance_m: float = 2e-5
    angle_tolerance_rad: float = 1e-4
    lookback_s: float = 0.5
    lead_s: float = 0.05
    hold_s: float = 0.05
    solver_twin: bool = True

    def check(self):
        one_of(self, "pairs", ("translation", "all"))
        one_of(self, "events", ("all", "near"))
        positive(self, "finest_step_s", "position_tolerance_m", "angle_tolerance_rad",
                 "lead_s", "hold_s")
        nonnegative(self, "lookback_s")
        if self.lookback_s > 5.0:
            raise ParameterError("lookback_s", self.lookback_s,
                                 "must be <= 5 s (a window is run at every halving)")
        return self


@dataclasses.dataclass
class Simulator:
    """``end_time_s``: None runs the whole manoeuvre; a value stops earlier. ``start``:
    static_equilibrium (at rest where the lubricated car settles on its tyres, as a multibody
    code's static analysis precedes its dynamic run) or design (the model's design position:
    the car drops onto its tyres); the equilibrium is found by settling the lubricated car for
    ``equilibrium_settle_s`` at ``equilibrium_time_step_s`` (None: the scene's own step; the
    default, 1 ms, gives every step of an accuracy sweep the same initial state and keeps a
    microsecond-step run from settling for millions of steps). ``sap_pacer``: keep SAP from
    returning its initial guess near a balance (``systems.sap_pacer``). ``monitor_period_s``:
    how often the divergence monitor checks the state. ``airborne_limit_s``: how long all four
    wheels may stay off a flat road before the monitor stops the run (``sim.monitor``: 0.2 s is
    a ballistic hop of g T² / 8 = 5 cm, which no drive on a flat road makes).
    ``resolve_events``: resolve the struts' stick-slip events locally (``ResolveEvents``;
    None: the whole run at its step).
    ``sap_tolerance_factor``: SAP's relative stopping tolerance (Drake's 1e-6, not settable from
    Python) loosened by this factor wherever the car's motion sets SAP's momentum scale, by a
    decoupled ballast (``systems.sap_ballast``); 1 adds none. The error budget's solver axis
    runs a twin at 2 (``sweep.refine``); a tighter tolerance is out of reach."""

    end_time_s: typing.Optional[float] = None
    start: str = "static_equilibrium"
    equilibrium_settle_s: float = 6.0
    equilibrium_time_step_s: typing.Optional[float] = 1e-3
    sap_pacer: bool = True
    monitor_period_s: float = 0.01
    airborne_limit_s: float = 0.2
    resolve_events: typing.Optional[ResolveEvents] = None
    sap_tolerance_factor: float = 1.0

    def check(self):
        if self.end_time_s is not None:
            positive(self, "end_time_s")
        if self.resolve_events is not None:
            checked(self.resolve_events, "resolve_events")
        one_of(self, "start", ("static_equilibrium", "design"))
        positive(self, "equilibrium_settle_s", "monitor_period_s", "airborne_limit_s")
        if self.equilibrium_time_step_s is not None:
            positive(self, "equilibrium_time_step_s")
            if self.equilibrium_time_step_s > 0.01:
                raise ParameterError("equilibrium_time_step_s", self.equilibrium_time_step_s,
                                     "must be <= 0.01 s")
        twin = 2.0 if getattr(self.resolve_events, "solver_twin", False) else 1.0
        if not (math.isfinite(self.sap_tolerance_factor)
                and 1.0 <= self.sap_tolerance_factor <= MAX_FACTOR / twin):
            raise ParameterError("sap_tolerance_factor", self.sap_tolerance_factor, (
                f"must be a number from 1 to {MAX_FACTOR / twin:g} (SAP's tolerance can only be "
                "loosened from Python" + ("; resolve_events.solver_twin runs at twice it)"
                                          if twin > 1 else ")")))
        if self.equilibrium_settle_s > 60.0:
            raise ParameterError("equilibrium_settle_s", self.equilibrium_settle_s,
                                 "must be <= 60 s (the car settles within ~5 s)")
        return self
