"""What a sweep's folder holds against the runs a command asks for, in words (read from each
run folder's status.json and the head of its scene.yaml: no history is read): for a command
that finds none of its runs there, so it can say what the folder holds instead."""

from collections import Counter
from pathlib import Path

from drake_car.scene.load import scene_hash
from drake_car.sweep.store import read_status


def _car_file(folder):
    """The car file a run's scene names (its scene.yaml's ``car_file``, in the lines before
    its car's values), or None: the shipped car."""
    try:
        with open(Path(folder) / "scene.yaml") as f:
            for _, line in zip(range(12), f):
                if line.startswith("  car_file:"):
                    value = line.split(":", 1)[1].strip().strip("'\"")
                    return None if value in ("", "null", "~") else value
                if line.startswith("  car:"):
                    break
    except OSError:
        pass
    return None


def holdings(out, scene_hashes):
    """{"finished": ok runs, "asked_other_code": runs of ``scene_hashes`` (the scenes' content
    hashes) made by other code or tyre files, "other_scenes": ok runs of other scenes, "cars":
    Counter of those runs' car files (None: the shipped car)}."""
    runs = Path(out) / "runs"
    held = {"finished": 0, "asked_other_code": 0, "other_scenes": 0, "cars": Counter()}
    if not runs.is_dir():
        return held
    for folder in sorted(runs.iterdir()):
        record = read_status(folder)
        if folder.name.startswith(".") or record is None or record["status"] != "ok":
            continue
        held["finished"] += 1
        if (record.get("key") or {}).get("scene_hash") in scene_hashes:
            held["asked_other_code"] += 1
        else:
            held["other_scenes"] += 1
            held["cars"][_car_file(folder)] += 1
    return held


def holdings_words(held):
    """"it holds 10 finished runs: 10 of other scenes (cars/hatch.yaml: 10)", or "it holds no
    finished run"."""
    if not held["finished"]:
        return "it holds no finished run"
    parts = []
    if held["other_scenes"]:
        cars = ", ".join(f"{car or 'the shipped car'}: {n}"
                         for car, n in held["cars"].most_common(4))
        more = len(held["cars"]) - 4
        parts.append(f"{held['other_scenes']} of other scenes (their cars: {cars}"
                     + (f" and {more} more" if more > 0 else "") + ")")
    if held["asked_other_code"]:
        parts.append(f"{held['asked_other_code']} of these scenes made by other code or tyre "
                     "files (not reused: a run is keyed by the code that made it)")
    return f"it holds {held['finished']} finished runs: " + "; ".join(parts)


def none_of_these(out, scenes, found, what):
    """Why ``out`` gives a command none of its runs ``scenes`` (name -> scene) to analyse:
    ``found`` (names) are there without what the analysis pairs them with (their half-step
    twins), or none is there and what the folder holds instead. ``what``: the runs' owner in
    words ("this car's ride runs")."""
    if found:
        return (f"holds {len(found)} of {what} but not with their half-step twins (run "
                "without --no_run to finish them)")
    held = holdings(out, {scene_hash(s) for s in scenes.values()})
    return (f"holds none of {what} (none of the {len(scenes)} this command asks for); "
            f"{holdings_words(held)}; run without --no_run to make them")
