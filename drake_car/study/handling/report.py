"""The handling study's report (report.md): the tyre the car runs on and what changed against
the shipped tyre (``tyre_section``), the metrics beside the single-track model, step steer, the understeer budget term by term, and the cross-check with every difference over 10 %
attributed."""

import math

from drake_car.study.handling import tyre_section
from drake_car.study.handling.measures import DEG_PER_G as DEG

def _f(value, digits=3, signed=False):
    if value is None or not math.isfinite(value):  # NaN: CommonRoad's model stopped before it
        return "–"
    return f"{value:+.{digits}g}" if signed else f"{value:.{digits}g}"


def _fixed(value, digits=3):
    return "–" if value is None else f"{value:+.{digits}f}"


def _diff(ours, theirs):
    """ours against theirs in %; None where either is missing or no number (NaN: CommonRoad's
    model stopped before it), or theirs is 0."""
    if ours is None or theirs is None or theirs == 0:
        return None
    if not (math.isfinite(ours) and math.isfinite(theirs)):
        return None
    return 100.0 * (ours - theirs) / abs(theirs)


def report(result):
    prov, walls = result["provenance"], result["wall_s"]
    ss, st, budget = result["steady_state"], result["step_steer"], result["budget"]
    m, single = ss["metrics"], ss["single_track"]
    lo, hi = result["fit_range_mps2"]
    v = m["speed_mps"]
    wall_parts = ", ".join(f"{k} {v:.1f} s" for k, v in walls.items() if k != "total")
    torque_gradient = (m["rack_force_gradient_N_per_g"] * result["rack_gain_m_per_rad"]
                       * result.get("steering_sign", 1.0))
    lines = [
        "# drake_car: handling (ISO 4138, ISO 7401), understeer budget, cross-check", "",
        f"Made by `{prov['command']}`; {prov['created_utc']}, drake {prov['drake']}, commit "
        f"{(prov['git_commit'] or 'unknown')[:10]}. Drive: **{result['drive']}**. Wall time "
        f"**{walls['total']:.0f} s** ({wall_parts}). The scenes as they ran: "
        "`steady_state/scene.yaml`, `step_steer/scene.yaml`.", "",
        "Signs are ISO 8855 (x forward, y left, z up): in a left turn δ, r, a_y and roll (right "
        "side down) are positive; sideslip is positive with the velocity left of the heading. "
        "The chassis channels are logged at the body origin (the ground point midway between "
        "the front wheels); the standards' CoG quantities are moved to the CoG "
        f"({result['cog_offset_m']:.3f} m behind it) by rigid-body kinematics in the heading "
        "frame (v_y,G = v_y,O − a r); a_y at the CoG is the whole car's by Newton, the tyres' "
        "lateral forces (heading frame) over the mass. **δ from the rack** is the road-wheel "
        "angle the rack alone gives (mean of left and right, chassis fixed: `steering.csv`), "
        "i.e. ISO's steering-wheel angle over the overall steering ratio; **δ of the wheels** "
        "is the measured mean of the two front wheels' steer to the body (roll steer "
        f"included). Gradients are least-squares slopes over a_y = {lo:g} … {hi:g} m/s² "
        f"(t = {m['t_range_s'][0]:.2f} … {m['t_range_s'][1]:.2f} s, {m['samples']} samples), "
        f"at the speed the car held there: {v:.3f} m/s = {3.6 * v:.2f} km/h "
        f"({m['speed_range_mps'][0]:.3f} … {m['speed_range_mps'][1]:.3f} m/s).", "",
        *tyre_section.section(result),
        "## Steady-state circular driving (ISO 4138, continuous ramp steer)", "",
        "| quantity | value |", "|---|---|",
        f"| understeer gradient K = d(δ − L r/V)/da_y, δ from the rack | "
        f"**{m['understeer_gradient_deg_per_g']:.3f} deg/g** |",
        f"| understeer gradient, δ of the wheels | "
        f"{m['understeer_gradient_wheel_deg_per_g']:.3f} deg/g |",
        f"| steer-angle gradient dδ/da_y (rack) | {m['steer_gradient_deg_per_g']:.3f} deg/g |",
        f"| roll gradient | **{m['roll_gradient_deg_per_g']:.2f} deg/g** |",
        f"| sideslip gradient at the CoG | {m['sideslip_gradient_deg_per_g']:.2f} deg/g |",
        f"| rack-force gradient | {m['rack_force_gradient_N_per_g']:.0f} N/g |",
        f"| steering-wheel torque gradient (rack force × c, unassisted) | "
        f"{torque_gradient:.2f} N m/g |",
        f"| overall steering ratio at the centre, 1/(c dδ/dq) | "
        f"{result['steering_ratio']:.1f} : 1 (rack gain c = "
        f"{1e3 * result['rack_gain_m_per_rad']:g} mm/rad, `car.front.rack_gain_m_per_rad`) |",
        f"| yaw-rate gain dr/dδ (rack) | {m['yaw_rate_gain_per_s']:.3f} 1/s = "
        f"**{ss['yaw_gain_ratio']:.3f} × single track** ({single['yaw_rate_gain_per_s']:.3f} 1/s)"
        " |",
        f"| yaw-rate gain dr/dδ (wheels) | {m['yaw_rate_gain_wheel_per_s']:.3f} 1/s = "
        f"{ss['yaw_gain_ratio_wheel']:.3f} × single track |",
        f"| highest a_y of the run | {m['max_ay_mps2']:.2f} m/s² |",
        f"| a_y rise in the fit range | {m['ay_rate_mps2_per_s']:.2f} m/s² per s |", "",
        "Local understeer gradient (rack δ), how it grows towards the limit: " + ", ".join(
            f"{b['ay_range_mps2'][0]:g}–{b['ay_range_mps2'][1]:g} m/s²: "
            f"{b['understeer_gradient_deg_per_g']:.2f}" for b in m["local_understeer"])
        + " deg/g.", "",
        "**The single-track model from the car's own parameters**: mass "
        f"{result['mass_kg']:.1f} kg, CoG {result['cog_offset_m']:.3f} m behind the front axle, "
        f"wheelbase {result['wheelbase_m']:.3f} m; axle cornering stiffness from the .tir at "
        "half the static axle load per tyre (m g b/L, m g a/L: "
        f"{single['axle_loads_N']['front']:.0f} / {single['axle_loads_N']['rear']:.0f} N), "
        "zero camber: C_f = "
        f"{single['front_stiffness_N_per_rad'] / 1e3:.1f} kN/rad, C_r = "
        f"{single['rear_stiffness_N_per_rad'] / 1e3:.1f} kN/rad; K = m/L (b/C_f − a/C_r) = "
        f"{single['understeer_gradient_deg_per_g']:.3f} deg/g, r/δ = V/(L + K V²) = "
        f"{single['yaw_rate_gain_per_s']:.3f} 1/s at {v:.2f} m/s, sideslip gradient "
        f"{single['sideslip_gradient_deg_per_g']:.2f} deg/g, characteristic speed "
        f"{_f(single['characteristic_speed_kph'], 4)} km/h.", "",
        f"The steering servo (the rack held at its command by a stiff PD) gives "
        f"{ss['steering_servo_deg_per_g']:+.3f} deg/g more if K is taken on the rack's command "
        "instead of its position; K above uses the position (a real column's compliance "
        "would add here).", "",
    ]
    lines += _step_section(st)
    lines += _budget_section(budget, m)
    lines += _crosscheck_section(result)
    lines += ["## Figures", ""] + [f"- `{name}`: {caption}"
                                   for name, caption in result["figures"].items()] + [""]
    return "\n".join(lines)


