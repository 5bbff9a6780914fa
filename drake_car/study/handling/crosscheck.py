"""Cross-check against an independent model of the same car: CommonRoad's multi-body model (MB,
``vehiclemodels.vehicle_dynamics_mb`` of the PyPI package commonroad-vehicle-models, a test
extra) with its parameter set of the car that ran (set 1, the Ford Escort of the NHTSA report
the shipped car's parameters come from; set 2, the BMW 320i of the second shipped car:
``parameter_set_of``), driven through our run's road-wheel steer series at the speed our car
held. A car CommonRoad has no set of is not cross-checked.

Its conventions, read from its equations (SAE J670: x forward, y right, z down): steer, yaw
rate, lateral velocity, sideslip and lateral acceleration are positive to the right; roll is
positive with the right side down, as ISO's. So steer, yaw rate, a_y and sideslip change sign
between its frame and ours (ISO 8855); roll does not. Its a, b are the sprung mass's CoG
distances (the Escort's 0.884 / 1.509 m; ours are the whole car's); its a_y is its whole car's (Σ tyre
forces over m, as ours), its sideslip and speed are the sprung mass's CoG's.

What the wrapper adds; the package's model runs unchanged:
- steering: its input is the steer rate, clipped at ±0.4 rad/s; a tracker
  u = δ̇_ref + k (δ_ref − δ) follows the series (within 0.01° at k = 50 /s);
- speed: a PI controller on its acceleration input follows our speed series;
- start: ``init_mb`` is not a rest state (the sprung mass starts at its springs' free length),
  so the car first drives straight for ``settle_s`` with its tyres' camber-sign terms off: its
  tyre model writes the camber shifts as sign(γ)(p_hy1 + ...), which makes straight running a
  self-excited roll limit cycle of about ±0.3° (they are on again for the run itself);
- integration: fixed-step RK4 at 1 ms (its right-hand side has the sign switches, clips and
  max(0, ·) clamps an adaptive solver stumbles on; its fastest mode, the wheel slip at about
  350 /s, is well inside RK4's limit at 1 ms at 60 km/h).
"""

import contextlib
import math

import numpy as np

from drake_car.study.handling.measures import single_track

# 0-based indices into MB's 29 states that the outputs use.
DELTA, VX, YAW_RATE, ROLL, VY = 2, 3, 5, 6, 10
G = 9.81  # the package's own


def available():
    """(True, "") if the package imports, else (False, why)."""
    try:
        import vehiclemodels.vehicle_dynamics_mb  # noqa: F401
    except ImportError as e:
        return False, f"commonroad-vehicle-models is not installed ({e}); pip install " \
                      "'drake_car[test]' or commonroad-vehicle-models"
    return True, ""


# CommonRoad's parameter sets of passenger cars (its set 4 is a semi-trailer truck): a car of
# the same mass and front track (``parameter_set_of``) is cross-checked against its model.
PARAMETER_SETS = {1: "Ford Escort", 2: "BMW 320i", 3: "VW Vanagon"}


def parameters(vehicle_id=1):
    """MB's parameter set ``vehicle_id`` (PARAMETER_SETS)."""
    from vehiclemodels.vehicle_parameters import setup_vehicle_parameters
    return setup_vehicle_parameters(vehicle_id=vehicle_id)


def parameter_set_of(car):
    """(id, name) of CommonRoad's parameter set of ``car`` (``CarParameters``): the set whose
    total mass is the car's within 0.1 % and front track within 5 mm; None if none is."""
    for vehicle_id, name in PARAMETER_SETS.items():
        p = parameters(vehicle_id)
        if (abs(p.m / car.mass.total_mass_kg - 1) < 1e-3
                and abs(p.T_f - car.front.track_m) < 5e-3):
            return vehicle_id, name
    return None


@contextlib.contextmanager
def _camber_sign_off():
    from vehiclemodels.utils import tire_model
    sign = tire_model.sign
    tire_model.sign = lambda value: 0
    try:
        yield
    finally:
        tire_model.sign = sign


class BrokeDown(Exception):
    """CommonRoad's model cannot go on at ``time`` (a wheel rolling backwards divides by its
    zero speed, a state that is no number): the car has spun in it."""

    def __init__(self, time, why):
        super().__init__(f"at {time:.3f} s: {why}")
        self.time, self.why = time, why


def _rk4(rhs, y, t0, steps, dt, record=None):
    t = t0
    for _ in range(steps):
        try:
            k1 = rhs(t, y)
            k2 = rhs(t + dt / 2, y + dt / 2 * k1)
            k3 = rhs(t + dt / 2, y + dt / 2 * k2)
            k4 = rhs(t + dt, y + dt * k3)
        except (ArithmeticError, ValueError) as e:
            raise BrokeDown(t, f"{type(e).__name__}: {e}") from None
        y = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        if not np.all(np.isfinite(y)):
            raise BrokeDown(t, "its state is no longer finite")
        t += dt
        if record is not None:
            record(t, y)
    return y


