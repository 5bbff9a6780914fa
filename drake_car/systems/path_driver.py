"""A driver that follows a path: path preview on the steering, a speed controller on the drive
(the closed-loop driver of Adams/Car's driving machine and Chrono's path follower, in its
simplest form). A generic LeafSystem: it reads a vehicle's planar motion and writes a rack
position and a drive torque; it knows no car (the car-specific numbers come in its laws).

Steering: single-point preview on the path's tangent (the linearised form of "the lateral
offset of a point ``preview_m`` ahead"; Chrono's ``ChPathSteeringController`` takes the
offset of such a point from the path itself). With the car's station s on the path, its
lateral offset e (left +) and heading error e_ψ = χ - ψ_path(s), χ = ψ + β the direction the
reference point travels (the body's yaw ψ plus the sideslip β there, blended in between
``COURSE_SPEEDS_MPS``: at a crawl the sideslip is not defined; Chrono's XT controller also
switches to the velocity's direction once the car moves):

    e_L = e + L sin e_ψ                        the offset of the point L ahead, from the tangent
    δ   = l κ(s) - k e_L                       road-wheel angle: curvature feed-forward plus
                                               preview feedback
    rack = clip(c δ, ±rack limit)              c: rack travel per road-wheel angle

Why this and not pure pursuit or the point's offset from the path itself: on a circle the
point L ahead along the heading lies L²/(2R) outside the path, so a law on that offset cuts
every corner by about that much (0.6 m for L = 10 m, R = 40 m) unless its gain is tuned to the
radius; measured from the tangent, e_L is zero whenever the car is on the path and travels
along it, so the curvature feed-forward l κ (the Ackermann angle) holds a circle exactly for a
neutral-steer car and the feedback only corrects. Pure pursuit has the same chord error.

The gain from the preview (``preview_gain_rad_per_m``): a neutral-steer kinematic car at speed
u on a straight path, y' = u ψ, ψ' = u δ / l, with δ = -k (y + L ψ), has the characteristic
polynomial s² + (u k L / l) s + u² k / l: ω_n = u sqrt(k / l), ζ = (L / 2) sqrt(k / l), so
k = 4 ζ² l / L² gives the damping ratio ζ at every speed (ω_n = 2 ζ u / L). Understeer lowers
the yaw gain by η = 1 + K u² / (g l) (K the understeer gradient, rad per g): ω_n and ζ both
fall by sqrt(η). A path is then held with a residual offset of about K a_y / (g k).

Speed (``SpeedLaw``): a PI controller on the drive torque, T = K_v (e_v + (1/T_i) ∫ e_v),
clamped to ±``max_torque_Nm``, the integral held while the clamp acts (no wind-up). For a car of
effective mass m (the wheels' spin inertia included) on driven wheels of rolling radius R,
m v' = T / R - F_resist: K_v = m R / τ makes the proportional loop a first-order lag τ, and
T_i = 4 τ makes the PI loop critically damped (s² + s/τ + 1/(τ T_i)); the integral cancels
the rolling resistance (``speed_gains``).

Sampling: the driver updates every ``period_s`` (a driving machine's controller rate; a human
driver's reaction time is longer) and holds its commands in between.
"""

import dataclasses
import math

import numpy as np
from pydrake.systems.framework import LeafSystem

# The columns of the motion input the driver reads (any others are ignored).
MOTION_NEEDS = ("x_m", "y_m", "yaw_rad", "speed_mps", "sideslip_rad")
# Below the first speed the heading error is the body's, above the second the direction of
# travel's, linear in between (m/s) [EST: the sideslip at the reference point settles once the
# tyres roll; Chrono's XT controller switches at 1 m/s].
COURSE_SPEEDS_MPS = (1.0, 3.0)
# What the ``tracking`` output holds.
TRACKING_COLUMNS = ("station_m", "offset_m", "heading_error_rad")


@dataclasses.dataclass(frozen=True)
class SteeringLaw:
    """Path preview in rack units: ``preview_m`` L, ``gain_rad_per_m`` k (road-wheel angle per
    metre of e_L), ``wheelbase_m`` l (the curvature feed-forward), ``rack_per_steer_m_per_rad``
    c (rack travel per road-wheel angle at centre, sign included: the car's steering linkage)
    and ``rack_limit_m`` (the rack's stroke)."""

    preview_m: float
    gain_rad_per_m: float
    wheelbase_m: float
    rack_per_steer_m_per_rad: float
    rack_limit_m: float


@dataclasses.dataclass(frozen=True)
class SpeedLaw:
    """Hold ``target_mps`` with a PI on the drive torque (module docstring)."""

    target_mps: float
    gain_Nm_per_mps: float
    integral_time_s: float
    max_torque_Nm: float


def preview_gain_rad_per_m(preview_m, wheelbase_m, damping_ratio=1.0):
    """k = 4 ζ² l / L²: the preview gain giving a neutral-steer car the damping ratio ζ."""
    return 4.0 * damping_ratio ** 2 * wheelbase_m / preview_m ** 2


