"""Accuracy on demand for the design study's jam cases, and every row's error.

Where a dry strut jams (μs at or above the spec's ``accuracy.jam_mu_s``) its lasting state takes
one of two branches, and the time step can decide which (the paper's study: a jammed strut's
lasting split is 5.0 or 6.7 % of the corner load depending on the step). Those runs of the parts
named in ``accuracy.parts`` are refined by ``sweep.refine`` (dt, dt/2, dt/4, then halved where
an outcome has not converged, down to ``accuracy.finest_step_s``) on the study's own sweep
folder, so a rerun reuses every step already run. Each row of the study's table then carries,
per outcome it decides with (the lasting split, the pull):

- ``<outcome>``: the value at the finest step its run reached (refined runs), else at the
  study's step;
- ``<outcome>_error``: the run's own error (``classify``: the last difference when converged,
  the span of the last three steps when not), else the half-step noise sample's largest change
  (``tables.noise_levels``), said by ``<outcome>_error_from`` ("own steps" or "noise sample");
- ``<outcome>_converged``: yes / no (refined), "-" (not judged);
- ``<outcome>_step_s`` and ``<outcome>_values`` (";"-joined values at each step tried).
"""

import math

from drake_car.study.design.spec import outcomes
from drake_car.sweep.refine import refine
from drake_car.sweep.store import key_parts, run_key

# The outcomes the design study decides with, and their units in ``refine``'s terms.
DECIDING = {"split_change_rel": "fraction", "pull_deg": "deg"}
YES_NO = {True: "yes", False: "no", None: "-"}


def jam_scenes(study, parts):
    """name -> scene of the runs refined: those of ``study.accuracy.parts`` whose μs is at
    least ``jam_mu_s``, and every run of the user's change (``parts["compare"]``: its answer
    carries its own error at any μs) (``parts``: role -> {name: (scene, values)})."""
    a = study.accuracy
    scenes = {name: scene for name, (scene, _) in parts.get("compare", {}).items()}
    for role in a.parts:
        for name, (scene, _) in parts.get(role, {}).items():
            if scene.friction is not None and scene.friction.law.mu_s >= a.jam_mu_s * (1 - 1e-9):
                scenes[name] = scene
    return scenes


def tolerances(study):
    return {"split_change_rel": study.accuracy.split_tolerance,
            "pull_deg": study.accuracy.pull_tolerance_deg}


def outcomes_of(study):
    """``refine``'s outcomes: the deciding outcomes of each run (the pull where it has one)."""
    def of(runs):
        out = {}
        for name, run in runs.items():
            found = outcomes(run.history, run.scene, study)
            for key, unit in DECIDING.items():
                if math.isfinite(found[key]):
                    out[(name, key)] = (found[key], unit)
        return out
    return of


def refine_jam_cases(study, parts, simulate):
    """``sweep.refine.Refined`` of the jam cases (None when there are none). ``simulate``:
    name -> Scene to name -> Run, leaving failed runs out (``run_scenes(...,
    skip_failed=True)`` on the study's sweep folder)."""
    scenes = jam_scenes(study, parts)
    if not scenes:
        return None
    a = study.accuracy
    return refine(scenes, outcomes_of(study), tolerances(study), simulate,
                  finest_step_s=a.finest_step_s, budget_s=a.budget_s)


def apply(rows, refined, noise):
    """Each row's deciding outcomes with their errors (see the module), in place. ``noise``:
    outcome -> the half-step sample's largest change (the error of the runs not refined)."""
    found = {} if refined is None else refined.outcomes
    for row in rows:
        row["resolved_by"] = ("halving" if refined is not None and row["status"] == "ok"
                              and row["name"] in refined.steps_s else "-")
        for key in DECIDING:
            own = found.get((row["name"], key))
            if own is not None and row["status"] == "ok":
                row[key] = own["value"]
                row |= {f"{key}_error": own["error"], f"{key}_error_from": "own steps",
                        f"{key}_converged": YES_NO[own["converged"]],
                        f"{key}_step_s": own["step_s"],
                        f"{key}_values": ";".join(repr(float(v)) for v in own["values"])}
            else:
                level = noise.get(key, math.nan) if math.isfinite(row[key]) else math.nan
                row |= {f"{key}_error": level, f"{key}_error_from": "noise sample",
                        f"{key}_converged": "-", f"{key}_step_s": row.get("step_s", math.nan),
                        f"{key}_values": ""}
        row["refine_wall_s"] = (refined.run_wall_s(row["name"])
                                if refined is not None and row["name"] in refined.steps_s
                                else math.nan)
    return rows


