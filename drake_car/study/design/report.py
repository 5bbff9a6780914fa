"""The design study's report (pure): the Markdown that answers the study's question in plain
words (``answers``), from the summary ``design_analysis.analyse`` makes of the rows
(``design_tables``): the car that ran (its base scene's), the answers, how it was made, the
factors with this car's values, the maps, lines, Sobol indices, jam states and mitigations, the
user's change (``--compare``), the accuracy. A smoke test (``--quick``) says so first."""

import math

from drake_car.law.numerics.round_off import cleaned
from drake_car.study.car.describe import car_lines
from drake_car.study.design.answers import line_values
from drake_car.study.design.compare import compare_lines
from drake_car.study.design.jam_cases import report_lines
from drake_car.study.design.resolved_runs import report_lines as local_report_lines
from drake_car.study.design.spec import car_value, paper_value
from drake_car.study.design.unmeasured import not_measured


# How the noise of each outcome is written: (scale, unit).
NOISE_UNITS = {"split_change_N": (1.0, "N"), "split_change_rel": (100.0, "% of the corner load"),
               "stuck_left": (100.0, "% of the run"), "stuck_right": (100.0, "% of the run"),
               "dd_left_a_m": (1e3, "mm"), "dd_left_b_m": (1e3, "mm"),
               "dd_right_a_m": (1e3, "mm"), "dd_right_b_m": (1e3, "mm"),
               "rack_force_change_N": (1.0, "N"), "wheel_torque_change_Nm": (1.0, "N m"),
               "pull_deg": (1.0, "deg"), "pull_lateral_m": (1.0, "m")}


def _pct(share):
    return "n/a" if share is None or not math.isfinite(share) else f"{100 * share:.0f}"


def _fmt(x, unit="", digits=2):
    return "n/a" if x is None or not math.isfinite(x) else f"{x:.{digits}f}{unit}"


