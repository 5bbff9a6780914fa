"""Tyre kinematics and transient slip (pure Python): from a wheel's motion to κ, α, γ.

The contact frame at a wheel: e_x = heading (spin axis × road normal), e_y = n × e_x, n = road
normal (+z). Slip velocities of the contact patch: V_sx = V_cx - Ω R_e (R_e the effective
rolling radius), V_sy = lateral velocity of the wheel's material point at the contact.

Transient slip (first-order relaxation, Pacejka 2006 section 7.2): contact-patch deflections
u_x, u_y with
    du_x/dt = -V_sx - |V_cx| u_x / σκ,   κ' = u_x / σκ,
    du_y/dt =  V_sy - |V_cx| u_y / σα,   tan α' = u_y / σα,
integrated exactly over a step with the slip velocities held (the update itself is stable at
any step; coupled to the wheels, whose spin it acts on explicitly, it needs the step limit of
``explicit_time_step_limit_s``; at standstill the deflections act as springs). Without relaxation, the steady
slips κ = -V_sx/|V_cx|, tan α = V_sy/|V_cx| are used, with |V_cx| floored at ``v_floor``.
"""

import dataclasses
import math

from drake_car.law.checks import ParameterError, nonnegative, positive



@dataclasses.dataclass
class SlipOptions:
    """How slips are formed (loadable: a scene's ``tyres.slip``)."""

    # [EST] relaxation lengths of a 205/60R15 passenger tyre at nominal load: Pacejka (2006)
    # gives σα of the order of the tyre radius to twice it and σκ several times shorter.
    relaxation_length_long_m: float = 0.15
    relaxation_length_lat_m: float = 0.45
    relaxation: bool = True
    # Take the relaxation lengths from the tyre file's PTX*/PTY* (PAC2002) at the car's wheel
    # load at rest instead of the two above.
    relaxation_lengths_from_file: bool = False
    # Without relaxation, the steady-state slips use this speed as the smallest denominator.
    v_floor_mps: float = 1.0
    # Viscous contact damping faded in below ``low_speed_mps`` (damps the standstill springs).
    low_speed_mps: float = 1.0
    low_speed_damping_Nspm: float = 1500.0

    def check(self):
        positive(self, "relaxation_length_long_m", "relaxation_length_lat_m", "v_floor_mps",
                 "low_speed_mps")
        nonnegative(self, "low_speed_damping_Nspm")
        for name in ("relaxation_length_long_m", "relaxation_length_lat_m"):
            if getattr(self, name) > 5.0:
                raise ParameterError(name, getattr(self, name),
                                     "must be <= 5 m (a passenger tyre relaxes within a few "
                                     "tyre radii)")
        return self



def explicit_time_step_limit_s(slip_stiffness_N, slip: SlipOptions, relaxation_length_long_m,
                               radius_m, spin_inertia_kgm2):
    """The largest stable step of the tyres' horizontal forces, which act on the wheels' spin
    explicitly: the low-speed damping c needs dt < 2 I / (c R²), and with relaxation the contact
    patch's longitudinal spring K_x/σκ (K_x the slip stiffness ``slip_stiffness_N``) needs
    dt < 2/ω, ω = R sqrt(K_x / (σκ I)). Infinite when neither acts."""
    limits = []
    if slip.low_speed_damping_Nspm > 0:
        limits.append(2 * spin_inertia_kgm2 / (slip.low_speed_damping_Nspm * radius_m ** 2))
    if slip.relaxation:
        omega = radius_m * (slip_stiffness_N / (relaxation_length_long_m
                                                * spin_inertia_kgm2)) ** 0.5
        limits.append(2.0 / omega)
    return min(limits) if limits else math.inf

@dataclasses.dataclass
class ContactKinematics:
    e_x: tuple  # unit heading, horizontal: (x, y, 0)
    e_y: tuple  # unit lateral, horizontal: (x, y, 0)
    gamma: float  # ISO inclination: rotation about e_x, positive with the top leaning right
    v_cx: float  # forward speed of the wheel centre (m/s)
    v_sx: float  # longitudinal slip velocity (m/s)
    v_sy: float  # lateral slip velocity of the contact (m/s)


def contact_kinematics(spin_axis, centre, velocity, angular_velocity, contact,
                       rolling_radius):
    """Contact frame, inclination and slip velocities of one wheel (all vectors in world).
    Written out in scalars: this runs four times per step."""
    ax, ay, az = float(spin_axis[0]), float(spin_axis[1]), float(spin_axis[2])
    # e_x = a × n with n = +z; e_y = n × e_x.
    ex, ey = ay, -ax
    norm = math.hypot(ex, ey)
    if norm > 1e-9:
        ex, ey = ex / norm, ey / norm
    else:
        ex, ey = 1.0, 0.0
    e_x = (ex, ey, 0.0)
    e_y = (-ey, ex, 0.0)
    gamma = math.asin(max(-1.0, min(1.0, az)))
    vx, vy = float(velocity[0]), float(velocity[1])
    wx, wy, wz = (float(angular_velocity[0]), float(angular_velocity[1]),
                  float(angular_velocity[2]))
    rx, ry, rz = (float(contact[0] - centre[0]), float(contact[1] - centre[1]),
                  float(contact[2] - centre[2]))
    # material point velocity v + ω × r, projected on e_y
    mx = vx + wy * rz - wz * ry
    my = vy + wz * rx - wx * rz
    v_cx = vx * ex + vy * ey
    spin = wx * ax + wy * ay + wz * az
    return ContactKinematics(e_x, e_y, gamma, v_cx, v_cx - spin * rolling_radius,
                             -mx * ey + my * ex)


def relax(deflection, slip_velocity_term, speed, length, dt):
    """Exact step of du/dt = s - (|V|/σ) u with s held: returns u(t + dt)."""
    rate = abs(speed) / length
    if rate * dt < 1e-9:
        return deflection + slip_velocity_term * dt
    decay = math.exp(-rate * dt)
    return deflection * decay + slip_velocity_term / rate * (1.0 - decay)


def steady_slips(kin: ContactKinematics, options: SlipOptions):
    speed = max(abs(kin.v_cx), options.v_floor_mps)
    return -kin.v_sx / speed, math.atan(kin.v_sy / speed)


def transient_slips(u_x, u_y, options: SlipOptions):
    return (u_x / options.relaxation_length_long_m,
            math.atan(u_y / options.relaxation_length_lat_m))


def low_speed_weight(v_cx, options: SlipOptions):
    """1 at standstill, fading linearly to 0 at ``low_speed_mps``."""
    return max(0.0, 1.0 - abs(v_cx) / options.low_speed_mps)
