"""Where a wheel touches the road, and the tyre's radial force there (pure Python, no Drake).

The tyre is a rigid rim of radius R0 with a radial spring-damper at one contact point: the point
of the wheel's mid-plane circle that lies deepest below the road (for a flat road, the point of
the circle in the direction of -z projected onto the wheel plane). The road is given as a height
function z = h(x, y); its local normal is taken as +z (road slopes are small).
"""

import dataclasses
import math



@dataclasses.dataclass(frozen=True)
class RadialTyre:
    unloaded_radius_m: float
    radial_stiffness_Npm: float
    radial_damping_Nspm: float

    def __post_init__(self):
        for name in ("unloaded_radius_m", "radial_stiffness_Npm"):
            if not getattr(self, name) > 0:
                raise ValueError(f"tyre {name} = {getattr(self, name)} must be > 0")
        if not self.radial_damping_Nspm >= 0:
            raise ValueError(f"tyre radial_damping_Nspm = {self.radial_damping_Nspm} must be >= 0")


def vertical_from_file(tyre):
    """(radial stiffness N/m, radial damping N s/m) of a tyre property file (a
    ``magic_formula.MagicFormulaTyre``): VERTICAL_STIFFNESS and VERTICAL_DAMPING, the stiffness
    of an MF 6.x file times (1 + PFZ1 dpi) at its pressure (the MF-Tyre 6.1 vertical stiffness's
    pressure term; Pacejka and Besselink 2012, appendix 3, eq. A3.5 as TyreDyn cites it; PFZ1
    absent: 0). Raises ValueError naming the file and the key it lacks."""
    missing = [k for k in ("VERTICAL_STIFFNESS", "VERTICAL_DAMPING") if not hasattr(tyre, k)]
    if missing:
        raise ValueError(f"{tyre.name} has no {' and no '.join(missing)}")
    stiffness = tyre.VERTICAL_STIFFNESS
    if tyre.form in ("MF 6.1", "MF 6.2"):
        stiffness *= 1.0 + getattr(tyre, "PFZ1", 0.0) * tyre.DPI
    if not (stiffness > 0 and tyre.VERTICAL_DAMPING >= 0):
        raise ValueError(f"{tyre.name}: VERTICAL_STIFFNESS {stiffness:g} N/m must be > 0 and "
                         f"VERTICAL_DAMPING {tyre.VERTICAL_DAMPING:g} N s/m >= 0")
    return stiffness, tyre.VERTICAL_DAMPING


def contact_point(centre, spin_axis, radius, road_height):
    """Lowest point of the wheel circle and the tyre's deflection there.

    Returns (p_contact on the road surface, deflection >= 0, radial unit vector from the centre
    towards the contact), the vectors as 3-tuples. ``spin_axis`` is a unit vector,
    ``road_height(x, y)`` a callable. Written out in scalars: this runs four times per step.
    """
    ax, ay, az = float(spin_axis[0]), float(spin_axis[1]), float(spin_axis[2])
    # -z projected onto the wheel plane: (0, 0, -1) + a_z a
    dx, dy, dz = az * ax, az * ay, -1.0 + az * az
    norm = math.sqrt(dx * dx + dy * dy + dz * dz)
    if norm < 1e-9:  # wheel lying flat: no rolling contact defined
        return (float(centre[0]), float(centre[1]), float(centre[2])), 0.0, (0.0, 0.0, -1.0)
    dx, dy, dz = dx / norm, dy / norm, dz / norm
    x = float(centre[0]) + radius * dx
    y = float(centre[1]) + radius * dy
    z = float(centre[2]) + radius * dz
    ground = road_height(x, y)
    deflection = max(0.0, ground - z)
    return (x, y, ground), deflection, (dx, dy, dz)


def radial_force(tyre: RadialTyre, deflection, deflection_rate):
    """Vertical load Fz >= 0 (N): spring plus damper, never pulling the wheel down."""
    if deflection <= 0.0:
        return 0.0
    return max(0.0, tyre.radial_stiffness_Npm * deflection
               + tyre.radial_damping_Nspm * deflection_rate)

