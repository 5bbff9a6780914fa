"""The car's strut friction: both front struts' cylindrical pairs with the FRD law, wired to the
car's joints and strut geometry (the generic system is ``systems.strut_friction``)."""

from drake_car.law.friction.frd import StrutFrictionParameters, explicit_time_step_limit_s
from drake_car.model.geometry import SIDES, design_axle_loads_N
from drake_car.systems.friction_pairs import Strut, declare_pairs
from drake_car.systems.strut_friction import StrutFriction

# [EST] the strut's normal force at rest as a share of the front corner's design load: 1.39 kN
# of 3.8 kN (0.37) measured on the default car (b = 80 mm); 0.4 bounds it.
NORMAL_FORCE_AT_REST_SHARE = 0.4


def strut_effective_mass_kg(params):
    """The mass the strut's sliding pair moves against the body: knuckle, wheel and half the
    lower arm (the arm pivots on the body)."""
    m = params.mass
    return m.front_knuckle_kg + m.front_wheel_kg + 0.5 * m.front_lower_arm_kg


def reference_time_step_limit_s(params, law: StrutFrictionParameters):
    """The explicit (reference) scheme's largest stable step on this car
    (the law's ``law.friction.frd.explicit_time_step_limit_s`` with the strut's effective mass and
    its normal force at rest, ``NORMAL_FORCE_AT_REST_SHARE`` of the corner load). Measured on
    the default car with μs = 0.4: 5 µs converges, 10 µs does not (limit 6.5 µs)."""
    normal = NORMAL_FORCE_AT_REST_SHARE * design_axle_loads_N(params)["front"] / 2
    return explicit_time_step_limit_s(strut_effective_mass_kg(params), normal, law.translation())


def declare_strut_friction(plant, car, *, rotation, scheme):
    """Adds each front strut's friction actuators to ``plant`` (before Finalize); returns
    side -> list of FrictionPair."""
    declarations = {}
    for side in SIDES:
        prismatic, revolute = car.strut_joints(side)
        declarations[side] = declare_pairs(plant, prismatic, revolute if rotation else None,
                                           scheme, prefix=f"strut_friction_{side}")
    return declarations


def strut_geometry(front):
    """A front strut's geometry as ``friction_pairs.Strut`` takes it: the prismatic joint's
    child is the cylinder (the knuckle), its frame Jc at the guide, q the rod's extension s:
    the overlap is d = l - s, and the overlap's middle lies d/2 beyond Jc along the joint axis
    (a(q) = -l/2 + q/2 along the axis); the rod's radius r."""
    length = front.guide_length_l_m
    return {"overlap_m": (length, -1.0), "moment_arm_offset_m": (-0.5 * length, 0.5),
            "rod_radius_m": front.rod_radius_r_m}


def make_strut_friction(plant, car, declarations, law: StrutFrictionParameters, *, scheme,
                        extra_struts=()):
    """One StrutFriction for both front struts (and ``extra_struts`` after them: a hands-off
    column's pair), each of ``strut_geometry``."""
    geometry = strut_geometry(car.params.front)
    struts = [Strut(pairs, side, **geometry)
              for side, pairs in declarations.items()] + list(extra_struts)
    return StrutFriction(plant, struts, law, scheme=scheme, name="strut_friction")