def _step_section(st):
    sm = st["metrics"]
    y, a = sm["yaw_rate"], sm["lateral_acceleration"]
    return [
        "## Step steer (ISO 7401)", "",
        f"Road-wheel step {sm['steer_deg']:.2f} deg (from the rack), speed held "
        f"{sm['speed_mps']:.3f} m/s. Times from 50 % of the steer input; steady values over "
        "the last second.", "",
        "| | yaw rate | a_y at the CoG |", "|---|---|---|",
        f"| steady value | {math.degrees(y['steady']):.3f} deg/s | {a['steady']:.3f} m/s² |",
        f"| gain per road-wheel angle (rack) | {y['gain']:.3f} 1/s | {a['gain']:.1f} m/s² per "
        "rad |",
        f"| gain per road-wheel angle (wheels) | {st['wheel_steer_gains']['yaw_rate_per_s']:.3f}"
        f" 1/s | {st['wheel_steer_gains']['lateral_acceleration_mps2_per_rad']:.1f} m/s² per "
        "rad |",
        f"| response time (50 % steer → 90 % of steady) | **{_f(y['response_time_s'])} s** | "
        f"**{_f(a['response_time_s'])} s** |",
        f"| peak response time | {_f(y['peak_response_time_s'])} s | "
        f"{_f(a['peak_response_time_s'])} s |",
        f"| overshoot | {y['overshoot_pct']:.1f} % | {a['overshoot_pct']:.1f} % |", "",
        f"Steady roll {math.degrees(sm['roll']['steady']):.2f} deg (overshoot "
        f"{sm['roll']['overshoot_pct']:.1f} %), sideslip at the CoG "
        f"{math.degrees(sm['sideslip']['steady']):.2f} deg.", ""]


