"""A path on the road for a driver to follow, and the lanes it runs through (pure numpy, no
Drake): a centre line sampled densely with its heading and curvature, where a point lies from
it (station s along it, lateral offset left +), the cone lanes of ISO 3888-2's double lane
change, and how far a car's footprint pokes out of lanes.

ISO 3888-2:2011 (Passenger cars — Test track for a severe lane-change manoeuvre — Part 2:
Obstacle avoidance), the course as used here (``iso3888_2_lanes``):

=========  ========  ===========================  ======================================
section    length    width                        lateral place
=========  ========  ===========================  ======================================
1 (entry)  12 m      1.1 w + 0.25 m               centred on the approach line (y = 0)
2          13.5 m    (no lane)
3          11 m      w + 1 m                      its right edge 1 m left of lane 1's left
                                                  edge
4          12.5 m    (no lane)
5 (exit)   12 m      1.3 w + 0.25 m, >= 3 m       its right edge on lane 1's right edge
=========  ========  ===========================  ======================================

w is the vehicle's width; the course is 61 m long; the first move is to the left. Sources: the
standard's scope and §4 as published (the 61 m length, widths as functions of the vehicle
width, cone-marked lanes with the track limits tangent to the cones' bases) and its Table 1 as
reproduced in two public implementations, which agree on sections 1-4 and differ on the exit
lane: Project Chrono's ISO 3888 double-lane-change demo (HMMWV) gives it a fixed 3 m with its
right edge on lane 1's (used here: the same 3 m for any car narrower than 2.1 m), the
``iso_maneuvers`` scripts (github AhmadAmine998) min(1.3 w + 0.25, 3) m centred on lane 1's
centre line (2.45 m for this car's 1.69 m). Not checked against the standard's own Table 1 and
Figure 1 (not at hand): lane 5's width rule and where it lies.
"""

import dataclasses
import math

import numpy as np

# Samples of a centre line per metre (the driver interpolates between them).
SAMPLES_PER_M = 10.0
# ISO 3888-2's sections (m): lane 1, gap, lane 3, gap, lane 5 (table above).
ISO3888_2_LENGTHS_M = (12.0, 13.5, 11.0, 12.5, 12.0)
ISO3888_2_OFFSET_M = 1.0  # lane 3's right edge beyond lane 1's left edge
ISO3888_2_EXIT_MIN_WIDTH_M = 3.0


@dataclasses.dataclass(frozen=True)
class Lane:
    """A stretch of road between two cone lines: x from ``start_m`` to ``end_m``, y between
    ``right_m`` and ``left_m`` (m, world frame, y to the left)."""

    start_m: float
    end_m: float
    right_m: float
    left_m: float

    @property
    def centre_m(self):
        return 0.5 * (self.left_m + self.right_m)

    @property
    def width_m(self):
        return self.left_m - self.right_m


class CentreLine:
    """A path through the points (x, y) with its heading (rad) and curvature (1/m, left +) at
    each, sampled densely (``SAMPLES_PER_M``), linear in between."""

    def __init__(self, x_m, y_m, heading_rad, curvature_1pm):
        self.x, self.y = np.asarray(x_m, float), np.asarray(y_m, float)
        self.heading = np.asarray(heading_rad, float)
        self.curvature = np.asarray(curvature_1pm, float)
        if len(self.x) < 2:
            raise ValueError("CentreLine: needs at least two points")
        steps = np.hypot(np.diff(self.x), np.diff(self.y))
        if not np.all(steps > 0):
            raise ValueError("CentreLine: consecutive points must differ")
        self.station = np.concatenate([[0.0], np.cumsum(steps)])
        self._dx, self._dy, self._steps = np.diff(self.x), np.diff(self.y), steps

    @property
    def length_m(self):
        return float(self.station[-1])

    def locate(self, x, y, near_m=None, window_m=math.inf):
        """(station s, lateral offset of (x, y) from the line (m, left +), the line's heading
        and curvature at s) of the line's point nearest (x, y); ``near_m``: look only within
        ``window_m`` of that station (a follower's last station: a line that crosses or
        comes back near itself, such as a circle driven twice, is found where the car is)."""
        lo, hi = 0, len(self._steps)
        if near_m is not None and math.isfinite(window_m):
            lo = max(0, int(np.searchsorted(self.station, near_m - window_m)) - 1)
            hi = min(len(self._steps), int(np.searchsorted(self.station, near_m + window_m)) + 1)
        dx, dy, steps = self._dx[lo:hi], self._dy[lo:hi], self._steps[lo:hi]
        px, py = x - self.x[lo:hi], y - self.y[lo:hi]
        t = np.clip((px * dx + py * dy) / steps ** 2, 0.0, 1.0)
        distance = np.hypot(px - t * dx, py - t * dy)
        i = int(np.argmin(distance))
        f = float(t[i])
        k = lo + i
        offset = float((dx[i] * py[i] - dy[i] * px[i]) / steps[i])
        # heading: interpolated on the circle (a line that turns through ±π)
        h0, h1 = self.heading[k], self.heading[k + 1]
        heading = h0 + f * math.remainder(h1 - h0, 2 * math.pi)
        curvature = (1 - f) * self.curvature[k] + f * self.curvature[k + 1]
        return self.station[k] + f * steps[i], offset, heading, curvature

    def offset_of(self, x, y):
        """Lateral offsets (m, left +) of the points (arrays), each from the nearest point of
        the line, followed along it as a car drives (each point searched near the last)."""
        offsets, near = np.empty(len(x)), None
        for i, (xi, yi) in enumerate(zip(x, y)):
            near, offsets[i], _, _ = self.locate(float(xi), float(yi), near, 20.0)
        return offsets


