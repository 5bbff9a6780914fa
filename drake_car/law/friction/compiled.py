"""One step of the FRD friction law for a set of friction pairs, compiled with numba: line for
line ``law.friction.frd`` (the reference; ``tests/test_compiled_law.py`` checks the two agree to
round-off) and the per-step values of the schemes of ``systems.strut_friction`` (which
documents them). No Drake here.

Why: the law runs every step for every pair, where Python's per-call cost dominates. All the
compiled code lives in this one module (numba's on-disk cache is invalidated by a change of the
file holding a function only, not of the functions it calls). The pairs and struts are arrays,
one row each (``pack_pair``, ``pack_strut``; columns ``P`` and ``S``).
"""

import enum
import math

import numba
import numpy as np

from drake_car.law.friction.frd import NORMAL_FORCE_FORMS

# The friction phases, as ``law.friction.frd``'s (a test checks they are equal). Defined here, not
# imported: numba freezes the globals a compiled function reads into its on-disk cache, which
# is invalidated by a change of this file only, so an imported value could go stale there.
STATIC = 0.0
KINETIC = 1.0

P = enum.IntEnum("P", {name: i for i, name in enumerate((
    "MU_S", "MU_D", "DV", "DMAX", "BETA_CUBIC", "CREEP_CUBIC", "ROTATION", "STRUT", "Q_INDEX",
    "V_INDEX", "KD_UNIT", "KP_UNIT", "ROD_RADIUS", "PRELOAD_MOMENT", "STRUT_MU_S"))})
S = enum.IntEnum("S", {name: i for i, name in enumerate((
    "FROM_REACTION", "CONSTANT", "HAS_INITIAL", "INITIAL", "Q_INDEX", "OVERLAP_0", "OVERLAP_1",
    "OFFSET_0", "OFFSET_1", "AXIS_X", "AXIS_Y", "AXIS_Z", "PRELOAD_FORCE", "MU_S", "FORM",
    "MOMENT_SIGN"))})
# Floor on PD gains: Drake removes a controller whose gains are both zero.
MIN_GAIN = 1e-9
# Below this fraction of Δv the fast scheme's damping floor blends to the steeper branch (the
# velocity may change sign within the step); ``systems.strut_friction`` says why.
SLOW_FRACTION = 0.1


def pack_pair(law, strut_law, *, rotation, strut, q_index, v_index, rod_radius):
    """One pair's row: ``law`` its ``FrictionPairLaw``, ``strut_law`` its strut's
    ``StrutFrictionParameters``, ``strut`` the strut's row, ``q_index``/``v_index`` the
    joint's entries in the plant's state [q; v]."""
    row = np.zeros(len(P))
    row[P.MU_S], row[P.MU_D], row[P.DV], row[P.DMAX] = law.mu_s, law.mu_d, law.dv, law.dmax
    row[P.BETA_CUBIC] = law.beta_shape == "cubic"
    row[P.CREEP_CUBIC] = law.creep_shape == "cubic"
    row[P.ROTATION], row[P.STRUT], row[P.Q_INDEX], row[P.V_INDEX] = (
        rotation, strut, q_index, v_index)
    # The fast scheme's gains per unit of the pair's N-scale and of the law's slopes.
    row[P.KD_UNIT] = 1.0 / law.dv
    row[P.KP_UNIT] = law.mu_s / law.dmax
    row[P.ROD_RADIUS], row[P.PRELOAD_MOMENT], row[P.STRUT_MU_S] = (
        rod_radius, strut_law.preload_moment_Nm, strut_law.mu_s)
    return row


def pack_strut(strut_law, *, constant=None, initial=None, q_index=0, overlap=(0.0, 0.0),
               offset=(0.0, 0.0), axis=(0.0, 0.0, 1.0), mirrored=False):
    """One strut's row: its normal force ``constant``, or from its joint's reaction (then
    ``initial`` before the first step, if given; ``q_index`` the joint's position, ``overlap``
    and ``offset`` as ``friction_pairs.Strut``'s, ``axis`` the joint's unit axis, ``mirrored``
    as ``law.friction.frd.normal_force``'s: the moment's sign in eq. (4))."""
    row = np.zeros(len(S))
    row[S.FROM_REACTION] = constant is None
    row[S.CONSTANT] = 0.0 if constant is None else constant
    row[S.HAS_INITIAL] = initial is not None
    row[S.INITIAL] = 0.0 if initial is None else initial
    row[S.Q_INDEX] = q_index
    row[S.OVERLAP_0], row[S.OVERLAP_1] = overlap
    row[S.OFFSET_0], row[S.OFFSET_1] = offset
    row[S.AXIS_X], row[S.AXIS_Y], row[S.AXIS_Z] = axis
    row[S.PRELOAD_FORCE], row[S.MU_S] = strut_law.preload_force_N, strut_law.mu_s
    row[S.FORM] = NORMAL_FORCE_FORMS.index(strut_law.normal_force_form)
    row[S.MOMENT_SIGN] = -1.0 if mirrored else 1.0
    return row


