"""Closed forms of the friction rig's cases under ideal Coulomb friction (stick up to μs N, slide
at μd N), and where the FRD law's regularisation (``frd``: Δv, Δmax, the Stribeck blend of
eq. 3) moves the law's own solution away from them. No Drake here.

The law is Coulomb friction wherever the relative velocity u is outside the band |u| ≤ 1.5 Δv:
there μ = -μd sgn(u) exactly (eq. 2-3). Inside the band it is regularised: the static phase
(eq. 1) for |u| ≤ Δv, the Stribeck blend from μs down to μd for Δv < |u| < 1.5 Δv. So every
departure from the Coulomb closed form comes from the band, and each is bounded by what can
happen there; |μ| ≤ μs N holds throughout.

Belt (``belt_cycle``, ``belt_shift``). A block of mass m on a spring k to a fixed anchor rides a
belt moving at V; x is its position from the anchor, u = ẋ - V. Coulomb: it sticks (ẋ = V) until
k x reaches μs N at x_s = μs N / k, then slips on the harmonic arc about x_d = μd N / k
(ω = √(k/m)) until ẋ = V again, at X = x - x_d = -(x_s - x_d), and sticks again: a cycle of
period T_C. The law:

1. Between the band's edges (|u| > 1.5 Δv) the slip is that same arc, exactly. Let the slip
   start where u leaves the band (u = -1.5 Δv, at x_1 = x_s + ξ) and end where it re-enters
   (u = -1.5 Δv again); between these the block moves at V + u with |u| ≤ 1.5 Δv and lags the
   belt by D = -∫u dt. Then, exactly,

       T_law = T_arc(x_1, V - 1.5 Δv) + D / V,

   T_arc (``belt_cycle(..., start_m=x_1, start_speed_mps=V - 1.5 Δv, end_speed_mps=V - 1.5 Δv)``)
   the arc from (x_1, V - 1.5 Δv) until ẋ = V - 1.5 Δv plus the stick at exactly V back to x_1.
   (In the limit cycle the slip starts where the last one started.) The regularisation enters
   only through ξ, through D and through the arc's ends at 1.5 Δv instead of 0.
2. ξ ≥ 0: at the static band's edge (|u| = Δv) β = 1 and μ = μs, so u can leave the band only
   once k x ≥ μs N. ξ ≤ V τ1: from x_s on, the spring's excess k (x - x_s) ≥ k (V - 1.5 Δv) t
   over μs N accelerates the block relative to the belt, so |u| reaches 1.5 Δv within
   τ1 = √(3 m Δv / (k (V - 1.5 Δv))) (the friction never exceeds μs N).
3. 0 ≤ D ≤ Δmax + 1.5 Δv (τ1 + τin): in the static phase the block's relative displacement is
   its creep (which starts from 0 at re-entry) while that is below Δmax; at Δmax the friction
   is μs N against the motion, so the block moves on only while it breaks away (within τ1).
   It crosses the band's ends at |u| ≤ 1.5 Δv: at re-entry the friction exceeds the spring's
   load by at least (μs - μd) N, so it passes 1.5 Δv → Δv within
   τin = 0.5 m Δv / ((μs - μd) N); at break-away within τ1.

So T_law - T_C lies in [min T_arc - T_C, max T_arc - T_C + D_max / V] over ξ in [0, V τ1]
(``belt_shift``; T_arc grows with ξ while ω² (x_1 - x_d)² > 1.5 Δv V). D / V is of first
order in Δmax (or in Δv, whichever holds the load in the stick). ξ is not of first order in
Δv: both the β STEP and
the Stribeck STEP have zero slope at Δv, so nothing pushes the block out of the band but the
spring's growing excess over μs N. Two regimes:

- the creep reaches Δmax before break-away (Δmax small against Δv times the stick): then
  μ = μs exactly across the static band, the excess k V t accelerates the block from u ≈ 0,
  and it leaves after τ* = √(2 m Δv / (k V)): ξ ≈ V τ*, of order √Δv;
- the creep is below Δmax (the β term holds the load): quasi-statically
  β(|u|/Δv) = (k x / N - μ1) / (μs - μ1), so |u| → Δv as k x → μs N along the STEP's flat top,
  1 - β ≈ 3 z², z = 1 - |u|/Δv. With inertia z' = -a (3 z² - σ), σ = (μs - k x / N)/(μs - μ1)
  falling at c = k V / (N (μs - μ1)), a = N (μs - μ1) / (m Δv): a Riccati (Airy) equation whose
  only time scale is a^(-2/3) c^(-1/3), so ξ is of order Δv^(2/3).

Measured (benchmarks/reference_convergence.py, the belt of ``study.rig.closed_forms``: Δv = 1 %
of V, Δmax = 1 % of the 10 mm stick, creep at 0.71 Δmax when it breaks away): the law's period
+0.613 % off T_C (bracket -0.22 .. +2.11 %), ξ = 0.44 mm = 0.36 V τ1, D = 71 µm; at Δv/4 and
Δv/16 (Δmax kept) the shift is +0.215 % and +0.086 % and ξ falls with orders 0.76 and 0.67.

Free oscillator (``oscillator_decay_per_cycle_m``). A block on a spring k, released from rest
beyond x_s. Coulomb: each half cycle is a harmonic arc about ±x_d and the amplitude falls by
2 μd N / k, 4 μd N / k per cycle. The law: the arcs are exact outside the band; at a turning
point at spring force k|x| > μs N the net force on the block is at least k|x| - μs N (toward
the anchor), so the block spends at most τturn = 3 Δv m / (k|x| - μs N) in the band and moves
at most 1.5 Δv τturn there. Each turning point is moved by at most that travel plus the
arc's own change, (1.5 Δv / ω)² / |X| (leaving the band at 1.5 Δv instead of 0): a shift of
second order in Δv and independent of Δmax (``oscillator_turn_bound_m``).

Incline (``incline_acceleration_mps2``). Tilted by θ: below tan θ = μs the law holds the block
at its creep's fixed point μ1(Δ*) = tan θ, |Δ*| ≤ Δmax (Coulomb: Δ* = 0); above, once
|u| > 1.5 Δv, it slides at a = g (sin θ - μd cos θ) exactly, after a start in the band of at
most 1.5 Δv / (g (sin θ - μs cos θ)).
"""

