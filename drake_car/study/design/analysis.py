"""The design study from its finished runs: the tidy table (one row per run: every varied value,
every outcome, the run's key) and the analysis that the report reads (maps, lines, Sobol,
Monte Carlo and mitigations, the numerical noise), with the figures written beside it."""

import math

import numpy as np

from drake_car.results.provenance import provenance
from drake_car.study.design.resolved_runs import resolution_fields
from drake_car.study.design import answers
from drake_car.study.design.base_car import shipped_profile
from drake_car.study.design import figures
from drake_car.study.design import report
from drake_car.study.design import runs as runs_of
from drake_car.study.design import tables
from drake_car.study.design import unmeasured
from drake_car.study.car.describe import car_facts
from drake_car.study.design import smoke as smoke_test
from drake_car.study.design.spec import (
    OUTCOMES, car_value, factor, is_paper_car, outcomes, value_of)
from drake_car.sweep.store import key_parts, load_run, read_status, run_key


def table(study, parts, sweep_dir):
    """One row per run of ``parts`` ({role: {name: (scene, values)}}), from ``sweep_dir``."""
    keys = [f.key for f in study.factors] + [line.key for line in study.lines
                                             if line.key not in {f.key for f in study.factors}]
    rows = []
    for role, part in parts.items():
        for name, (scene, values) in part.items():
            key = run_key(key_parts(scene))
            status = (read_status(sweep_dir / "runs" / key) or {}).get("status", "missing")
            row = {"name": name, "role": role, "hash": key, "status": status,
                   "step_s": scene.plant.time_step}
            row |= {k: value_of(scene, k) for k in keys}
            row |= {"sample": values.get("sample", ""), "mitigation": values.get("mitigation", ""),
                    "line": values.get("line", ""), "of": values.get("of", "")}
            run = load_run(sweep_dir, key)[1] if status == "ok" else None
            result = (outcomes(run.history, scene, study) if run is not None
                      else {k: math.nan for k in (*OUTCOMES, "speed_a_kph", "speed_asked_kph")})
            rows.append(row | result | resolution_fields(run))
    return rows