_jit = numba.njit(cache=True)


@_jit
def _sign(x):
    return 1.0 if x > 0 else (-1.0 if x < 0 else 0.0)


@_jit
def shape(x, cubic):
    """``law.friction.frd.shape``."""
    x = 0.0 if 0.0 > x else x  # Python's min(max(x, 0.0), 1.0)
    x = 1.0 if 1.0 < x else x
    return x * x * (3.0 - 2.0 * x) if cubic else x


@_jit
def shape_slope(x, cubic):
    """``law.friction.frd.shape_slope``."""
    if not (0.0 <= x < 1.0):
        return 0.0
    return 6.0 * x * (1.0 - x) if cubic else 1.0


@_jit
def mu_kinetic(speed, mu_s, mu_d, dv):
    """``law.friction.frd.mu_kinetic``."""
    speed = abs(speed)
    if speed <= dv:
        return mu_s
    if speed >= 1.5 * dv:
        return mu_d
    k = (speed - dv) / (0.5 * dv)
    return mu_s + (mu_d - mu_s) * k * k * (3.0 - 2.0 * k)


@_jit
def friction_coefficient(velocity, creep, mu_s, mu_d, dv, dmax, beta_cubic, creep_cubic):
    """``law.friction.frd.friction_coefficient``: (mu, beta, mu1, phase)."""
    if abs(velocity) <= dv:
        b = shape(abs(velocity) / dv, beta_cubic)
        m1 = mu_s * shape(abs(creep) / dmax, creep_cubic)
        mu = -(1.0 - b) * m1 * _sign(creep) - b * mu_s * _sign(velocity)
        return mu, b, m1, STATIC
    return -mu_kinetic(velocity, mu_s, mu_d, dv) * _sign(velocity), 1.0, 0.0, KINETIC


@_jit
def advance_creep(creep, phase, velocity, displacement, dv, dmax):
    """``law.friction.frd.advance_creep``: (creep, phase)."""
    if abs(velocity) > dv:
        return 0.0, KINETIC
    if phase == KINETIC:
        return 0.0, STATIC
    creep = creep + displacement
    creep = -dmax if -dmax > creep else creep  # Python's min(max(c, -dmax), dmax)
    return (dmax if dmax < creep else creep), STATIC


@_jit
def normal_force(fx, fy, fz, mx, my, mz, overlap, preload_force, mu_s, form, ux, uy, uz):
    """``law.friction.frd.normal_force`` (``form``: the index in ``NORMAL_FORCE_FORMS``)."""
    preload = preload_force / mu_s if preload_force > 0 else 0.0
    if form == 0:
        return math.sqrt((mx / overlap + fx) ** 2 + (my / overlap + fy) ** 2
                         + (mz / overlap + fz) ** 2) + preload
    if form == 1:
        return (math.sqrt(fx * fx + fy * fy + fz * fz)
                + math.sqrt(mx * mx + my * my + mz * mz) / overlap + preload)
    k = 2.0 / overlap
    cx, cy, cz = k * (uy * mz - uz * my), k * (uz * mx - ux * mz), k * (ux * my - uy * mx)
    return 0.5 * (math.sqrt((fx - cx) ** 2 + (fy - cy) ** 2 + (fz - cz) ** 2)
                  + math.sqrt((fx + cx) ** 2 + (fy + cy) ** 2 + (fz + cz) ** 2)) + preload


