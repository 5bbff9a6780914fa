"""Does the car keep its mirror? For each friction set asked for: run a_k and b_k of the paper's
study, print the left-right differences of a_k's rods and front corner loads while it drives
straight (at given times and the largest before the lane change), claim 4's mirror residual
max |Δd(a, side) - Δd(b, other side)| and the lasting front split of both (issue 32); once the
run reaches place a (the 0.3 s before the lane change), a_k's rack force and sum of the front
steer angles there (a symmetric car driving straight holds 0: what is not is the launch's broken
mirror, docs/accuracy.md "The mirror").
``--seed_m`` adds an antisymmetric seed to a_k's rack position at the start (m), to see whether
a left-right difference is the run's own or any seed's.

  python benchmarks/mirror.py [--sets 1,2,3] [--scene_text YAML] [--end_s 10] [--seed_m 0]
                              [--times 0.5,1.1,4.9]
"""

import time

import numpy as np

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.load import load_scene
from drake_car.sim.simulate import SceneRunner
from drake_car.study.paper.claims import place_values, study_columns

TIMES_S = (0.5, 1.1, 4.9)


def run(name, text, end_s, seed_m=0.0):
    scene = load_scene(resource("scenes/paper_study.yaml"), child=name,
                       scene_text=f"{{{text}{', ' if text else ''}"
                                  f"simulator: {{end_time_s: {end_s}}}}}")
    runner = SceneRunner(scene)
    if seed_m:  # after the initial state is set, before Drake's initialization events
        built, initial = runner.built, runner.built.set_initial_state

        def seeded(root):
            initial(root)
            context = built.plant.GetMyMutableContextFromRoot(root)
            rack = built.car.joint("rack_slide")
            rack.set_translation(context, rack.get_translation(context) + seed_m)
        built.set_initial_state = seeded
    runner.start()
    began = time.process_time()
    runner.advance_to(scene.end_time_s)
    result = runner.finish()
    columns = study_columns(result.history)
    columns["steer_sum_rad"] = result.history["steer_fl_rad"] + result.history["steer_fr_rad"]
    return scene, columns, time.process_time() - began


def split(h, timeline):
    fl, fr = (place_values(h, timeline, f"Fz_{w}_N") for w in ("fl", "fr"))
    corner = 0.5 * (h["Fz_fl_N"][0] + h["Fz_fr_N"][0])
    return ((fl[1] - fr[1]) - (fl[0] - fr[0])) / corner


def main():
    parser = cli.parser(__doc__, prog="benchmarks/mirror.py", out=False,
                        scene_text="YAML laid over each run, its outer braces left out "
                                   "(\"friction: {pairs: translation}\")")
    parser.add_argument("--sets", default="1,2,3")
    parser.add_argument("--end_s", type=float, default=10.0)
    parser.add_argument("--seed_m", type=float, default=0.0)
    parser.add_argument("--times", default=",".join(f"{t:g}" for t in TIMES_S),
                        help="the times (s) at which a_k's left - right differences are printed")
    args = parser.parse_args()
    for k in args.sets.split(","):
        scene, a, cpu_a = run(f"a_{k}", args.scene_text, args.end_s, args.seed_m)
        t = a["t"]
        cells = []
        for ts in (float(x) for x in args.times.split(",")):
            if ts <= t[-1]:
                i = int(np.argmin(np.abs(t - ts)))
                cells.append(f"t {t[i]:.3f} s: rods {abs(a['dd_left_m'][i] - a['dd_right_m'][i]):.2e}"
                             f" m, loads {abs(a['Fz_fl_N'][i] - a['Fz_fr_N'][i]):.2e} N, rack "
                             f"force {a['rack_force_N'][i]:+.2e} N")
        straight = t < scene.manoeuvre.timeline.boundaries()[1]
        cells.append(f"largest before the lane change: rods "
                     f"{np.max(np.abs(a['dd_left_m'] - a['dd_right_m'])[straight]):.2e} m, loads "
                     f"{np.max(np.abs(a['Fz_fl_N'] - a['Fz_fr_N'])[straight]):.2e} N")
        t3 = scene.manoeuvre.timeline.boundaries()[1]
        if t[-1] >= t3 - 0.01:
            force, steer = (place_values(a, scene.manoeuvre.timeline, c)[0]
                            for c in ("rack_force_N", "steer_sum_rad"))
            cells.append(f"place a: rack force {force:+.3g} N, steer fl + fr {steer:+.2e} rad")
        print(f"a_{k} left - right: " + "; ".join(cells) + f" (CPU {cpu_a:.1f} s)", flush=True)
        if args.seed_m:
            continue
        _, b, cpu_b = run(f"b_{k}", args.scene_text, args.end_s)
        residual = max(float(np.max(np.abs(a[f"dd_{s}_m"] - b[f"dd_{o}_m"])))
                       for s, o in (("left", "right"), ("right", "left")))
        line = f"a_{k}|b_{k} mirror residual {residual:.3e} m"
        if args.end_s >= scene.manoeuvre.timeline.boundaries()[2] + 0.5:
            timeline = scene.manoeuvre.timeline
            line += (f"; lasting split a {100 * split(a, timeline):+.4f} %, "
                     f"b {100 * split(b, timeline):+.4f} %")
        print(line + f" (CPU {cpu_b:.1f} s)", flush=True)


if __name__ == "__main__":
    main()
