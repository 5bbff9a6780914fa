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


def strut_geometry(front, side="left"):
    """The ``side`` front strut's geometry as ``friction_pairs.Strut`` takes it: the prismatic
    joint's child is the cylinder (the knuckle), its frame Jc at the guide, q the rod's
    extension s: the overlap is d = l - s, and the overlap's middle lies d/2 beyond Jc along the
    joint axis (a(q) = -l/2 + q/2 along the axis); the rod's radius r; the right strut
    ``mirrored`` (the left's mirror image: eq. 4 in the left's reflected frame,
    ``make_strut_friction``)."""
    length = front.guide_length_l_m
    return {"overlap_m": (length, -1.0), "moment_arm_offset_m": (-0.5 * length, 0.5),
            "rod_radius_m": front.rod_radius_r_m, "mirrored": SIDES[side] < 0}


def make_strut_friction(plant, car, declarations, law: StrutFrictionParameters, *, scheme,
                        extra_struts=()):
    """One StrutFriction for both front struts (and ``extra_struts`` after them: a hands-off
    column's pair), each of ``strut_geometry``.

    The right strut is the left's mirror image (``mirrored``): eq. (4)'s vector form adds the
    reaction's force (a polar vector) to its moment (an axial vector), so in one frame for both
    struts it gives the left |M/d + F| and the right, in the left's terms, |F - M/d|. That broke
    the mirror of the whole car: driving straight from a symmetric state, the
    struts' normal forces differed by 0.23 N of 1414 N at the first step, the rotation pairs
    then changed phase at different steps, and a_3's rods were 64 µm apart in the launch; case
    b of set 3 ended 3.5 mm away from case a mirrored. The left strut is the reference (its
    numbers are those of one frame, as before). What is left at 1 ms is the scheme's, not the
    car's: in the launch the rotation pairs reach the Stribeck band, where the fast scheme's
    lagged effort limit amplifies round-off about 30-fold per step (tests/test_mirror.py)."""
    struts = [Strut(pairs, side, **strut_geometry(car.params.front, side))
              for side, pairs in declarations.items()] + list(extra_struts)
    return StrutFriction(plant, struts, law, scheme=scheme, name="strut_friction")