import dataclasses
import math


@dataclasses.dataclass(frozen=True)
class BeltCycle:
    """One stick-slip cycle on a belt: ``period_s`` = ``slip_s`` + ``stick_s``;
    ``peak_to_peak_m`` of the block's position; ``slip_end_m`` where the slip's arc ends."""

    period_s: float
    slip_s: float
    stick_s: float
    peak_to_peak_m: float
    slip_end_m: float


def belt_cycle(*, mass_kg, spring_Npm, normal_N, mu_d, belt_speed_mps, start_m,
               start_speed_mps=None, end_speed_mps=None):
    """The cycle of a block on a spring to a fixed anchor on a belt at V that slips (kinetic
    friction μd N, forward) from position ``start_m`` at speed ``start_speed_mps`` (default V)
    on the harmonic arc about x_d = μd N / k until its speed is ``end_speed_mps`` again
    (default V; ≤ V) and then moves at exactly V back to ``start_m``. Coulomb's cycle: start at
    x_s = μs N / k, both speeds V. The arc: X = x - x_d, Y = ẋ/ω turn clockwise on the circle
    of radius |(X, Y)|; it ends at Y = end/ω, X < 0."""
    V = belt_speed_mps
    start_speed = V if start_speed_mps is None else start_speed_mps
    end_speed = V if end_speed_mps is None else end_speed_mps
    omega = math.sqrt(spring_Npm / mass_kg)
    x_d = mu_d * normal_N / spring_Npm
    x0, y0 = start_m - x_d, start_speed / omega
    radius = math.hypot(x0, y0)
    y_end = end_speed / omega
    if not (0 < V and 0 <= end_speed <= V and y_end < radius):
        raise ValueError("belt_cycle: needs 0 <= end speed <= V and an arc that reaches it")
    x_end = -math.sqrt(radius * radius - y_end * y_end)
    swept = math.atan2(y0, x0) - math.atan2(y_end, x_end) + 2.0 * math.pi
    slip_s = swept / omega
    stick_s = (start_m - (x_d + x_end)) / V
    return BeltCycle(slip_s + stick_s, slip_s, stick_s, 2.0 * radius, x_d + x_end)


