"""The tyre's per-step maths compiled with numba: the Magic Formula, the radial contact, the slips
and one step of four wheels, line for line the pure-Python law of ``magic_formula``,
``law.tyre.contact``, ``law.tyre.slip`` and ``law.road.profiles`` (the reference;
``tests/test_compiled_law.py`` checks the two agree to round-off). No Drake here.

Why: these run every step for four wheels, where Python's per-call cost dominates (the Magic
Formula for four wheels: 26 µs as scalar Python, about 2 µs compiled). Everything compiled lives
in this one module: numba's on-disk cache (``cache=True``) is invalidated by a change of the
file holding the function only, not of the functions it calls, so a compiled caller must not
call into another module's compiled code. Arrays instead of objects (``law.tyre.packing``
makes them): the coefficients (indexed by ``K``), the settings (by ``C``), the road.
"""

import enum
import math

import numba
import numpy as np


# The coefficients the compiled formula reads (defined here, not imported: the cached code and
# its indices come from one file).
COEFFICIENTS = tuple("""
    UNLOADED_RADIUS FNOMIN LONGVL PCX1 PDX1 PDX2 PDX3 PEX1 PEX2 PEX3 PEX4 PKX1 PKX2 PKX3 PHX1
    PHX2 PVX1 PVX2 RBX1 RBX2 RBX3 RCX1 REX1 REX2 RHX1 PCY1 PDY1 PDY2 PDY3 PEY1 PEY2 PEY3 PEY4
    PEY5 PKY1 PKY2 PKY3 PKY4 PKY5 PKY6 PKY7 PHY1 PHY2 PHY3 PVY1 PVY2 PVY3 PVY4 RBY1 RBY2 RBY3
    RBY4 RCY1 REY1 REY2 RHY1 RHY2 RVY1 RVY2 RVY3 RVY4 RVY5 RVY6 QBZ1 QBZ2 QBZ3 QBZ4 QBZ5 QBZ6
    QBZ9 QBZ10 QCZ1 QDZ1 QDZ2 QDZ3 QDZ4 QDZ6 QDZ7 QDZ8 QDZ9 QDZ10 QDZ11 QEZ1 QEZ2 QEZ3 QEZ4 QEZ5
    QHZ1 QHZ2 QHZ3 QHZ4 SSZ1 SSZ2 SSZ3 SSZ4 QSY1 QSY2 QSY3 QSY4 QSY5 QSY6 QSY7 QSY8 PPX1 PPX2
    PPX3 PPX4 PPY1 PPY2 PPY3 PPY4 PPY5 PPZ1 PPZ2 LFZO LCX LMUX LEX LKX LHX LVX LCY LMUY LEY LKY
    LKYC LKZC LHY LVY LTR LRES LXAL LYKA LVYKA LS LMY LGAX LGAY LGAZ FORM DPI P_RATIO LMUX_S
    LMUY_S FZ0_S CLIP FZMIN FZMAX KPUMIN KPUMAX ALPMIN ALPMAX CAMMIN CAMMAX
""".split())  # the last 15: magic_formula.DERIVED
K = enum.IntEnum("K", {name: i for i, name in enumerate(COEFFICIENTS)})
# The tyre system's settings (``pack_config``); the flags are 0.0 or 1.0.
C = enum.IntEnum("C", {name: i for i, name in enumerate((
    "RADIUS", "STIFFNESS", "DAMPING", "MAGIC", "LINEAR", "COMBINED", "RELAXED",
    "SIGMA_KAPPA", "SIGMA_ALPHA", "V_FLOOR", "LOW_SPEED", "LOW_SPEED_DAMPING", "MAX_LOAD",
    "TIME_STEP", "MIRROR_FL", "MIRROR_FR", "MIRROR_RL", "MIRROR_RR"))})
FLAT, COSINE_BUMP, SAMPLED = 0.0, 1.0, 2.0
# Per wheel and step: the force and moment in the wheel's frame, the diagnostics
# (``systems.tyre.DIAGNOSTIC_FIELDS``).
WRENCH_PER_WHEEL, DIAGNOSTICS_PER_WHEEL = 6, 9


_jit = numba.njit(cache=True)