def simulate_mb(t, steer_rad, speed_mps, *, p=None, dt=1e-3, settle_s=4.0, steer_gain=50.0,
                speed_gains=(2.0, 1.0), camber_sign=True):
    """MB on the road-wheel steer series ``steer_rad`` (ISO: left +) at the speeds
    ``speed_mps`` (both sampled at ``t``). Returns a history in our channels' names and ISO
    signs: t, steer_rad (its realised δ), yaw_rate_radps, ay_mps2 (the whole car's CoG: Σ of
    the tyre forces over m), ay_sprung_mps2, and at its sprung mass's CoG roll_rad,
    sideslip_rad, speed_mps, ax_mps2; broke_down_s: where the model could not go on
    (``BrokeDown``; its channels NaN from there), else None. ``camber_sign``: False switches its
    tyres' camber shifts off for the run too (a diagnostic: how much of its behaviour they
    make)."""
    from vehiclemodels.init_mb import init_mb
    from vehiclemodels.vehicle_dynamics_mb import vehicle_dynamics_mb
    p = p or parameters()
    t = np.asarray(t, float)
    ref = -np.asarray(steer_rad, float)  # to its sign
    slope = np.diff(ref) / np.diff(t)
    speed_ref = np.broadcast_to(np.asarray(speed_mps, float), t.shape)
    kp, ki = speed_gains

    def steer_reference(time):
        if time <= t[0]:
            return ref[0], 0.0
        if time >= t[-1]:
            return ref[-1], 0.0
        i = int(np.searchsorted(t, time, side="right")) - 1
        return ref[i] + slope[i] * (time - t[i]), slope[i]

    def rhs(time, y):
        d_ref, rate = steer_reference(time)
        error = float(np.interp(time, t, speed_ref)) - math.hypot(y[VX], y[VY])
        u = [rate + steer_gain * (d_ref - y[DELTA]), kp * error + ki * y[29]]
        return np.array(vehicle_dynamics_mb([float(v) for v in y[:29]], u, p) + [error])

    y = np.array(list(init_mb([0.0, 0.0, ref[0], float(speed_ref[0]), 0.0, 0.0, 0.0], p)) + [0.0])
    with _camber_sign_off():  # the steer held at its first value, the speed at its first
        y = _rk4(rhs, y, t[0] - settle_s, int(round(settle_s / dt)), dt)
    steps = int(math.ceil((t[-1] - t[0]) / dt - 1e-9))
    grid_t, grid_y = [t[0]], [y.copy()]
    record = lambda time, yy: (grid_t.append(time), grid_y.append(yy.copy()))  # noqa: E731
    ended = why = None
    with contextlib.nullcontext() if camber_sign else _camber_sign_off():
        try:
            _rk4(rhs, y, t[0], steps, dt, record)
        except BrokeDown as e:  # what it ran before is kept; after it, no numbers (NaN)
            ended, why = e.time, e.why
        grid = np.array(grid_y)
        reached = (np.ones(len(t), bool) if ended is None  # the grid's end may round short
                   else t <= grid_t[-1] + 0.5 * dt)
        states = np.full((len(t), grid.shape[1]), np.nan)
        states[reached] = np.column_stack([np.interp(t[reached], np.array(grid_t), grid[:, j])
                                           for j in range(grid.shape[1])])
        derivatives = np.full_like(states, np.nan)
        for i in np.flatnonzero(reached):
            try:  # at the breakdown's own state its model fails again: NaN there
                derivatives[i] = rhs(t[i], states[i])
            except (ArithmeticError, ValueError):
                if ended is None:
                    raise
    r, vx, vy = states[:, YAW_RATE], states[:, VX], states[:, VY]
    ay_s = derivatives[:, VY] + r * vx
    ay_total = (p.m_s * ay_s + p.m_uf * (derivatives[:, 15] + r * vx)
                + p.m_ur * (derivatives[:, 20] + r * vx)) / p.m
    return {"t": t, "steer_rad": -states[:, DELTA], "yaw_rate_radps": -r, "ay_mps2": -ay_total,
            "ay_sprung_mps2": -ay_s, "roll_rad": states[:, ROLL],
            "sideslip_rad": -np.arctan2(vy, vx), "speed_mps": np.hypot(vx, vy),
            "ax_mps2": derivatives[:, VX] - r * vy, "broke_down_s": ended,
            "broke_down_why": why}


# -- its own numbers: loads, tyre, single track, roll ---------------------------------------

def static_axle_loads(p):
    """MB's static axle loads (N) as ``init_mb`` sets them: sprung mass by its a, b plus the
    unsprung masses at the axles."""
    L = p.a + p.b
    return {"front": p.m_s * G * p.b / L + p.m_uf * G, "rear": p.m_s * G * p.a / L + p.m_ur * G}


