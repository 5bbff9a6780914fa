"""The paper's FRD friction law (Harlecki & Kubas, section 2.2 and 3; ADAMS "cylindrical joint
with friction"), as pure functions of scalars. No Drake here.

Per friction pair (translation along the strut axis, or rotation about it), with relative
velocity v, creep Δ (relative displacement accumulated in the static phase), coefficients
μs ≥ μd ≥ 0, threshold velocity Δv > 0 and maximum creep Δmax > 0:

Static phase, |v| ≤ Δv:   μ = -(1 - β) μ1 sgn(Δ) - β μs sgn(v)                         (1)
    β = β(|v|) rises from 0 at v = 0 to 1 at |v| = Δv;
    μ1 = μ1(|Δ|) rises from 0 at Δ = 0 to μs at |Δ| = Δmax and stays μs beyond.
    Shapes: "cubic" is ADAMS' STEP, s(x) = x²(3 - 2x); "linear" is s(x) = x (x clipped to [0, 1]).
Kinetic phase, |v| > Δv:  μ = -μk(|v|) sgn(v)                                            (2)
    μk = μs + (μd - μs) k²(3 - 2k), k = (|v| - Δv) / (0.5 Δv), for Δv < |v| < 1.5 Δv;
    μk = μd above 1.5 Δv.                                                                (3)
Normal force from the joint's transverse reaction force F and bending moment M:
    N = |M/d + F| + F0/μs       (paper's vector form, default)                            (4)
    N = |F| + |M|/d + F0/μs     (ADAMS documentation's magnitude sum, option)
    N = |F1| + |F2| + F0/μs     (option: the two contact forces at guide and piston that carry
                                 F and M, F1,2 = (F ∓ (2/d) û×M)/2; needs the axis û)
Friction force and moment:  F_fric = μ N  (5),   M_fric = μ_rot (N r + M0/μs)  (6).

A mirrored strut (``mirrored``): eq. (4)'s vector form adds a polar vector (F) to an axial one
(M), so it is not invariant under a reflection R: a mirror image's force is R·F but its moment
-R·M (det R = -1). Evaluated in one right-handed frame on both sides of a mirror-symmetric
car, it gives the left strut |M/d + F| and the right strut, in the left's terms, |F - M/d|: a
car whose right strut is not the mirror image of its left (measured on the paper's car at
rest: N 1413.81 N left, 1413.57 N right, 1.6e-4 of N, in a state symmetric to 3e-15 m; it
broke the mirror of the study's a and b runs). A strut that is the mirror image of a
reference strut is evaluated in the reference's reflected frame: its moment enters with the
opposite sign. The other two forms hold only |F|, |M| and û×M (a polar vector): the sign
leaves them unchanged, bit for bit.

Phases: static -> kinetic when |v| > Δv, and then the creep (so μ1) resets to 0; kinetic ->
static when |v| falls to Δv or below, and the creep accumulates again from 0.

Where this departs from or fills in the paper: the creep is the reversible pre-sliding
displacement and is bounded to |Δ| ≤ Δmax (motion beyond it, still at |v| ≤ Δv, is sliding that
does not build up further "memory"); μ1 saturates at μs there, as the paper states. sgn(0) = 0.
"""

import dataclasses
import math

from drake_car.law.checks import ParameterError, nonnegative, one_of, positive

STATIC = 0.0
KINETIC = 1.0

SHAPES = ("cubic", "linear")
NORMAL_FORCE_FORMS = ("vector", "magnitude_sum", "contact_pair")


@dataclasses.dataclass(frozen=True)
class FrictionPairLaw:
    """Parameters of one friction pair. ``dv`` in m/s (rad/s), ``dmax`` in m (rad). Made from
    checked ``StrutFrictionParameters`` (``translation()``, ``rotation()``), which check every
    value once, where the scene is loaded: this constructor trusts them."""

    mu_s: float
    mu_d: float
    dv: float = 1e-4
    dmax: float = 5e-6
    beta_shape: str = "cubic"
    creep_shape: str = "cubic"

    @property
    def lubricated(self):
        return self.mu_s == 0.0


def _sign(x):
    return 1.0 if x > 0 else (-1.0 if x < 0 else 0.0)


def shape(x, kind):
    """s(x) on [0, 1], clipped outside: cubic STEP x²(3 - 2x) or linear x."""
    x = min(max(x, 0.0), 1.0)
    return x * x * (3.0 - 2.0 * x) if kind == "cubic" else x


# A normal force no strut of a car reaches (N): 10^4 times a 1300 kg car's weight.
MAX_NORMAL_FORCE_N = 1e8


def shape_slope(x, kind):
    """ds/dx of ``shape`` at x: 6x(1 - x) for the cubic STEP, 1 for linear, on [0, 1); 0 outside
    (where the shape is clipped)."""
    if not 0.0 <= x < 1.0:
        return 0.0
    return 6.0 * x * (1.0 - x) if kind == "cubic" else 1.0