def summary(refined, rows, study):
    """What the refinement found and cost, for the report: per part, the runs refined, how many
    converged for each outcome, the finest steps they needed, and every run that did not
    converge with its values at each step."""
    if refined is None:
        return None
    a = study.accuracy
    names = set(refined.steps_s)
    by_part = {}
    for row in rows:
        if row["name"] not in names:
            continue
        part = by_part.setdefault(row["role"], {"runs": 0, "needed_step_s": {}, **{
            key: {"converged": 0, "not_converged": 0} for key in DECIDING}})
        part["runs"] += 1
        step = min(refined.steps_s[row["name"]] or [math.nan])
        label = f"{1e3 * step:g} ms"
        part["needed_step_s"][label] = part["needed_step_s"].get(label, 0) + 1
        for key in DECIDING:
            flag = row.get(f"{key}_converged")
            if flag == "yes":
                part[key]["converged"] += 1
            elif flag == "no":
                part[key]["not_converged"] += 1
    unconverged = [{"name": r["name"], "role": r["role"], "outcome": key,
                    "values": r[f"{key}_values"], "step_s": r[f"{key}_step_s"]}
                   for r in rows for key in DECIDING
                   if r["name"] in names and r.get(f"{key}_converged") == "no"]
    return {"jam_mu_s": a.jam_mu_s, "parts": list(a.parts),
            "compare": any(part == "compare" for part in by_part),
            "tolerances": tolerances(study), "finest_step_s": a.finest_step_s,
            "budget_s": a.budget_s, "runs": len(names), "by_part": by_part,
            "failed": list(refined.failed), "not_converged": unconverged,
            "rounds": refined.rounds, "wall_s": refined.wall_s, "stopped": refined.stopped,
            "loops_cpu_s": loops_cpu_s(refined, rows)}


def loops_cpu_s(refined, rows):
    """The CPU of the runs' simulation loops (each run's ``cpu_s``, every distinct run once):
    {"unrefined": the study's own runs (its table's, the noise sample's included), "refinement":
    the jam cases' runs at the halved steps}."""
    own = {}
    for row in rows:
        if row["status"] == "ok" and math.isfinite(row.get("run_cpu_s", math.nan)):
            own[row["hash"]] = row["run_cpu_s"]
    halved = {}
    for level, runs in refined.runs.items():
        if isinstance(level, int) and level > 0:
            for run in runs.values():
                key = run_key(key_parts(run.scene))  # the sweep's key, as the rows'
                if key not in own and math.isfinite(run.cpu_s):  # a noise run may be one
                    halved[key] = run.cpu_s
    return {"unrefined": sum(own.values()), "refinement": sum(halved.values())}


def report_lines(acc, figures=""):
    """The report's section on the jam cases' accuracy."""
    if acc is None:
        return ["## Accuracy where the struts jam", "",
                "Not refined (`--no_verify`, or no run of the refined parts reaches the jam "
                "μs): every error is the half-step noise sample's.", ""]
    tol = acc["tolerances"]
    lines = ["## Accuracy where the struts jam", "",
             f"The {acc['runs']} runs of {', '.join(acc['parts'])} at μs ≥ "
             f"{acc['jam_mu_s']:g}" + (" and of the user's change (--compare) at any μs"
                                       if acc.get("compare") else "")
             + " were repeated at half and a quarter of their step and halved "
             f"further, down to {1e3 * acc['finest_step_s']:g} ms, until the lasting split "
             f"agreed within {100 * tol['split_change_rel']:g} % of the corner load and the pull "
             f"within {tol['pull_deg']:g} deg (rounds: {len(acc['rounds'])}, "
             f"{acc['wall_s'] / 60:.1f} min of wall; stopped: {acc['stopped']}). Their values "
             "in the maps, lines and mitigations are the finest step's, their errors their own "
             f"(`{figures}table.csv`: `*_error`, `*_converged`, `*_values` at each step)."
             + _cost(acc.get("loops_cpu_s")), "",
             "| part | runs | split converged / not | pull converged / not | finest step "
             "needed (runs) |", "|---|---|---|---|---|"]
    for role, p in acc["by_part"].items():
        steps = ", ".join(f"{k}: {v}" for k, v in sorted(p["needed_step_s"].items(),
                                                        key=lambda kv: -float(kv[0][:-3])))
        lines.append(f"| {role} | {p['runs']} | {p['split_change_rel']['converged']} / "
                     f"{p['split_change_rel']['not_converged']} | {p['pull_deg']['converged']} / "
                     f"{p['pull_deg']['not_converged']} | {steps} |")
    lines.append("")
    if acc["not_converged"]:
        lines += ["Not converged at the finest step tried (values at each step, coarsest "
                  "first; the split in % of the corner load, the pull in deg):", ""]
        for u in acc["not_converged"]:
            scale = 100.0 if u["outcome"] == "split_change_rel" else 1.0
            values = " / ".join(f"{scale * float(v):+.2f}" for v in u["values"].split(";"))
            lines.append(f"- {u['name']} ({u['role']}), {u['outcome']}: {values} (finest "
                         f"{1e3 * u['step_s']:g} ms)")
        lines.append("")
    if acc["failed"]:
        lines += [f"Failed at some step (not refined further): {', '.join(acc['failed'])}.", ""]
    return lines


def _cost(loops):
    """What the refinement cost, in the runs' simulation loops (``loops_cpu_s``)."""
    if not loops or not loops["unrefined"]:
        return ""
    ratio = (loops["unrefined"] + loops["refinement"]) / loops["unrefined"]
    return (f" In the runs' simulation loops (each run's `cpu_s`, every distinct run once) the "
            f"unrefined study took {loops['unrefined']:.0f} s of CPU and the refinement "
            f"{loops['refinement']:.0f} s: the study with it {ratio:.2f} × the study without.")
