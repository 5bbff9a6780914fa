"""What the design study did not measure, and why, in words (pure). A missing value (NaN in the
table) is a run that failed, a hands-on run (no pull: the Sobol sample), or a hands-off run
that ended before the pull distance: ``runs.hands_off`` lengthens a run by the pull distance
at its asked speed, so a car that runs slower (a launch it cannot follow) covers less. The
report says "not measured (why)" there, and draws no conclusion from such a value."""

import math

NOT_MEASURED = "not measured"


def not_measured(why=None):
    """"not measured (why)"."""
    return NOT_MEASURED + (f" ({why})" if why else "")


def finite(values):
    """The finite ones of ``values`` (a list)."""
    return [v for v in values if v is not None and math.isfinite(v)]


def _hands_on(row):
    return row.get("role") == "sobol" or str(row.get("of", "")).startswith("sobol_")


def why(study, rows, outcome):
    """Why ``outcome`` is missing in some of ``rows`` (the design table's), in words; None
    if every row has it."""
    missing = [r for r in rows if not math.isfinite(r.get(outcome, math.nan))]
    if not missing:
        return None
    failed = [r for r in missing if r.get("status") != "ok"]
    ok = [r for r in missing if r.get("status") == "ok"]
    hands_on = [r for r in ok if outcome.startswith("pull") and _hands_on(r)]
    short = [r for r in ok if outcome.startswith("pull") and not _hands_on(r)]
    parts = []
    if short:
        text = (f"{_runs(short, len(rows))} ended before {study.pull_distance_m:g} m hands off")
        speeds = finite([r.get("speed_a_kph", math.nan) for r in short])
        asked = study.base.manoeuvre.timeline.speed_kph
        if speeds and max(speeds) < asked:
            low, high = min(speeds), max(speeds)
            ran = f"{low:.1f}" if f"{low:.1f}" == f"{high:.1f}" else f"{low:.1f} to {high:.1f}"
            text += f", their length set for {asked:g} km/h and their speed {ran} km/h"
        parts.append(text)
    if hands_on:
        parts.append(f"{_runs(hands_on, len(rows))} hands on (the Sobol sample's): no pull")
    if failed:
        parts.append(f"{_runs(failed, len(rows))} did not finish")
    others = len(missing) - len(failed) - len(hands_on) - len(short)
    if others:
        parts.append(f"{others} of {len(rows)} runs gave no value")
    return "; ".join(parts)


def _runs(some, total):
    """"the runs" (all of them), "the run" (the one), "3 of 5 runs"."""
    if len(some) == total:
        return "the run" if total == 1 else "the runs"
    return f"{len(some)} of {total} runs"
