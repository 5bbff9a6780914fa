"""Road height profiles z = h(x, y) (m) for the tyres' contact (pure numpy), as loadable
dataclasses (a scene's ``road`` is one of them, chosen by its YAML tag: ``!Flat``,
``!CosineBump``, ``!SampledProfile``). The road's local normal is taken as +z by the tyre model,
so profiles must have gentle slopes: ``check()`` refuses slopes above ``MAX_SLOPE``."""

import dataclasses
import math
import typing

import numpy as np

from drake_car.law.checks import ParameterError, finite, positive

# The tyre model takes the road normal as +z: slopes up to 0.3 (17 deg) keep cos(slope) > 0.95,
# i.e. the normal load within 5 % of what a tilted normal would give.
MAX_SLOPE = 0.3
# A road that is not a road: profiles are bounded to ±1 m of height and 10 km of length.
MAX_HEIGHT_M = 1.0
MAX_LENGTH_M = 1e4
# Samples of a !SampledProfile: 10^7 took ~30 min and 17 GB to load and settle (main
# f5ab02c), i.e. ~0.2 ms and ~1.7 kB a sample [EST: scaled from that one measurement]; 10^5
# samples (~20 s, ~170 MB; 1 m stations over 100 km, or 1 cm over 1 km) bound that. A scene
# file's size limit (scene.guard) holds about as many written out.
MAX_ROAD_SAMPLES = 100_000
ROAD_SAMPLE_S, ROAD_SAMPLE_BYTES = 2e-4, 1.7e3


@dataclasses.dataclass
class Flat:
    """The flat road z = 0."""

    def check(self):
        return self

    def height(self, x, y):
        return 0.0

    def flat_up_to_m(self):
        """The road is z = 0 wherever x <= this (m)."""
        return math.inf

    __call__ = height


@dataclasses.dataclass
class CosineBump:
    """A bump (height > 0) or pothole (height < 0) across the whole road: one cosine wave of
    ``length_m`` starting at ``start_x_m`` (smooth, zero slope at both ends; largest slope
    π·|h|/L)."""

    start_x_m: float = 40.0
    length_m: float = 1.5
    height_m: float = 0.05

    def check(self):
        finite(self, "start_x_m", "height_m")
        positive(self, "length_m")
        if self.length_m > MAX_LENGTH_M:
            raise ParameterError("length_m", self.length_m, f"must be <= {MAX_LENGTH_M:g} m")
        if abs(self.height_m) > MAX_HEIGHT_M:
            raise ParameterError("height_m", self.height_m,
                                 f"must lie in [-{MAX_HEIGHT_M:g}, {MAX_HEIGHT_M:g}] m")
        slope = math.pi * abs(self.height_m) / self.length_m
        if slope > MAX_SLOPE:
            raise ParameterError("length_m", self.length_m,
                                 f"is too short for height_m = {self.height_m}: the largest "
                                 f"slope π|h|/L = {slope:.2f} must be <= {MAX_SLOPE} (the tyre "
                                 "model takes the road normal as vertical)")
        return self

    def height(self, x, y):
        s = (x - self.start_x_m) / self.length_m
        if s <= 0.0 or s >= 1.0:
            return 0.0
        return 0.5 * self.height_m * (1.0 - math.cos(2.0 * math.pi * s))

    def flat_up_to_m(self):
        return self.start_x_m

    __call__ = height


@dataclasses.dataclass
class SampledProfile:
    """A measured profile: heights ``z_m`` at stations ``x_m`` (strictly increasing), linear in
    between, the end heights held outside. One profile across the road, or two tracks:
    ``z_right_m`` (same stations) for the right-hand half of the road (y < 0), ``z_m`` then for
    the left-hand half (y >= 0); empty: ``z_m`` across the whole road."""

    x_m: typing.List[float] = dataclasses.field(default_factory=lambda: [0.0, 1.0])
    z_m: typing.List[float] = dataclasses.field(default_factory=lambda: [0.0, 0.0])
    z_right_m: typing.List[float] = dataclasses.field(default_factory=list)

    def check(self):
        for name in ("x_m", "z_m", "z_right_m"):
            n = len(getattr(self, name))
            if n > MAX_ROAD_SAMPLES:
                raise ParameterError(name, f"{n} samples",
                                     f"is over the limit of {MAX_ROAD_SAMPLES} samples (about "
                                     f"{n * ROAD_SAMPLE_S:.0f} s and "
                                     f"{n * ROAD_SAMPLE_BYTES / 1e9:.1f} GB to load and settle "
                                     "[EST]); resample the profile more coarsely")
        x = list(self.x_m)
        tracks = {"z_m": list(self.z_m)}
        if len(self.z_right_m):
            tracks["z_right_m"] = list(self.z_right_m)
        for name, z in tracks.items():
            if len(x) < 2 or len(x) != len(z):
                raise ParameterError("x_m", f"{len(x)} samples",
                                     f"and {name} ({len(z)} samples) must be lists of the same "
                                     "length >= 2")
        for name, values in (("x_m", x), *tracks.items()):
            for i, value in enumerate(values):
                if not (isinstance(value, (int, float)) and math.isfinite(value)):
                    raise ParameterError(f"{name}[{i}]", value, "must be a finite number")
        for i in range(1, len(x)):
            if not x[i] > x[i - 1]:
                raise ParameterError(f"x_m[{i}]", x[i],
                                     f"must be > x_m[{i - 1}] = {x[i - 1]} (strictly "
                                     "increasing)")
        for name, z in tracks.items():
            for i in range(1, len(x)):
                slope = abs(z[i] - z[i - 1]) / (x[i] - x[i - 1])
                if slope > MAX_SLOPE:
                    raise ParameterError(f"{name}[{i}]", z[i],
                                         f"makes a slope of {slope:.2f} from sample {i - 1}; "
                                         f"slopes must be <= {MAX_SLOPE} (the tyre model takes "
                                         "the road normal as vertical)")
            if max(abs(v) for v in z) > MAX_HEIGHT_M:
                raise ParameterError(name, max(z, key=abs),
                                     f"must lie in [-{MAX_HEIGHT_M:g}, {MAX_HEIGHT_M:g}] m")
        return self

    def right_track(self):
        """The right-hand track's heights (``z_m`` when the road has one profile)."""
        return self.z_right_m if len(self.z_right_m) else self.z_m

    def height(self, x, y):
        # Arrays made at the first call (a profile is not changed once a simulation uses it).
        arrays = self.__dict__.get("_arrays")
        if arrays is None:
            arrays = tuple(np.asarray(v, dtype=float)
                           for v in (self.x_m, self.z_m, self.right_track()))
            self.__dict__["_arrays"] = arrays
        return float(np.interp(x, arrays[0], arrays[1] if y >= 0.0 else arrays[2]))

    def flat_up_to_m(self):
        if self.z_m[0] != 0.0 or self.right_track()[0] != 0.0:
            return -math.inf
        for i in range(1, len(self.x_m)):
            if self.z_m[i] != 0.0 or self.right_track()[i] != 0.0:
                return self.x_m[i - 1]
        return math.inf

    __call__ = height


ROAD_TYPES = (Flat, CosineBump, SampledProfile)
Road = typing.Union[Flat, CosineBump, SampledProfile]
