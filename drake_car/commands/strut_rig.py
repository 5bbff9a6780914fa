"""The strut side-load friction rig (drake_car/sim/rigs/strut.py): the front strut of the
scene's car (--scene, --scene_text; default: the shipped car) clamped at its top mount, the
knuckle loaded with a side force, the rod stroked sinusoidally through the rig's load cell.
The rig is loaded as the car's strut at rest (drake_car/sim/rigs/at_rest.py): the side force
at the top mount that gives the strut the normal force (eq. 4) the car's has at its static
equilibrium; the study's side loads are multiples of it. The scene's dry friction law, when it
has one, makes the synthetic loop (and gives the paper's sets its Δv, Δmax, shapes). Writes
into DIR:

  at_rest.json     the car's strut at rest: its reaction, N, and the rig's side load and N
  loops.png        hysteresis loops (load cell force against stroke) for μs 0.2 and 0.4 at
                   0.5, 1 and 2 times the car's side load at rest (10 mm, 0.5 Hz)
  side_load.png    break-away and sliding force against side force, with μ·N of eq. (4)
  rig.csv          one row per run: break-away, sliding, apparent μs, measured μd, the friction
                   moment (with the rod's rotation), amplitude and frequency variants
  synthetic.csv, fit.json
                   the synthetic measured loop (the rig with the scene's law, else μs 0.3,
                   μd 0.22, at the car's side load at rest, plus noise) and the fit to it
  report.md        the car and its strut (car file, mass, b, l, r, the corner load), its
                   strut at rest, every rig run's break-away and sliding, the fit
  scene.yaml       the scene whose car's strut ran (drake-car-strut-rig --scene it reruns it)
  measured_fit.json  with --measured CSV (columns stroke_m in m, force_N in N, optionally
                   t_s; one row per sample), the test's --side_force_N and where it acts,
                   --side_force_point_below_top_m (default 0: the top mount, where the rig's
                   own loops and at_rest.json apply it): the fit, whether it is a confident
                   value, where the side force acted, the test's options, the car (and
                   scene.yaml, the scene whose car's strut the loop is fitted on)

A measured loop is checked against the rig it claims to come from before it is fitted
(study/rig/measured.py): a stroke beyond the strut's travel (a stroke in mm), a force beyond
what μ <= 2 allows at the side load, a force of the opposite sign, an amplitude or frequency
other than --amplitude_m and --frequency_hz (taken from the loop when left out) or a time
base other than --sample_period_s are refused, one line naming the file and the option. A fit
whose residual is far above the loop's own noise (the law does not describe the loop) is
flagged on stderr and in measured_fit.json, never printed as a confident value.

Example:  drake-car-strut-rig --out results/strut_rig
          drake-car-strut-rig --out results/my_strut --scene my_car.yaml:settle
          drake-car-strut-rig --out results/fit --measured loop.csv --side_force_N 1500 \\
              --sample_period_s 0.001
          drake-car-strut-rig --out results/fit --measured loop.csv --side_force_N 1000 \\
              --side_force_point_below_top_m 0.47    # at the shipped strut's lower mount
"""

import time

from drake_car.commands import cli
from drake_car.results.files import write_csv, write_json, write_text
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.sim.rigs.at_rest import SIDE_FORCE_POINT_BELOW_TOP_M
from drake_car.sim.rigs.strut import MAX_SIDE_FORCE_POINT_BELOW_TOP_M
from drake_car.study.rig.figures import plot_loops, plot_side_load
from drake_car.study.rig.fit import fit_loop_file
from drake_car.study.rig.loops import SYNTHETIC_NOISE, rig_study
from drake_car.study.rig.measured import side_force_where
from drake_car.study.rig.report import report, strut_facts
from drake_car.scene.load import dump_scene_file


