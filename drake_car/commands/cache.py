"""The project's disk caches: where they are, how many entries each holds, and --clear.

Two caches live under one root (``DRAKE_CAR_CACHE_DIR``, default ~/.cache/drake_car; ``off``
turns both off): the static equilibria (``sim.equilibrium_cache``) and the lane change's rack
calibrated per car (``sim.lane_change_cache``). Entries are keyed by the content of their inputs
and by the code that made them, so a stale entry is never used; --clear deletes them all (the
next runs settle and calibrate anew).

  drake-car-cache [--clear]
"""

from drake_car.commands import cli
from drake_car.sim import equilibrium_cache, lane_change_cache

CACHES = {"static equilibria": equilibrium_cache, "lane-change calibrations": lane_change_cache}


def main(argv=None):
    p = cli.parser(__doc__, name="cache", out=False)
    p.add_argument("--clear", action="store_true", help="delete every entry of both caches")
    args = p.parse_args(argv)
    for what, cache in CACHES.items():
        folder = cache.cache_folder()
        if folder is None:
            print(f"{what}: off ({equilibrium_cache.ENVIRONMENT_VARIABLE}=off)")
            continue
        count = len(list(folder.glob("*.json"))) if folder.is_dir() else 0
        line = f"{what}: {folder} ({count} entries)"
        if args.clear:
            line += f"; deleted {cache.clear()}"
        print(line)


def console():
    """The console script ``drake-car-cache``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