def report(s, figures=""):
    """Markdown of a design-study summary ``s`` (drake-car-design); ``figures``:
    the path of the figures and the table from where the report is written."""
    study_threshold = 100 * s["split_threshold"]
    smoke = s.get("smoke_test")
    lines = ["# Where does strut friction change the wheel loads and the steering?"
             + (" (SMOKE TEST: not findings)" if smoke else ""), ""]
    if smoke:
        lines += [f"> **{smoke['note']}** What --quick changed: "
                  + "; ".join(smoke["changes"]) + ".", ""]
    lines += [f"Made by `{s['provenance']['command']}`, commit "
             f"{(s['provenance']['git_commit'] or 'unknown')[:10]}, {s['provenance']['created_utc']}; "
             f"{s['runs']['total']} rows of the table, {s['runs']['distinct']} distinct runs "
             f"({s['runs']['reused']} reused, {s['runs']['failed']} failed), "
             f"{s['wall_s'] / 60:.1f} min wall (the sweep "
             f"{s['runs'].get('sweep_wall_s', math.nan) / 60:.1f} min"
             + (f", accuracy on demand {s['accuracy']['wall_s'] / 60:.1f} min"
                if (s.get("accuracy") or {}).get("wall_s") is not None else "") + ")"
             + (" (the dirty checkout's files, not the commit's)"
                if s['provenance'].get('dirty') else "") + ".", "",
             "## The car", "", *car_lines(s["car"]), "",
             "## The question and the answer" + (" (smoke test: not findings)" if smoke else ""),
             "",
             "A strut that sticks leaves the coil spring of its side loaded differently from the "
             "other side's after a manoeuvre: the car then carries its weight unequally on its "
             "front wheels, the tie rods pull unequally on the rack, and a car whose driver lets "
             "go of the wheel turns. The paper found this effect \"practically zero\" for its "
             f"car. Here it counts when the front left/right load split changes by more than "
             f"{study_threshold:g} % of the static corner load "
             f"({s['split_threshold'] * s['car']['corner_load_N']['front']:.0f} N on this car), "
             f"or when the car turns by more than {s['pull_threshold_deg']:g} deg over "
             f"{s['pull_distance_m']:g} m hands off.", ""]
    lines += [f"- {line}" for line in s["answers"]] + [""]
    lines += _manoeuvre_lines(s.get("manoeuvre"))
    lines += compare_lines(s.get("compare"), smoke is not None)
    lines += ["## How it was made", ""]
    if s.get("scene"):
        lines += [f"- The base scene: the study's (`{s['study_file']}`) with the values of "
                  f"`--scene {s['scene']}` laid over it, so over every run."]
    if s.get("scene_text"):
        lines += [f"- Laid over the study's base scene, so over every run (`--scene_text`): "
                  f"`{s['scene_text']}`."]
    lines += [f"- {line}" for line in s["method"]] + [""]
    paper = "" if s.get("paper_car") else " | the paper's car"
    lines += ["## Factors and ranges", "", f"| factor | range | this car{paper} | why |",
              "|---|---|---|---|" + ("" if s.get("paper_car") else "---|")]
    lines += [factor_row(f, s.get("paper_car")) for f in s["factors"]]
    lines += ["", "## Maps", ""]
    for m in s["maps"]:
        lines.append(f"- `{figures}{m['figure']}`: {m['caption']}")
    lines += _line_section(s, figures)
    lines += ["", "## Which factors decide (Sobol indices, 95 % intervals)", ""]
    if s["sobol"] is None:
        lines.append("Not computed: Saltelli's estimators need every run of the sample, and "
                     f"these failed: {', '.join(s['sobol_failed'])} (see `{figures}table.csv` "
                     "and their `status.json`; rerun the command to retry).")
    else:
        for outcome, rows in s["sobol"].items():
            lines += [f"**{outcome}** (`{figures}sobol.png`):", "",
                      "| factor | S1 | ST | ranked? |", "|---|---|---|---|"]
            for r in rows:
                ranked = "yes" if r["resolved"] else "no: the interval is wider than the index"
                lines.append(f"| {r['label']} | {r['S1']:.3f} ± {r['S1_conf']:.3f} | "
                             f"{r['ST']:.3f} ± {r['ST_conf']:.3f} | {ranked} |")
            lines.append("")
    mc = s["monte_carlo"]
    lines += ["## Jam states and mitigations (Monte Carlo)", "",
              f"{mc['samples']} runs over random road unevenness before the manoeuvre "
              f"(±{1e3 * mc['roughness_m']:g} mm every {mc['spacing_m']:g} m, independent left "
              f"and right, from {mc['start_m']:g} to {mc['length_m']:g} m: during the "
              "speed-up), the driver letting go after it. The mitigations over the first "
              f"{s['mitigation_samples']} of the same states, against the car as it is at "
              f"their μs (`{figures}monte_carlo.png`).", "",
              "| case | runs | abs. split median / p90 [%] | above threshold [% of states] | "
              "abs. pull median / p90 [deg] | above threshold [% of states] | abs. split "
              "against the baseline, state by state: median [%] / lower beyond the errors in "
              "[% of states] | runs not converged |", "|---|---|---|---|---|---|---|---|"]
    for m in [s["jam_states"], *s["mitigations"]]:
        sp, pu, pa = m["split"], m["pull"], m.get("paired", {})
        lines.append(f"| {m['mitigation']} | {m['runs']} | {_fmt(sp.get('median'))} / "
                     f"{_fmt(sp.get('p90'))} | {_pct(sp.get('share_above'))} | "
                     f"{_fmt(pu.get('median'))} / {_fmt(pu.get('p90'))} | "
                     f"{_pct(pu.get('share_above'))} | "
                     + (f"{pa['median']:+.2f} / {_pct(pa['share_lower'])}" if pa.get("n")
                        else "-") + f" | {m.get('not_converged', 0)} |")
    lines += _gaps_note(s, ("mc", "mitigation"),
                        [m["pull"] for m in [s["jam_states"], *s["mitigations"]]])
    acc = s.get("accuracy")
    lines += [""] + (local_report_lines(acc) if (acc or {}).get("route") == "local"
                     else report_lines(acc, figures))
    lines += ["## Numerical noise", "",
              f"{s['noise']['pairs']} runs repeated at half the step; the largest change of "
              "each outcome, the error of every run not refined (the Sobol sample's and the "
              "runs below the jam μs):", ""]
    for key, level in s["noise"]["levels"].items():
        scale, unit = NOISE_UNITS.get(key, (1.0, ""))
        lines.append(f"- {key}: {scale * level:.3g} {unit}".rstrip())
    if s["noise"]["pairs"] and "pull_deg" not in s["noise"]["levels"]:
        why = (s.get("not_measured") or {}).get("noise")
        lines.append("- pull_deg: " + not_measured(
            "no half-step pair has it" + (f": {why}" if why else "")))
    lines += ["", "## Files", "",
              f"`{figures}table.csv`: one row per run (every varied value, every outcome, the "
              "run's key; `pandas.read_csv`); `sweep/runs/<hash>/`: each run's history and "
              "scene as it ran; figures as above.", ""]
    return "\n".join(lines)


