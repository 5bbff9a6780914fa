"""The tyre the car runs on, in the handling study: its curves, figures and summary as the tyre
command writes them (``tyre_curves``, into the study's ``tyre/``), its numbers at the car's
static wheel loads, and -- when it is not the tyre drake_car ships -- what changed against the
shipped tyre, measured by running the same handling tests on both (``shipped_scenes``,
``changes``)."""

import dataclasses
from pathlib import Path

from drake_car.law.tyre.magic_formula import (
    MagicFormulaTyre,
    magic_formula,
    relaxation_lengths_m,
    relaxation_source,
)
from drake_car.law.tyre.plausibility import wheel_load_note
from drake_car.model.geometry import design_axle_loads_N
from drake_car.model.loading import tir_path
from drake_car.scene.borrowed import relaxation, relaxation_words
from drake_car.scene.limits import warn_radius
from drake_car.scene.scene import DEFAULT_TIR
from drake_car.study.handling import tyre_curves

FIGURES = {"fy_alpha.png": "Fy against α at 0.5-2 FNOMIN, with and without camber",
           "mz_alpha.png": "Mz against α", "fx_kappa.png": "Fx against κ",
           "friction_ellipse.png": "combined slip at FNOMIN",
           "stiffness_load.png": "slip and cornering stiffness against load"}


def tyre_of(scene):
    return MagicFormulaTyre.from_file(tir_path(scene.tyres.tir_file))


def is_shipped(scene):
    """Whether the scene's tyre file is the one drake_car ships (``scene.DEFAULT_TIR``)."""
    return (Path(tir_path(scene.tyres.tir_file)).resolve()
            == Path(tir_path(DEFAULT_TIR)).resolve())


def facts(scene):
    """The tyre's numbers for the report (no curves): format, FNOMIN and ranges, peak μ,
    Kxκ and Kyα at FNOMIN and at the car's static front and rear wheel loads (half the static
    axle loads, as the single-track model), relaxation lengths there when the file has them,
    the coefficients defaulted, the load note."""
    tyre = tyre_of(scene)
    loads = {axle: load / 2 for axle, load in design_axle_loads_N(scene.car).items()}
    at = {}
    for where, fz in (("FNOMIN", tyre.FNOMIN), ("front", loads["front"]),
                      ("rear", loads["rear"])):
        f = magic_formula(tyre, fz, 0.0, 0.0, 0.0, tyre.LONGVL)
        mux, muy = tyre_curves.peak_mu(tyre, fz)
        at[where] = {"fz_N": fz, "mu_x": mux, "mu_y": muy,
                     "slip_stiffness_N": f.slip_stiffness,
                     "cornering_stiffness_N_per_rad": f.cornering_stiffness,
                     "relaxation_lengths_m": relaxation_lengths_m(tyre, fz)}
    return {"file": tyre.name, "form": tyre.form, "format_note": tyre.format_note,
            "side": tyre.side, "fnomin_N": tyre.FNOMIN,
            "fz_range_N": [tyre.FZMIN, tyre.FZMAX], "at": at,
            "relaxation_source": relaxation_source(tyre),
            "defaulted": list(tyre.defaulted), "warnings": list(tyre.warnings),
            "load_note": wheel_load_note(tyre, loads), "shipped": is_shipped(scene),
            "no_combined_fit": tyre.RBX1 == 0.0 or tyre.RBY1 == 0.0,
            "radial_stiffness_Npm": scene.car.tyre.radial_stiffness_Npm,
            "radial_damping_Nspm": scene.car.tyre.radial_damping_Nspm,
            "vertical_from_file": scene.tyres.vertical_from_file,
            "relaxation_used": relaxation_words(relaxation(scene))}


def write(out, scene):
    """The tyre command's files for the scene's tyre into ``out`` (created)."""
    out.mkdir()
    tyre_curves.write(tyre_of(scene), out)