def _samples(length_m):
    return max(2, int(math.ceil(length_m * SAMPLES_PER_M)) + 1)


def lane_line(lanes, start_m, end_m):
    """The centre line through ``lanes`` (in order along x) from x = ``start_m`` to
    ``end_m``: straight on each lane's centre line, and between two lanes a transition
    y = Δy (ξ - sin(2πξ)/(2π)), ξ = (x - x0)/L across the gap L (tangent to both centre lines
    with zero curvature there, so a driver's curvature feed-forward has no step; y'' peaks at
    2πΔy/L² a quarter and three quarters across); before the first lane on the first's centre
    line, after the last on the last's."""
    x = np.linspace(start_m, end_m, _samples(end_m - start_m))
    y, slope, curve = (np.full_like(x, lanes[0].centre_m), np.zeros_like(x),
                       np.zeros_like(x))
    for before, after in zip(lanes, lanes[1:]):
        gap = after.start_m - before.end_m
        rise = after.centre_m - before.centre_m
        xi = np.clip((x - before.end_m) / gap, 0.0, 1.0)
        inside = (xi > 0) & (xi < 1)
        y += rise * (xi - np.sin(2 * math.pi * xi) / (2 * math.pi))
        slope += np.where(inside, rise / gap * (1 - np.cos(2 * math.pi * xi)), 0.0)
        curve += np.where(inside, rise * 2 * math.pi / gap ** 2 * np.sin(2 * math.pi * xi), 0.0)
    heading = np.arctan(slope)
    curvature = curve / (1 + slope ** 2) ** 1.5
    return CentreLine(x, y, heading, curvature)


def circle_line(entry_m, radius_m, left, length_m, approach_m=50.0):
    """Straight along the x axis from ``entry_m - approach_m`` to ``entry_m``, then a circle of
    ``radius_m`` tangent to it there (to the left or right) for ``length_m`` along it."""
    sign = 1.0 if left else -1.0
    xa = np.linspace(entry_m - approach_m, entry_m, _samples(approach_m))[:-1]
    angle = np.linspace(0.0, length_m / radius_m, _samples(length_m))
    xc = entry_m + radius_m * np.sin(angle)
    yc = sign * radius_m * (1 - np.cos(angle))
    return CentreLine(np.concatenate([xa, xc]), np.concatenate([np.zeros_like(xa), yc]),
                      np.concatenate([np.zeros_like(xa), sign * angle]),
                      np.concatenate([np.zeros_like(xa), np.full_like(angle, sign / radius_m)]))


def iso3888_2_lanes(vehicle_width_m, entry_m=0.0):
    """ISO 3888-2's three cone lanes (module docstring) for a vehicle ``vehicle_width_m``
    wide, the course starting at x = ``entry_m``, lane 1 centred on y = 0, lane 3 to the left."""
    w = vehicle_width_m
    l1, g2, l3, g4, l5 = ISO3888_2_LENGTHS_M
    width1, width3 = 1.1 * w + 0.25, w + 1.0
    width5 = max(1.3 * w + 0.25, ISO3888_2_EXIT_MIN_WIDTH_M)
    right1 = -0.5 * width1
    right3 = 0.5 * width1 + ISO3888_2_OFFSET_M
    x3 = entry_m + l1 + g2
    x5 = x3 + l3 + g4
    return (Lane(entry_m, entry_m + l1, right1, right1 + width1),
            Lane(x3, x3 + l3, right3, right3 + width3),
            Lane(x5, x5 + l5, right1, right1 + width5))


def footprint_corners(x, y, yaw, width_m, ahead_m, behind_m):
    """The four corners (arrays n x 4 for x and y) of a car's footprint, a rectangle
    ``width_m`` wide from ``ahead_m`` in front of its reference point to ``behind_m`` behind,
    at poses (x, y, yaw) (arrays)."""
    along = np.array([ahead_m, ahead_m, -behind_m, -behind_m])
    across = 0.5 * width_m * np.array([1.0, -1.0, 1.0, -1.0])
    c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
    return x[:, None] + c * along - s * across, y[:, None] + s * along + c * across


def lane_excursion_m(lanes, corner_x, corner_y):
    """How far (m) any corner came out of the lane it was in, over all samples (each corner
    counts while its x lies within a lane's x range; <= 0: every corner stayed inside, by that
    margin), and the index of the lane where the worst excursion happened."""
    worst, where = -math.inf, None
    for i, lane in enumerate(lanes):
        inside = (corner_x >= lane.start_m) & (corner_x <= lane.end_m)
        if not np.any(inside):
            continue
        out = np.maximum(corner_y - lane.left_m, lane.right_m - corner_y)[inside]
        if out.max() > worst:
            worst, where = float(out.max()), i
    return worst, where
