"""Runs many scenes on Dask and keeps each result as it completes (``sweep.runner``):

  DIR/runs/<key>/   each run by its key (the scene's content, the files it reads, the code):
                    status.json (ok or failed, wall time, worker, error, the files'
                    checksums), scene.yaml (the scene as it ran), and for an ok run
                    history.csv, run.json (the worker's provenance) and diagram.dot
  DIR/index.csv     hash, name, status, wall_s, error: a row per run
  DIR/sweep.json    how it was made: each invocation's command, options, scenes (name ->
                    hash), counts and wall time

Scenes: every entry of --scene FILE (or the one of FILE:ENTRY), with --scene_text laid over
each, then each point of the --grid product (every --grid KEY=V1,V2,... a dotted scene key and
its values, YAML; a key may not be set by --scene_text too), named ENTRY[KEY=V,...] in the
index (its scene.yaml keeps the entry's name). Every scene is checked before anything runs:
bad input (a key, a value, an option, the folder) is one line on stderr naming it, exit status
2, nothing written.

Runs go to a local cluster (one single-threaded worker process per core, or --workers N; its
scheduler, workers and dashboards listen on 127.0.0.1 only) or, with --scheduler tcp://HOST:PORT,
to a running Dask cluster (its workers must be able to import drake_car: an installed package
or PYTHONPATH). Run the same command again to finish a killed sweep: the runs already in DIR
are kept and only the missing ones run, and those that Dask or the disk lost (a killed worker,
files not written; --rerun_failed: every failed one); unlike other commands' --out, a sweep's
folder is added to, never replaced (delete it to start afresh; a new folder that ends in an
error before any run finished is removed again). A run that fails is recorded and the others
go on; the exit status is then 1. An OS error (a full disk) stops the sweep: one line on
stderr, exit status 2, the runs finished kept whole.

  drake-car-sweep --scene scenes/paper_study.yaml --out results/sweep \\
      --scene_text "simulator: {end_time_s: 3.0}" --grid friction.law.mu_s=0.2,0.3,0.4
"""

import contextlib
import sys
import time

from pydrake.common.yaml import yaml_load

from drake_car.commands import cli
from drake_car.results.files import write_json
from drake_car.results.signals import terminate_as_exit
from drake_car.results.provenance import provenance
from drake_car.scene.load import SceneError
from drake_car.scene.scene import MeshcatLive
from drake_car.sweep.runner import jobs_of, missing, run_sweep
from drake_car.sweep.scene_grid import GRID_MAX_SCENES, build_scenes
from drake_car.sweep.store import check_sweep_folder, read_sweep_log, sweep_output

GRID_FORM = "KEY=V1,V2,... (KEY a dotted scene key, e.g. friction.law.mu_s=0.1,0.2)"


def main(argv=None):
    p = cli.parser(__doc__, name="sweep", scene=True, scene_required=True,
                   scene_help="scenes file (each entry a run) or FILE:ENTRY",
                   scene_text="YAML laid over every scene", cluster=True,
                   out_help="the sweep's folder: added to run by run, never replaced (the same "
                            "command again finishes a killed sweep; delete it to start afresh)")
    p.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2,...",
                   help="a scene key and its values; several --grid make their product")
    p.add_argument("--rerun_failed", action="store_true", help="run the failed runs again")
    p.add_argument("--large", action="store_true",
                   help=f"go on with a --grid product over {GRID_MAX_SCENES} scenes")
    args = p.parse_args(argv)
    grid = [_grid_option(p, item) for item in args.grid]
    if len({key for key, _ in grid}) < len(grid):
        p.error("--grid: a key is given twice")
    check_sweep_folder(args.out)
    scenes = build_scenes(args.scene, args.scene_text, grid,  # all checked, before any work
                          large=args.large)
    for name, scene in scenes.items():
        if isinstance(scene.visualization, MeshcatLive):
            raise SceneError(f"scene {name}: visualization = !MeshcatLive: a sweep's runs are "
                             "not watched; use !MeshcatReplay (replay.html) or leave it out")
    jobs = jobs_of(scenes)  # each run's key, once
    todo = missing(scenes, args.out, rerun_failed=args.rerun_failed, jobs=jobs)
    print(f"{len(scenes)} scenes: {len(todo)} runs to do", file=sys.stderr)
    began = time.perf_counter()
    with contextlib.ExitStack() as stack:
        # an OS error on DIR is one line; a new DIR that gets no run is removed again
        stack.enter_context(sweep_output(args.out))
        # SIGTERM: cancel what is left, close the cluster, rebuild the index, as on Ctrl-C
        stack.enter_context(terminate_as_exit(once=True))
        client = None
        if todo:  # connected before anything is written
            client = stack.enter_context(cli.cluster_client(args, len(todo)))
        workers = len(client.scheduler_info()["workers"]) if client else 0
        if client:
            print(f"on {workers} workers of {args.scheduler or 'a local cluster'}"
                  + (" (none yet: the runs wait for one)" if not workers else ""),
                  file=sys.stderr)
        entry = {"provenance": provenance(), "scenes_file": args.scene,
                 "scene_text": args.scene_text, "grid": dict(grid),
                 "scheduler": args.scheduler or "local cluster", "workers": workers,
                 "rerun_failed": args.rerun_failed, "scenes": {}, "summary": None}
        log = _log_invocation(args.out, entry)
        summary = run_sweep(scenes, args.out, client=client, progress=not args.quiet,
                            rerun_failed=args.rerun_failed, jobs=jobs)
        wall = time.perf_counter() - began
        entry["scenes"] = summary["hashes"]
        entry["summary"] = {k: summary[k] for k in ("ok", "failed", "reused")} | {"wall_s": wall}
        write_json(args.out / "sweep.json", log)
    failed = sorted(k for k, s in summary["status"].items() if s == "failed")
    print(f"{len(summary['status'])} runs: {summary['ok']} done now, {summary['reused']} "
          f"reused, {len(failed)} failed, in {wall:.1f} s; wrote {args.out} (index: "
          f"{args.out / 'index.csv'})", file=sys.stderr)
    if failed:
        raise SystemExit(1)


def _grid_option(p, item):
    key, sep, values = item.partition("=")
    key, values = key.strip(), [v.strip() for v in values.split(",")]
    if not sep or not all(key.split(".")) or not all(values):
        p.error(f"--grid {item!r}: must be {GRID_FORM}")
    if len(set(values)) < len(values):
        p.error(f"--grid {item!r}: a value is given twice")
    for v in values:
        try:
            yaml_load(data=f"value: {v}")
        except Exception:
            p.error(f"--grid {item!r}: {v!r} is not a YAML value")
    return key, values


def _log_invocation(out, entry):
    """sweep.json's record of invocations with ``entry`` appended (written now: the folder is
    then a sweep's, resumable even if this one is killed)."""
    out.mkdir(parents=True, exist_ok=True)
    log = read_sweep_log(out)
    log["invocations"].append(entry)
    write_json(out / "sweep.json", log)
    return log


def console():
    """The console script ``drake-car-sweep``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