def tyre_stiffness(p, wheel_load_N):
    """Its tyre's cornering stiffness (N/rad, positive) at zero camber: K_y = |p_ky1| F_z (no
    load sensitivity: the same per unit load at any load)."""
    return abs(p.tire.p_ky1) * wheel_load_N


def mb_single_track(p, speed_mps, *, front_stiffness=None, rear_stiffness=None):
    """The single-track model of MB's data (its mass, its a as the yaw lever, its static axle
    loads) with its tyre's stiffness, or with the stiffnesses given (e.g. our tyre's at its
    loads)."""
    loads = static_axle_loads(p)
    cf = front_stiffness or 2 * tyre_stiffness(p, loads["front"] / 2)
    cr = rear_stiffness or 2 * tyre_stiffness(p, loads["rear"] / 2)
    return single_track(mass_kg=p.m, wheelbase_m=p.a + p.b, cog_to_front_m=p.a,
                        front_stiffness=cf, rear_stiffness=cr, speed_mps=speed_mps)


def roll_model(p):
    """Its roll model in numbers: one spring per corner (K_s T²/2 per axle) plus the auxiliary
    torsion stiffness (−K_ts: negative means added), each axle in series with its tyres
    (K_zt T²/2), roll axis at the ground (h_raf = h_rar = 0), so the sprung mass's arm is h_s:
    dφ/da_y = m_s h_s / (K_φ − m_s g h_s)."""
    front = p.K_sf * p.T_f ** 2 / 2 - p.K_tsf
    rear = p.K_sr * p.T_r ** 2 / 2 - p.K_tsr
    tyre_f, tyre_r = p.K_zt * p.T_f ** 2 / 2, p.K_zt * p.T_r ** 2 / 2
    total = 1 / (1 / front + 1 / tyre_f) + 1 / (1 / rear + 1 / tyre_r)
    arm = p.h_s - 0.5 * (p.h_raf + p.h_rar)
    gradient = p.m_s * arm / (total - p.m_s * G * arm)
    return {"suspension_front_Nm_per_rad": front, "suspension_rear_Nm_per_rad": rear,
            "with_tyres_Nm_per_rad": total, "roll_arm_m": arm, "sprung_mass_kg": p.m_s,
            "roll_gradient_deg_per_g": math.degrees(gradient) * G}


def equivalent_roll_arm(roll_gradient_deg_per_g, roll_stiffness_Nm_per_rad, sprung_mass_kg):
    """The roll arm (m) that gives ``roll_gradient_deg_per_g`` with this roll stiffness and
    sprung mass: φ' = m_s h / (K − m_s g h) solved for h."""
    phi = math.radians(roll_gradient_deg_per_g) / G  # rad per m/s²
    return roll_stiffness_Nm_per_rad * phi / (sprung_mass_kg * (1 + G * phi))


def car_inertia(params):
    """The whole car's mass (kg), CoG (m, in the vehicle frame) and yaw inertia about its CoG
    (kg m²) at the design position, from the plant built from ``params``."""
    from pydrake.multibody.plant import MultibodyPlant

    from drake_car.model.car import add_car
    plant = MultibodyPlant(time_step=1e-3)
    car = add_car(plant, params)
    plant.Finalize()
    context = plant.CreateDefaultContext()
    bodies = [plant.get_body(i).index() for i in plant.GetBodyIndices(car.instance)]
    inertia = plant.CalcSpatialInertia(context, plant.world_frame(), bodies)
    cog = inertia.get_com()
    about_cog = inertia.Shift(cog)
    return {"mass_kg": float(inertia.get_mass()), "cog_m": cog.tolist(),
            "yaw_inertia_kgm2": float(about_cog.CalcRotationalInertia().get_moments()[2])}


# -- attributing the differences ------------------------------------------------------------

def _pct(ours, theirs):
    return 100.0 * (ours - theirs) / abs(theirs) if theirs else None


