"""The solver axis of the error budget, measured: one run of the paper's study at several steps
and several looseness factors of SAP's relative tolerance (``simulator.sap_tolerance_factor``,
``systems.sap_ballast``); prints claim 2's values (each rod's Δd(b) - Δd(a)), the lasting front
split and the CPU of each. The twin that ``sweep.refine`` runs is factor 2 against 1 at the
finest step (issue 32).

  python benchmarks/solver_axis.py [--run b_3] [--steps_s 1e-3,2.5e-4] [--factors 1,1.25,2]
"""

import time

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.load import load_scene
from drake_car.sim.simulate import simulate
from drake_car.study.paper.claims import place_values, study_columns


def main():
    parser = cli.parser(__doc__, prog="benchmarks/solver_axis.py", out=False)
    parser.add_argument("--run", default="b_3")
    parser.add_argument("--steps_s", default="1e-3,2.5e-4")
    parser.add_argument("--factors", default="1,1.25,2")
    args = parser.parse_args()
    for step in (float(s) for s in args.steps_s.split(",")):
        for factor in (float(f) for f in args.factors.split(",")):
            scene = load_scene(resource("scenes/paper_study.yaml"), child=args.run,
                               scene_text=f"{{plant: {{time_step: {step}}}, simulator: "
                                          f"{{sap_tolerance_factor: {factor}}}}}")
            began = time.process_time()
            h = study_columns(simulate(scene).history)
            cpu = time.process_time() - began
            timeline = scene.manoeuvre.timeline
            shifts = []
            for side in ("left", "right"):
                at_a, at_b = place_values(h, timeline, f"dd_{side}_m")
                shifts.append(f"{side} {1e3 * (at_b - at_a):.6f} mm")
            fl, fr = (place_values(h, timeline, f"Fz_{w}_N") for w in ("fl", "fr"))
            corner = 0.5 * (h["Fz_fl_N"][0] + h["Fz_fr_N"][0])
            split = ((fl[1] - fr[1]) - (fl[0] - fr[0])) / corner
            print(f"{args.run} at {1e3 * step:g} ms, SAP tolerance x{factor:g}: Δd(b) - Δd(a) "
                  f"{', '.join(shifts)}; lasting split {100 * split:+.4f} %; CPU {cpu:.1f} s",
                  flush=True)


if __name__ == "__main__":
    main()