@_jit
def road_height(road, x, y):
    kind = road[0]
    if kind == FLAT:
        return 0.0
    if kind == COSINE_BUMP:
        s = (x - road[1]) / road[2]
        if s <= 0.0 or s >= 1.0:
            return 0.0
        return 0.5 * road[3] * (1.0 - math.cos(2.0 * math.pi * s))
    n = int(road[1])
    z = 2 + n if y >= 0.0 else 2 + 2 * n
    return np.interp(x, road[2:2 + n], road[z:z + n])


@_jit
def _sign(x):
    return 1.0 if x >= 0 else -1.0


@_jit
def _min1(x):  # Python's min(1.0, x)
    return x if x < 1.0 else 1.0


@_jit
def _mf(b, c, d, e, x):
    bx = b * x
    return d * math.sin(c * math.atan(bx - e * (bx - math.atan(bx))))


@_jit
def _mf_cos(b, c, d, e, x):
    bx = b * x
    return d * math.cos(c * math.atan(bx - e * (bx - math.atan(bx))))


@_jit
def _weight(b, c, e, x, shift):
    bu = b * (x + shift)
    g_x = math.cos(c * math.atan(bu - e * (bu - math.atan(bu))))
    bu = b * shift
    return g_x / math.cos(c * math.atan(bu - e * (bu - math.atan(bu))))


@_jit
def _lateral(t, fz, dfz, fz0, a, gs, gy):
    dpi = t[K.DPI]
    if t[K.FORM] == 0.0:
        ky = (t[K.PKY1] * fz0 * math.sin(t[K.PKY4] * math.atan(
            fz / ((t[K.PKY2] + t[K.PKY5] * gs * gs) * fz0)))
              / (1.0 + t[K.PKY3] * gs * gs) * t[K.LKY])
        muy = (t[K.PDY1] + t[K.PDY2] * dfz) / (1.0 + t[K.PDY3] * gs * gs) * t[K.LMUY]
    else:
        ky = (t[K.PKY1] * fz0 * (1.0 + t[K.PPY1] * dpi) * (1.0 - t[K.PKY3] * abs(gy))
              * math.sin(t[K.PKY4] * math.atan(fz / ((t[K.PKY2] + t[K.PKY5] * gy * gy)
                                                  * (1.0 + t[K.PPY2] * dpi) * fz0))) * t[K.LKY])
        muy = ((t[K.PDY1] + t[K.PDY2] * dfz) * (1.0 + t[K.PPY3] * dpi + t[K.PPY4] * dpi * dpi)
               * (1.0 - t[K.PDY3] * gy * gy) * t[K.LMUY])
    svyg = fz * (t[K.PVY3] + t[K.PVY4] * dfz) * gy * t[K.LKYC] * t[K.LMUY_S]
    svy = fz * (t[K.PVY1] + t[K.PVY2] * dfz) * t[K.LVY] * t[K.LMUY_S] + svyg
    shy = (t[K.PHY1] + t[K.PHY2] * dfz) * t[K.LHY]
    if t[K.FORM] == 1.0:
        shy += t[K.PHY3] * gy
    else:
        kyg = fz * (t[K.PKY6] + t[K.PKY7] * dfz) * (1.0 + t[K.PPY5] * dpi) * t[K.LKYC]
        shy += (kyg * gs - svyg) / ky if ky != 0 else 0.0
    ay = a + shy
    cy = t[K.PCY1] * t[K.LCY]
    dy = muy * fz
    ey = _min1((t[K.PEY1] + t[K.PEY2] * dfz)
             * (1.0 + t[K.PEY5] * gy * gy - (t[K.PEY3] + t[K.PEY4] * gy) * _sign(ay)) * t[K.LEY])
    by = ky / (cy * dy) if cy * dy != 0 else 0.0
    return _mf(by, cy, dy, ey, ay) + svy, ky, by, cy, muy, shy, svy


@_jit
def _rolling(t, fz, fx, gamma, vx):
    v = vx / t[K.LONGVL]
    bracket = t[K.QSY1] + t[K.QSY2] * fx / t[K.FZ0_S] + t[K.QSY3] * abs(v) + t[K.QSY4] * v ** 4.0
    if t[K.FORM] == 2.0:
        ratio = fz / t[K.FNOMIN]
        my = (-t[K.UNLOADED_RADIUS] * t[K.FNOMIN] * t[K.LMY]
              * (bracket + (t[K.QSY5] + t[K.QSY6] * ratio) * gamma * gamma)
              * ratio ** t[K.QSY7] * t[K.P_RATIO] ** t[K.QSY8])
    else:
        my = -t[K.UNLOADED_RADIUS] * fz * bracket * t[K.LMY]
    return my * math.tanh(vx / 0.1)  # smooth sign through standstill


