"""Road height profiles z = h(x, y) (m) for the tyres' contact (pure numpy). The road's local
normal is taken as +z by the tyre model, so profiles should have gentle slopes (a bump of
h over a length L has slope π h / L at most)."""

import dataclasses
import math

import numpy as np


class RoadProfileError(ValueError):
    """A road profile's parameters or samples are invalid; the message names them."""


def flat(x, y):
    return 0.0


@dataclasses.dataclass(frozen=True)
class CosineBump:
    """A bump (height > 0) or pothole (height < 0) across the whole road: one cosine wave of
    ``length_m`` starting at ``start_x_m`` (smooth, zero slope at both ends)."""

    start_x_m: float
    length_m: float
    height_m: float

    def __post_init__(self):
        if not (math.isfinite(self.length_m) and self.length_m > 0):
            raise RoadProfileError(f"road bump length_m = {self.length_m} must be > 0")
        if not (math.isfinite(self.start_x_m) and math.isfinite(self.height_m)):
            raise RoadProfileError("road bump start_x_m and height_m must be finite")

    def __call__(self, x, y):
        s = (x - self.start_x_m) / self.length_m
        if s <= 0.0 or s >= 1.0:
            return 0.0
        return 0.5 * self.height_m * (1.0 - math.cos(2.0 * math.pi * s))


@dataclasses.dataclass(frozen=True)
class SampledProfile:
    """A measured longitudinal profile: heights ``z_m`` at stations ``x_m`` (strictly
    increasing), linear in between, the end heights held outside."""

    x_m: tuple
    z_m: tuple

    def __post_init__(self):
        x, z = np.asarray(self.x_m, dtype=float), np.asarray(self.z_m, dtype=float)
        if x.ndim != 1 or x.shape != z.shape or x.size < 2:
            raise RoadProfileError(
                f"road samples: x_m and z_m must be lists of the same length >= 2 "
                f"(got {x.size} and {z.size})")
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(z))):
            bad = int(np.flatnonzero(~(np.isfinite(x) & np.isfinite(z)))[0])
            raise RoadProfileError(f"road samples: sample {bad} is not finite")
        steps = np.diff(x)
        if np.any(steps <= 0):
            bad = int(np.flatnonzero(steps <= 0)[0]) + 1
            raise RoadProfileError(f"road samples: x_m must increase strictly (sample {bad})")
        object.__setattr__(self, "_x", x)
        object.__setattr__(self, "_z", z)

    def __call__(self, x, y):
        return float(np.interp(x, self._x, self._z))
