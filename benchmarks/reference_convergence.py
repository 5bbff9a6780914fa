"""The explicit (reference) scheme on the friction rig's closed-form cases, by step, with the fast
scheme beside; the law's distance from the Coulomb closed form against its derived bracket
(``drake_car.law.friction.coulomb``, which derives it); and that distance's order in Δv.

Cases (``drake_car.study.rig.closed_forms``): a block stick-slipping on a belt at 0.1 m/s
(Δv = 1 % of it, Δmax = 1 % of the 10 mm stick), a free oscillator with friction (the paper's
law), an incline at 8° (sticks) and 14° (slides).

How to read it:
- belt: ``period_s`` of the last whole cycle (interpolated event times); ``vs_coulomb_pct``
  its distance from the Coulomb closed form; ``change_s`` its change from the row above (the
  same scheme at twice the step): a first-order scheme halves it with the step. ``xi_m``: how
  far beyond x_s = μs N / k the slip starts (bound V τ1); ``lag_m``: how far the block lags the
  belt while |u| ≤ 1.5 Δv (bound Δmax + ...); ``identity_s``: the law's period from these two
  (``coulomb.belt_law_period_s``) minus the measured one, the scheme's own error: it halves.
  The bracket line gives the law's period's derived range.
- oscillator: the largest |decay per cycle - 4 μd N / k| against the derived turn bound.
- incline: the creep held at 8° (m), the velocity after 0.3 s at 14° (m/s) and its slope
  against g (sin θ - μd cos θ).
- order: the reference's shift from Coulomb's period at Δv, Δv/4 and Δv/16 (Δmax fixed): the
  break-away delay is of order √Δv (the slope log(shift ratio)/log 4 ~ 0.5, not 1).

  python benchmarks/reference_convergence.py [--quick] [--out DIR]
"""

import math
import time

import numpy as np

from drake_car.commands import cli
from drake_car.law.friction.coulomb import incline_acceleration_mps2
from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.results.files import write_csv, write_json
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.study.rig.closed_forms import (
    BELT, BELT_LAW, belt_bracket, run_belt, run_incline, run_oscillator)

REFERENCE_STEPS_S = (8e-5, 4e-5, 2e-5, 1e-5, 5e-6)
FAST_STEPS_S = (1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2.5e-5)


def belt_table(steps_by_scheme):
    bracket = belt_bracket()
    x_s = BELT_LAW.mu_s * BELT["normal_force_N"] / BELT["spring_Npm"]
    print(f"belt: Coulomb's period {bracket.coulomb.period_s:.7f} s; the law's bracket "
          f"{bracket.period_low_s:.7f} .. {bracket.period_high_s:.7f} s "
          f"({100 * bracket.relative(bracket.period_low_s):+.3f} .. "
          f"{100 * bracket.relative(bracket.period_high_s):+.3f} %); ξ ≤ V τ1 = "
          f"{bracket.exit_bound_m:.3e} m, lag ≤ {bracket.lag_bound_m:.3e} m")
    rows = {k: [] for k in ("scheme", "time_step_s", "period_s", "vs_coulomb_pct", "change_s",
                            "xi_m", "lag_m", "identity_s", "cpu_s")}
    for scheme, steps in steps_by_scheme:
        last = None
        for dt in steps:
            began = time.process_time()
            r = run_belt(scheme, dt)
            cpu = time.process_time() - began
            period = float(r.periods_s[-1])
            row = dict(scheme=scheme, time_step_s=dt, period_s=period,
                       vs_coulomb_pct=100 * bracket.relative(period),
                       change_s=math.nan if last is None else period - last,
                       xi_m=float(r.slip_start_m[-1] - x_s), lag_m=float(r.lag_m[-1]),
                       identity_s=float(r.law_period_s[-1] - period), cpu_s=cpu)
            last = period
            for key, value in row.items():
                rows[key].append(value)
            print(f"  {scheme:9s} dt {dt:8.2e} s  period {period:.7f} s "
                  f"({row['vs_coulomb_pct']:+.4f} %)  change {row['change_s']:+.2e} s  "
                  f"ξ {row['xi_m']:.4e} m  lag {row['lag_m']:.4e} m  identity "
                  f"{row['identity_s']:+.2e} s  CPU {cpu:5.1f} s", flush=True)
    return rows


