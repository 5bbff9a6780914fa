"""What the design study costs, from a sample of its own runs: ``--per_part`` runs spread
evenly over each part (maps, lines, Sobol, Monte Carlo, mitigations) are run in one sweep on
a local cluster (one single-threaded worker per core, results in memory), timed; the estimate
of the whole study's sweep weights each part's mean worker time per run by its share of the
study's distinct runs and divides by the workers at the measured efficiency (the sum of the
runs' worker times over workers × wall). The refinement of the jam cases is not sampled (its
cost is in the study's own report). An estimate [EST]: a sample, not the study; run it on a
quiet machine and compare with the study's report.

``--resolve``: the same sample run twice more, alternately with every run with dry friction
resolving its events locally (``study.design.resolved_runs``; the study's default resolves its
jam cases only) and without (``--no_verify``); the runs' CPU time (Run.cpu_s: the simulation
loop, windows included) per part and in all, and their ratio: what resolving costs a run of
each part (the whole study's jobs: ``benchmarks/design_cost.py``).

  python benchmarks/design_sample_cost.py [--per_part 6] [--workers 2] [--resolve]
"""

import collections
import time

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.load import scene_hash
from drake_car.study.design import runs as runs_of
from drake_car.study.design.spec import load_study
from drake_car.sweep.runner import run_scenes


def main():
    p = cli.parser(__doc__, prog="benchmarks/design_sample_cost.py", out=False, cluster=True)
    p.add_argument("--per_part", type=int, default=6)
    p.add_argument("--resolve", action="store_true",
                   help="also the CPU ratio of the sample resolving its events locally")
    args = p.parse_args()
    if args.per_part < 1:
        p.error("--per_part must be >= 1")
    study = load_study(resource("scenes/studies/design.yaml"), "study")
    parts = {"map": {n: (runs_of.hands_off(study, s), v)
                     for n, (s, v) in runs_of.map_scenes(study).items()},
             "line": runs_of.line_scenes(study), "sobol": runs_of.sobol_scenes(study),
             "mc": runs_of.monte_carlo_scenes(study),
             "mitigation": runs_of.mitigation_scenes(study)}
    distinct = {role: len({scene_hash(s) for s, _ in part.values()})
                for role, part in parts.items()}
    sample = {}
    for role, part in parts.items():
        names = list(part)
        count = min(args.per_part, len(names))
        for k in range(count):
            name = names[int(k * len(names) / count)]
            sample[name] = (role, part[name][0])
    began = time.perf_counter()
    with cli.cluster_client(args, len(sample)) as client:
        workers = len(client.scheduler_info()["workers"])
        runs = run_scenes({n: s for n, (_, s) in sample.items()}, client=client)
    wall = time.perf_counter() - began
    per_role = collections.defaultdict(list)
    for name, run in runs.items():
        per_role[sample[name][0]].append(run.wall_s)
    busy = sum(r.wall_s for r in runs.values())
    efficiency = busy / (workers * wall)
    print(f"{len(runs)} runs on {workers} workers: {wall:.1f} s of wall, worker time "
          f"{busy:.1f} s, efficiency {efficiency:.2f} (start-up included)")
    total = 0.0
    for role, times in per_role.items():
        mean = sum(times) / len(times)
        total += mean * distinct[role]
        print(f"  {role:10s} {len(times)} sampled, {mean:.2f} s a run; the study has "
              f"{distinct[role]} distinct")
    print(f"the study's sweep [EST]: {total / 60:.1f} worker-minutes, "
          f"{total / workers / efficiency / 60:.1f} min of wall on {workers} workers at "
          f"{efficiency:.2f}")
    if args.resolve:
        resolved_cost(args, study, sample)


def resolved_cost(args, study, sample):
    """The sample's runs' CPU time plain and resolving their events locally, alternately."""
    from drake_car.study.design.resolved_runs import resolving
    plain = {n: s for n, (_, s) in sample.items()}
    resolved = {n: resolving(study, s) for n, s in plain.items()}
    cpu = {"plain": collections.defaultdict(float), "resolved": collections.defaultdict(float)}
    with cli.cluster_client(args, 2 * len(sample)) as client:
        for label, scenes in (("plain", plain), ("resolved", resolved)):
            for name, run in run_scenes(scenes, client=client).items():
                cpu[label][sample[name][0]] += run.cpu_s
    for role in cpu["plain"]:
        print(f"  {role:10s} CPU of the runs: {cpu['plain'][role]:7.1f} s plain, "
              f"{cpu['resolved'][role]:7.1f} s resolved: "
              f"{cpu['resolved'][role] / cpu['plain'][role]:.2f} x")
    total_plain, total_resolved = sum(cpu["plain"].values()), sum(cpu["resolved"].values())
    print(f"  all: {total_plain:.1f} s plain, {total_resolved:.1f} s resolved: "
          f"{total_resolved / total_plain:.2f} x (the runs' CPU; the study's start-up and "
          "analysis come on top of both)")


if __name__ == "__main__":
    main()