def main(argv=None):
    p = cli.parser(__doc__, name="strut_rig", scene=True,
                   scene_help="the scene whose car's front strut is on the rig, FILE[:ENTRY] "
                              "(default: the shipped car)")
    p.add_argument("--quick", action="store_true", help="three side loads, no variants")
    p.add_argument("--measured", default=None, help="a measured loop to fit (CSV)")
    p.add_argument("--side_force_N", type=cli.positive("side_force_N"), default=None,
                   help="the measured test's side load (N), acting at "
                        "--side_force_point_below_top_m; required with --measured")
    p.add_argument("--side_force_point_below_top_m", default=None,
                   type=cli.within("side_force_point_below_top_m", 0.0,
                                   MAX_SIDE_FORCE_POINT_BELOW_TOP_M, "m"),
                   help="where the measured test's side force acts on the strut axis, in m "
                        f"below the top mount, in [0, {MAX_SIDE_FORCE_POINT_BELOW_TOP_M:g}] "
                        f"(default {SIDE_FORCE_POINT_BELOW_TOP_M:g}: the top mount, where the "
                        "rig's own loops and at_rest.json apply it; the strut's lower mount is "
                        "the car's front.strut_lower_mount_below_top_m)")
    p.add_argument("--amplitude_m", type=cli.positive("amplitude_m"), default=None,
                   help="the test's stroke amplitude (default: the loop's; given: checked "
                        "against it)")
    p.add_argument("--frequency_hz", type=cli.positive("frequency_hz"), default=None,
                   help="the test's stroke frequency (default: the loop's; given: checked)")
    p.add_argument("--sample_period_s", type=cli.positive("sample_period_s"), default=None,
                   help="the time between the loop's samples (default: its t_s column's; "
                        "required without one)")
    args = p.parse_args(argv)
    loop_options = ("side_force_N", "side_force_point_below_top_m", "amplitude_m",
                    "frequency_hz", "sample_period_s")
    if not args.measured and any(getattr(args, name) is not None for name in loop_options):
        p.error(f"--{next(n for n in loop_options if getattr(args, n) is not None)} describes "
                "a --measured loop's test; without --measured the rig study runs its own")
    cli.check_out(args)
    # the rig uses the scene's car and friction law (the car at rest on vertical tyres): its
    # drive and tyres never run
    scene = cli.scene_from_args(args, runs=False)
    car = scene.car
    start, cpu = time.time(), time.process_time()
    if args.measured:
        point = args.side_force_point_below_top_m
        fit, options, notes = fit_loop_file(
            car, args.measured, side_force_N=args.side_force_N,
            side_force_point_below_top_m=SIDE_FORCE_POINT_BELOW_TOP_M if point is None
            else point, amplitude_m=args.amplitude_m, frequency_hz=args.frequency_hz,
            sample_period_s=args.sample_period_s)
        side_force = f"{options.side_force_N:g} N {side_force_where(car.front, options)}"
        with output_folder(args.out) as out:
            write_text(out / "scene.yaml", dump_scene_file(scene, "drake-car-strut-rig"))
            write_json(out / "measured_fit.json", provenance(
                car=strut_facts(scene), side_force=side_force, fit=fit.summary(),
                options=vars(options),
                taken_from_the_loop=notes))
        print(f"side force {side_force}: {fit.line()}")
        return
    study = rig_study(scene, quick=args.quick)
    options, h, stroke, force, fit = study.synthetic
    rest, facts = study.at_rest.summary(), strut_facts(scene)
    with output_folder(args.out) as out:
        write_text(out / "scene.yaml", dump_scene_file(scene, "drake-car-strut-rig"))
        write_json(out / "at_rest.json", provenance(scene=scene.name, car=facts, at_rest=rest))
        plot_loops(study.loops, out / "loops.png",
                   f"Strut side-load rig: {facts['car_file'] or scene.name}'s front strut, "
                   "side force at the top mount, 10 mm at 0.5 Hz")
        plot_side_load(study.rows, out / "side_load.png")
        write_csv(out / "rig.csv", {k: [r[k] for r in study.rows] for k in study.rows[0]})
        write_csv(out / "synthetic.csv", {"t_s": h["t"], "stroke_m": stroke, "force_N": force})
        write_json(out / "fit.json", provenance(
            scene=scene.name, true_mu_s=study.synthetic_law.mu_s,
            true_mu_d=study.synthetic_law.mu_d, noise=SYNTHETIC_NOISE,
            side_force_N=options.side_force_N,
            side_force_point_below_top_m=options.side_force_point_below_top_m,
            fit=fit.summary(), runs=study.runs,
            wall_s=time.time() - start, cpu_s=time.process_time() - cpu))
        write_text(out / "report.md", report(
            car=facts, at_rest=rest, rows=study.rows, law=study.synthetic_law,
            fit=fit, runs=study.runs, prov=provenance()))
    print(f"the car's strut at rest: N = {rest['car_normal_N']:.1f} N; on the rig "
          f"{rest['rig_side_force_N']:.1f} N "
          f"{side_force_where(car.front, study.at_rest.rig_options())} gives N = "
          f"{rest['rig_normal_N']:.1f} N")
    print(f"synthetic loop (μs {study.synthetic_law.mu_s:g}, μd {study.synthetic_law.mu_d:g}): "
          f"fitted μs = {fit.mu_s:.4f} ± {fit.mu_s_ci95:.4f}, μd = {fit.mu_d:.4f} ± "
          f"{fit.mu_d_ci95:.4f} (95 %); wall {time.time() - start:.0f} s, CPU "
          f"{time.process_time() - cpu:.0f} s")


def console():
    """The console script ``drake-car-strut-rig``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
