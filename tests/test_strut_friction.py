"""The StrutFriction system on one-degree-of-freedom rigs, against closed-form references.

Each scheme runs at its own step: ``fast`` at the car's 1 ms, ``reference`` (explicit) at a
step below its stability limit dt < 2 m / c, c = s'_β μs N / Δv the law's largest damping slope.
"""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import PrismaticJoint, SpatialInertia, UnitInertia
from pydrake.systems.analysis import Simulator

from drake_car.law.friction.frd import StrutFrictionParameters, shape_max_slope
from drake_car.sim.rigs.friction import RigOptions, build_rig, simulate_rig
from drake_car.systems.friction_pairs import Strut, declare_pairs
from drake_car.systems.strut_friction import StrutFriction

G = 9.81
MASS = 30.0
LAW = StrutFrictionParameters(mu_s=0.2, mu_d=0.15)
DMAX, DV = LAW.dmax_translation_m, LAW.dv_translation_mps


def reference_step(normal):
    """Half the explicit stability limit 2 m / c of the law's damping slope."""
    c = shape_max_slope(LAW.beta_shape) * LAW.mu_s * normal / DV
    return 0.5 * 2 * MASS / c


def expected_creep(load_ratio):
    """Δ* with μ1(Δ*) = load_ratio·μs for the cubic STEP μ1 = μs x²(3 - 2x), x = Δ/Δmax."""
    from scipy.optimize import brentq
    return DMAX * brentq(lambda x: x * x * (3 - 2 * x) - load_ratio, 0.0, 1.0, xtol=1e-14)


def schemes(normal):
    return [("fast", 1e-3), ("reference", min(reference_step(normal), 1e-4))]


def test_ports_and_discrete_update_alone():
    plant = MultibodyPlant(time_step=1e-3)
    body = plant.AddRigidBody("b", SpatialInertia(MASS, np.zeros(3), UnitInertia(1, 1, 1)))
    joint = plant.AddJoint(PrismaticJoint("j", plant.world_frame(), body.body_frame(),
                                          [1, 0, 0]))
    pairs = declare_pairs(plant, joint, None, "fast")
    plant.Finalize()
    system = StrutFriction(plant, [Strut(pairs, constant_normal_force_N=1000.0)], LAW,
                           scheme="fast")
    names = [system.get_input_port(i).get_name() for i in range(system.num_input_ports())]
    assert names == ["plant_state"]
    outputs = [system.get_output_port(i).get_name() for i in range(system.num_output_ports())]
    assert outputs == ["friction_actuation", "desired_state", "diagnostics"]
    context = system.CreateDefaultContext()
    # Joint at q = 2 µm, v = 0, memory (creep 0, static, q_prev = 0): one update accumulates
    # 2 µm of creep and computes the step's outputs from it.
    system.GetInputPort("plant_state").FixValue(context, [2e-6, 0.0])
    context.SetDiscreteState(system.EvalUniquePeriodicDiscreteUpdate(context))
    memory = context.get_discrete_state(0).get_value()  # [creep, phase, q_prev] of one pair
    assert_allclose(memory, [2e-6, 0.0, 2e-6], err_msg="creep, phase, q_prev")
    diagnostics = system.GetOutputPort("diagnostics").Eval(context)
    assert_allclose(diagnostics[1], 2e-6, err_msg="creep")
    mu1 = LAW.mu_s * (0.4 ** 2 * (3 - 0.8))  # cubic STEP at |Δ|/Δmax = 0.4
    assert_allclose(diagnostics[4], -mu1, rtol=1e-12, err_msg="mu")
    assert_allclose(diagnostics[7], -mu1 * 1000.0, rtol=1e-12, err_msg="friction")
    # Static phase: feed-forward = the law's force, PD targets = the current state.
    assert_allclose(system.GetOutputPort("friction_actuation").Eval(context), [-mu1 * 1000.0],
                    rtol=1e-12)
    assert_allclose(system.GetOutputPort("desired_state").Eval(context), [2e-6, 0.0])