def single_track_chain(p, *, speed_mps, our_mass_kg, our_cog_to_front_m, our_wheelbase_m,
                       our_front_stiffness, our_rear_stiffness, our_yaw_inertia_kgm2,
                       our_relaxation_m, t=None, steer_rad=None):
    """Single-track models from MB's data to ours, one difference at a time: its own (its
    tyre at its static loads, its sprung mass's a as the yaw lever, m, I_z); its tyre at the
    axle loads its a, b give (m g b/L, m g a/L); our tyres' axle stiffnesses (at our static
    loads); our mass, CoG and wheelbase; our yaw inertia; our tyres' relaxation length. Each
    with K, r/δ, the sideslip gradient and (given a steer series) the step-response times."""
    from drake_car.study.handling.measures import single_track_response, step_response
    loads = static_axle_loads(p)
    L = p.a + p.b
    models = [("MB data", dict(m=p.m, a=p.a, L=L, cf=2 * tyre_stiffness(p, loads["front"] / 2),
                              cr=2 * tyre_stiffness(p, loads["rear"] / 2), iz=p.I_z, sigma=0.0))]
    steps = (("MB, loads consistent with its a, b",
              dict(cf=2 * tyre_stiffness(p, p.m * G * p.b / L / 2),
                   cr=2 * tyre_stiffness(p, p.m * G * p.a / L / 2))),
             ("our tyres' Kyα", dict(cf=our_front_stiffness, cr=our_rear_stiffness)),
             ("our mass, CoG, wheelbase", dict(m=our_mass_kg, a=our_cog_to_front_m,
                                                L=our_wheelbase_m)),
             ("our yaw inertia", dict(iz=our_yaw_inertia_kgm2)),
             ("our tyres' relaxation", dict(sigma=our_relaxation_m)))
    for name, change in steps:
        models.append((name, models[-1][1] | change))
    out = []
    for name, d in models:
        row = {"model": name, "mass_kg": d["m"], "cog_to_front_m": d["a"],
               "front_stiffness_N_per_rad": d["cf"], "rear_stiffness_N_per_rad": d["cr"],
               "yaw_inertia_kgm2": d["iz"], "relaxation_m": d["sigma"]}
        row |= single_track(mass_kg=d["m"], wheelbase_m=d["L"], cog_to_front_m=d["a"],
                            front_stiffness=d["cf"], rear_stiffness=d["cr"],
                            speed_mps=speed_mps)
        if t is not None:
            r = single_track_response(t, steer_rad, speed_mps=speed_mps, mass_kg=d["m"],
                                      yaw_inertia_kgm2=d["iz"], cog_to_front_m=d["a"],
                                      wheelbase_m=d["L"], front_stiffness=d["cf"],
                                      rear_stiffness=d["cr"], relaxation_length_m=d["sigma"])
            for channel, key in (("yaw_rate", "yaw_rate"), ("lateral_acceleration", "ay")):
                s = step_response(t, steer_rad, r[key])
                row[f"{channel}_response_time_s"] = s["response_time_s"]
                row[f"{channel}_overshoot_pct"] = s["overshoot_pct"]
        out.append(row)
    return out


def understeer_reconciliation(*, ours_wheel_k, budget_rows, mb_k, mb_k_no_camber, chain):
    """The two understeer gradients (road-wheel angle) as sums of the same named parts, each
    column summing to its model's gradient: the single-track model (``single_track_chain``:
    MB's tyre at loads consistent with its levers; MB's lever/load inconsistency; our tyres'
    Kyα at our static loads; our mass and CoG), then lateral load transfer with load
    sensitivity, aligning moments, camber, drive with the Fy projections (our budget's terms;
    MB's camber from its run without the camber-sign terms) and the rest."""
    g = {r["key"]: r["gradient_deg_per_g"] for r in budget_rows}
    k = [c["understeer_gradient_deg_per_g"] for c in chain]
    drive = (g["drive_yaw"] + g["drive_lateral"] + g["drive_combined"]
             + g["steer_projection"])
    named = k[3] + g["load_transfer"] + g["aligning"] + g["camber"] + drive
    mb_camber = mb_k - mb_k_no_camber if mb_k_no_camber is not None else None
    return [
        {"key": "neutral", "part": "single track, MB's tyre (Kyα ∝ Fz) at loads consistent "
         "with its levers", "ours": k[1], "mb": k[1]},
        {"key": "levers", "part": "MB: sprung mass's a, b as yaw levers, whole-car static "
         "loads", "ours": 0.0, "mb": k[0] - k[1]},
        {"key": "tyres", "part": "our tyres' Kyα at our static loads (load sensitivity at the "
         "static loads)", "ours": k[2] - k[1], "mb": 0.0},
        {"key": "mass", "part": "our mass, CoG, wheelbase", "ours": k[3] - k[2], "mb": 0.0},
        {"key": "load_transfer", "part": "lateral load transfer × load sensitivity",
         "ours": g["load_transfer"], "mb": 0.0},
        {"key": "aligning", "part": "aligning moments", "ours": g["aligning"], "mb": 0.0},
        {"key": "camber", "part": "camber", "ours": g["camber"], "mb": mb_camber},
        {"key": "drive", "part": "drive (differential, Fx sin δ, combined slip), Fy "
         "projections", "ours": drive, "mb": None},
        {"key": "rest", "part": "rest (ours: tyre non-linearity, remainders; MB: its drive, "
         "compliant joints, combined slip)", "ours": ours_wheel_k - named,
         "mb": mb_k - k[0] - (mb_camber or 0.0)},
    ]