def _gaps_note(s, roles, summaries):
    """The line under a table whose pull cells say n/a: not measured, and why."""
    if all(p.get("n") for p in summaries):
        return []
    whys = {role: w for role in roles if (w := (s.get("not_measured") or {}).get(role))}
    why = (next(iter(whys.values())) if len(set(whys.values())) == 1 else
           "; ".join(f"{role}: {w}" for role, w in whys.items()))
    return ["", f"n/a: the pull {not_measured(why or None)}."]


def _manoeuvre_lines(m):
    """Whether the runs reached their speed before the lane change (``tables.manoeuvre_summary``)."""
    if not m or not m["runs"]:
        return []
    asked = f"{m['speed_kph']:g} ± {m['tolerance_kph']:g} km/h at place a"
    if not m["off"]:
        return [f"Every run ran its manoeuvre's speed ({asked}).", ""]
    parts = ", ".join(f"{role} {n}" for role, n in sorted(m["off_by_role"].items()))
    slow = m["slowest"]
    return [f"**{m['off']} of {m['runs']} runs did not reach {asked}** ({parts}; the slowest "
            f"{slow['name']} at {slow['speed_a_kph']:.1f} km/h): the car did not follow their "
            "launch, and their lane change ran at the speed they reached; their outcomes are of "
            "that speed (`table.csv`: `speed_a_kph`).", ""]


def factor_row(f, paper_car):
    """A factor's row of the report's table: its range, this car's value (and the paper's car's
    beside it unless this car is the paper's), round-off of 0 printed as 0 (``cleaned``)."""
    span = f["high"] - f["low"]
    theirs = ("" if paper_car else " - |" if math.isnan(f["paper"])
              else f" {cleaned(f['paper'], span):g} |")
    outside = "" if f["low"] <= f["car"] <= f["high"] else " (outside the range)"
    return (f"| {f['label']} (`{f['key']}`) | {f['low']:g} ... {f['high']:g} | "
            f"{cleaned(f['car'], span):g}{outside} |{theirs} {f['reason']} |")


def factor_rows(study):
    return [{"key": f.key, "label": f.label or f.key, "low": f.low, "high": f.high,
             "car": car_value(study, f), "paper": paper_value(study, f),
             "reason": " ".join(f.reason.split())} for f in study.factors]


def _line_section(s, figures):
    if not s.get("lines"):
        return []
    lines = ["", "## One factor at a time", "",
             f"Hands off, at each μs, the other factors at this car's values "
             f"(`{figures}lines.png`): the lasting split [% of corner load] and the pull "
             f"[deg over {s['pull_distance_m']:g} m].", ""]
    for line in s["lines"]:
        mus = sorted({p["mu_s"] for p in line["points"]})
        lines += [f"**{line['label']}** (`{line['key']}`): {line['reason']}", "",
                  "| value | " + " | ".join(f"split μs {m:g} | pull μs {m:g}" for m in mus) + " |",
                  "|---|" + "---|---|" * len(mus)]
        for value in line_values(line):
            cells = []
            for m in mus:
                p = next(p for p in line["points"] if p["value"] == value and p["mu_s"] == m)
                cells += [_fmt(p["split_pct"]), _fmt(p["pull_deg"])]
            lines.append(f"| {value:g} | " + " | ".join(cells) + " |")
        lines.append("")
    if any(not math.isfinite(p["pull_deg"]) for line in s["lines"] for p in line["points"]):
        why = (s.get("not_measured") or {}).get("line")
        lines += [f"n/a: {not_measured(why)}.", ""]
    return lines
