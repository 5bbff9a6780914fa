"""Manoeuvres defined by a path, and the driver that follows one: ``!DoubleLaneChange`` (ISO
3888-2's obstacle-avoidance course), ``!ConstantRadius`` (a steady-state circle, ISO 4138's
constant-radius method at one speed) and the steering ``!PathFollower`` (path preview on the
rack: ``systems.path_driver``; the speed is the scene's drive following the timeline's
profile).

Each path manoeuvre has the paper's phases (``scene.manoeuvres.Timeline``): I settle and speed
up to ``speed_kph`` along the x axis from where the car stands, II straight on, III the course
(its entry at the distance the speed profile reaches at the start of phase III), IV on along
the path. ``outcome(scene, history)`` says whether the run did what the manoeuvre asks (the
car's footprint inside the cone lanes; the car on the circle within a tolerance), from the
logged chassis channels.
"""

import dataclasses
import math

import numpy as np

from drake_car.law.checks import ParameterError, in_range, one_of, positive
from drake_car.law.road.centre_line import (
    ISO3888_2_LENGTHS_M, circle_line, footprint_corners, iso3888_2_lanes, lane_excursion_m,
    lane_line)
from drake_car.scene.manoeuvres import DrivingManoeuvre, Timeline, speed_profile

# Beyond the course the path runs straight on for the rest of the run and this much more (m).
RUN_OUT_M = 50.0
# Behind the car's start the path runs back this far (m): the car starts on it.
APPROACH_M = 50.0


@dataclasses.dataclass
class PathFollower:
    """The driver follows the manoeuvre's path (``systems.path_driver``): it looks
    ``preview_m`` ahead and steers the rack with the gain k = 4 ζ² l / L² that gives a
    neutral-steer car the damping ratio ``damping_ratio`` ζ at every speed, plus the path's
    curvature feed-forward; it updates every ``period_s``. The drive follows the timeline's
    speed profile (the scene's ``drive``)."""

    # [EST] about 0.6 s ahead at 60 km/h: ω_n = 2 ζ u / L = 3.3 rad/s there, well below the
    # rack servo's and the tyres' bandwidths, and the preview a driver uses in a lane change.
    preview_m: float = 10.0
    damping_ratio: float = 1.0
    # [EST] a driving machine's controller rate (100 Hz).
    period_s: float = 0.01

    def check(self):
        in_range(self, "preview_m", 1.0, 100.0, "m ahead of the car")
        in_range(self, "damping_ratio", 0.3, 3.0)
        in_range(self, "period_s", 1e-4, 0.1, "s: a driver updating less often than 10 Hz "
                 "is not a driving machine")
        return self


class PathManoeuvre(DrivingManoeuvre):
    """What the path manoeuvres share (not loadable itself): the course's entry, the path and
    the straight approach to it."""

    follows_path = True

    def entry_m(self):
        """Where the course begins (m along x): the speed profile's distance at phase III."""
        _, t3, _, _ = self.timeline.boundaries()
        return float(speed_profile(np.array([t3]), self.timeline)[1][0])

    def run_length_m(self):
        """How far the car can go in the whole run (m), with margin."""
        end = self.timeline.duration_s
        return float(speed_profile(np.array([end]), self.timeline)[1][0]) + RUN_OUT_M

    def _check_speed_covers(self, length_m, what):
        reach = self.timeline.speed_mps * self.timeline.steer_s
        if reach < length_m:
            raise ParameterError(
                "timeline.steer_s", self.timeline.steer_s,
                f"must cover {what} ({length_m:g} m): at {self.timeline.speed_kph:g} km/h "
                f"that takes >= {length_m / self.timeline.speed_mps:.3g} s")


