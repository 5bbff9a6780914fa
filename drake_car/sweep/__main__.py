"""Runs many scenes on Dask and keeps each result as it completes (``sweep.runner``):

  DIR/runs/<key>/   each run by its key (the scene's content, the files it reads, the code):
                    status.json (ok or failed, wall time, worker, error, the files'
                    checksums), scene.yaml (the scene as it ran), and for an ok run
                    history.csv, run.json (the worker's provenance) and diagram.dot
  DIR/index.csv     hash, name, status, wall_s, error: a row per run
  DIR/sweep.json    how it was made: each invocation's command, options, scenes (name ->
                    hash), counts and wall time

Scenes: every entry of --scenes FILE (or the one of FILE:ENTRY), with --scene_text laid over
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

  python -m drake_car.sweep --scenes scenes/paper_study.yaml --out results/sweep \\
      --scene_text "simulator: {end_time_s: 3.0}" --grid friction.law.mu_s=0.2,0.3,0.4
"""

import contextlib
import itertools
import math
import sys
import time

from pydrake.common.yaml import yaml_dump, yaml_load

from drake_car import cli
from drake_car.law.checks import one_line
from drake_car.results.files import write_json
from drake_car.results.folder import terminate_as_exit
from drake_car.results.provenance import provenance
from drake_car.scene.load import SceneError, load_scene, load_scene_file, parse_scene_option
from drake_car.scene.scene import MeshcatLive
from drake_car.sim.simulate import estimate_wall_s
from drake_car.sweep.store import check_sweep_folder, read_sweep_log, sweep_output
from drake_car.sweep.runner import cores, dask_client, jobs_of, missing, run_sweep
from drake_car.sweep.scheduler import SCHEDULER_ADDRESS

GRID_FORM = "KEY=V1,V2,... (KEY a dotted scene key, e.g. friction.law.mu_s=0.1,0.2)"


