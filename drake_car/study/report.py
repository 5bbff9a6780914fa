"""The paper's study as a summary (JSON-ready) and a report (Markdown), from the study's runs
and claims (pure: no simulation, no files)."""

import dataclasses

from drake_car.study.paper import (
    DISPLACEMENT_THRESHOLD_M, SYMMETRY_TOLERANCE, place_values, run_of)


def summary(study, claims, shifts, timeline, *, runs, half, figures, wall_s, provenance):
    """``study``: name -> StudyRun; ``runs``: name -> sim Run (for how each was made);
    ``half``: the half-step check (or None)."""
    rod_positions = {}
    for name, r in study.items():
        rod_positions[name] = {}
        for side in ("left", "right"):
            at_a, at_b = place_values(r.columns, timeline, f"dd_{side}_m")
            rod_positions[name][f"dd_{side}_at_a_m"] = at_a
            rod_positions[name][f"dd_{side}_at_b_m"] = at_b
    sets = {n: dataclasses.asdict(run_of(study, "a", n).friction) for n in (1, 2, 3)}
    return {
        "claims": claims,
        "friction_sets": sets,
        "cases": {"a": "lane change starting with a left turn",
                  "b": "lane change starting with a right turn"},
        "rod_positions": rod_positions,
        "rod_shift_b_minus_a_m": shifts,
        "runs": {name: run.record() | {"case": study[name].case,
                                       "friction_set": study[name].friction.number}
                 for name, run in runs.items()},
        "half_step_check": half,
        "timeline_s": dataclasses.asdict(timeline),
        "figures": figures,
        "wall_s": wall_s,
        "provenance": provenance,
    }


def report(s):
    """The Markdown report of a ``summary``."""
    prov = s["provenance"]
    lines = ["# The paper's study: lane change with strut friction", "",
             f"Made by `{prov['command']}`, commit {prov['git_commit'][:10]}, drake "
             f"{prov['drake']}, {prov['created_utc']}; {s['wall_s']:.0f} s wall in all.", "",
             "## Sets and cases", ""]
    for n, f in sorted(s["friction_sets"].items()):
        what = (f"lubricated strut: no dry friction, {f['damping_Nspm']:g} N s/m of damping"
                if f["mu_s"] == 0 else
                f"dry strut: μs = {f['mu_s']:g}, μd = {f['mu_d']:g}, no viscous damping")
        lines.append(f"- set {n}: {what}")
    for case, what in s["cases"].items():
        lines.append(f"- case {case}: {what}")
    lines += ["", "## The paper's claims", "",
              "| # | claim | reproduced | deciding number | figure |", "|---|---|---|---|---|"]
    half = s["half_step_check"]
    for i, c in enumerate(s["claims"], start=1):
        verdict = "yes" if c["reproduced"] else "**no**"
        if half is not None:
            verdict += f" (half step: {'yes' if half['verdicts'][i - 1] else 'no'})"
        lines.append(f"| {i} | {c['claim']} | {verdict} | {c['number']} | {c['figure']} |")
    lines += ["", f"\"Practically zero\" made explicit: {1e3 * DISPLACEMENT_THRESHOLD_M:g} mm "
              f"of rod displacement; \"almost identical\" curves: within "
              f"{100 * SYMMETRY_TOLERANCE:g} % of the largest |Δd|. Places a and b are averages "
              "over the 0.3 s before the lane change and the last 0.5 s.", ""]
    disagreements = [(i, c) for i, c in enumerate(s["claims"], start=1) if not c["reproduced"]]
    if disagreements:
        lines += ["## Where the model disagrees with the paper, and why", ""]
        for i, c in disagreements:
            lines.append(f"- **{i}. {c['claim']}**: {c.get('why', '').rstrip('.')}.")
        lines.append("")
    if half is not None:
        steps = ", ".join(f"{v:g}" for v in sorted(set(half["time_step_s"].values())))
        lines += [f"Every run was repeated at half its time step ({steps} s) "
                  "because at least one verdict disagrees with the paper; the verdicts above "
                  "show both.", ""]
    lines += ["## Rod positions at places a (before the lane change) and b (end)", "",
              "| run | Δd left a [mm] | Δd left b [mm] | Δd right a [mm] | Δd right b [mm] |",
              "|---|---|---|---|---|"]
    for name, pos in sorted(s["rod_positions"].items()):
        lines.append(f"| {name} | {1e3 * pos['dd_left_at_a_m']:.3f} | "
                     f"{1e3 * pos['dd_left_at_b_m']:.3f} | {1e3 * pos['dd_right_at_a_m']:.3f} | "
                     f"{1e3 * pos['dd_right_at_b_m']:.3f} |")
    lines += ["", "## Runs", "", "| run | case | set | wall [s] | real-time factor | "
              "frozen SAP steps | scene hash |", "|---|---|---|---|---|---|---|"]
    for name, info in sorted(s["runs"].items()):
        lines.append(f"| {name} | {info['case']} | {info['friction_set']} | "
                     f"{info['wall_s']:.1f} | {info['real_time_factor']:.2f} | "
                     f"{info['frozen_sap_steps']} | `{info['scene_hash']}` |")
    lines += ["", "Each run's scene, as it ran, is `<run>/scene.yaml` (rerun it with "
              "`python -m drake_car.run --scene <run>/scene.yaml --out DIR`). Frozen SAP steps: "
              "steps in which Drake's solver returned its initial guess "
              "(`drake_car/systems/sap_pacer.py`); the pacer keeps them at 0.",
              "", "Figures: " + ", ".join(f"`{f}`" for f in s["figures"]) +
              "; the Diagram: `diagram.svg`; the replay of run a_3: `a_3/replay.html`.", ""]
    return "\n".join(lines)

