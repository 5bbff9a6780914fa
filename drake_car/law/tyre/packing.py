"""The arrays ``law.tyre.compiled`` reads: a tyre's coefficients, the tyre system's settings,
the road (kept apart from the compiled module, whose indices ``K`` and ``C`` they follow)."""

import numpy as np

from drake_car.law.road.profiles import CosineBump, Flat, SampledProfile
from drake_car.law.tyre.compiled import COEFFICIENTS, COSINE_BUMP, FLAT, SAMPLED


def pack_coefficients(tyre):
    """A ``MagicFormulaTyre``'s coefficients as the array the compiled formula reads."""
    return np.array([getattr(tyre, name) for name in COEFFICIENTS], dtype=float)


def pack_config(radial_tyre, slip, *, magic, linear, combined, relaxed, max_load, time_step,
                mirror):
    values = (radial_tyre.unloaded_radius_m, radial_tyre.radial_stiffness_Npm,
              radial_tyre.radial_damping_Nspm, magic, linear, combined, relaxed,
              slip.relaxation_length_long_m, slip.relaxation_length_lat_m, slip.v_floor_mps,
              slip.low_speed_mps, slip.low_speed_damping_Nspm, max_load, time_step, *mirror)
    return np.array(values, dtype=float)


def pack_road(road):
    """[kind, parameters...]: Flat [0]; CosineBump [1, start, length, height]; SampledProfile
    [2, n, x_1..x_n, z_1..z_n (y >= 0), z_1..z_n (y < 0)]."""
    if isinstance(road, Flat):
        return np.array([FLAT])
    if isinstance(road, CosineBump):
        return np.array([COSINE_BUMP, road.start_x_m, road.length_m, road.height_m], dtype=float)
    if isinstance(road, SampledProfile):
        return np.array([SAMPLED, len(road.x_m), *road.x_m, *road.z_m, *road.right_track()],
                        dtype=float)
    raise TypeError(f"the compiled tyre knows the roads Flat, CosineBump and SampledProfile, "
                    f"not {type(road).__name__}")