def shipped_scenes(scenes):
    """The same scenes on the shipped tyre file, and a note when a setting had to change with
    it (the shipped file has no relaxation data: its run takes tyres.slip's lengths; nor
    vertical data: the runs keep this file's radial spring, already in car.tyre) or when the
    shipped tyre's unloaded radius is not the car's (said on stderr too, as a scene's load
    says it: ``scene.limits.warn_radius``)."""
    out, notes = {}, set()
    for name, scene in scenes.items():
        tyres = dataclasses.replace(scene.tyres, tir_file=DEFAULT_TIR)
        radius = warn_radius(DEFAULT_TIR, scene.car)
        if radius is not None:
            notes.add(f"**the shipped tyre is not this car's size**: {radius} (the comparison "
                      "is of the two Magic Formulas on this car's wheels, not of the car on "
                      "wheels of the shipped tyre's size)")
        if tyres.vertical_from_file:  # the scene's car.tyre already holds this file's values
            tyres = dataclasses.replace(tyres, vertical_from_file=False)
            notes.add("the radial stiffness and damping stay this tyre file's "
                      f"({scene.car.tyre.radial_stiffness_Npm:g} N/m, "
                      f"{scene.car.tyre.radial_damping_Nspm:g} N s/m), so only the Magic "
                      "Formula changes")
        if tyres.slip.relaxation and tyres.slip.relaxation_lengths_from_file and (
                relaxation_source(tyre_of(dataclasses.replace(scene, tyres=tyres))) is None):
            tyres = dataclasses.replace(tyres, slip=dataclasses.replace(
                tyres.slip, relaxation_lengths_from_file=False))
            notes.add("the shipped tyre has no relaxation data: its runs take tyres.slip's "
                      f"lengths ({tyres.slip.relaxation_length_long_m:g} m, "
                      f"{tyres.slip.relaxation_length_lat_m:g} m)")
        out[name] = dataclasses.replace(scene, tyres=tyres)
    return out, "; ".join(sorted(notes)) or None


# (label, path in the analysis' result, unit) of what the comparison shows.
QUANTITIES = (
    ("understeer gradient, δ from the rack", ("steady_state", "metrics",
                                               "understeer_gradient_deg_per_g"), "deg/g"),
    ("understeer gradient, δ of the wheels", ("steady_state", "metrics",
                                               "understeer_gradient_wheel_deg_per_g"), "deg/g"),
    ("steady-state yaw-rate gain dr/dδ (rack)", ("steady_state", "metrics",
                                                 "yaw_rate_gain_per_s"), "1/s"),
    ("steady-state yaw-rate gain dr/dδ (wheels)", ("steady_state", "metrics",
                                                   "yaw_rate_gain_wheel_per_s"), "1/s"),
    ("roll gradient", ("steady_state", "metrics", "roll_gradient_deg_per_g"), "deg/g"),
    ("sideslip gradient at the CoG", ("steady_state", "metrics",
                                      "sideslip_gradient_deg_per_g"), "deg/g"),
    ("rack-force gradient", ("steady_state", "metrics", "rack_force_gradient_N_per_g"), "N/g"),
    ("highest a_y of the ramp (same rack)", ("steady_state", "metrics", "max_ay_mps2"),
     "m/s²"),
    ("single track: front axle C_f", ("steady_state", "single_track",
                                      "front_stiffness_N_per_rad"), "N/rad"),
    ("single track: rear axle C_r", ("steady_state", "single_track",
                                     "rear_stiffness_N_per_rad"), "N/rad"),
    ("single track: understeer gradient", ("steady_state", "single_track",
                                           "understeer_gradient_deg_per_g"), "deg/g"),
    ("step: yaw-rate gain (rack)", ("step_steer", "metrics", "yaw_rate", "gain"), "1/s"),
    ("step: yaw-rate response time", ("step_steer", "metrics", "yaw_rate", "response_time_s"),
     "s"),
    ("step: yaw-rate overshoot", ("step_steer", "metrics", "yaw_rate", "overshoot_pct"), "%"),
    ("step: a_y response time", ("step_steer", "metrics", "lateral_acceleration",
                                 "response_time_s"), "s"),
    ("step: steady a_y", ("step_steer", "metrics", "lateral_acceleration", "steady"), "m/s²"),
)


def _get(result, path):
    for key in path:
        if not isinstance(result, dict) or key not in result:
            return None
        result = result[key]
    return None if result is None else float(result)


def changes(result, shipped):
    """Rows {quantity, unit, shipped, this, difference, difference_pct} of the handling
    analysis on this tyre (``result``) against the same on the shipped tyre (``shipped``),
    then the understeer budget's terms (deg/g)."""
    rows = [(label, unit, _get(shipped, path), _get(result, path))
            for label, path, unit in QUANTITIES]
    ours = {r["key"]: r for r in result["budget"]["rows"]}
    for row in shipped["budget"]["rows"]:
        if row["key"] in ours:
            rows.append((f"budget: {row['term']}", "deg/g", row["gradient_deg_per_g"],
                         ours[row["key"]]["gradient_deg_per_g"]))
    out = []
    for label, unit, a, b in rows:
        d = None if a is None or b is None else b - a
        pct = None if d is None or a == 0 else 100.0 * d / abs(a)
        out.append({"quantity": label, "unit": unit, "shipped": a, "this": b,
                    "difference": d, "difference_pct": pct,
                    "budget": label.startswith("budget: ")})
    return out