@pytest.mark.parametrize("scheme, dt", schemes(MASS * G))
@pytest.mark.parametrize("angle_deg", [8.0, 14.0])
def test_incline_sticks_below_and_slides_above_mu_s(scheme, dt, angle_deg):
    theta = math.radians(angle_deg)
    normal = MASS * G * math.cos(theta)
    options = RigOptions(mass_kg=MASS, normal_force_N=normal, incline_deg=angle_deg,
                         time_step_s=dt, scheme=scheme)
    h = simulate_rig(options, LAW, duration_s=0.4, record_period_s=0.01)
    if math.tan(theta) < LAW.mu_s:
        # Sticks: the block moves by its creep only, never beyond dmax, and comes to rest where
        # the creep term of eq. (1) carries the load: μ1(Δ*) = tan θ, i.e. Δ* = Δmax s⁻¹(tan θ/μs)
        # with s the cubic STEP. That is the fixed point of both schemes; 1 % covers the
        # remaining transient after 0.4 s.
        assert np.max(np.abs(h["creep_m"])) <= DMAX
        assert np.max(np.abs(h["x_m"])) <= DMAX, f"{scheme}: block drifted"
        assert np.all(h["phase"][1:] == 0.0)
        assert_allclose(-h["x_m"][-1], expected_creep(math.tan(theta) / LAW.mu_s), rtol=0.01)
    else:
        # Slides down with a = -g (sin θ - μd cos θ). In the kinetic phase the law's force is the
        # constant μd N, so only the solver's round-off separates the two: 1e-6 relative.
        expected = -G * (math.sin(theta) - LAW.mu_d * math.cos(theta))
        sliding = h["t"] >= 0.1
        assert np.all(np.abs(h["v_mps"][sliding]) > 1.5 * DV)
        t, v = h["t"][sliding], h["v_mps"][sliding]
        acceleration = (v[-1] - v[0]) / (t[-1] - t[0])
        assert_allclose(acceleration, expected, rtol=1e-6, err_msg=scheme)


@pytest.mark.parametrize("scheme, dt", schemes(3000.0))
def test_slow_ramp_breaks_free_at_mu_s_n(scheme, dt):
    normal, rate = 3000.0, 1000.0
    options = RigOptions(mass_kg=MASS, normal_force_N=normal, force_rate_Nps=rate,
                         time_step_s=dt, scheme=scheme)
    h = simulate_rig(options, LAW, duration_s=0.7, record_period_s=dt if dt >= 1e-4 else 1e-4)
    moving = np.flatnonzero(np.abs(h["v_mps"]) > DV)
    assert moving.size, "never broke free"
    breakaway = rate * h["t"][moving[0]]
    # Once the load passes μs N the excess r·τ accelerates the block: v = r τ²/(2m) reaches
    # Δv after τ = sqrt(2 m Δv / r); detection adds one sample of load.
    tolerance = math.sqrt(2 * MASS * DV * rate) + rate * max(dt, 1e-4)
    assert_allclose(breakaway, LAW.mu_s * normal, atol=tolerance, err_msg=scheme)
    before = h["t"] * rate < LAW.mu_s * normal - tolerance
    assert np.max(np.abs(h["x_m"][before])) <= DMAX, "moved before break-away"


@pytest.mark.parametrize("scheme, dt", schemes(3000.0))
@pytest.mark.parametrize("ratio", [0.8, 0.95])
def test_load_below_breakaway_removed_returns_within_dmax(scheme, dt, ratio):
    normal = 3000.0
    options = RigOptions(mass_kg=MASS, normal_force_N=normal, force_N=ratio * LAW.mu_s * normal,
                         force_off_s=0.2, time_step_s=dt, scheme=scheme)
    h = simulate_rig(options, LAW, duration_s=0.5, record_period_s=0.01)
    loaded = h["x_m"][np.searchsorted(h["t"], 0.2) - 1]
    assert abs(h["x_m"][-1]) <= DMAX, "must end within dmax of the start"
    assert abs(h["x_m"][-1]) < 0.1 * abs(loaded), "the creep must spring back once unloaded"
    assert np.all(h["phase"] == 0.0), "the block must never slide"
    if ratio == 0.8:  # well below break-away: the excursion is the creep, at most dmax
        assert np.max(np.abs(h["x_m"])) <= DMAX
        assert_allclose(loaded, expected_creep(ratio), rtol=0.01)