def main(argv=None):
    p = cli.parser(__doc__, prog="python -m drake_car.sweep", out_help=(
        "the sweep's folder: each run is added to it as it finishes and reused by the same "
        "command again; never replaced (delete it to start afresh)"))
    p.add_argument("--scenes", required=True, help="scenes file (each entry a run) or FILE:ENTRY")
    p.add_argument("--scene_text", default="", help="YAML laid over every scene")
    p.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2,...",
                   help="a scene key and its values; several --grid make their product")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="a running Dask scheduler, e.g. tcp://127.0.0.1:8786 (default: a "
                        "local cluster on 127.0.0.1)")
    p.add_argument("--workers", type=cli.count, default=None,
                   help="worker processes of the local cluster (default: one per core)")
    p.add_argument("--rerun_failed", action="store_true", help="run the failed runs again")
    p.add_argument("--large", action="store_true",
                   help=f"go on with a --grid product over {GRID_MAX_SCENES} scenes")
    args = p.parse_args(argv)
    if args.scheduler and args.workers:
        p.error("--workers sizes the local cluster; a --scheduler cluster has its own workers")
    if args.scheduler and not SCHEDULER_ADDRESS.match(args.scheduler):
        _refuse_scheduler(args.scheduler, "not a Dask scheduler address; give tcp://HOST:PORT")
    grid = [_grid_option(p, item) for item in args.grid]
    if len({key for key, _ in grid}) < len(grid):
        p.error("--grid: a key is given twice")
    check_sweep_folder(args.out)
    scenes = build_scenes(args.scenes, args.scene_text, grid,  # all checked, before any work
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
            try:
                client = stack.enter_context(dask_client(
                    args.scheduler, min(args.workers or cores(), len(todo))))
            except (OSError, ValueError) as e:
                if not args.scheduler:
                    raise
                _refuse_scheduler(args.scheduler, e)
        workers = len(client.scheduler_info()["workers"]) if client else 0
        if client:
            print(f"on {workers} workers of {args.scheduler or 'a local cluster'}"
                  + (" (none yet: the runs wait for one)" if not workers else ""),
                  file=sys.stderr)
        entry = {"provenance": provenance(), "scenes_file": args.scenes,
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


def _refuse_scheduler(address, reason):
    """One line, exit 2, before anything is written."""
    print(f"error: --scheduler {address}: {one_line(reason)}", file=sys.stderr)
    raise SystemExit(2)


# A --grid product's size, checked before it is expanded: announced (with its estimate) past
# GRID_ANNOUNCE_SCENES, refused past GRID_MAX_SCENES unless --large. Expanding costs about
# GRID_SCENE_S and GRID_SCENE_BYTES a scene [EST: 28 ms and 15 kB (peak RSS growth) a scene,
# measured for a 100-scene grid of paper_study a_1 on a loaded 2-core machine; issue 25 found
# ~7 ms a scene, 10^6 scenes in ~2 h].
GRID_ANNOUNCE_SCENES = 1_000
GRID_MAX_SCENES = 20_000
GRID_SCENE_S, GRID_SCENE_BYTES = 0.03, 15e3


def check_grid_size(path, bases, scene_text, grid, *, large=False):
    """Refuses (SceneError) a product of more than GRID_MAX_SCENES scenes unless ``large``,
    and announces one of more than GRID_ANNOUNCE_SCENES on stderr, each with an estimate of
    the time and memory to expand it and of its runs' wall time."""
    sizes = [len(values) for _, values in grid]
    n = len(bases) * math.prod(sizes)
    if n <= GRID_ANNOUNCE_SCENES:
        return
    runs_s = n * estimate_wall_s(load_scene(path, child=bases[0], scene_text=scene_text or None))
    what = (f"--grid: {n} scenes ({' x '.join(map(str, sizes))}"
            + (f" x {len(bases)} entries" if len(bases) > 1 else "") + f"): about "
            f"{_duration(n * GRID_SCENE_S)} and {n * GRID_SCENE_BYTES / 1e9:.2g} GB to expand, "
            f"then about {_duration(runs_s)} of runs (one worker) [EST]")
    if n > GRID_MAX_SCENES and not large:
        raise SceneError(f"{what}: over the limit of {GRID_MAX_SCENES} scenes; give fewer "
                         "values, or --large to go on")
    print(f"{what}; going on", file=sys.stderr)


def _duration(seconds):
    return (f"{seconds:.0f} s" if seconds < 120 else f"{seconds / 60:.0f} min"
            if seconds < 7200 else f"{seconds / 3600:.0f} h")


def build_scenes(scenes_option, scene_text, grid, *, large=False):
    """name -> Scene: every entry of the scenes file (or FILE:ENTRY), ``scene_text`` laid over
    each, then each point of ``grid`` ([(key, [value, ...])], their product); all checked.
    ``large``: go on with a product over GRID_MAX_SCENES (``check_grid_size``)."""
    path, child = parse_scene_option(scenes_option)
    if not grid and child is None:
        return load_scene_file(path, scene_text or None)
    if not grid:
        return {child: load_scene(path, child=child, scene_text=scene_text or None)}
    bases = [child] if child is not None else list(load_scene_file(path))
    check_grid_size(path, bases, scene_text, grid, large=large)
    scenes = {}
    for point in itertools.product(*[[(key, v) for v in values] for key, values in grid]):
        text = overlay(scene_text, point)
        for base in bases:
            name = f"{base}[{','.join(f'{k}={v}' for k, v in point)}]"
            try:
                scenes[name] = load_scene(path, child=base, scene_text=text)
            except SceneError as e:
                raise SceneError(f"scene {name}: {e}") from None
    return scenes


def overlay(scene_text, point):
    """YAML text: ``scene_text`` with each (dotted key, YAML value) of ``point`` laid in."""
    try:
        data = yaml_load(data=scene_text) if scene_text.strip() else {}
    except Exception as e:
        raise SceneError(f"--scene_text {scene_text!r}: not YAML: {one_line(e)}") from None
    if not isinstance(data, dict):
        raise SceneError(f"--scene_text {scene_text!r}: must be a mapping of scene keys")
    for key, value in point:
        node, parts = data, key.split(".")
        for i, part in enumerate(parts):
            here = ".".join(parts[:i + 1])
            last = i == len(parts) - 1
            if part in node and (last or not isinstance(node[part], dict)):
                raise SceneError(f"--grid {key}: --scene_text sets {here} too; give it in one "
                                 "of them")
            if last:
                node[part] = yaml_load(data=f"value: {value}")["value"]
            else:
                node = node.setdefault(part, {})
    return yaml_dump(data)


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