def _g(value, digits=4):
    return "–" if value is None else f"{value:.{digits}g}"


def section(result):
    """The report's lines on the tyre (``result["tyre"]``) and, when it is not the shipped
    one, the comparison (``result["tyre_change"]``)."""
    t = result["tyre"]
    lo, hi = t["fz_range_N"]
    lines = [
        "## The tyre the car runs on", "",
        f"`{t['file']}`: **{t['form']}** ({t['format_note']}), TYRESIDE {t['side']} (the other "
        f"side mirrored); FNOMIN {t['fnomin_N']:g} N, valid for Fz {lo:g}..{hi:g} N"
        + (" — the tyre drake_car ships." if t["shipped"] else "."), ""]
    if t["load_note"]:
        lines += [f"**Warning:** {t['load_note']}.", ""]
    lines += ["| at | Fz (N) | peak μx | peak μy | Kxκ (N) | Kyα (N/rad) | Kyα/Fz | σκ / σα (m) |",
              "|---|---|---|---|---|---|---|---|"]
    for where, label in (("FNOMIN", "FNOMIN"), ("front", "static front wheel"),
                         ("rear", "static rear wheel")):
        a = t["at"][where]
        sigma = a["relaxation_lengths_m"]
        lines.append(
            f"| {label} | {a['fz_N']:.0f} | {a['mu_x']:.3f} | {a['mu_y']:.3f} | "
            f"{a['slip_stiffness_N']:.4g} | {a['cornering_stiffness_N_per_rad']:.4g} | "
            f"{a['cornering_stiffness_N_per_rad'] / a['fz_N']:.2f} | "
            + ("–" if sigma is None else f"{sigma[0]:.3f} / {sigma[1]:.3f}") + " |")
    defaulted = t["defaulted"]
    lines += [
        "", "Peak μ: the largest |F|/Fz of the pure-slip sweeps (κ to ±0.3, α to ±15°, zero "
        "camber, inside the file's ranges); stiffnesses at zero slip and camber (ISO-W signs: "
        "Kyα < 0). σ: the file's own relaxation lengths ("
        + {"PTX/PTY": "PAC2002's PTX*/PTY*", "carcass": "MF 6.x: Kxκ/Cx, |Kyα|/Cy",
           None: "none in the file; the runs use tyres.slip's"}[t["relaxation_source"]]
        + f"). Coefficients defaulted (absent from the file): **{len(defaulted)}**"
        + (f" ({', '.join(defaulted)})" if defaulted else "") + "."
        + (" RBX1 or RBY1 is 0 (the file has no combined-slip fit): Fx and Fy do not weaken "
           "each other in combined slip (the budget's drive terms shrink with it)."
           if t["no_combined_fit"] else "")
        + "".join(f" Plausibility: {w}." for w in t["warnings"])
        + f" The runs relax with: {t['relaxation_used']}."
        + f" Radial spring and damper: {t['radial_stiffness_Npm']:g} N/m, "
        f"{t['radial_damping_Nspm']:g} N s/m ("
        + ("the file's VERTICAL_STIFFNESS and VERTICAL_DAMPING: tyres.vertical_from_file"
           if t["vertical_from_file"] else "car.tyre's") + ").", "",
        "Curves, figures and summary as `drake-car-tyre` writes them: "
        "`tyre/curves.csv`, `tyre/summary.txt`, "
        + ", ".join(f"[`tyre/{name}`](tyre/{name}) ({caption})"
                    for name, caption in FIGURES.items()) + ".", ""]
    change = result.get("tyre_change")
    if change is None:
        return lines
    if "skipped" in change:
        return lines + ["## What changed against the shipped tyre", "",
                        f"Not measured: {change['skipped']}.", ""]
    lines += [
        "## What changed against the shipped tyre", "",
        f"The same two tests (same scenes, fit range and analysis), run again with only "
        f"`tyres.tir_file` set back to the shipped `{DEFAULT_TIR}` (its runs in "
        "`shipped_tyre/`)" + (f"; {change['note']}" if change.get("note") else "") + ". "
        "Difference = this tyre − shipped.", "",
        "| quantity | shipped tyre | this tyre | difference | |", "|---|---|---|---|---|"]
    # (budget terms: no percentage -- a term near zero on one tyre gives a meaningless one)
    for r in change["rows"]:
        pct = r["difference_pct"]
        lines.append(
            f"| {r['quantity']} ({r['unit']}) | {_g(r['shipped'])} | {_g(r['this'])} | "
            + ("–" if r["difference"] is None else f"{r['difference']:+.4g}")
            + f" | {'' if pct is None or r['budget'] else f'{pct:+.1f} %'} |")
    return lines + [""]