@dataclasses.dataclass
class DoubleLaneChange(PathManoeuvre):
    """ISO 3888-2's severe lane change (obstacle avoidance): cone lanes whose widths follow
    the vehicle's width (``law.road.centre_line``: the geometry, its source and what was not
    checked), entered at ``timeline.speed_kph``. The path runs along the lanes' centre lines,
    from one to the next by a transition of continuous curvature across each gap; the first move is to the
    ``direction`` side (the standard's: left). ``vehicle_width_m`` and the overhangs ahead of
    the front axle and behind the rear axle give the footprint checked against the lanes.
    The speed is held through the course (the standard's driver, as far as could be
    checked, releases the accelerator at the entry: not modelled)."""

    timeline: Timeline = dataclasses.field(
        default_factory=lambda: Timeline(straight_s=1.2, steer_s=4.0, calm_s=1.0))
    direction: str = "left"
    # [EST] the 1990-2000 Ford Escort's body is about 1.69 m wide without mirrors, 4.1 m long
    # on its 2.52 m wheelbase; the overhangs split the rest, the front one longer.
    vehicle_width_m: float = 1.69
    front_overhang_m: float = 0.85
    rear_overhang_m: float = 0.70

    def _check_own(self):
        one_of(self, "direction", ("left", "right"))
        in_range(self, "vehicle_width_m", 1.2, 2.6, "m: a passenger car's or van's body")
        in_range(self, "front_overhang_m", 0.0, 2.0)
        in_range(self, "rear_overhang_m", 0.0, 2.0)
        self._check_speed_covers(sum(ISO3888_2_LENGTHS_M), "the 61 m course")

    def lanes(self):
        """The three cone lanes in the world (mirrored for a first move to the right)."""
        lanes = iso3888_2_lanes(self.vehicle_width_m, self.entry_m())
        if self.direction == "right":
            lanes = tuple(dataclasses.replace(lane, left_m=-lane.right_m, right_m=-lane.left_m)
                          for lane in lanes)
        return lanes

    def centre_line(self):
        return lane_line(self.lanes(), -APPROACH_M, self.run_length_m())

    def outcome(self, scene, history):
        """Whether the car's footprint stayed inside the lanes (``inside``), by how much its
        worst corner came out (``excursion_m``, < 0: the margin kept) and in which lane."""
        x, y, yaw = (np.asarray(history[c]) for c in ("x_m", "y_m", "yaw_rad"))
        corners = footprint_corners(x, y, yaw, self.vehicle_width_m, self.front_overhang_m,
                                    scene.car.wheelbase_m + self.rear_overhang_m)
        worst, lane = lane_excursion_m(self.lanes(), *corners)
        reached = bool(np.max(x) + self.front_overhang_m >= self.lanes()[-1].end_m)
        return {"manoeuvre": "DoubleLaneChange", "course_completed": reached,
                "inside": bool(reached and worst <= 0.0),
                "excursion_m": worst if lane is not None else None,
                "worst_lane": None if lane is None else (1, 3, 5)[lane]}


@dataclasses.dataclass
class ConstantRadius(PathManoeuvre):
    """A steady-state circle of ``radius_m`` to the ``direction`` side at the timeline's speed
    (ISO 4138's constant-radius method at one speed: a sweep over ``timeline.speed_kph`` gives
    its steps). The circle starts at the entry; the run checks, from a quarter turn into the
    circle on, that the car's reference point stays within ``tolerance_m`` of it."""

    timeline: Timeline = dataclasses.field(
        default_factory=lambda: Timeline(speed_kph=40.0, straight_s=1.0, steer_s=12.0,
                                         calm_s=0.0))
    radius_m: float = 40.0
    direction: str = "left"
    # [EST] a driver holding a painted circle: half a tyre width either side of the line.
    tolerance_m: float = 0.5

    def _check_own(self):
        one_of(self, "direction", ("left", "right"))
        in_range(self, "radius_m", 10.0, 1000.0, "m")
        positive(self, "tolerance_m")
        if self.tolerance_m > 0.1 * self.radius_m:
            raise ParameterError("tolerance_m", self.tolerance_m,
                                 f"must be <= a tenth of radius_m = {self.radius_m:g} m")
        self._check_speed_covers(0.5 * math.pi * self.radius_m, "a quarter turn")

    def centre_line(self):
        return circle_line(self.entry_m(), self.radius_m, self.direction == "left",
                           self.run_length_m() - self.entry_m(), approach_m=APPROACH_M
                           + self.entry_m())

    def outcome(self, scene, history):
        """The reference point's distance from the circle's centre against ``radius_m``, from
        a quarter turn into the circle on: ``radius_error_m`` (largest |r - R|), ``mean_radius_m``
        and ``within`` (the largest error <= ``tolerance_m``)."""
        x, y = np.asarray(history["x_m"]), np.asarray(history["y_m"])
        sign = 1.0 if self.direction == "left" else -1.0
        cx, cy = self.entry_m(), sign * self.radius_m
        r = np.hypot(x - cx, y - cy)
        # the angle swept about the centre since the entry (0 there, pi/2 a quarter turn on)
        angle = np.unwrap(np.arctan2(x - cx, sign * (cy - y)))
        past = np.nonzero(angle >= 0.5 * math.pi)[0]
        if not past.size:
            return {"manoeuvre": "ConstantRadius", "quarter_turn_reached": False,
                    "within": False, "radius_error_m": None, "mean_radius_m": None}
        steady = slice(int(past[0]), None)
        error = float(np.max(np.abs(r[steady] - self.radius_m)))
        return {"manoeuvre": "ConstantRadius", "quarter_turn_reached": True,
                "within": error <= self.tolerance_m, "radius_error_m": error,
                "mean_radius_m": float(np.mean(r[steady]))}


PATH_MANOEUVRES = (DoubleLaneChange, ConstantRadius)