@_jit
def magic_formula(t, fz, kappa, alpha, gamma, vx, combined):
    """``magic_formula.magic_formula`` on packed coefficients ``t``: returns (fx, fy, mz, my,
    fx0, fy0, cornering_stiffness, slip_stiffness, pneumatic_trail)."""
    if t[K.CLIP] != 0.0:
        fz = min(fz, t[K.FZMAX])
        kappa = min(max(kappa, t[K.KPUMIN]), t[K.KPUMAX])
        alpha = min(max(alpha, t[K.ALPMIN]), t[K.ALPMAX])
        gamma = min(max(gamma, t[K.CAMMIN]), t[K.CAMMAX])
    if fz <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    fz0 = t[K.FNOMIN] * t[K.LFZO]
    dfz = (fz - fz0) / fz0
    r0, dpi, form = t[K.UNLOADED_RADIUS], t[K.DPI], t[K.FORM]
    gs = math.sin(gamma)  # γ*
    a = alpha if form == 0.0 else math.tan(alpha)  # α* (4.E3)
    if form == 1.0:
        gx, gy, gz = gs * t[K.LGAX], gs * t[K.LGAY], gs * t[K.LGAZ]
    else:
        gx, gy, gz = (gamma if form == 0.0 else gs), gs, gs

    # Longitudinal, pure slip (4.E9-4.E18).
    shx = (t[K.PHX1] + t[K.PHX2] * dfz) * t[K.LHX]
    kx_ = kappa + shx
    cx = t[K.PCX1] * t[K.LCX]
    mux = ((t[K.PDX1] + t[K.PDX2] * dfz) * (1.0 + t[K.PPX3] * dpi + t[K.PPX4] * dpi * dpi)
           * (1.0 - t[K.PDX3] * gx * gx) * t[K.LMUX])
    dx = mux * fz
    ex = _min1((t[K.PEX1] + t[K.PEX2] * dfz + t[K.PEX3] * dfz * dfz)
             * (1.0 - t[K.PEX4] * _sign(kx_)) * t[K.LEX])
    kx = (fz * (t[K.PKX1] + t[K.PKX2] * dfz) * math.exp(t[K.PKX3] * dfz)
          * (1.0 + t[K.PPX1] * dpi + t[K.PPX2] * dpi * dpi) * t[K.LKX])
    bx = kx / (cx * dx) if cx * dx != 0 else 0.0
    svx = fz * (t[K.PVX1] + t[K.PVX2] * dfz) * t[K.LVX] * t[K.LMUX_S]
    fx0 = _mf(bx, cx, dx, ex, kx_) + svx

    # Lateral, pure slip (4.E19-4.E30).
    fy0, ky, by, cy, muy, shy, svy = _lateral(t, fz, dfz, fz0, a, gs, gy)
    # MF 6.x's aligning moment takes the side force without camber (4.E74).
    fy0_trail = _lateral(t, fz, dfz, fz0, a, 0.0, 0.0)[0] if form == 2.0 else fy0

    # Aligning moment, pure slip (4.E31-4.E49).
    sht = t[K.QHZ1] + t[K.QHZ2] * dfz + (t[K.QHZ3] + t[K.QHZ4] * dfz) * gz
    bt = ((t[K.QBZ1] + t[K.QBZ2] * dfz + t[K.QBZ3] * dfz * dfz)
          * (1.0 + t[K.QBZ4] * gz + t[K.QBZ5] * abs(gz) + t[K.QBZ6] * gz * gz)
          * t[K.LKY] / t[K.LMUY])
    ct = t[K.QCZ1]
    dt = (fz * (t[K.QDZ1] + t[K.QDZ2] * dfz) * (1.0 - t[K.PPZ1] * dpi)
          * (1.0 + t[K.QDZ3] * (abs(gz) if form == 0.0 else gz) + t[K.QDZ4] * gz * gz)
          * (r0 / fz0) * t[K.LTR])
    at = a + sht
    et = _min1((t[K.QEZ1] + t[K.QEZ2] * dfz + t[K.QEZ3] * dfz * dfz)
             * (1.0 + (t[K.QEZ4] + t[K.QEZ5] * gz) * (2.0 / math.pi) * math.atan(bt * ct * at)))
    shf = shy + (svy / ky if ky != 0 else 0.0)
    ar = a + shf
    br = t[K.QBZ9] * t[K.LKY] / t[K.LMUY] + t[K.QBZ10] * by * cy
    cos_a = math.cos(alpha)  # cos'α = V_cx/V_c
    dr = (fz * r0 * ((t[K.QDZ6] + t[K.QDZ7] * dfz) * t[K.LRES]
                     + ((t[K.QDZ8] + t[K.QDZ9] * dfz) * (1.0 + t[K.PPZ2] * dpi)
                        + (t[K.QDZ10] + t[K.QDZ11] * dfz) * abs(gz)) * gz * t[K.LKZC])
          * t[K.LMUY] * cos_a)

    if combined:
        # Combined slip (4.E50-4.E67).
        bxa = ((t[K.RBX1] + t[K.RBX3] * gs * gs) * math.cos(math.atan(t[K.RBX2] * kappa))
               * t[K.LXAL])
        exa = _min1(t[K.REX1] + t[K.REX2] * dfz)
        fx = _weight(bxa, t[K.RCX1], exa, a, t[K.RHX1]) * fx0
        shyk = t[K.RHY1] + t[K.RHY2] * dfz
        byk = ((t[K.RBY1] + t[K.RBY4] * gs * gs) * math.cos(math.atan(t[K.RBY2] * (a - t[K.RBY3])))
               * t[K.LYKA])
        eyk = _min1(t[K.REY1] + t[K.REY2] * dfz)
        dvyk = (muy * fz * (t[K.RVY1] + t[K.RVY2] * dfz + t[K.RVY3] * gy)
                * math.cos(math.atan(t[K.RVY4] * a)))
        svyk = dvyk * math.sin(t[K.RVY5] * math.atan(t[K.RVY6] * kappa)) * t[K.LVYKA]
        gyk = _weight(byk, t[K.RCY1], eyk, kappa, shyk)
        fy = gyk * fy0 + svyk
        ratio = (kx / ky) if ky != 0 else 0.0
        if form == 0.0:  # the book's 4.E77-4.E78
            at_eq = math.sqrt(at * at + (ratio * kappa) ** 2.0) * _sign(at)
            ar_eq = math.sqrt(ar * ar + (ratio * kappa) ** 2.0) * _sign(ar)
        else:  # the TNO solver's (Besselink et al. 2010, A54)
            at_eq = math.atan(math.sqrt(math.tan(at) ** 2 + (ratio * kappa) ** 2.0)) * _sign(at)
            ar_eq = math.atan(math.sqrt(math.tan(ar) ** 2 + (ratio * kappa) ** 2.0)) * _sign(ar)
        trail = _mf_cos(bt, ct, dt, et, at_eq) * cos_a
        mzr = dr * math.cos(math.atan(br * ar_eq))
        s = ((t[K.SSZ1] + t[K.SSZ2] * (fy / t[K.FZ0_S]) + (t[K.SSZ3] + t[K.SSZ4] * dfz) * gz)
             * r0 * t[K.LS])
        mz = -trail * gyk * fy0_trail + mzr + s * fx
    else:
        fx, fy = fx0, fy0
        trail = _mf_cos(bt, ct, dt, et, at) * cos_a
        mz = -trail * fy0_trail + dr * math.cos(math.atan(br * ar))
    my = _rolling(t, fz, fx, gamma, vx)
    return fx, fy, mz, my, fx0, fy0, ky, kx, trail


