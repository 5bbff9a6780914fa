"""What a driving manoeuvre says it does, and whether a run did it (pure: a history in, the
measures beside their targets out). The paper's lane change (section 4): 60 km/h reached and
held before the lane change, the track moved 3.7 m sideways in the 2.4 s of phase III, ending
parallel to its start.

The tolerances (a run outside one is not the manoeuvre it says it is):
- speed at place a (the mean over the 0.3 s before phase III: the paper study's place a,
  ``study.paper.claims.place_values``): within ``SPEED_TOLERANCE_KPH`` = 1 km/h of the
  timeline's speed;
- the track's lateral shift over phase III: within ``SHIFT_TOLERANCE_M`` = 0.05 m of the lane
  change's ``shift_m``, to the left in case a, to the right in case b;
- the heading at the end of phase III: parallel to the start within the angle that would move
  the car sideways by the shift's tolerance over the length of one more lane change,
  ψ_tol = SHIFT_TOLERANCE_M / (v · steer_s): 1.25 mrad = 0.072° at 60 km/h and 2.4 s. (The
  shipped Escort's six runs end their lane change within 0.018° of parallel.)

The shift and the heading are judged where the struts' dry friction cannot move them: on a
run without it (μs = 0). Every run of a study gets the same rack input; with dry struts the
path follows it differently, and that difference is the friction's effect the study measures
(a run's ``friction_effect``), reported beside the targets, not a manoeuvre that is off.
"""

import dataclasses
import math

import numpy as np

from drake_car.scene.manoeuvres import LaneChange

# Place a: the window before the lane change over which the paper study averages (s).
PLACE_A_S = 0.3
SPEED_TOLERANCE_KPH = 1.0
SHIFT_TOLERANCE_M = 0.05


@dataclasses.dataclass
class Measure:
    """One thing a manoeuvre says it does: ``value`` against ``target`` ± ``tolerance`` (in
    ``unit``, as the report writes them); ``value`` None: not measured (the run stopped
    before, or did not log it)."""

    what: str
    value: float | None
    target: float
    tolerance: float
    unit: str
    # the run's dry strut friction moves this value: reported, not judged (see the module)
    friction_effect: bool = False

    @property
    def within(self):
        return self.value is None or abs(self.value - self.target) <= self.tolerance

    @property
    def ok(self):
        return self.within or self.friction_effect

    def describe(self):
        if self.value is None:
            return f"{self.what}: not measured (the run stopped before, or did not log it)"
        return (f"{self.what} {self.value:.2f} {self.unit}, asked {self.target:.2f} ± "
                f"{self.tolerance:.2g} {self.unit}" + (
                    "" if self.within else ": beyond it, with dry strut friction, which "
                    "moves the path (not judged)" if self.friction_effect else
                    ": OFF"))


def dry_friction(scene):
    """Whether the scene's struts have dry friction (μs > 0), which moves the car's path."""
    return scene.friction is not None and scene.friction.law.mu_s > 0


def heading_tolerance_rad(timeline):
    """The heading within which a lane change ends parallel (rad): see the module."""
    return SHIFT_TOLERANCE_M / (timeline.speed_mps * timeline.steer_s)


def place_a(t, timeline):
    """The samples of place a (the ``PLACE_A_S`` before phase III; at least the last sample
    before it)."""
    t = np.asarray(t)
    t3 = timeline.boundaries()[1]
    window = (t >= t3 - PLACE_A_S) & (t < t3)
    if not window.any():
        window = np.arange(len(t)) == max(int(np.searchsorted(t, t3)) - 1, 0)
    return window


def speed_at_place_a_mps(history, timeline):
    """The car's mean speed over place a (m/s; None when the run stopped before it or did not
    log its speed)."""
    t = history.get("t")
    if t is None or "speed_mps" not in history or t[-1] < timeline.boundaries()[1] - 1e-9:
        return None
    return float(np.mean(np.asarray(history["speed_mps"])[place_a(t, timeline)]))


def lane_change_metrics(history, timeline):
    """Lateral shift of the car over phase III and heading change at its end (None when the
    history stops before phase III ends)."""
    t = history["t"]
    _, t3, t4, _ = timeline.boundaries()
    if t[-1] < t4:
        return None
    i3, i4 = np.searchsorted(t, t3), min(np.searchsorted(t, t4), len(t) - 1)
    heading = history["yaw_rad"]
    y = history["y_m"]
    return {"shift_m": float(y[i4] - y[i3]),
            "heading_change_deg": float(math.degrees(heading[i4] - heading[i3])),
            "final_heading_deg": float(math.degrees(heading[-1] - heading[i3])),
            "final_shift_m": float(y[-1] - y[i3])}


def manoeuvre_measures(history, manoeuvre, dry=False):
    """The measures of a driving manoeuvre's run (``Measure`` list; [] for a manoeuvre that
    does not drive): the speed at place a for every driving manoeuvre; the lateral shift and
    the heading at the end of phase III for a lane change, the friction's effect where the
    run has dry friction (``dry``: ``dry_friction(scene)``)."""
    if not manoeuvre.drives:
        return []
    timeline = manoeuvre.timeline
    speed = speed_at_place_a_mps(history, timeline)
    measures = [Measure("speed at place a", None if speed is None else 3.6 * speed,
                        timeline.speed_kph, SPEED_TOLERANCE_KPH, "km/h")]
    if isinstance(manoeuvre, LaneChange):
        logged = all(k in history for k in ("y_m", "yaw_rad"))
        m = lane_change_metrics(history, timeline) if logged else None
        sign = 1.0 if manoeuvre.case == "a" else -1.0
        measures += [
            Measure("lateral shift over the lane change", None if m is None else
                    sign * m["shift_m"], manoeuvre.shift_m, SHIFT_TOLERANCE_M, "m", dry),
            Measure("heading change at its end", None if m is None else
                    m["heading_change_deg"], 0.0,
                    math.degrees(heading_tolerance_rad(timeline)), "deg", dry)]
    return measures


def manoeuvre_failures(history, manoeuvre, dry=False):
    """One line per measure the run is off (empty: it did what its manoeuvre says; with
    ``dry`` friction its path is the friction's effect, not judged)."""
    return [m.describe() for m in manoeuvre_measures(history, manoeuvre, dry) if not m.ok]