@pytest.mark.parametrize("initial", [None, "static"])
def test_normal_force_from_reaction_and_first_step(initial):
    """On an 8 deg incline N comes from the joint's reaction, m g cos θ. Drake's sampled
    reaction port reads zero before the first step: without an initial N the block slips in
    that step; with it the block stays stuck from t = 0."""
    theta = math.radians(8.0)
    weight_normal = MASS * G * math.cos(theta)
    options = RigOptions(mass_kg=MASS, incline_deg=8.0, normal_from_reaction=True,
                         initial_normal_force_N=None if initial is None else weight_normal)
    rig = build_rig(options, LAW)
    simulator = Simulator(rig.diagram)
    simulator.AdvanceTo(0.2)
    context = rig.friction.GetMyContextFromRoot(simulator.get_context())
    names = rig.friction.diagnostic_names()
    diagnostics = rig.friction.GetOutputPort("diagnostics").Eval(context)
    assert_allclose(diagnostics[names.index("translation_N")], weight_normal, rtol=1e-6)
    h = simulate_rig(options, LAW, duration_s=0.2, record_period_s=1e-3)
    if initial is None:
        assert h["phase"][1] == 1.0 and np.max(np.abs(h["x_m"])) > DMAX
    else:
        assert np.all(h["phase"] == 0.0) and np.max(np.abs(h["x_m"])) <= DMAX


# The project's accuracy target for the rod displacement (issue 6): 0.1 mm.
DISPLACEMENT_TARGET_M = 1e-4


def test_fast_scheme_converges_to_reference():
    """Stick-slip on a spring under a sinusoidal load (10 mm peak excursion, several stick and
    slip phases): the fast scheme's error against the converged reference shrinks as the step
    shrinks over 1.5 decades, and at the car's 1 ms it meets the 0.1 mm target. The errors are
    printed (pytest -s); benchmarks/friction_convergence.py records the full table."""
    normal = 500.0
    base = dict(mass_kg=MASS, normal_force_N=normal, spring_Npm=2.0e4, force_amp_N=150.0,
                force_freq_hz=2.0)
    ref_dt = reference_step(normal)
    reference = simulate_rig(RigOptions(time_step_s=ref_dt, scheme="reference", **base), LAW,
                             duration_s=0.5, record_period_s=1e-3)
    finer = simulate_rig(RigOptions(time_step_s=ref_dt / 2, scheme="reference", **base), LAW,
                         duration_s=0.5, record_period_s=1e-3)
    reference_change = float(np.max(np.abs(finer["x_m"] - reference["x_m"])))
    errors = {}
    for dt in (1e-3, 1e-4, 3e-5):
        fast = simulate_rig(RigOptions(time_step_s=dt, scheme="fast", **base), LAW,
                            duration_s=0.5, record_period_s=1e-3)
        errors[dt] = float(np.max(np.abs(fast["x_m"] - finer["x_m"])))
    print(f"reference change on halving its step {reference_change:.2e} m; fast vs reference, "
          f"max |x error| by step: {errors}")
    # The reference is converged well below the errors it is used to measure.
    assert reference_change < 0.5 * errors[3e-5], (reference_change, errors)
    assert errors[1e-3] > errors[1e-4] > errors[3e-5], errors
    assert errors[1e-3] <= DISPLACEMENT_TARGET_M, errors