def shape_max_slope(kind):
    """max ds/dx of the shape: 1.5 for the cubic STEP, 1 for linear."""
    return 1.5 if kind == "cubic" else 1.0


def explicit_time_step_limit_s(mass, normal, law):
    """The law's own stability bound: the largest stable step of the ``reference`` (explicit)
    scheme on a pair of effective mass (or inertia) ``mass`` under the normal force ``normal`` (for a rotation pair: its moment
    scale N r), ``law`` a ``FrictionPairLaw``: the β term of eq. (1) is a damper whose largest
    slope is s'·μs·N/Δv (s' = 1.5 for the cubic STEP), and an explicit damper c on a mass m is
    stable for dt < 2m/c. Infinite when μs = 0."""
    slope = shape_max_slope(law.beta_shape) * law.mu_s * normal
    if slope <= 0:
        return math.inf
    return 2.0 * mass * law.dv / slope


def beta(speed, law: FrictionPairLaw):
    """β(|v|): 0 at rest, 1 at the threshold velocity Δv."""
    return shape(abs(speed) / law.dv, law.beta_shape)


def mu1(creep, law: FrictionPairLaw):
    """μ1(|Δ|): 0 at zero creep, μs at |Δ| ≥ Δmax."""
    return law.mu_s * shape(abs(creep) / law.dmax, law.creep_shape)


def mu_kinetic(speed, law: FrictionPairLaw):
    """Eq. (3): μs at |v| ≤ Δv, cubic blend down to μd at 1.5 Δv, μd above."""
    speed = abs(speed)
    if speed <= law.dv:
        return law.mu_s
    if speed >= 1.5 * law.dv:
        return law.mu_d
    k = (speed - law.dv) / (0.5 * law.dv)
    return law.mu_s + (law.mu_d - law.mu_s) * k * k * (3.0 - 2.0 * k)


def friction_coefficient(velocity, creep, law: FrictionPairLaw):
    """Signed μ of eqs. (1)-(3) and its parts: returns (mu, beta, mu1, phase).

    ``phase`` is STATIC for |v| ≤ Δv and KINETIC above; in the kinetic phase β = 1, μ1 = 0.
    """
    if abs(velocity) <= law.dv:
        b = beta(velocity, law)
        m1 = mu1(creep, law)
        mu = -(1.0 - b) * m1 * _sign(creep) - b * law.mu_s * _sign(velocity)
        return mu, b, m1, STATIC
    return -mu_kinetic(velocity, law) * _sign(velocity), 1.0, 0.0, KINETIC


def advance_creep(creep, phase, velocity, displacement, law: FrictionPairLaw):
    """Phase logic and creep accumulation over one step.

    ``velocity`` is the relative velocity at the end of the step, ``displacement`` the relative
    displacement over it. Returns (creep, phase) at the end of the step.
    """
    if abs(velocity) > law.dv:
        return 0.0, KINETIC
    if phase == KINETIC:  # re-entering the static phase: creep starts again from zero
        return 0.0, STATIC
    return min(max(creep + displacement, -law.dmax), law.dmax), STATIC


def normal_force(f_transverse, m_transverse, overlap, preload_force, mu_s, form="vector",
                 axis=None, mirrored=False):
    """Eq. (4). ``f_transverse`` and ``m_transverse`` are 3-vectors of the joint's reaction force
    and bending moment perpendicular to the joint axis, the moment taken about the middle of the
    overlap; ``overlap`` is d > 0 (m); ``axis`` the unit joint axis (for "contact_pair");
    ``mirrored``: the strut is the mirror image of a reference strut, eq. (4) is evaluated in the
    reference's reflected frame (the module's docstring says why). Returns N ≥ 0 (N)."""
    if not overlap > 0:
        raise ParameterError("overlap d", overlap, "must be > 0 (m)")
    preload = preload_force / mu_s if preload_force > 0 else 0.0
    fx, fy, fz = f_transverse
    mx, my, mz = m_transverse
    if mirrored:  # M is an axial vector: reflected, it changes sign against F
        mx, my, mz = -mx, -my, -mz
    if form == "vector":
        return math.sqrt((mx / overlap + fx) ** 2 + (my / overlap + fy) ** 2
                         + (mz / overlap + fz) ** 2) + preload
    if form == "magnitude_sum":
        return (math.sqrt(fx * fx + fy * fy + fz * fz)
                + math.sqrt(mx * mx + my * my + mz * mz) / overlap + preload)
    if form == "contact_pair":
        if axis is None:
            raise ValueError("normal-force form 'contact_pair' needs the joint axis")
        ux, uy, uz = axis
        k = 2.0 / overlap  # (2/d) û × M
        cx, cy, cz = k * (uy * mz - uz * my), k * (uz * mx - ux * mz), k * (ux * my - uy * mx)
        return 0.5 * (math.sqrt((fx - cx) ** 2 + (fy - cy) ** 2 + (fz - cz) ** 2)
                      + math.sqrt((fx + cx) ** 2 + (fy + cy) ** 2 + (fz + cz) ** 2)) + preload
    raise ParameterError("normal_force_form", form, f"must be one of {NORMAL_FORCE_FORMS}")


