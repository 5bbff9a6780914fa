"""The friction schemes against a converged reference on the one-DOF rig: error vs step and
wall time (a work-precision table). Case: 30 kg block, N = 500 N, spring 2e4 N/m, a 150 N 2 Hz
sinusoidal load (stick-slip), 0.5 s. Then the law at its threshold: a load of 0.95 and
0.999 μs·N held on the block (N = 3 kN) for 0.2 s, the fast scheme's largest creep and its
largest distance from the law's (the explicit scheme at a quarter of its limit), by step.

  python benchmarks/friction_convergence.py [--out results/convergence]
"""

import time


import numpy as np  # noqa: E402

from drake_car.commands import cli  # noqa: E402
from drake_car.law.friction.frd import StrutFrictionParameters, shape_max_slope  # noqa: E402
from drake_car.results.files import write_csv, write_json  # noqa: E402
from drake_car.results.folder import output_folder  # noqa: E402
from drake_car.results.provenance import provenance  # noqa: E402
from drake_car.sim.rigs.friction import RigOptions, simulate_rig  # noqa: E402

LAW = StrutFrictionParameters(mu_s=0.2, mu_d=0.15)
CASE = dict(mass_kg=30.0, normal_force_N=500.0, spring_Npm=2.0e4, force_amp_N=150.0,
            force_freq_hz=2.0)


def main():
    p = cli.parser(__doc__, prog="benchmarks/friction_convergence.py", out="optional")
    p.add_argument("--duration_s", type=float, default=0.5)
    args = p.parse_args()
    c = shape_max_slope(LAW.beta_shape) * LAW.mu_s * CASE["normal_force_N"] / LAW.dv_translation_mps
    explicit_limit = 2 * CASE["mass_kg"] / c
    ref_dt = explicit_limit / 8
    start = time.perf_counter()
    reference = simulate_rig(RigOptions(time_step_s=ref_dt, scheme="reference", **CASE), LAW,
                             duration_s=args.duration_s, record_period_s=1e-3)
    print(f"reference: explicit at dt = {ref_dt:.2e} s (stability limit {explicit_limit:.2e} s),"
          f" {time.perf_counter() - start:.1f} s wall")
    rows = {"scheme": [], "time_step_s": [], "max_abs_x_error_m": [], "final_x_error_m": [],
            "wall_s": []}
    runs = [("reference", explicit_limit / 2), ("reference", explicit_limit / 4),
            ("reference", 2 * explicit_limit)]
    runs += [("fast", dt) for dt in (5e-3, 2e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5)]
    for scheme, dt in runs:
        t0 = time.perf_counter()
        h = simulate_rig(RigOptions(time_step_s=dt, scheme=scheme, **CASE), LAW,
                         duration_s=args.duration_s, record_period_s=1e-3)
        wall = time.perf_counter() - t0
        error = np.abs(h["x_m"] - reference["x_m"])
        for key, value in (("scheme", scheme), ("time_step_s", dt),
                           ("max_abs_x_error_m", float(np.max(error))),
                           ("final_x_error_m", float(error[-1])), ("wall_s", wall)):
            rows[key].append(value)
        print(f"{scheme:9s} dt = {dt:8.2e} s  max |x - x_ref| = {np.max(error):9.3e} m  "
              f"wall {wall:6.2f} s")
    threshold = threshold_table()
    if args.out:
        with output_folder(args.out) as out:
            write_csv(out / "friction_threshold.csv", threshold)
            write_csv(out / "friction_convergence.csv", rows)
            write_json(out / "friction_convergence.json",
                       provenance(reference_time_step_s=ref_dt, case=CASE))


def threshold_table(normal=3000.0, steps=(2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4)):
    """The fast scheme's creep under a held load near μs·N against the law's, by step."""
    rows = {"load_ratio": [], "time_step_s": [], "max_creep_m": [], "max_abs_x_error_m": [],
            "slid": []}
    limit = 2 * CASE["mass_kg"] * LAW.dv_translation_mps / (
        shape_max_slope(LAW.beta_shape) * LAW.mu_s * normal)
    for ratio in (0.95, 0.999):
        case = dict(mass_kg=CASE["mass_kg"], normal_force_N=normal,
                    force_N=ratio * LAW.mu_s * normal)
        law = simulate_rig(RigOptions(time_step_s=limit / 4, scheme="reference", **case), LAW,
                           duration_s=0.2, record_period_s=1e-3)
        print(f"threshold {ratio} μs N: the law's largest creep {np.max(law['x_m']):.3e} m")
        for dt in steps:
            h = simulate_rig(RigOptions(time_step_s=dt, scheme="fast", **case), LAW,
                             duration_s=0.2, record_period_s=1e-3)
            error = float(np.max(np.abs(h["x_m"] - law["x_m"])))
            for key, value in (("load_ratio", ratio), ("time_step_s", dt),
                               ("max_creep_m", float(np.max(np.abs(h["x_m"])))),
                               ("max_abs_x_error_m", error),
                               ("slid", bool(np.any(h["phase"] > 0)))):
                rows[key].append(value)
            print(f"  fast dt = {dt:8.2e} s  largest creep {rows['max_creep_m'][-1]:.3e} m  "
                  f"max |x - x_law| = {error:.3e} m ({100 * error / LAW.dmax_translation_m:.1f} "
                  f"% of Δmax)")
    return rows


if __name__ == "__main__":
    main()