@_jit
def linear_tyre(t, fz, kappa, alpha, gamma, vx):
    """``magic_formula.linear_tyre`` on packed coefficients; returns as ``magic_formula``."""
    if t[K.CLIP] != 0.0:
        fz = min(fz, t[K.FZMAX])
        gamma = min(max(gamma, t[K.CAMMIN]), t[K.CAMMAX])
    f = magic_formula(t, fz, 0.0, 0.0, gamma, vx, False)
    fx = f[0] + f[7] * kappa
    fy = f[1] + f[6] * alpha
    my = _rolling(t, fz, fx, gamma, vx) if fz > 0.0 else 0.0
    mz = f[2] - f[8] * f[6] * alpha
    return fx, fy, mz, my, fx, fy, f[6], f[7], f[8]


@_jit
def relax(deflection, slip_velocity_term, speed, length, dt):
    """``law.tyre.slip.relax``."""
    rate = abs(speed) / length
    if rate * dt < 1e-9:
        return deflection + slip_velocity_term * dt
    decay = math.exp(-rate * dt)
    return deflection * decay + slip_velocity_term / rate * (1.0 - decay)


@_jit
def _deflection_rate(road, x, y, vx, vy, vz):
    """``systems.tyre``'s dδ/dt: the rate at which the road rises under the wheel, less v_z."""
    if road[0] == FLAT:
        return -vz
    eps = 1e-3
    dh_dx = (road_height(road, x + eps, y) - road_height(road, x - eps, y)) / (2 * eps)
    dh_dy = (road_height(road, x, y + eps) - road_height(road, x, y - eps)) / (2 * eps)
    return dh_dx * vx + dh_dy * vy - vz


