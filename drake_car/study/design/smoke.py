"""The design study's smoke test (``--quick``): every part of the study run on a shortened
version of it, to see that the machinery works; its numbers are not findings. What it changes is
listed (``quick`` returns it), and every page says so: the report's first lines, every figure's
title (``TITLE``), summary.json's ``smoke_test``, and stderr when it starts."""

import dataclasses

TITLE = "SMOKE TEST (--quick), not findings: "
NOTE = ("Smoke test (--quick): every part of the study ran on a shortened version of it, to "
        "see that the machinery works. Its numbers are not findings about this car: do not "
        "read a verdict, a boundary or a ranking from them; run without --quick for those.")


def _timeline_text(t):
    return (f"rest {t.settle_s:g} s, speed-up {t.speed_up_s:g} s, straight {t.straight_s:g} s, "
            f"lane change {t.steer_s:g} s, after it {t.calm_s:g} s")


def quick(study):
    """(the smoke version of ``study``, what it changed: a list of sentences). Every phase
    shortened (the speed-up to 0.6 s: faster than any car can follow), 2 × 2 maps, the
    smallest Sobol sample, 4 Monte-Carlo states on a 1 m rough stretch, 2 per mitigation, 2
    noise runs, each line's first two values at one μs, a 2 m pull distance, the jam cases
    refined in one round (1/2 and 1/4 of the step)."""
    t = study.base.manoeuvre.timeline
    timeline = dataclasses.replace(t, settle_s=0.1, speed_up_s=0.6, straight_s=0.3,
                                   steer_s=0.6, calm_s=0.5)
    base = dataclasses.replace(study.base, manoeuvre=dataclasses.replace(
        study.base.manoeuvre, timeline=timeline))
    accel_g = t.speed_mps / timeline.speed_up_s / 9.81
    mc = study.monte_carlo
    smoke = dataclasses.replace(
        study, base=base, maps=[dataclasses.replace(m, points=2) for m in study.maps],
        sobol_base_samples=2, monte_carlo=dataclasses.replace(mc, samples=4, start_m=1.0,
                                                              length_m=2.0, spacing_m=0.5),
        mitigation_samples=2, noise_samples=2, pull_distance_m=2.0,
        accuracy=dataclasses.replace(study.accuracy,
                                     finest_step_s=study.base.plant.time_step / 4),
        lines=[dataclasses.replace(line, values=line.values[:2]) for line in study.lines],
        line_mu_s=study.line_mu_s[:1])
    changes = [
        f"the manoeuvre's timeline shortened from the base scene's ({_timeline_text(t)}) to "
        f"{_timeline_text(timeline)}: a speed-up to {t.speed_kph:g} km/h in "
        f"{timeline.speed_up_s:g} s asks {accel_g:.1f} g, which no car follows, so the lane "
        "change does not run at its speed",
        f"the maps {', '.join(f'{m.points} × {m.points}' for m in study.maps)} points → 2 × 2",
        f"Sobol's sample {study.sobol_base_samples} → 2 base samples",
        f"the Monte Carlo {mc.samples} → 4 jam states on a rough stretch of 1 to 2 m (the "
        f"study's: {mc.start_m:g} to {mc.length_m:g} m)",
        f"the mitigations over {study.mitigation_samples} → 2 states",
        f"the half-step noise sample {study.noise_samples} → 2 runs",
        f"the pull taken over {study.pull_distance_m:g} → 2 m",
        "the lines: each line's first two values, at μs "
        f"{', '.join(f'{m:g}' for m in study.line_mu_s[:1])} only",
        f"accuracy on demand down to a quarter of the step only (the study's: "
        f"{1e3 * study.accuracy.finest_step_s:g} ms)"]
    return smoke, changes
