"""The strut rig study's report (``drake-car-strut-rig``'s report.md): the car's strut at rest
and the rig loaded as it, every rig run's break-away and sliding, and the synthetic loop's
fit; the numbers of at_rest.json, rig.csv and fit.json, as Markdown (pure: no files)."""

import math

from drake_car.model.geometry import design_axle_loads_N
from drake_car.model.hard_point_table import differences, value_text
from drake_car.study.car.describe import is_shipped_car
from drake_car.study.car.report import base_car


def strut_facts(scene):
    """JSON-ready facts of the car whose front strut goes on the rig (``scene``'s): which car
    (its car file, or the shipped car, or the scene's car values), its mass and static front
    corner load, and the strut's b, l, r and guide position."""
    car, f = scene.car, scene.car.front
    changed = [f"{name} = {value_text(mine)}"
               for name, _, mine in differences(base_car(scene), car)]
    return {"scene": scene.name, "car_file": scene.car_file or None, "changed": changed,
            "shipped": is_shipped_car(car), "mass_kg": car.mass.total_mass_kg,
            "design_corner_load_N": design_axle_loads_N(car)["front"] / 2,
            "ball_joint_offset_b_m": f.ball_joint_offset_b_m,
            "guide_length_l_m": f.guide_length_l_m, "rod_radius_r_m": f.rod_radius_r_m,
            "guide_below_top_mount_m": f.guide_below_top_mount_m,
            "strut_length_m": f.strut_lower_mount_below_top_m,
            "strut_damping_Nspm": f.strut_damping_Nspm}


def _which_car(car):
    if car["car_file"]:
        return f"the car of the car file `{car['car_file']}`" + (
            f" with the scene's car: values over it ({', '.join(car['changed'])})"
            if car["changed"] else "")
    if car["shipped"]:
        return "the shipped car (the Ford Escort of `drake_car/model/parameters.py`)"
    return ("the scene's car (the shipped car's values with the scene's `car:` over them: "
            + ", ".join(car["changed"]) + ")")


def _car_lines(car, at_rest):
    return [
        "## The car and its strut", "",
        f"- the car: {_which_car(car)}, scene `{car['scene']}` (as it ran: `scene.yaml`); "
        f"{car['mass_kg']:g} kg, static front corner load {car['design_corner_load_N']:.0f} N "
        "(half the front axle load of its centre of gravity)",
        f"- the strut on the rig: its {at_rest['side']} front strut, ball-joint offset b = "
        f"{1e3 * car['ball_joint_offset_b_m']:.1f} mm, guide length l = "
        f"{1e3 * car['guide_length_l_m']:.1f} mm, rod radius r = "
        f"{1e3 * car['rod_radius_r_m']:.1f} mm, rod guide "
        f"{1e3 * car['guide_below_top_mount_m']:.0f} mm below the top mount, top mount to lower mount {1e3 * car['strut_length_m']:.0f} mm",
        f"- the corner load it is loaded as: {at_rest['corner_load_N']:.1f} N, the settled "
        f"car's {at_rest['side']} front tyre load at rest (lubricated struts, vertical tyres)",
        ""]


def report(*, car, at_rest, rows, law, fit, runs, prov):
    """Markdown of the rig study: ``car`` (``strut_facts`` of the scene), ``at_rest``
    (``StrutAtRest.summary()``), ``rows`` (one per rig run, ``loops.rig_study``), ``law`` the
    synthetic loop's law, ``fit`` its ``LoopFit``, ``runs`` how the rig's runs went, ``prov``
    the provenance."""
    shares = ", ".join(f"{name} {value:+.1f} N" for name, value in at_rest["shares_N"].items())
    lines = [
        f"# The strut side-load rig: the front strut of {_which_car(car)}", "",
        f"Made by `{prov['command']}`, commit {prov['git_commit']}"
        f"{' (uncommitted changes)' if prov['dirty'] else ''}, drake {prov['drake']}, "
        f"{prov['created_utc']}; {runs['runs']} rig runs, {runs['cpu_s']:.0f} s of CPU.", "",
        *_car_lines(car, at_rest),
        "## The car's strut at rest, and the rig loaded as it", "",
        f"- the car's {at_rest['side']} strut at its static equilibrium: normal force "
        f"N = {at_rest['car_normal_N']:.1f} N (eq. 4 on the strut joint's reaction)",
        f"- the transverse force through the top mount |F| = "
        f"{at_rest['transverse_force_N']:.1f} N; its shares: {shares}",
        f"- on the rig: {at_rest['rig_side_force_N']:.1f} N at "
        f"{at_rest['rig_side_force_point_below_top_m']:.3f} m below the top mount gives "
        f"N = {at_rest['rig_normal_N']:.1f} N (the bound on the difference: "
        f"{at_rest['rig_difference_bound_N']:.1f} N)",
        f"- the tyre's share alone through the ball joint (`corner_side_force_N`): "
        f"{at_rest['corner_side_force_N']:.1f} N, N = "
        f"{at_rest['corner_side_force_normal_N']:.1f} N", "",
        "## The synthetic loop and its fit", "",
        f"A loop made by the rig with μs = {law.mu_s:g}, μd = {law.mu_d:g} at the car's side "
        f"load at rest, plus noise, fitted: {fit.line()}; apparent μs "
        f"{fit.apparent_mu_s:.4f}; residual {fit.residual_rms_N:.1f} N; Δmax resolved: "
        f"{fit.dmax_resolved}, Δv resolved: {fit.dv_resolved}.", "",
        "## Every rig run", "",
        "Side force at the top mount; break-away and sliding are the load cell's force at each "
        "reversal and at mid-stroke, averaged over the cycles (`rig.csv` has every digit).", "",
        "| μs | μd | side force (N) | amplitude (mm) | frequency (Hz) | rotation (rad) | N (N) "
        "| break-away (N) | sliding (N) | apparent μs | measured μd | friction moment (N m) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append("| " + " | ".join([
            f"{r['mu_s']:g}", f"{r['mu_d']:g}", f"{r['side_force_N']:.1f}",
            f"{1e3 * r['amplitude_m']:g}", f"{r['frequency_hz']:g}",
            f"{r['rotation_amplitude_rad']:g}", f"{r['normal_N']:.1f}",
            _force(r["breakaway_N"], r.get("note")), _force(r["sliding_N"]),
            _ratio(r["apparent_mu_s"]),
            _ratio(r["mu_d_measured"]), f"{r['max_friction_moment_Nm']:.2f}"]) + " |")
    lines += ["", "Figures: `loops.png` (load cell force against stroke), `side_load.png` "
              "(break-away and sliding force against side force, with μ·N of eq. 4).", ""]
    return "\n".join(lines)


def _force(value, note=None):
    if math.isfinite(value):
        return f"{value:.1f}"
    return f"- ({note})" if note else "-"


def _ratio(value):
    return "-" if value is None or not math.isfinite(value) else f"{value:.4f}"