@_jit
def tyre_step(frames, twists, wheels, relaxation, advance, config, coefficients, road, torques,
              driven, body, wrenches, loads, diagnostics):
    """One step of four wheels (``systems.tyre.TyreSystem``, which documents the model), from
    bodies' poses ``frames`` (n x 3 x 4, [R | p] in world) and ``twists`` (n x 6, [ω; v] in
    world), the wheels' at the rows ``wheels`` (fl, fr, rl, rr). ``relaxation`` (8: u_x, u_y
    per wheel) is advanced in place over the step when
    ``advance`` (the forces then use the advanced values). Writes ``wrenches``: per wheel the
    tyre's force and its moment about the wheel's origin, both in the wheel's frame
    (``WRENCH_PER_WHEEL``); then the drive ``torques`` (N m) about the spin axes of the wheels
    ``driven`` (wheel numbers; as given: the knuckles' share) and the moment reacting their sum
    on the body at row ``body``, in its frame. Writes ``loads`` (Fz of the four wheels, then
    their deflections) and ``diagnostics``. Returns -1, or the first wheel whose load exceeds
    the Magic Formula's range (the wrenches are then not all written)."""
    radius = config[C.RADIUS]
    magic = config[C.MAGIC] != 0.0
    for k in range(4):
        row = wheels[k]
        (r00, r01, r02, px), (r10, r11, r12, py), (r20, r21, r22, pz) = (
            frames[row, 0], frames[row, 1], frames[row, 2])
        wx, wy, wz, vx, vy, vz = twists[row]
        # The contact point (law.tyre.contact.contact_point; the spin axis a is the body y).
        ax, ay, az = r01, r11, r21
        dx, dy, dz = az * ax, az * ay, -1.0 + az * az
        norm = math.sqrt(dx * dx + dy * dy + dz * dz)
        if norm < 1e-9:
            x, y, ground, deflection = px, py, pz, 0.0
        else:
            dx, dy, dz = dx / norm, dy / norm, dz / norm
            x = px + radius * dx
            y = py + radius * dy
            z = pz + radius * dz
            ground = road_height(road, x, y)
            deflection = ground - z
            deflection = deflection if deflection > 0.0 else 0.0
        # The radial force (law.tyre.contact.radial_force).
        fz = 0.0
        if deflection > 0.0:
            fz = (config[C.STIFFNESS] * deflection
                  + config[C.DAMPING] * _deflection_rate(road, x, y, vx, vy, vz))
            fz = fz if fz > 0.0 else 0.0
        rx, ry, rz = x - px, y - py, ground - pz  # from the wheel's origin to the contact
        f_w = (0.0, 0.0, fz)  # force and moment at the contact, in world
        m_w = (0.0, 0.0, 0.0)
        loads[k], loads[4 + k] = fz, deflection
        d = diagnostics[DIAGNOSTICS_PER_WHEEL * k:DIAGNOSTICS_PER_WHEEL * (k + 1)]
        d[:] = 0.0
        d[2], d[8] = fz, deflection
        if magic:
            if fz > config[C.MAX_LOAD]:
                return k
            # The contact kinematics (law.tyre.slip.contact_kinematics).
            ex, ey = ay, -ax
            norm = math.hypot(ex, ey)
            if norm > 1e-9:
                ex, ey = ex / norm, ey / norm
            else:
                ex, ey = 1.0, 0.0
            clipped = az if az < 1.0 else 1.0  # Python's max(-1.0, min(1.0, a_z))
            gamma = math.asin(clipped if clipped > -1.0 else -1.0)
            mx = vx + wy * rz - wz * ry
            my = vy + wz * rx - wx * rz
            v_cx = vx * ex + vy * ey
            spin = wx * ax + wy * ay + wz * az
            v_sx = v_cx - spin * (radius - deflection / 3.0)
            v_sy = -mx * ey + my * ex
            # The slips: transient (relaxation, advanced first) or steady (law.tyre.slip).
            if config[C.RELAXED] != 0.0:
                if advance:
                    if fz <= 0.0:  # wheel off the road: the contact patch relaxes to zero
                        relaxation[2 * k] = relaxation[2 * k + 1] = 0.0
                    else:
                        relaxation[2 * k] = relax(relaxation[2 * k], -v_sx, v_cx,
                                                  config[C.SIGMA_KAPPA], config[C.TIME_STEP])
                        relaxation[2 * k + 1] = relax(relaxation[2 * k + 1], v_sy, v_cx,
                                                      config[C.SIGMA_ALPHA],
                                                      config[C.TIME_STEP])
                kappa = relaxation[2 * k] / config[C.SIGMA_KAPPA]
                alpha = math.atan(relaxation[2 * k + 1] / config[C.SIGMA_ALPHA])
            else:
                floor = config[C.V_FLOOR]
                speed = floor if floor > abs(v_cx) else abs(v_cx)
                kappa, alpha = -v_sx / speed, math.atan(v_sy / speed)
            mirror = config[C.MIRROR_FL + k]
            if config[C.LINEAR] != 0.0:
                f = linear_tyre(coefficients, fz, kappa, mirror * alpha, mirror * gamma, v_cx)
            else:
                f = magic_formula(coefficients, fz, kappa, mirror * alpha, mirror * gamma,
                                  v_cx, config[C.COMBINED] != 0.0)
            f_x, f_y, m_z, m_y = f[0], f[1], f[2], f[3]
            if mirror < 0:  # right-hand tyre: the data's lateral offsets mirrored
                f_y, m_z = -f_y, -m_z
            damping = 0.0
            if fz > 0:  # viscous contact damping faded in at low speed
                weight = 1.0 - abs(v_cx) / config[C.LOW_SPEED]
                damping = config[C.LOW_SPEED_DAMPING] * (weight if weight > 0.0 else 0.0)
            f_x = f_x - damping * v_sx
            f_y = f_y - damping * v_sy
            # F = fx e_x + fy e_y + fz n, M = Mz n + My e_y; e_x = (c, s, 0), e_y = (-s, c, 0).
            f_w = (f_x * ex - f_y * ey, f_x * ey + f_y * ex, fz)
            m_w = (-m_y * ey, m_y * ex, m_z)
            d[0], d[1], d[3], d[4], d[5], d[6], d[7] = f_x, f_y, m_z, kappa, alpha, gamma, v_cx
        # About the wheel's origin: M + r × F; both in the wheel's frame: R^T (.).
        m_o = (m_w[0] + ry * f_w[2] - rz * f_w[1], m_w[1] + rz * f_w[0] - rx * f_w[2],
               m_w[2] + rx * f_w[1] - ry * f_w[0])
        w = wrenches[WRENCH_PER_WHEEL * k:WRENCH_PER_WHEEL * (k + 1)]
        w[0] = r00 * f_w[0] + r10 * f_w[1] + r20 * f_w[2]
        w[1] = r01 * f_w[0] + r11 * f_w[1] + r21 * f_w[2]
        w[2] = r02 * f_w[0] + r12 * f_w[1] + r22 * f_w[2]
        w[3] = r00 * m_o[0] + r10 * m_o[1] + r20 * m_o[2]
        w[4] = r01 * m_o[0] + r11 * m_o[1] + r21 * m_o[2]
        w[5] = r02 * m_o[0] + r12 * m_o[1] + r22 * m_o[2]
    # Drive torques about the driven wheels' spin axes (the knuckles' share, as given), and
    # their sum reversed on the reacting body, in its frame.
    n = driven.shape[0]
    if n:
        total_x = total_y = total_z = 0.0
        for j in range(n):
            row = wheels[driven[j]]
            t = torques[j]
            wrenches[4 * WRENCH_PER_WHEEL + j] = t
            total_x = total_x + t * frames[row, 0, 1]
            total_y = total_y + t * frames[row, 1, 1]
            total_z = total_z + t * frames[row, 2, 1]
        r = frames[body]
        for i in range(3):
            wrenches[4 * WRENCH_PER_WHEEL + n + i] = -(
                r[0, i] * total_x + r[1, i] * total_y + r[2, i] * total_z)
    return -1
