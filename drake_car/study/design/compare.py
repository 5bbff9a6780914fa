"""What the user's own design change does (``drake-car-design --compare YAML``), with its error:
the change (YAML laid over the study's base scene, e.g. ``"car: {front: {spring_offset_m:
0.03}}"``) against the car as it is, on the flat road hands off at each of the study's line μs
(``compare_scenes``: always made accurate, with the jam cases), and state by state over the
Monte Carlo's jam states as one more mitigation (``with_compare``). The answer: the lasting
split (N and % of the corner load), the pull and the steering-wheel torque, with and without
the change, each with its run's own error, and whether the difference exceeds the errors."""

import dataclasses
import math

from drake_car.scene.load import load_scene
from drake_car.study.design.runs import hands_off
from drake_car.study.design.spec import Mitigation, with_value

NAME = "your change (--compare)"
PART = "compare"


def with_compare(study, text):
    """``study`` with the change as one more mitigation (over the same jam states); checked:
    the change must make a valid scene over the base."""
    load_scene(scene_text=text, base=study.base, text_origin="--compare")
    return dataclasses.replace(study, mitigations=[*study.mitigations, Mitigation(
        name=NAME, scene_text=text, reason=f"the change given by --compare: {text}")])


def compare_scenes(study, text):
    """{name: (scene, values)}: the base scene hands off on the flat road at each of the
    study's ``line_mu_s``, as it is and with the change."""
    scenes = {}
    for j, mu_s in enumerate(study.line_mu_s):
        for which in ("base", "change"):
            name = f"compare_mu{j}_{which}"
            base = study.base if which == "base" else load_scene(
                scene_text=text, base=study.base, text_origin="--compare")
            scene = hands_off(study, with_value(study, {"friction.law.mu_s": mu_s}, name=name,
                                                base=base))
            scenes[name] = (scene, {"mu_s": mu_s, "compare": which})
    return scenes


def _cell(row, key, scale=1.0):
    value = scale * row.get(key, math.nan)
    error = scale * row.get(f"{key}_error", math.nan)
    return {"value": value, "error": error, "converged": row.get(f"{key}_converged", "-"),
            "values": row.get(f"{key}_values", "")}


def compare_summary(study, rows, text, noise):
    """Per μs the base and the changed run's outcomes with their errors, the difference and
    whether it is resolved (larger than the two errors together); the jam states' paired
    result is the mitigations' (``tables.mitigation_table``)."""
    if text is None:
        return None
    by_name = {r["name"]: r for r in rows if r["role"] == PART}
    out = []
    for j, mu_s in enumerate(study.line_mu_s):
        base, change = by_name.get(f"compare_mu{j}_base"), by_name.get(f"compare_mu{j}_change")
        if base is None or change is None or "ok" not in (base["status"], change["status"]):
            out.append({"mu_s": mu_s, "failed": True})
            continue
        cells = {}
        for which, row in (("base", base), ("change", change)):
            corner = row["split_change_N"] / row["split_change_rel"] \
                if row["split_change_rel"] else math.nan
            cells[which] = {
                "split_rel": _cell(row, "split_change_rel", 100.0),
                "split_N": {k: (v * corner if k in ("value", "error") else v)
                            for k, v in _cell(row, "split_change_rel").items()},
                "pull_deg": _cell(row, "pull_deg"),
                "torque_Nm": {"value": row["wheel_torque_change_Nm"],
                              "error": noise.get("wheel_torque_change_Nm", math.nan)}}
        diff = {}
        for key in ("split_rel", "pull_deg"):
            b, c = cells["base"][key], cells["change"][key]
            d = abs(c["value"]) - abs(b["value"])
            e = b["error"] + c["error"]
            open_ = "no" in (b["converged"], c["converged"])
            diff[key] = {"value": d, "error": e, "open": open_,
                         "verdict": ("not measured" if not math.isfinite(d) else
                                     "not converged" if open_ else
                                     "within the errors" if not abs(d) > e else
                                     "lower" if d < 0 else "higher")}
        out.append({"mu_s": mu_s} | cells | {"difference": diff})
    return {"text": text, "by_mu_s": out}


def _pm(cell, digits, unit=""):
    v, e = cell["value"], cell["error"]
    if not math.isfinite(v):
        return "n/a"
    shown = f"{v:+.{digits}f}{unit}"
    if cell.get("converged") == "no":
        return shown + " (not converged)"
    return shown + (f" ± {e:.{digits}f}" if math.isfinite(e) else "")


def compare_lines(c, smoke=False):
    """The report's section on the user's change (nothing without --compare)."""
    if c is None:
        return []
    lines = [f"## Your change: `{c['text']}`" + (" (smoke test: not findings)" if smoke else ""),
             "", "Laid over the base scene, against the car as it is, each on the flat road "
             "after the lane change, hands off; each run made accurate with the jam cases and "
             "carrying its own error (\"Accuracy where the struts jam\" says how: windows "
             "resolved locally, or the run's own halvings). The split is the "
             "lasting change of Fz_fl - Fz_fr from place a to b; the steering-wheel torque "
             "the lasting change the driver holds before letting go (± the half-step noise); "
             "the pull the heading change hands off. A difference counts where it exceeds the "
             "two runs' errors together.", "",
             "| μs | split as it is [N] / [%] | split with the change [N] / [%] | |split| "
             "changes by [% of the corner load] | pull as it is / with it [deg] | |pull| "
             "changes by [deg] | steering-wheel torque as it is / with it [N m] |",
             "|---|---|---|---|---|---|---|"]
    for r in c["by_mu_s"]:
        if r.get("failed"):
            lines.append(f"| {r['mu_s']:g} | a run failed | | | | | |")
            continue
        b, ch, d = r["base"], r["change"], r["difference"]
        lines.append(
            f"| {r['mu_s']:g} | {_pm(b['split_N'], 0)} / {_pm(b['split_rel'], 2)} | "
            f"{_pm(ch['split_N'], 0)} / {_pm(ch['split_rel'], 2)} | "
            f"{_pm(d['split_rel'], 2)}: {d['split_rel']['verdict']} | "
            f"{_pm(b['pull_deg'], 3)} / {_pm(ch['pull_deg'], 3)} | "
            f"{_pm(d['pull_deg'], 3)}: {d['pull_deg']['verdict']} | "
            f"{_pm(b['torque_Nm'], 3)} / {_pm(ch['torque_Nm'], 3)} |")
    return lines + ["", f"Over the jam states (Monte Carlo, state by state): the row "
                    f"\"{NAME}\" of the mitigations' table below.", ""]
