"""One-degree-of-freedom friction rig: a block on a prismatic joint over a belt, with the strut
friction (paper's FRD law) acting on the block-belt joint under a constant normal force.

External force on the block: F(t) = force_N + force_rate_Nps·t + force_amp_N·sin(2π·force_freq_hz·t),
switched off after force_off_s; a spring of spring_Npm from the block to a fixed anchor.
Writes DIR/history.csv (t, x_m, v_mps [relative to the belt], creep_m, mu, phase [0 static,
1 kinetic], friction_N [on the block]) and DIR/history.png.

The rig runs on the one runner, as a car's scene does: under the divergence monitor, with a
progress bar (not with --quiet), Ctrl-C/SIGTERM taken between the monitor's chunks; DIR/rig.json
holds the options, the law, how the run went (wall and CPU time, steps) and its provenance. The
explicit (reference) scheme refuses a step above its stability limit before it runs.
--resolve_events resolves the block's slips locally, as a car's scene does (sim.resolve): the
history's windows are sampled at their finer steps.

Example (break-away under a slow ramp):
  drake-car-friction-rig --out results/rig --force_rate_Nps 1000 --duration_s 1
"""

import dataclasses
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from drake_car.commands import cli  # noqa: E402
from drake_car.scene.load import load_section  # noqa: E402
from drake_car.scene.scene import Friction, ResolveEvents  # noqa: E402
from drake_car.results.files import write_csv, write_json  # noqa: E402
from drake_car.results.folder import output_folder  # noqa: E402
from drake_car.results.provenance import provenance  # noqa: E402
from drake_car.sim.rigs.friction import RigOptions, run_rig  # noqa: E402


def main(argv=None):
    p = cli.parser(__doc__, name="friction_rig")
    P, N, Z = cli.positive, cli.nonnegative, cli.number
    p.add_argument("--mass_kg", type=P("mass_kg"), default=30.0)
    p.add_argument("--normal_force_N", type=N("normal_force_N"), default=3000.0)
    p.add_argument("--force_N", type=Z("force_N"), default=0.0)
    p.add_argument("--force_rate_Nps", type=Z("force_rate_Nps"), default=0.0)
    p.add_argument("--force_amp_N", type=Z("force_amp_N"), default=0.0)
    p.add_argument("--force_freq_hz", type=N("force_freq_hz"), default=0.0)
    p.add_argument("--force_off_s", type=N("force_off_s"), default=math.inf)
    p.add_argument("--spring_Npm", type=N("spring_Npm"), default=0.0)
    p.add_argument("--belt_speed_mps", type=Z("belt_speed_mps"), default=0.0)
    p.add_argument("--x0_m", type=Z("x0_m"), default=0.0)
    p.add_argument("--v0_mps", type=Z("v0_mps"), default=0.0)
    p.add_argument("--duration_s", type=P("duration_s"), default=1.0)
    p.add_argument("--time_step_s", type=P("time_step_s"), default=1e-3,
                   help="the rig's plant step (s)")
    p.add_argument("--friction", default="{}",
                   help="the friction law and scheme, as a scene's friction section in YAML "
                        "(default: the paper's μs = 0.2, μd = 0.15, fast scheme), e.g. "
                        "\"{scheme: reference, law: {mu_s: 0.4, mu_d: 0.3}}\"")
    p.add_argument("--resolve_events", default=None,
                   help="resolve the block's slips locally (sim.resolve): a scene's "
                        "simulator.resolve_events section in YAML, without its solver twin "
                        "(the rig has no SAP ballast), e.g. \"{}\" or "
                        "\"{position_tolerance_m: 5e-6}\"; rig.json's run.resolution says "
                        "what it did (default: the whole run at its step)")
    args = p.parse_args(argv)
    cli.check_out(args)
    friction = load_section(Friction, "friction", args.friction, f"--friction {args.friction!r}")
    resolve = (None if args.resolve_events is None else load_section(
        ResolveEvents, "resolve_events", args.resolve_events,
        f"--resolve_events {args.resolve_events!r}"))
    if resolve is not None and resolve.solver_twin:
        if "solver_twin" in args.resolve_events:  # asked for: the rig cannot
            p.error("--resolve_events: solver_twin must be false on the friction rig (it has "
                    "no SAP ballast to loosen its solver's tolerance with)")
        resolve = dataclasses.replace(resolve, solver_twin=False)
    if resolve is not None and resolve.finest_step_s > args.time_step_s / 2:
        p.error(f"--resolve_events: finest_step_s = {resolve.finest_step_s:g} must be at most "
                f"half of --time_step_s ({args.time_step_s:g} s)")
    if args.time_step_s > args.duration_s:
        p.error("--time_step_s must not exceed --duration_s")
    options = RigOptions(
        mass_kg=args.mass_kg, normal_force_N=args.normal_force_N, force_N=args.force_N,
        force_rate_Nps=args.force_rate_Nps, force_amp_N=args.force_amp_N,
        force_freq_hz=args.force_freq_hz, force_off_s=args.force_off_s,
        spring_Npm=args.spring_Npm, belt_speed_mps=args.belt_speed_mps, x0_m=args.x0_m,
        v0_mps=args.v0_mps, time_step_s=args.time_step_s, scheme=friction.scheme)
    options.check(friction.law)
    with output_folder(args.out) as out:
        run = run_rig(options, friction.law, duration_s=args.duration_s,
                      progress=not args.quiet, resolve=resolve)
        history = run.history
        write_csv(out / "history.csv", history)
        write_json(out / "rig.json", provenance(
            options=dataclasses.asdict(options), law=dataclasses.asdict(friction.law),
            duration_s=args.duration_s, run=run.record()))
        plot(history, out / "history.png", options, friction.law)
    resolution = run.resolution
    windows = "" if resolution is None else (
        f"{resolution['window_count']} window(s) ({resolution['resolved']} resolved"
        + (f", finest step {resolution['finest_step_s']:g} s" if resolution["window_count"]
           else "") + "); ")
    print(f"final x = {history['x_m'][-1]:.6g} m, v = {history['v_mps'][-1]:.3g} m/s; "
          f"{windows}{run.wall_s:.1f} s wall, {run.cpu_s:.1f} s CPU; wrote "
          f"{args.out}/history.csv")


def plot(h, path, options, law):
    fig, axes = plt.subplots(4, 1, figsize=(8, 8), sharex=True)
    axes[0].plot(h["t"], 1e3 * h["x_m"])
    axes[0].set_ylabel("x [mm]")
    axes[1].plot(h["t"], h["v_mps"])
    axes[1].set_ylabel("v rel. belt [m/s]")
    axes[2].plot(h["t"], 1e6 * h["creep_m"])
    axes[2].axhline(1e6 * law.dmax_translation_m, color="k", lw=0.6, ls=":")
    axes[2].axhline(-1e6 * law.dmax_translation_m, color="k", lw=0.6, ls=":")
    axes[2].set_ylabel("creep [µm]")
    axes[3].plot(h["t"], h["friction_N"])
    axes[3].set_ylabel("friction [N]")
    axes[3].set_xlabel("t [s]")
    fig.suptitle(f"Friction rig: {options.scheme} scheme, dt = {options.time_step_s:g} s, "
                 f"μs = {law.mu_s}, μd = {law.mu_d}, N = {options.normal_force_N:g} N")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def console():
    """The console script ``drake-car-friction-rig``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