@_jit
def friction_step(x, reactions, initial, fast, pairs, struts, memory, actuation, diagnostics,
                  desired, gains):
    """One step of ``systems.strut_friction.StrutFriction``: advances each pair's memory
    (``memory`` = [creep..., phase..., position at the last step...], in place) to the plant's
    state ``x`` and writes the friction, the fast scheme's PD targets ``desired`` ([q_d...,
    v_d...]) and ``gains`` ([Kp..., Kd..., effort limit...]), and the diagnostics.
    ``reactions``: per strut the coefficients [m; f] of its joint's reaction (Drake's
    SpatialForce). ``initial``: the step before the first (struts
    with an initial normal force use it). Returns -1, or the first strut whose overlap is not
    positive (nothing is then written)."""
    n_struts = struts.shape[0]
    normals = np.empty(n_struts)
    for s in range(n_struts):
        strut = struts[s]
        if strut[S.FROM_REACTION] == 0.0:
            normals[s] = strut[S.CONSTANT]
            continue
        if initial and strut[S.HAS_INITIAL] != 0.0:
            normals[s] = strut[S.INITIAL]
            continue
        q = x[int(strut[S.Q_INDEX])]
        overlap = strut[S.OVERLAP_0] + strut[S.OVERLAP_1] * q
        if not overlap > 0:
            return s
        mx, my, mz, fx, fy, fz = reactions[s]
        ux, uy, uz = strut[S.AXIS_X], strut[S.AXIS_Y], strut[S.AXIS_Z]
        offset = strut[S.OFFSET_0] + strut[S.OFFSET_1] * q
        mx += offset * (uy * fz - uz * fy)
        my += offset * (uz * fx - ux * fz)
        mz += offset * (ux * fy - uy * fx)
        # A mirrored strut: eq. (4) in the reference strut's reflected frame (law.friction.frd).
        sign = strut[S.MOMENT_SIGN]
        mx, my, mz = sign * mx, sign * my, sign * mz
        f_axial = fx * ux + fy * uy + fz * uz
        m_axial = mx * ux + my * uy + mz * uz
        normals[s] = normal_force(fx - f_axial * ux, fy - f_axial * uy, fz - f_axial * uz,
                                  mx - m_axial * ux, my - m_axial * uy, mz - m_axial * uz,
                                  overlap, strut[S.PRELOAD_FORCE], strut[S.MU_S],
                                  int(strut[S.FORM]), ux, uy, uz)
    n = pairs.shape[0]
    creep, phase, last_q = memory[:n], memory[n:2 * n], memory[2 * n:]
    kp, kd, effort = gains[:n], gains[n:2 * n], gains[2 * n:]
    for i in range(n):
        pair = pairs[i]
        normal = normals[int(pair[P.STRUT])]
        mu_s, dv, dmax = pair[P.MU_S], pair[P.DV], pair[P.DMAX]
        q = x[int(pair[P.Q_INDEX])]
        v = x[int(pair[P.V_INDEX])]
        creep[i], phase[i] = advance_creep(creep[i], phase[i], v, q - last_q[i], dv, dmax)
        last_q[i] = q
        mu, beta, mu1, _ = friction_coefficient(v, creep[i], mu_s, pair[P.MU_D], dv, dmax,
                                                pair[P.BETA_CUBIC] != 0.0,
                                                pair[P.CREEP_CUBIC] != 0.0)
        # What μ multiplies: N for the translation pair (eq. 5), N r + M0/μs for the rotation
        # pair (eq. 6): law.friction.frd.friction_force / friction_moment at μ = 1.
        if pair[P.ROTATION] != 0.0:
            preload = (pair[P.PRELOAD_MOMENT] / pair[P.STRUT_MU_S]
                       if pair[P.PRELOAD_MOMENT] > 0 else 0.0)
            scale = 1.0 * (normal * pair[P.ROD_RADIUS] + preload)
        else:
            scale = 1.0 * normal
        force = mu * scale
        d = diagnostics[8 * i:8 * (i + 1)]
        d[0], d[1], d[2], d[3], d[4], d[5], d[6], d[7] = (v, creep[i], beta, mu1, mu,
                                                          phase[i], normal, force)
        actuation[i] = force
        if not fast:
            continue
        # The fast scheme (systems.strut_friction: the law's tangent, its damping slope
        # floored by the secant of the branch the velocity is on).
        beta_cubic = pair[P.BETA_CUBIC] != 0.0
        desired[i], desired[n + i] = q, 0.0
        if phase[i] == STATIC:
            desired[n + i] = v
            x_v = abs(v) / dv
            with_creep = v == 0.0 or creep[i] == 0.0 or (v > 0.0) == (creep[i] > 0.0)
            branch = mu_s - mu1 if with_creep else mu_s + mu1
            weight = 1.0 - x_v / SLOW_FRACTION
            weight = 0.0 if 0.0 > weight else weight
            secant = branch + (mu_s + mu1 - branch) * weight
            tangent = shape_slope(x_v, beta_cubic) * branch
            gain = (tangent if tangent > secant else secant) * pair[P.KD_UNIT] * scale
            kd[i] = MIN_GAIN if MIN_GAIN > gain else gain
            gain = ((1.0 - beta) * shape_slope(abs(creep[i]) / dmax, pair[P.CREEP_CUBIC] != 0.0)
                    * pair[P.KP_UNIT] * scale)
            kp[i] = MIN_GAIN if MIN_GAIN > gain else gain
            limit = mu_s * scale
        else:
            actuation[i] = 0.0
            gain = (1.5 if beta_cubic else 1.0) * mu_s * pair[P.KD_UNIT] * scale
            kd[i] = MIN_GAIN if MIN_GAIN > gain else gain
            kp[i] = MIN_GAIN
            limit = mu_kinetic(v, mu_s, pair[P.MU_D], dv) * scale
        effort[i] = MIN_GAIN if MIN_GAIN > limit else limit
    return -1