def _budget_section(budget, m):
    lines = [
        "## Understeer budget", "",
        "The identity: with α* = −α (the logged slip angle is ISO's, positive when the wheel "
        "moves to its left, the force then negative) the axles' mean slip angles towards the "
        "turn, a rigid car in a steady turn at small angles (tan α ≈ α, cos δ ≈ 1, V r ≈ a_y) "
        "has δ_wheels − L r/V = α*_f − α*_r + ε, and δ_rack = δ_wheels + roll steer. The force "
        "each axle needs comes from the steady lateral and yaw balances about the CoG "
        "(Y_f = m a_y b/L − Σ Fx sin δ − (ΣMz + M_x)/L, Y_r = m a_y a/L + (ΣMz + M_x)/L, "
        "M_x = −Σ y_i Fx_i cos δ_i, plus the front Fy's own cos δ and track × sin δ "
        "projections); the slip an axle needs for a force is the common slip of its two "
        "tyres (the scene's Magic Formula, right tyres mirrored) at given loads, cambers and "
        "longitudinal slips. Each term below changes one thing along that chain (in the "
        "table's order; an interaction lands in the later term) and is the gradient of the "
        "change of α*_f − α*_r against a_y, so the terms sum exactly to the measured "
        "gradient; what the named terms do not explain is in the three remainders. "
        "Source: `drake_car/study/handling/understeer.py`.", "",
        "| term | deg/g | share | how |", "|---|---|---|---|"]
    for row in budget["rows"]:
        lines.append(f"| {row['term']} | {row['gradient_deg_per_g']:+.3f} | "
                     f"{row['share_pct']:+.1f} % | {row['how']} |")
    ok = abs(budget["remainder_pct"]) <= 10
    lines += [
        f"| **named terms** | **{budget['named_sum_deg_per_g']:.3f}** | "
        f"{100 - budget['remainder_pct']:.1f} % | |",
        f"| **measured (δ from the rack)** | **{budget['measured_deg_per_g']:.3f}** | 100 % | "
        f"fit over the same {budget['samples']} samples; {m['understeer_gradient_deg_per_g']:.3f}"
        " over all of them |", "",
        f"The named terms give {budget['named_sum_deg_per_g']:.3f} of the measured "
        f"{budget['measured_deg_per_g']:.3f} deg/g: the remainders are "
        f"{budget['remainder_pct']:+.1f} % ({'within' if ok else 'NOT within'} 10 %). "
        "Static state (the straight's last second): wheel loads "
        + ", ".join(f"{w} {v:.0f} N" for w, v in budget["static_wheel_loads_N"].items())
        + "; axle cornering stiffness there "
        f"{budget['axle_stiffness_N_per_rad']['front'] / 1e3:.1f} / "
        f"{budget['axle_stiffness_N_per_rad']['rear'] / 1e3:.1f} kN/rad (front/rear). "
        "Without roll steer (δ of the wheels) the gradient is "
        f"{budget['measured_wheel_deg_per_g']:.3f} deg/g.", ""]
    return lines


def _broke_down_lines(cc):
    """Where CommonRoad's model could not go on (a wheel rolling backwards: the car spun in
    it), and that it is compared only before that."""
    runs = {"steady_state": "ramp steer", "step_steer": "step steer"}
    said = [f"in the {runs[name]} at {e['t_s']:.2f} s (our car there: road-wheel steer "
            f"{e['steer_deg']:.2f} deg, a_y {e['ay_mps2']:.2f} m/s²; its model: "
            f"{e.get('why') or 'stopped'})" for name, e in cc.get("broke_down", {}).items()]
    if not said:
        return []
    spun = any("ZeroDivision" in (e.get("why") or "") for e in cc["broke_down"].values())
    return [f"**CommonRoad's model could not go on** {'; '.join(said)}"
            + (": a wheel rolling backwards in it divides its slip by its zero speed, i.e. "
               "the car spun in it" if spun else "")
            + ". It is compared below only on what it ran before that; its channels are "
            "empty after it.", ""]


