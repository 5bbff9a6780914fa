"""How a sweep scales with its workers: the same short runs (the paper's six lane changes cut to
--end_s, in --runs distinct scenes: each repeat ends 1 ms later, so no two share a content hash)
on a local cluster of 1 worker and of one worker per core, each through ``sweep.runner.run_sweep``
into a fresh results folder. Prints runs per second and the efficiency, speed-up / workers
(target >= 0.9).

What is timed: the sweep on a started cluster (its start, 1-2 s, is printed apart), i.e. the
runs (build, simulation), the scheduler's round trips and the parent writing each run's files.
The static equilibria the runs start from are settled on every worker before the clock starts
(they are cached per worker process, and which runs share one depends on where they land);
--equilibrium_in_runs times them instead, one per run (each scene named apart). The machine may
be shared: the load average and the cores other processes kept busy during each phase (the
machine's busy CPU time less this benchmark's processes', per second) are printed beside, with
"busy", the share of the workers' time spent in runs (the rest is the sweep's own overhead:
waiting for the scheduler and the parent), which other load does not change. On each cluster,
after the sweep, --empty_tasks tasks that do nothing are mapped and gathered as the sweep's are:
their wall per task is the scheduler's (and the client's) own cost of a task, with no run in it.

  python benchmarks/sweep_scaling.py [--runs 12] [--end_s 2.0] [--worker_counts 1,2]
                                     [--equilibrium_in_runs] [--empty_tasks 200] [--out DIR]
"""

import dataclasses
import os
import statistics
import tempfile
import time
from pathlib import Path

import psutil
from distributed import Client

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.load import dump_scene, load_scene
from drake_car.results.files import write_json
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.sweep.runner import cores, local_cluster, run_sweep
from drake_car.sweep.store import read_status

CHILDREN = ("a_1", "a_2", "a_3", "b_1", "b_2", "b_3")


def scenes(runs, end_s, *, apart=False):
    """``runs`` scenes; ``apart``: each named apart (the equilibrium cache is keyed by name)."""
    path = resource("scenes/paper_study.yaml")
    found = {}
    for i in range(runs):
        child, repeat = CHILDREN[i % 6], i // 6
        scene = load_scene(path, child=child, scene_text=(
            f"simulator: {{end_time_s: {end_s + 1e-3 * repeat!r}}}"))
        found[f"{child}#{repeat}"] = dataclasses.replace(
            scene, name=f"{child}#{repeat}") if apart else scene
    return found


def settle(scene_yamls):
    """On a worker: the static equilibrium of every scene, into the worker's cache."""
    from pydrake.common.yaml import yaml_load_typed

    from drake_car.scene.scene import Scene
    from drake_car.sim.simulate import static_equilibrium
    for text in scene_yamls:
        static_equilibrium(yaml_load_typed(schema=Scene, data=text))
    return len(scene_yamls)


def cpu_s():
    """(the machine's busy CPU seconds, this process tree's, this process's) so far."""
    t = psutil.cpu_times()
    machine = sum(getattr(t, k, 0.0) for k in ("user", "system", "nice", "irq", "softirq",
                                                "steal"))
    me = psutil.Process()
    tree = 0.0
    for p in [me, *me.children(recursive=True)]:
        try:
            c = p.cpu_times()
            tree += c.user + c.system
        except psutil.NoSuchProcess:
            pass
    c = me.cpu_times()
    return machine, tree, c.user + c.system


def nothing(i):
    """A task that does nothing (the scheduler's own cost per task)."""
    return i


def empty_tasks_ms(client, n):
    """Wall ms per task of ``n`` tasks that do nothing, mapped and gathered on ``client``
    (distinct keys, as the sweep's: nothing is reused)."""
    if n <= 0:
        return None
    began = time.perf_counter()
    client.gather(client.map(nothing, range(n), pure=False))
    return 1e3 * (time.perf_counter() - began) / n


def phase(todo, workers, *, warm, empty_tasks=0):
    """One sweep of ``todo`` on a fresh local cluster of ``workers``: its figures."""
    began = time.perf_counter()
    with local_cluster(workers) as cluster, Client(cluster, set_as_default=False) as client:
        client.run(lambda: bool(__import__("drake_car.sim.simulate")))  # the workers' imports
        started = time.perf_counter() - began
        if warm:
            yamls = [dump_scene(s) for s in todo.values()]
            client.gather([client.submit(settle, yamls, workers=[w], allow_other_workers=False,
                                         pure=False) for w in client.scheduler_info()["workers"]])
        load = os.getloadavg()[0]
        before = cpu_s()
        with tempfile.TemporaryDirectory() as out:
            summary = run_sweep(todo, out, client=client, progress=False)
            tasks = [read_status(p)["wall_s"] for p in (Path(out) / "runs").iterdir()]
        machine, tree, parent = (b - a for a, b in zip(before, cpu_s()))
        empty_ms = empty_tasks_ms(client, empty_tasks)
    wall = summary["wall_s"]
    if summary["failed"]:
        raise SystemExit(f"{summary['failed']} runs failed")
    others = max(0.0, machine - tree) / wall
    return {"workers": workers, "runs": summary["ok"], "wall_s": wall,
            "runs_per_s": summary["ok"] / wall, "mean_task_s": sum(tasks) / len(tasks),
            # the share of the workers' time spent in runs (the rest: waiting for work)
            "workers_busy": sum(tasks) / (workers * wall),
            "cluster_start_s": started, "load_average_1min_at_start": load,
            "parent_cores_busy": parent / wall, "others_cores_busy": others,
            # the cores the workers could have had: theirs, less what others took
            "free_cores": max(0.05, min(workers, cores() - others)),
            "empty_task_ms": empty_ms}