@pytest.mark.parametrize("ratio", [0.8, 1.2])
def test_rotation_pair_sticks_below_and_slides_above_mu_s(ratio):
    """A torque of ratio·μs·N·r on a revolute joint (inertia 0.5 kg m², about a knuckle and
    wheel about the strut axis): sticks within Δmax (rad) below 1, spins up at
    (τ - μd N r)/I above."""
    normal, radius, inertia = 3000.0, RigOptions().rod_radius_m, 0.5
    torque = ratio * LAW.mu_s * normal * radius
    options = RigOptions(mass_kg=inertia / 0.01, normal_force_N=normal, force_N=torque,
                         rotational=True, time_step_s=1e-3, scheme="fast")
    h = simulate_rig(options, LAW, duration_s=0.3, record_period_s=0.01)
    if ratio < 1:
        assert np.max(np.abs(h["x_m"])) <= LAW.dmax_rotation_rad
        assert np.all(h["phase"] == 0.0)
    else:
        spinning = h["t"] >= 0.1
        t, w = h["t"][spinning], h["v_mps"][spinning]
        expected = (torque - LAW.mu_d * normal * radius) / inertia
        assert_allclose((w[-1] - w[0]) / (t[-1] - t[0]), expected, rtol=1e-6)


# -- the law at its threshold (issue 19, item 6) -------------------------------------------

@pytest.mark.parametrize("ratio", [0.5, 0.95, 0.99, 0.999])
def test_fast_creep_at_the_threshold_follows_the_law(ratio):
    """A load ratio·μs·N held from t = 0 on the 30 kg block (N = 3 kN): the creep at the car's
    1 ms stays within 5 % of Δmax of the law's own (the explicit scheme at half its stability
    limit, ~3 µs) at every millisecond, never exceeds Δmax and never slides; at 0.1 ms it is
    closer still (the scheme converges to the law). The 5 % is the issue's bound, a fraction of
    the law's Δmax; where the law itself passes Δmax (ratio 0.999: 5.015 µm, sliding within the
    static band once μ1 = μs), Δmax is still the fast scheme's bound at 1 ms."""
    normal = 3000.0
    base = dict(mass_kg=MASS, normal_force_N=normal, force_N=ratio * LAW.mu_s * normal)
    law = simulate_rig(RigOptions(time_step_s=reference_step(normal), scheme="reference",
                                  **base), LAW, duration_s=0.2, record_period_s=1e-3)
    deviation = {}
    for dt in (1e-3, 1e-4):
        fast = simulate_rig(RigOptions(time_step_s=dt, scheme="fast", **base), LAW,
                            duration_s=0.2, record_period_s=1e-3)
        assert np.all(fast["phase"] == 0.0), f"slid at {dt:g} s"
        deviation[dt] = float(np.max(np.abs(fast["x_m"] - law["x_m"])))
        if dt == 1e-3:
            assert np.max(np.abs(fast["x_m"])) <= DMAX, np.max(np.abs(fast["x_m"]))
    print(f"ratio {ratio}: law's final creep {law['x_m'][-1]:.4e} m, fast - law at most "
          f"{deviation} m")
    assert deviation[1e-3] <= 0.05 * DMAX, deviation
    assert deviation[1e-4] < deviation[1e-3], deviation


def karnopp_cycle(m, k, normal, mu_d, belt_speed, x_breakaway, v_breakaway):
    """Period and peak-to-peak excursion of the stick-slip cycle of a block (mass m) on a
    spring k to a fixed anchor, on a belt at speed V, with kinetic friction μd N while it slips
    and sticking (moving with the belt) otherwise: slip starts at x_b with velocity v_b (the
    Coulomb limit: x_b = μs N / k, v_b = V). The slip is the harmonic arc about
    x_d = μd N / k, X = x - x_d, Y = ẋ/ω, ω = sqrt(k/m), radius A = |(X_b, Y_b)|, turned
    clockwise from (X_b, Y_b) until ẋ = V again, at Y = V/ω, X < 0; the stick carries the block
    back to x_b at speed V."""
    omega = math.sqrt(k / m)
    x_d = mu_d * normal / k
    xb, yb = x_breakaway - x_d, v_breakaway / omega
    radius = math.hypot(xb, yb)
    y_end = belt_speed / omega
    x_end = -math.sqrt(radius ** 2 - y_end ** 2)
    swept = math.atan2(yb, xb) - math.atan2(y_end, x_end) + 2 * math.pi
    slip_s = swept / omega
    stick_s = (x_breakaway - (x_d + x_end)) / belt_speed
    return slip_s + stick_s, 2 * radius