def oscillator_table(steps_by_scheme):
    rows = {k: [] for k in ("scheme", "time_step_s", "max_decay_error_m", "bound_m",
                            "decay_per_cycle_m")}
    for scheme, steps in steps_by_scheme:
        for dt in steps:
            r = run_oscillator(scheme, dt)
            error = float(np.max(np.abs(r.decay_per_cycle_m - r.coulomb_m)))
            for key, value in zip(rows, (scheme, dt, error, r.bound_m, r.coulomb_m)):
                rows[key].append(value)
            print(f"  oscillator {scheme:9s} dt {dt:8.2e} s  |decay - 4 μd N/k| ≤ "
                  f"{error:.3e} m (4 μd N/k = {r.coulomb_m:.4g} m, the law's turn bound "
                  f"{r.bound_m:.2e} m)", flush=True)
    return rows


def incline_table(steps_by_scheme):
    theta = math.radians(14.0)
    a = -incline_acceleration_mps2(incline_rad=theta, mu_d=0.15)
    rows = {k: [] for k in ("scheme", "time_step_s", "creep_8deg_m", "v_14deg_mps",
                            "slope_14deg_mps2")}
    for scheme, steps in steps_by_scheme:
        for dt in steps:
            creep = run_incline(scheme, dt, 8.0)[0]
            _, v, slope = run_incline(scheme, dt, 14.0)
            for key, value in zip(rows, (scheme, dt, creep, v, slope)):
                rows[key].append(value)
            print(f"  incline {scheme:9s} dt {dt:8.2e} s  creep at 8° {creep:.7e} m  v at 14° "
                  f"{v:.7f} m/s (a t = {a * 0.3:.7f})  slope {slope:.7f} (a = {a:.7f})",
                  flush=True)
    return rows


def order_table(fractions=(1.0, 0.25, 0.0625)):
    """The reference's period shift at Δv·fraction (Δmax fixed), at an eighth of its limit."""
    rows = {k: [] for k in ("dv_mps", "time_step_s", "shift_pct", "xi_m", "exit_bound_m")}
    x_s = BELT_LAW.mu_s * BELT["normal_force_N"] / BELT["spring_Npm"]
    for fraction in fractions:
        dv = BELT_LAW.dv_translation_mps * fraction
        law = StrutFrictionParameters(mu_s=BELT_LAW.mu_s, mu_d=BELT_LAW.mu_d,
                                      dv_translation_mps=dv,
                                      dmax_translation_m=BELT_LAW.dmax_translation_m)
        dt = 2 * BELT["mass_kg"] * dv / (1.5 * law.mu_s * BELT["normal_force_N"]) / 8
        r = run_belt("reference", dt, law=law)
        bracket = belt_bracket(law)
        shift = 100 * bracket.relative(float(r.periods_s[-1]))
        for key, value in zip(rows, (dv, dt, shift, float(r.slip_start_m[-1] - x_s),
                                     bracket.exit_bound_m)):
            rows[key].append(value)
        print(f"  order: Δv {dv:.3e} m/s  dt {dt:.2e} s  shift {shift:+.4f} %  ξ "
              f"{rows['xi_m'][-1]:.4e} m (bound {bracket.exit_bound_m:.4e})", flush=True)
    xi = np.array(rows["xi_m"])
    print("  ξ's order in Δv: " + ", ".join(
        f"{math.log(xi[i] / xi[i + 1]) / math.log(fractions[i] / fractions[i + 1]):.2f}"
        for i in range(len(xi) - 1)))
    return rows


def main():
    p = cli.parser(__doc__, prog="benchmarks/reference_convergence.py", out="optional",
                   out_help="a folder for the CSV tables (written all or nothing)")
    p.add_argument("--quick", action="store_true",
                   help="two steps per scheme and no order table (about a minute of CPU)")
    args = p.parse_args()
    reference = REFERENCE_STEPS_S[:2] if args.quick else REFERENCE_STEPS_S
    fast = FAST_STEPS_S[2:4] if args.quick else FAST_STEPS_S
    tables = {"belt": belt_table((("reference", reference), ("fast", fast)))}
    tables["oscillator"] = oscillator_table((("reference", (2e-5, 1e-5)),
                                             ("fast", (1e-3, 5e-4, 1e-4))))
    tables["incline"] = incline_table((("reference", (2e-5, 1e-5)), ("fast", (1e-3, 1e-4))))
    if not args.quick:
        tables["order"] = order_table()
    if args.out:
        with output_folder(args.out) as out:
            for name, rows in tables.items():
                write_csv(out / f"{name}.csv", rows)
            write_json(out / "reference_convergence.json", provenance(
                belt=BELT, belt_law=vars(BELT_LAW)))


if __name__ == "__main__":
    main()