def friction_force(mu, normal):
    """Eq. (5): F_fric = μ N."""
    return mu * normal


def friction_moment(mu_rot, normal, rod_radius, preload_moment, mu_s):
    """Eq. (6): M_fric = μ_rot (N r + M0/μs)."""
    preload = preload_moment / mu_s if preload_moment > 0 else 0.0
    return mu_rot * (normal * rod_radius + preload)


@dataclasses.dataclass
class StrutFrictionParameters:
    """Both pairs of a cylindrical joint with friction (paper section 3): the law's parameters,
    loadable from a scene (``friction.law``). Paper values default, with the "practically
    realistic" dry set (μs, μd) = (0.2, 0.15). The rod radius r of eq. (6) is the strut's
    geometry, not the law's: the system takes it from the model. ``check()`` refuses a value
    out of range; a scene's load runs it once (the one place it is checked), and everything made
    from the parameters after (the pairs' laws, the systems) trusts them."""

    mu_s: float = 0.2
    mu_d: float = 0.15
    dv_translation_mps: float = 1e-4
    dmax_translation_m: float = 5e-6
    dv_rotation_radps: float = 1e-4
    dmax_rotation_rad: float = 5e-6
    beta_shape: str = "cubic"  # cubic (ADAMS STEP) | linear
    creep_shape: str = "cubic"  # cubic (ADAMS STEP) | linear
    preload_force_N: float = 0.0  # F0 of eq. (4)
    preload_moment_Nm: float = 0.0  # M0 of eq. (6)
    normal_force_form: str = "vector"  # vector (paper) | magnitude_sum (ADAMS) | contact_pair

    def check(self):
        """Raises ParameterError naming the first field out of range."""
        nonnegative(self, "mu_s", "mu_d", "preload_force_N", "preload_moment_Nm")
        positive(self, "dv_translation_mps", "dmax_translation_m", "dv_rotation_radps",
                 "dmax_rotation_rad")
        if self.mu_s > 2.0:
            raise ParameterError("mu_s", self.mu_s, "must be <= 2 (dry metal on metal is "
                                 "below 1; larger values are a typing error)")
        if self.mu_s < self.mu_d:
            raise ParameterError("mu_d", self.mu_d, f"must be <= mu_s = {self.mu_s}")
        one_of(self, "beta_shape", SHAPES)
        one_of(self, "creep_shape", SHAPES)
        one_of(self, "normal_force_form", NORMAL_FORCE_FORMS)
        # The fast scheme's PD gains per newton of normal force (law.friction.compiled):
        # slope / dv (damping) and slope mu_s / dmax (stiffness); times a normal force up to
        # MAX_NORMAL_FORCE_N they must stay below 1e308, finite (5e-324 made inf inside Drake).
        for name, shape, factor in (("dv_translation_mps", self.beta_shape, 1.0),
                                    ("dv_rotation_radps", self.beta_shape, 1.0),
                                    ("dmax_translation_m", self.creep_shape, self.mu_s),
                                    ("dmax_rotation_rad", self.creep_shape, self.mu_s)):
            value = getattr(self, name)
            slope = shape_max_slope(shape) * max(factor, 1.0)
            least = slope * MAX_NORMAL_FORCE_N / 1e308  # float's largest is 1.8e308
            if value < least:
                raise ParameterError(name, value,
                                     f"is too small: the PD gain it makes ({slope:g} / {name} "
                                     f"per newton, up to {MAX_NORMAL_FORCE_N:g} N) would not be "
                                     f"a finite number; it must be >= {least:.3g}")
        for name in ("preload_force_N", "preload_moment_Nm"):
            if getattr(self, name) > 0 and self.mu_s == 0:
                raise ParameterError(name, getattr(self, name),
                                     "must be 0 when mu_s = 0: eqs. (4) and (6) divide the "
                                     "preload by mu_s (a lubricated strut has no preload)")
        return self

    def translation(self):
        return FrictionPairLaw(self.mu_s, self.mu_d, self.dv_translation_mps,
                               self.dmax_translation_m, self.beta_shape, self.creep_shape)

    def rotation(self):
        return FrictionPairLaw(self.mu_s, self.mu_d, self.dv_rotation_radps,
                               self.dmax_rotation_rad, self.beta_shape, self.creep_shape)