@pytest.mark.slow
def test_reference_reproduces_the_stick_slip_cycle_on_a_belt():
    """The explicit scheme (the law as stated) on a block on a spring over a belt at 0.1 m/s
    (μs = 0.4, μd = 0.3, N = 300 N, k = 6 kN/m, 30 kg: a 10 mm stick-slip cycle of ~0.46 s)
    reproduces the closed-form cycle (``karnopp_cycle``) within 1 % in period and amplitude.

    The law's regularisation shifts the Coulomb closed form in one place: the block does not
    break away at x_s = μs N / k with the belt's speed but once its relative velocity leaves
    the static band, |v| > Δv, later by at most τ* = sqrt(2 m Δv / (k V)) (the spring's excess
    k V t over μs N accelerating the block out of the band; 3.2 ms here), so at x_b ≤ x_s +
    V τ* with velocity V - Δv. The creep (≤ Δmax = 5 µm against a 10 mm cycle) and the Stribeck
    band (μs to μd over Δv..1.5Δv, left within ~1e-4 s) shift it by < 0.1 %. The test reads the
    breakaway state from the run, checks it against that bound, and compares the cycle with the
    closed form from it; the Coulomb limit (x_b = x_s) is printed beside (measured: period
    +0.26 %, amplitude +1.1 %)."""
    law = StrutFrictionParameters(mu_s=0.4, mu_d=0.3)
    m, normal, k, speed = MASS, 300.0, 6000.0, 0.1
    dt = 0.5 * 2 * m * law.dv_translation_mps / (1.5 * law.mu_s * normal)  # half the limit
    h = simulate_rig(RigOptions(mass_kg=m, normal_force_N=normal, spring_Npm=k,
                                belt_speed_mps=speed, time_step_s=dt, scheme="reference"),
                     law, duration_s=2.0, record_period_s=dt)
    t, x, phase = h["t"], h["x_m"], h["phase"]
    onsets = np.flatnonzero((phase[1:] > 0) & (phase[:-1] == 0)) + 1
    assert onsets.size >= 4, "expected at least 4 slip onsets in 2 s"
    periods = np.diff(t[onsets])[1:]  # the first cycle starts from rest: skip it
    last = slice(onsets[-2], onsets[-1])
    amplitude = float(np.max(x[last]) - np.min(x[last]))
    x_s = law.mu_s * normal / k
    tau = math.sqrt(2 * m * law.dv_translation_mps / (k * speed))
    x_b = float(x[onsets[-2]])
    assert x_s <= x_b <= x_s + speed * tau + speed * dt, (x_b, x_s, speed * tau)
    period, p2p = karnopp_cycle(m, k, normal, law.mu_d, speed, x_b,
                                speed - law.dv_translation_mps)
    coulomb = karnopp_cycle(m, k, normal, law.mu_d, speed, x_s, speed)
    print(f"period {np.mean(periods):.6f} s, amplitude {amplitude:.6e} m; closed form from the "
          f"breakaway at x_s + {x_b - x_s:.3e} m: {period:.6f} s, {p2p:.6e} m; Coulomb limit "
          f"{coulomb[0]:.6f} s, {coulomb[1]:.6e} m")
    assert_allclose(periods, period, rtol=0.01)
    assert_allclose(amplitude, p2p, rtol=0.01)