def main():
    p = cli.parser(__doc__, prog="benchmarks/sweep_scaling.py", out="optional")
    p.add_argument("--runs", type=int, default=12, help="distinct runs (default: %(default)s)")
    p.add_argument("--end_s", type=float, default=2.0,
                   help="simulated seconds of each run (default: %(default)s)")
    p.add_argument("--worker_counts", default=f"1,{cores()}",
                   help="worker counts, comma separated (default: %(default)s)")
    p.add_argument("--repeats", type=int, default=1,
                   help="rounds over the worker counts; medians are compared (default: 1)")
    p.add_argument("--equilibrium_in_runs", action="store_true",
                   help="time each run's static equilibrium too (default: settled before)")
    p.add_argument("--empty_tasks", type=int, default=200,
                   help="tasks that do nothing, timed on each cluster after its sweep: the "
                        "scheduler's cost per task (0: none; default: %(default)s)")
    args = p.parse_args()
    counts = [int(w) for w in args.worker_counts.split(",")]
    if (args.runs < 1 or not 0 < args.end_s <= 10 or min(counts) < 1 or args.repeats < 1
            or not 0 <= args.empty_tasks <= 100000):
        p.error("--runs >= 1, 0 < --end_s <= 10, --worker_counts >= 1 each, --repeats >= 1, "
                "0 <= --empty_tasks <= 100000")
    todo = scenes(args.runs, args.end_s, apart=args.equilibrium_in_runs)
    print(f"{cores()} cores; load average {' '.join(f'{x:.2f}' for x in os.getloadavg())} "
          f"before; {args.runs} runs of {args.end_s:g} s, static equilibria "
          + ("settled in each run" if args.equilibrium_in_runs else "settled beforehand"))
    print("workers  runs  wall_s  runs/s  task_s  busy  start_s  load  parent  others' cores"
          "  empty task ms")
    phases = []
    for _ in range(args.repeats):
        for n in counts:
            r = phase(todo, n, warm=not args.equilibrium_in_runs,
                      empty_tasks=args.empty_tasks)
            phases.append(r)
            print(f"{n:7d}  {r['runs']:4d}  {r['wall_s']:6.1f}  {r['runs_per_s']:6.3f}  "
                  f"{r['mean_task_s']:6.2f}  {r['workers_busy']:4.2f}  "
                  f"{r['cluster_start_s']:7.1f}  "
                  f"{r['load_average_1min_at_start']:4.2f}  {r['parent_cores_busy']:6.2f}  "
                  f"{r['others_cores_busy']:13.2f}  "
                  + (f"{r['empty_task_ms']:13.2f}" if r["empty_task_ms"] is not None else ""))
    summary = {}
    for n in counts:
        mine = [r for r in phases if r["workers"] == n]
        best = max(mine, key=lambda r: r["runs_per_s"])
        summary[n] = {k: statistics.median(r[k] for r in mine)
                      for k in ("runs_per_s", "others_cores_busy", "free_cores")}
        summary[n] |= {"best_runs_per_s": best["runs_per_s"],
                       "others_cores_busy_in_best": best["others_cores_busy"]}
    base = summary[counts[0]]
    print("workers  median: runs/s  speed-up  efficiency  others' cores  efficiency on the "
          "cores left  |  best: runs/s  efficiency  others' cores")
    for n, m in summary.items():
        m["speed_up"] = m["runs_per_s"] / base["runs_per_s"] * counts[0]
        m["efficiency"] = m["speed_up"] / n
        m["efficiency_free"] = (m["runs_per_s"] / m["free_cores"]) / (
            base["runs_per_s"] / base["free_cores"])
        m["efficiency_best"] = m["best_runs_per_s"] / base["best_runs_per_s"] * counts[0] / n
        print(f"{n:7d}  {m['runs_per_s']:14.3f}  {m['speed_up']:8.2f}  {m['efficiency']:10.2f}"
              f"  {m['others_cores_busy']:13.2f}  {m['efficiency_free']:26.2f}  |  "
              f"{m['best_runs_per_s']:12.3f}  {m['efficiency_best']:10.2f}  "
              f"{m['others_cores_busy_in_best']:13.2f}")
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())} after. Target: "
          "efficiency >= 0.9. On the cores left: runs/s per core the workers could have had, "
          "min(workers, cores - others' cores), against the first row's; best: the fastest "
          "phase of each worker count (the least disturbed)")
    if args.out:
        with output_folder(args.out) as out:
            write_json(out / "results.json", {
                "phases": phases, "summary": summary, "runs": args.runs, "end_s": args.end_s,
                "cores": cores(), "equilibrium_in_runs": args.equilibrium_in_runs,
                "provenance": provenance()})


if __name__ == "__main__":
    main()