def analyse(study, rows, out, sweep, wall_s, noise, acc=None, smoke=None, adapted=()):
    """The study's summary (what ``design_report.report`` writes up); figures into ``out``.
    ``rows``: the table with every row's errors (``jam_cases.apply``); ``noise``: the half-step
    sample's levels (``tables.noise_levels`` of the rows before); ``acc``: the jam cases'
    ``jam_cases.summary`` (None: not refined); ``smoke``: what ``--quick`` changed (None: the
    study as specified), said on every figure and in the summary."""
    threshold = 100 * study.split_threshold
    prefix = smoke_test.TITLE if smoke is not None else ""
    car = car_facts(study.base)
    star = "the paper's car" if is_paper_car(study) else "this car (the base scene's values)"
    outcomes_drawn = (("split_change_rel", 100.0, threshold,
                       "lasting front load split change [% of corner load]"),
                      ("pull_deg", 1.0, study.pull_threshold_deg,
                       f"heading change over {study.pull_distance_m:g} m hands off [deg]"))
    maps = []
    for i, spec in enumerate(study.maps):
        part = [r for r in rows if r["name"].startswith(f"map{i}_")]
        fx, fy = factor(study, spec.x), factor(study, spec.y)
        for outcome, scale, limit, unit in outcomes_drawn:
            xs, ys, values = tables.map_grid(study, spec, part, outcome, scale)
            _, _, errors = tables.map_grid(study, spec, part, f"{outcome}_error", scale)
            unconverged = tables.map_flags(study, spec, part, f"{outcome}_converged", "no")
            name = f"map{i}_{outcome}.png"
            why = unmeasured.why(study, part, outcome)
            figures.heat_map(xs, ys, values, x_label=fx.label, y_label=fy.label,
                             paper=(car_value(study, fx), car_value(study, fy)),
                             threshold=limit, title=f"{fy.label} × {fx.label}",
                             path=out / name, value_label=unit, noise=errors,
                             unconverged=unconverged, star_label=star, prefix=prefix,
                             missing=why)
            caption = (f"{unit} over {fx.label} × {fy.label}; the star is {star}, the line "
                       "the threshold; x marks cells within their numerical error of it, a "
                       "square cells not converged at the finest step tried")
            if why is not None and not np.isfinite(values).any():
                caption = (f"{unit} over {fx.label} × {fy.label}: "
                           f"{unmeasured.not_measured(why)}; no value, no threshold line")
            elif why is not None:
                caption += f"; n/m marks the cells {unmeasured.not_measured(why)}"
            maps.append({"figure": name, "caption": caption})
    lines = tables.line_tables(study, [r for r in rows if r["role"] == "line"])
    if lines:
        figures.lines(lines, study.line_mu_s, split_threshold=threshold,
                      pull_threshold=study.pull_threshold_deg,
                      noise=(100 * noise.get("split_change_rel", 0.0), noise.get("pull_deg", 0.0)),
                      path=out / "lines.png", prefix=prefix)
    sobol_rows = [r for r in rows if r["role"] == "sobol"]
    sobol = tables.sobol_tables(study, sobol_rows)
    if sobol is not None:
        figures.sobol_bars(sobol, out / "sobol.png", prefix=prefix)
    jam_label = f"jam states (μs {study.base.friction.law.mu_s:g})"
    jam_states = tables.group_summary(jam_label, [r for r in rows if r["role"] == "mc"], study)
    baseline = runs_of.mitigation_baseline(study)
    mitigations = tables.mitigation_table(study, rows, baseline)
    cases = {jam_label: [100 * r["split_change_rel"] for r in rows if r["role"] == "mc"]}
    for m in mitigations:
        cases[m["mitigation"]] = [100 * r["split_change_rel"] for r in rows
                                  if r["role"] == "mitigation"
                                  and r["mitigation"] == m["mitigation"]]
    figures.distributions(cases, x_label="|lasting front load split change| [% of corner "
                          "load]", threshold=threshold, path=out / "monte_carlo.png",
                          title="Jam states (Monte Carlo) and mitigations", prefix=prefix)
    failed = [r["name"] for r in rows if r["status"] != "ok"]
    return {"smoke_test": None if smoke is None else {"note": smoke_test.NOTE,
                                                      "changes": list(smoke)},
            "car": car, "paper_car": is_paper_car(study), "star": star,
            "mu_s": study.base.friction.law.mu_s if study.base.friction else 0.0,
            "split_threshold": study.split_threshold,
            "pull_threshold_deg": study.pull_threshold_deg,
            "pull_distance_m": study.pull_distance_m,
            "factors": report.factor_rows(study), "maps": maps, "lines": lines,
            "sobol": sobol, "sobol_failed": [r["name"] for r in sobol_rows
                                             if r["status"] != "ok"],
            "monte_carlo": vars(study.monte_carlo), "mitigation_samples": study.mitigation_samples,
            "jam_states": jam_states, "mitigation_mu_s": study.mitigation_mu_s,
            "mitigations": mitigations,
            "noise": {"pairs": sum(r["role"] == "noise" for r in rows), "levels": noise},
            "not_measured": {role: unmeasured.why(study, [r for r in rows if r["role"] == role],
                                                  "pull_deg")
                             for role in ("mc", "mitigation", "line", "noise")},
            "manoeuvre": tables.manoeuvre_summary(study, rows),
            "accuracy": acc,
            "answers": answers.answers(study, rows, sobol, jam_states, mitigations, noise,
                                     lines),
            "method": answers.method(study, adapted, shipped_profile(), smoke=bool(smoke)),
            "manoeuvre_adapted": list(adapted),
            "runs": {"total": len(rows), "distinct": len({r["hash"] for r in rows}),
                     "reused": sweep["reused"], "failed": len(failed),
                     "sweep_wall_s": sweep["wall_s"],
                     "failed_names": failed},
            "wall_s": wall_s, "provenance": provenance()}