def speed_gains(mass_kg, radius_m, time_constant_s):
    """(K_v, T_i) = (m R / τ, 4 τ): a first-order lag τ for the proportional loop, critical
    damping with the integral."""
    return mass_kg * radius_m / time_constant_s, 4.0 * time_constant_s


class PathDriver(LeafSystem):
    """Follows ``line`` (``law.road.centre_line.CentreLine``) with ``steering`` and, when
    ``speed`` is given, holds a speed with the drive torque.

    .. pydrake_system::

        name: PathDriver
        input_ports:
        - chassis_motion
        output_ports:
        - rack_position_m
        - drive_torque_Nm (with a speed law)
        - tracking

    ``chassis_motion``: a vector whose entries are named by ``motion_columns``; the driver
    reads x_m, y_m (the reference point's position, m), yaw_rad (heading, rad), speed_mps
    (horizontal speed, m/s) and sideslip_rad (the angle from the heading to the reference
    point's velocity, rad). ``rack_position_m``: the rack's commanded position (m, left +: a
    left turn). ``drive_torque_Nm``: the total drive torque at the driven wheels (N m).
    ``tracking``: station along the path (m), lateral offset from it (m, left +), heading
    error (rad) at the last update.
    """

    def __init__(self, line, steering: SteeringLaw, *, motion_columns, period_s=0.01,
                 speed: SpeedLaw | None = None):
        super().__init__()
        missing = [c for c in MOTION_NEEDS if c not in motion_columns]
        if missing:
            raise ValueError(f"PathDriver: motion_columns lacks {missing}")
        if not period_s > 0:
            raise ValueError(f"PathDriver: period_s = {period_s} must be > 0")
        self._line, self._steering, self._speed = line, steering, speed
        self._period = period_s
        self._read = [list(motion_columns).index(c) for c in MOTION_NEEDS]
        self._motion_port = self.DeclareVectorInputPort("chassis_motion", len(motion_columns))
        self._rack = self.DeclareDiscreteState(1)
        self._tracking = self.DeclareDiscreteState(len(TRACKING_COLUMNS))
        self._integral = self.DeclareDiscreteState(1)  # ∫ e_v dt (m)
        self.DeclareInitializationDiscreteUpdateEvent(self._initialize)
        self.DeclarePeriodicDiscreteUpdateEvent(period_s, 0.0, self._update)
        self.DeclareForcedDiscreteUpdateEvent(self._update)  # a test's forced update
        self._rack_port = self.DeclareStateOutputPort("rack_position_m", self._rack)
        self._torque_port = None
        if speed is not None:
            self._torque = self.DeclareDiscreteState(1)
            self._torque_port = self.DeclareStateOutputPort("drive_torque_Nm", self._torque)
        self._tracking_port = self.DeclareStateOutputPort("tracking", self._tracking)

    def chassis_motion_input_port(self):
        return self._motion_port

    def rack_output_port(self):
        return self._rack_port

    def drive_torque_output_port(self):
        return self._torque_port

    def tracking_output_port(self):
        return self._tracking_port

    def _initialize(self, context, discrete_state):
        self._step(context, discrete_state, near=None, dt=0.0)

    def _update(self, context, discrete_state):
        near = context.get_discrete_state(self._tracking).get_value()[0]
        self._step(context, discrete_state, near=near, dt=self._period)

    def _step(self, context, discrete_state, *, near, dt):
        motion = self._motion_port.Eval(context)
        x, y, yaw, speed, sideslip = (float(motion[i]) for i in self._read)
        law = self._steering
        # Look within the distance the car can have moved since the last update, and more.
        window = 10.0 + 2.0 * abs(speed) * self._period
        station, offset, heading, curvature = self._line.locate(x, y, near, window)
        low, high = COURSE_SPEEDS_MPS
        course = yaw + sideslip * min(1.0, max(0.0, (abs(speed) - low) / (high - low)))
        heading_error = math.remainder(course - heading, 2.0 * math.pi)
        preview_offset = offset + law.preview_m * math.sin(heading_error)
        steer = law.wheelbase_m * curvature - law.gain_rad_per_m * preview_offset
        rack = float(np.clip(law.rack_per_steer_m_per_rad * steer, -law.rack_limit_m,
                             law.rack_limit_m))
        discrete_state.get_mutable_vector(self._rack).SetFromVector([rack])
        discrete_state.get_mutable_vector(self._tracking).SetFromVector(
            [station, offset, heading_error])
        if self._speed is None:
            return
        s = self._speed
        error = s.target_mps - speed
        integral = context.get_discrete_state(self._integral).get_value()[0]
        unclamped = s.gain_Nm_per_mps * (error + integral / s.integral_time_s)
        torque = float(np.clip(unclamped, -s.max_torque_Nm, s.max_torque_Nm))
        if torque == unclamped or (error > 0) != (unclamped > 0):  # no wind-up
            integral += error * dt
        discrete_state.get_mutable_vector(self._integral).SetFromVector([integral])
        discrete_state.get_mutable_vector(self._torque).SetFromVector([torque])