@dataclasses.dataclass(frozen=True)
class BeltShift:
    """The law's belt cycle against Coulomb's (``belt_shift``): ``coulomb`` the closed form;
    ``exit_time_bound_s`` τ1 and ``exit_bound_m`` V τ1 (bounds of ξ); ``lag_bound_m`` D_max;
    ``period_low_s``, ``period_high_s`` the bracket of the law's period."""

    coulomb: BeltCycle
    exit_time_bound_s: float
    exit_bound_m: float
    lag_bound_m: float
    period_low_s: float
    period_high_s: float

    def relative(self, period_s):
        """``period_s`` relative to Coulomb's, T / T_C - 1."""
        return period_s / self.coulomb.period_s - 1.0


def belt_exit_speed_mps(law, belt_speed_mps):
    """The block's speed where its slip starts and ends in the law: V - 1.5 Δv (the end of the
    Stribeck band, beyond which the friction is μd N exactly)."""
    return belt_speed_mps - 1.5 * law.dv


def belt_shift(*, mass_kg, spring_Npm, normal_N, law, belt_speed_mps):
    """The bracket of the law's stick-slip period around Coulomb's (the module's items 1-3);
    ``law`` a ``frd.FrictionPairLaw``."""
    m, k, N, V = mass_kg, spring_Npm, normal_N, belt_speed_mps
    edge = belt_exit_speed_mps(law, V)
    x_s = law.mu_s * N / k
    coulomb = belt_cycle(mass_kg=m, spring_Npm=k, normal_N=N, mu_d=law.mu_d,
                         belt_speed_mps=V, start_m=x_s)
    tau1 = math.sqrt(3.0 * m * law.dv / (k * edge))
    tau_in = 0.5 * m * law.dv / ((law.mu_s - law.mu_d) * N) if law.mu_s > law.mu_d else tau1
    lag = law.dmax + 1.5 * law.dv * (tau1 + tau_in)

    def law_period(xi, lag_m):
        return belt_cycle(mass_kg=m, spring_Npm=k, normal_N=N, mu_d=law.mu_d, belt_speed_mps=V,
                          start_m=x_s + xi, start_speed_mps=edge,
                          end_speed_mps=edge).period_s + lag_m / V

    # T_arc over ξ in [0, V τ1] (monotone unless the arc is tiny: sampled, not assumed).
    arcs = [law_period(V * tau1 * i / 100, 0.0) for i in range(101)]
    return BeltShift(coulomb, tau1, V * tau1, lag, min(arcs), max(arcs) + lag / V)


def belt_law_period_s(*, mass_kg, spring_Npm, normal_N, law, belt_speed_mps, slip_start_m,
                      lag_m):
    """Item 1's identity: the law's period from where its slip starts (x_1) and its lag D."""
    edge = belt_exit_speed_mps(law, belt_speed_mps)
    return belt_cycle(mass_kg=mass_kg, spring_Npm=spring_Npm, normal_N=normal_N, mu_d=law.mu_d,
                      belt_speed_mps=belt_speed_mps, start_m=slip_start_m,
                      start_speed_mps=edge, end_speed_mps=edge).period_s + lag_m / belt_speed_mps


def oscillator_decay_per_cycle_m(*, spring_Npm, normal_N, mu_d):
    """Coulomb's free oscillator: the amplitude falls by 4 μd N / k per cycle."""
    return 4.0 * mu_d * normal_N / spring_Npm


def oscillator_turn_bound_m(*, mass_kg, spring_Npm, normal_N, law, spring_force_N):
    """How far the law can move one turning point of the free oscillator from Coulomb's, at a
    spring force k|x| > μs N there: the travel in the band, 1.5 Δv · 3 Δv m / (k|x| - μs N),
    plus the arc's change from leaving at 1.5 Δv, (1.5 Δv / ω)² / |X|, X = x - x_d."""
    excess = spring_force_N - law.mu_s * normal_N
    if not excess > 0:
        raise ValueError("oscillator_turn_bound_m: the spring force must exceed mu_s N")
    omega2 = spring_Npm / mass_kg
    amplitude = (spring_force_N - law.mu_d * normal_N) / spring_Npm
    edge = 1.5 * law.dv
    return edge * 3.0 * law.dv * mass_kg / excess + edge * edge / omega2 / amplitude


def incline_acceleration_mps2(*, incline_rad, mu_d, gravity_mps2=9.81):
    """Sliding down an incline (tan θ > μs) with kinetic friction μd: g (sin θ - μd cos θ)."""
    return gravity_mps2 * (math.sin(incline_rad) - mu_d * math.cos(incline_rad))