def _crosscheck_section(result):
    cc = result["crosscheck"]
    if "skipped" in cc:
        return ["## Cross-check against CommonRoad's multi-body model", "",
                f"Not run: {cc['skipped']}.", ""]
    ours, mb, chain = result["steady_state"]["metrics"], cc["ramp"], cc["chain"]
    p, roll = cc["parameters"], cc["roll_model"]
    vehicle = cc.get("vehicle", {"id": 1, "name": "Ford Escort"})
    # Its whole car's CoG: the sprung mass at a, the unsprung masses at the axles.
    mb_whole_a = (p["m_s"] * p["a"] + p.get("m_ur", 0.0) * (p["a"] + p["b"])) / p["m"]
    step, mb_step = result["step_steer"]["metrics"], cc["step"]
    v = ours["speed_mps"]
    rec = {r["key"]: r for r in cc["reconciliation"]}
    k_o, k_m = ours["understeer_gradient_wheel_deg_per_g"], mb["understeer_gradient_deg_per_g"]
    L, L_mb = result["wheelbase_m"], p["a"] + p["b"]
    gain = (lambda k, length: v / (length + k / DEG * v * v))
    predicted = gain(k_o, L) / gain(k_m, L_mb)
    measured = ours["yaw_rate_gain_wheel_per_s"] / mb["yaw_rate_gain_per_s"]
    c_mb, _, c_tyre, c_ours, _, c_relax = chain
    r_ours = cc["our_roll_stiffness"]
    arm = cc["our_equivalent_roll_arm_m"]
    ay_ratio = step["lateral_acceleration"]["steady"] / mb_step["lateral_acceleration"]["steady"]

    def chain_text(key):
        steps = ", ".join(f"{c['model']} {_f(c[key])}" for c in chain[1:])
        return f"single track (same steer) from its data {_f(c_mb[key])} s; then {steps} s"

    def rest(measured, model, channel):
        a, b = measured[channel]["response_time_s"], model[f"{channel}_response_time_s"]
        return "–" if a is None or b is None or not math.isfinite(a - b) else f"{a - b:+.3f} s"

    k_text = ("reconciled part by part in the next table: MB's lever/load inconsistency "
              f"{rec['levers']['mb']:+.2f} (its), our tyres' Kyα at our static loads "
              f"{rec['tyres']['ours']:+.2f}, our load sensitivity "
              f"{rec['load_transfer']['ours']:+.2f} and aligning moments "
              f"{rec['aligning']['ours']:+.2f} (MB has neither), camber ours "
              f"{rec['camber']['ours']:+.2f} vs its {_f(rec['camber']['mb'], 2, True)}, our "
              f"drive and Fy projections {rec['drive']['ours']:+.2f}, rest ours "
              f"{rec['rest']['ours']:+.2f} vs its {rec['rest']['mb']:+.2f} deg/g")
    rows = [
        ("understeer gradient, δ of the wheels (deg/g)", k_o, k_m, k_text),
        ("yaw-rate gain dr/dδ (1/s)", ours["yaw_rate_gain_wheel_per_s"],
         mb["yaw_rate_gain_per_s"],
         f"follows K: V/(L + K V²) with the two K's gives ours/its {predicted:.3f} (measured "
         f"{measured:.3f})"),
        ("roll gradient (deg/g)", ours["roll_gradient_deg_per_g"], mb["roll_gradient_deg_per_g"],
         f"its roll model: roll axis at the ground (arm h_s = {roll['roll_arm_m']:.3f} m), "
         f"K_φ = {roll['with_tyres_Nm_per_rad'] / 1e3:.1f} kN m/rad (corner springs "
         f"{roll['suspension_front_Nm_per_rad'] / 1e3:.1f} / "
         f"{roll['suspension_rear_Nm_per_rad'] / 1e3:.1f} incl. its K_tsf, tyres in series): "
         f"{roll['roll_gradient_deg_per_g']:.2f} deg/g by hand. Our parameters counted the "
         f"same way (wheel rates, anti-roll bars, tyres) give K_φ = "
         f"{r_ours['with_tyres_Nm_per_rad'] / 1e3:.1f} kN m/rad; with it our gradient needs an "
         f"arm of {arm:.3f} m, i.e. our suspension kinematics (roll centres, and jacking "
         f"by the tyres' forces) act as a roll axis ≈{roll['roll_arm_m'] - arm:.2f} m above "
         "the ground on average (its: at the ground)"),
        ("sideslip gradient at the CoG (deg/g)", ours["sideslip_gradient_deg_per_g"],
         mb["sideslip_gradient_deg_per_g"],
         "rear tyre stiffness: single track b/V² − m a/(L C_r) gives "
         f"{c_mb['sideslip_gradient_deg_per_g']:+.2f} with its C_r = "
         f"{c_mb['rear_stiffness_N_per_rad'] / 1e3:.0f} kN/rad, "
         f"{c_tyre['sideslip_gradient_deg_per_g']:+.2f} with our .tir's "
         f"{c_tyre['rear_stiffness_N_per_rad'] / 1e3:.0f} kN/rad, "
         f"{c_ours['sideslip_gradient_deg_per_g']:+.2f} with our mass and CoG; beyond the "
         "single track (load transfer, camber, aligning moments, roll) ours "
         f"{ours['sideslip_gradient_deg_per_g'] - c_ours['sideslip_gradient_deg_per_g']:+.2f}"
         f", its {mb['sideslip_gradient_deg_per_g'] - c_mb['sideslip_gradient_deg_per_g']:+.2f}"),
        ("step: yaw-rate gain, δ of the wheels (1/s)",
         result["step_steer"]["wheel_steer_gains"]["yaw_rate_per_s"], mb_step["yaw_rate"]["gain"],
         "as the ramp's yaw-rate gain (K)"),
        ("step: yaw-rate response time (s)", step["yaw_rate"]["response_time_s"],
         mb_step["yaw_rate"]["response_time_s"], chain_text("yaw_rate_response_time_s")
         + "; the rest (beyond the single track: roll, load transfer, camber, roll steer) ours "
         + rest(step, c_relax, "yaw_rate") + ", its " + rest(mb_step, c_mb, "yaw_rate")),
        ("step: yaw-rate overshoot (%)", step["yaw_rate"]["overshoot_pct"],
         mb_step["yaw_rate"]["overshoot_pct"],
         "single-track overshoot from its data to ours: "
         + ", ".join(f"{c['yaw_rate_overshoot_pct']:.1f}" for c in chain)
         + " %; the rest is the roll and load-transfer dynamics"),
        ("step: a_y response time (s)", step["lateral_acceleration"]["response_time_s"],
         mb_step["lateral_acceleration"]["response_time_s"],
         chain_text("lateral_acceleration_response_time_s")
         + "; the rest (roll, load transfer and camber building up over the roll mode) ours "
         + rest(step, c_relax, "lateral_acceleration") + ", its "
         + rest(mb_step, c_mb, "lateral_acceleration")),
        ("step: steady a_y (m/s²)", step["lateral_acceleration"]["steady"],
         mb_step["lateral_acceleration"]["steady"],
         "the same steer, its higher yaw-rate gain (K, above)"),
        ("step: steady roll (deg)", math.degrees(step["roll"]["steady"]),
         math.degrees(mb_step["roll"]["steady"]),
         f"its higher a_y (ours/its {ay_ratio:.3f}) times the roll gradients' ratio "
         f"{ours['roll_gradient_deg_per_g'] / mb['roll_gradient_deg_per_g']:.3f} (above): "
         f"{ay_ratio * ours['roll_gradient_deg_per_g'] / mb['roll_gradient_deg_per_g']:.3f}"),
        ("step: steady sideslip at the CoG (deg)", math.degrees(step["sideslip"]["steady"]),
         math.degrees(mb_step["sideslip"]["steady"]), "as the sideslip gradient (above)"),
    ]
    lines = [
        f"## Cross-check against CommonRoad's multi-body model ({vehicle['name']}, parameter "
        f"set {vehicle['id']})",
        "",
        "CommonRoad's MB model (`vehiclemodels`, unchanged; wrapper "
        "`drake_car/study/handling/crosscheck.py`) driven by our runs' measured road-wheel angle (mean "
        "of steer_fl/fr, its sign flipped to its SAE frame) at the speed our car held, "
        "settled straight for 4 s first. Its steer, yaw rate, a_y and sideslip are converted "
        "back to ISO signs (roll keeps its sign). a_y is each whole car's CoG's (its tyre "
        f"forces over its mass), sideslip is at its sprung mass's CoG ({p['a']:.3f} m behind "
        f"the front axle) and at the point on the ground below our CoG ({p['a']:.3f} m). Both "
        "understeer gradients here use the wheels' angle (ours without roll steer). "
        "Differences over 10 % are attributed in the last column.", "",
        *_broke_down_lines(cc),
        "| quantity | drake_car | CommonRoad MB | difference | attribution |",
        "|---|---|---|---|---|"]
    for name, a, b, why in rows:
        d = _diff(a, b)
        nan = isinstance(b, float) and math.isnan(b)  # CommonRoad's column
        note = ("no value: CommonRoad's model stopped before it" if nan
                else why if d is None or abs(d) > 10 else "within 10 %")
        lines.append(f"| {name} | {_f(a, 4)} | {_f(b, 4)} | "
                     f"{'–' if d is None else f'{d:+.0f} %'} | {note} |")
    lines += [
        "", "**The understeer gradients as sums of the same parts** (deg/g; each column sums "
        "to its model's gradient with the wheels' angle):", "",
        "| part | drake_car | CommonRoad MB |", "|---|---|---|"]
    for r in cc["reconciliation"]:
        lines.append(f"| {r['part']} | {_fixed(r['ours'])} | {_fixed(r['mb'])} |")
    lines += [
        f"| **sum** | **{k_o:.3f}** | **{k_m:.3f}** |", "",
        f"MB's camber part is its gradient with its tyres' camber-sign terms off for the run "
        f"({cc['ramp_no_camber_sign']['understeer_gradient_deg_per_g']:.3f} deg/g) subtracted "
        f"from its own. Its tyre: Kyα = {abs(p['tire_p_ky1']):.2f} Fz per tyre at any load (no "
        "load sensitivity, so lateral load transfer does not change its axles' stiffness), no "
        "aligning moment, no relaxation; its static loads "
        f"{cc['static_axle_loads_N']['front']:.0f} / {cc['static_axle_loads_N']['rear']:.0f} N "
        "include the unsprung masses while its yaw lever arms are the sprung mass's a, b "
        f"(its whole-car CoG is {mb_whole_a:.3f} m behind the front axle).", "",
        "**Single-track models from its data to ours**, one difference at a time (the step's "
        "times from the same steer series):", "",
        "| model | C_f / C_r (kN/rad) | m (kg) | a (m) | I_z (kg m²) | σ (m) | K (deg/g) | "
        "r/δ (1/s) | sideslip grad. | yaw resp. (s) | a_y resp. (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in chain:
        lines.append(
            f"| {c['model']} | {c['front_stiffness_N_per_rad'] / 1e3:.1f} / "
            f"{c['rear_stiffness_N_per_rad'] / 1e3:.1f} | {c['mass_kg']:.1f} | "
            f"{c['cog_to_front_m']:.3f} | {c['yaw_inertia_kgm2']:.0f} | {c['relaxation_m']:.2f} "
            f"| {c['understeer_gradient_deg_per_g']:.3f} | {c['yaw_rate_gain_per_s']:.3f} | "
            f"{c['sideslip_gradient_deg_per_g']:+.2f} | {_f(c['yaw_rate_response_time_s'])} | "
            f"{_f(c['lateral_acceleration_response_time_s'])} |")
    inertia = cc["our_inertia"]
    lines += [
        "", f"Our whole car (the plant at its design position): {inertia['mass_kg']:.1f} kg, "
        f"CoG {-inertia['cog_m'][0]:.4f} m behind the front axle and {inertia['cog_m'][2]:.3f} m "
        f"high, yaw inertia {inertia['yaw_inertia_kgm2']:.0f} kg m² (MB: {p['I_z']:.0f}, the "
        "sprung mass's, used for the whole car). Sprung mass ours "
        f"{cc['our_sprung_mass_kg']:.1f} kg, its {p['m_s']:.1f} kg.", ""]
    return lines

