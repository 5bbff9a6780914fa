"""One-degree-of-freedom friction rig: a block on a prismatic joint over a belt, with the strut
friction (paper's FRD law) acting on the block-belt joint under a constant normal force.

External force on the block: F(t) = force_N + force_rate_Nps·t + force_amp_N·sin(2π·force_freq_hz·t),
switched off after force_off_s; a spring of spring_Npm from the block to a fixed anchor.
Writes DIR/history.csv (t, x_m, v_mps [relative to the belt], creep_m, mu, phase [0 static,
1 kinetic], friction_N [on the block]) and DIR/history.png.

Example (break-away under a slow ramp):
  python experiments/friction_rig.py --out results/rig --force_rate_Nps 1000 --duration_s 1
"""

import dataclasses
import math

import _common  # noqa: F401

import matplotlib.pyplot as plt

from drake_car.law.frd_friction import StrutFrictionParameters
from drake_car.outputs import output_folder, provenance, write_csv, write_json
from drake_car.rig import RigOptions, simulate_rig


def main():
    p = _common.parser(__doc__)
    P, N, Z = _common.positive, _common.nonnegative, _common.number
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
    p.add_argument("--time_step_s", type=P("time_step_s"), default=1e-3)
    p.add_argument("--scheme", choices=["reference", "fast"], default="fast")
    p.add_argument("--mu_s", type=N("mu_s"), default=0.2)
    p.add_argument("--mu_d", type=N("mu_d"), default=0.15)
    p.add_argument("--dv_mps", type=P("dv_mps"), default=1e-4)
    p.add_argument("--dmax_m", type=P("dmax_m"), default=5e-6)
    p.add_argument("--shape", choices=["cubic", "linear"], default="cubic")
    _common.add_scene_options(p)
    args = p.parse_args()
    scene = _common.load_scene_option(p, args)
    if scene is not None:  # the law and the scheme from the scene's friction section
        friction = _common.resolve_or_exit(p, scene).friction
        if friction is None:
            p.error(f"--scene: scene {scene.name!r} has friction mode 'off'; the rig needs a "
                    "friction law")
        law, args.scheme = friction.params, friction.scheme
    else:
        try:
            law = StrutFrictionParameters(mu_s=args.mu_s, mu_d=args.mu_d,
                                          dv_translation_mps=args.dv_mps,
                                          dmax_translation_m=args.dmax_m,
                                          beta_shape=args.shape, creep_shape=args.shape)
        except ValueError as e:
            p.error(f"friction parameters: {e}")
    if args.time_step_s > args.duration_s:
        p.error("--time_step_s must not exceed --duration_s")
    options = RigOptions(
        mass_kg=args.mass_kg, normal_force_N=args.normal_force_N, force_N=args.force_N,
        force_rate_Nps=args.force_rate_Nps, force_amp_N=args.force_amp_N,
        force_freq_hz=args.force_freq_hz, force_off_s=args.force_off_s,
        spring_Npm=args.spring_Npm, belt_speed_mps=args.belt_speed_mps, x0_m=args.x0_m,
        v0_mps=args.v0_mps, time_step_s=args.time_step_s, scheme=args.scheme)
    history = simulate_rig(options, law, duration_s=args.duration_s)
    with output_folder(args.out) as out:
        write_csv(out / "history.csv", history)
        write_json(out / "rig.json", provenance(
            options=vars(args) | {"out": str(args.out)}, law=dataclasses.asdict(law)))
        plot(history, out / "history.png", args)
    print(f"final x = {history['x_m'][-1]:.6g} m, v = {history['v_mps'][-1]:.3g} m/s; "
          f"wrote {args.out}/history.csv")


def plot(h, path, args):
    fig, axes = plt.subplots(4, 1, figsize=(8, 8), sharex=True)
    axes[0].plot(h["t"], 1e3 * h["x_m"])
    axes[0].set_ylabel("x [mm]")
    axes[1].plot(h["t"], h["v_mps"])
    axes[1].set_ylabel("v rel. belt [m/s]")
    axes[2].plot(h["t"], 1e6 * h["creep_m"])
    axes[2].axhline(1e6 * args.dmax_m, color="k", lw=0.6, ls=":")
    axes[2].axhline(-1e6 * args.dmax_m, color="k", lw=0.6, ls=":")
    axes[2].set_ylabel("creep [µm]")
    axes[3].plot(h["t"], h["friction_N"])
    axes[3].set_ylabel("friction [N]")
    axes[3].set_xlabel("t [s]")
    fig.suptitle(f"Friction rig: {args.scheme} scheme, dt = {args.time_step_s:g} s, "
                 f"μs = {args.mu_s}, μd = {args.mu_d}, N = {args.normal_force_N:g} N")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
