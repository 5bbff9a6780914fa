"""The handling study's figures: steady state against the single-track model, step steer,
the understeer budget, and the cross-check against CommonRoad's model."""

import math

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DPI = 110
OUTSIDE = dict(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=8)


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    plt.close(fig)


def _shade(ax, fit_range):
    ax.axvspan(*fit_range, color="0.9", zorder=0, label="fit range")


def handling_figures(result, out):
    ss, st, budget = result["steady_state"], result["step_steer"], result["budget"]
    m, single, s = ss["metrics"], ss["single_track"], ss["series"]
    fit = result["fit_range_mps2"]
    turning = s["t"] >= result["t_steer_s"]["steady_state"]
    ay = s["ay_mps2"][turning]
    v = m["speed_mps"]
    L = result["wheelbase_m"]
    line = np.linspace(0.0, float(ay.max()), 50)
    fig, axes = plt.subplots(2, 3, figsize=(15, 8))
    ax = axes[0, 0]
    _shade(ax, fit)
    ax.plot(ay, s["understeer_deg"][turning], label="δ (rack) − L r/V")
    ax.plot(ay, (s["wheel_steer_deg"] - s["steer_deg"] + s["understeer_deg"])[turning],
            label="δ (wheels) − L r/V")
    k = m["understeer_gradient_deg_per_g"]
    ax.plot(line, m["understeer_intercept_deg"] + k * line / 9.81, "k--", lw=1,
            label=f"fit: {k:.2f} deg/g")
    ax.plot(line, single["understeer_gradient_deg_per_g"] * line / 9.81, ":", color="tab:red",
            label=f"single track: {single['understeer_gradient_deg_per_g']:.2f} deg/g")
    ax.set(xlabel="a_y at the CoG (m/s²)", ylabel="deg", title="understeer (ISO 4138)")
    ax.legend(fontsize=8)
    ax = axes[0, 1]
    ax.plot(ay, s["steer_deg"][turning], label="δ from the rack")
    ax.plot(ay, s["wheel_steer_deg"][turning], label="δ of the wheels")
    ax.plot(line, np.degrees(L * line / v ** 2), "k:", label="neutral: L a_y/V²")
    ax.set(xlabel="a_y (m/s²)", ylabel="road-wheel angle (deg)", title="steer angle")
    ax.legend(fontsize=8)
    for ax, key, label, grad in (
            (axes[0, 2], "roll_deg", "roll (deg)", "roll_gradient_deg_per_g"),
            (axes[1, 0], "sideslip_cog_deg", "sideslip at the CoG (deg)",
             "sideslip_gradient_deg_per_g"),
            (axes[1, 1], "rack_force_N", "rack force (N)", "rack_force_gradient_N_per_g")):
        _shade(ax, fit)
        ax.plot(ay, s[key][turning])
        value = f"{m[grad]:.0f} N/g" if key == "rack_force_N" else f"{m[grad]:.2f} deg/g"
        ax.set(xlabel="a_y (m/s²)", ylabel=label,
               title=f"{label.split(' (')[0]}: {value} in the fit range")
    axes[1, 0].plot(line, single["sideslip_gradient_deg_per_g"] * line / 9.81, ":",
                    color="tab:red", label="single track")
    axes[1, 0].legend(fontsize=8)
    ax = axes[1, 2]
    ax.plot(s["steer_deg"][turning], s["yaw_rate_degps"][turning], label="measured")
    d = np.linspace(0.0, float(s["steer_deg"][turning].max()), 20)
    ax.plot(d, single["yaw_rate_gain_per_s"] * d, ":", color="tab:red",
            label=f"single track: {single['yaw_rate_gain_per_s']:.2f} /s")
    ax.set(xlabel="δ from the rack (deg)", ylabel="yaw rate (deg/s)",
           title=f"yaw-rate gain {m['yaw_rate_gain_per_s']:.2f} /s in the fit range "
                 f"({ss['yaw_gain_ratio']:.3f} of the single track)")
    ax.legend(fontsize=8)
    fig.suptitle(f"Steady-state circular driving, ramp steer at {3.6 * v:.1f} km/h "
                 f"({result['drive']})")
    _save(fig, out / "steady_state" / "steady_state.png")

    sr, sm = st["series"], st["metrics"]
    t50 = sm["yaw_rate"]["steer_50pct_s"]
    t = sr["t"] - t50
    show = (t > -0.5) & (t < 2.5)
    fig, axes = plt.subplots(2, 2, figsize=(12, 7))
    axes[0, 0].plot(t[show], sr["steer_deg"][show], label="from the rack")
    axes[0, 0].plot(t[show], sr["wheel_steer_deg"][show], label="of the wheels")
    axes[0, 0].set(ylabel="road-wheel angle (deg)", title="steer")
    axes[0, 0].legend(fontsize=8)
    for ax, key, name, scale, unit in (
            (axes[0, 1], "yaw_rate_degps", "yaw_rate", math.degrees(1), "deg/s"),
            (axes[1, 0], "ay_mps2", "lateral_acceleration", 1.0, "m/s²")):
        r = sm[name]
        ax.plot(t[show], sr[key][show])
        ax.axhline(r["steady"] * scale, color="k", lw=0.8, ls="--", label="steady")
        ax.axhline(0.9 * r["steady"] * scale, color="0.5", lw=0.8, ls=":", label="90 %")
        ax.axvline(r["response_time_s"], color="tab:green", lw=0.8,
                   label=f"response time {r['response_time_s']:.3f} s")
        if r["peak_response_time_s"] is not None:
            ax.axvline(r["peak_response_time_s"], color="tab:red", lw=0.8,
                       label=f"peak {r['peak_response_time_s']:.3f} s, "
                             f"+{r['overshoot_pct']:.1f} %")
        ax.set(ylabel=unit, title=name.replace("_", " ") + " (at the CoG)")
        ax.legend(fontsize=8)
    ax = axes[1, 1]
    ax.plot(t[show], sr["roll_deg"][show], label="roll")
    ax.plot(t[show], sr["sideslip_cog_deg"][show], label="sideslip at the CoG")
    ax.set(ylabel="deg", title="roll and sideslip")
    ax.legend(fontsize=8)
    for ax in axes.flat:
        ax.set_xlabel("time from 50 % steer (s)")
        ax.grid(alpha=0.3)
    fig.suptitle(f"Step steer at {3.6 * sm['speed_mps']:.1f} km/h (ISO 7401, {result['drive']})")
    _save(fig, out / "step_steer" / "step_steer.png")

    rows = budget["rows"]
    fig, ax = plt.subplots(figsize=(10, 6))
    names = [r["term"] for r in rows]
    values = [r["gradient_deg_per_g"] for r in rows]
    colours = ["0.6" if "remainder" in r["key"] or r["key"] == "slip_spread" else "tab:blue"
               for r in rows]
    y = np.arange(len(rows))[::-1]
    ax.barh(y, values, color=colours)
    ax.set_yticks(y, names, fontsize=8)
    ax.axvline(0, color="k", lw=0.8)
    ax.set(xlabel="contribution to the understeer gradient (deg/g)",
           title=f"Understeer budget: measured {budget['measured_deg_per_g']:.3f} deg/g, named "
                 f"terms {budget['named_sum_deg_per_g']:.3f}, remainders (grey) "
                 f"{budget['remainder_deg_per_g']:+.3f}")
    _save(fig, out / "budget.png")
    return {"steady_state/steady_state.png": "ramp steer: understeer, steer angle, roll, "
                                             "sideslip, rack force against a_y; yaw rate "
                                             "against steer; the single-track model dotted",
            "step_steer/step_steer.png": "step steer: steer, yaw rate and a_y with their "
                                         "response and peak times, roll and sideslip",
            "budget.png": "the understeer budget's terms"}


def crosscheck_figures(result, out):
    cc = result["crosscheck"]
    s = cc["series_ramp"]
    fit = result["fit_range_mps2"]
    v = result["steady_state"]["metrics"]["speed_mps"]
    L, L_mb = result["wheelbase_m"], cc["parameters"]["a"] + cc["parameters"]["b"]
    turning = s["t"] >= result["t_steer_s"]["steady_state"]
    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    for ax, key, label in ((axes[0, 0], "under", "δ (wheels) − L r/V (deg)"),
                           (axes[0, 1], "roll_deg", "roll (deg)"),
                           (axes[1, 0], "sideslip_deg", "sideslip at the CoG (deg)")):
        _shade(ax, fit)
        if key == "under":
            ours = s["steer_deg"] - np.degrees(L * np.radians(s["yaw_rate_degps"]) / s["speed_mps"])
            mb = s["mb_steer_deg"] - np.degrees(
                L_mb * np.radians(s["mb_yaw_rate_degps"]) / s["mb_speed_mps"])
        else:
            ours, mb = s[key], s["mb_" + key]
        ax.plot(s["ay_mps2"][turning], ours[turning], label="drake_car")
        ax.plot(s["mb_ay_mps2"][turning], mb[turning], label="CommonRoad MB")
        ax.set(xlabel="a_y (m/s²)", ylabel=label)
        ax.legend(fontsize=8)
    ax = axes[1, 1]
    ax.plot(s["steer_deg"][turning], s["yaw_rate_degps"][turning], label="drake_car")
    ax.plot(s["mb_steer_deg"][turning], s["mb_yaw_rate_degps"][turning], label="CommonRoad MB")
    ax.set(xlabel="road-wheel angle (deg)", ylabel="yaw rate (deg/s)")
    ax.legend(fontsize=8)
    vehicle = cc.get("vehicle", {"id": 1, "name": "Ford Escort"})
    fig.suptitle(f"Ramp steer at {3.6 * v:.1f} km/h: drake_car against CommonRoad's multi-body "
                 f"model (parameter set {vehicle['id']}, {vehicle['name']}), same road-wheel "
                 "steer")
    _save(fig, out / "crosscheck" / "crosscheck_ramp.png")

    s = cc["series_step"]
    t50 = result["step_steer"]["metrics"]["yaw_rate"]["steer_50pct_s"]
    t = s["t"] - t50
    fig, axes = plt.subplots(2, 2, figsize=(12, 7))
    for ax, key, label in ((axes[0, 0], "yaw_rate_degps", "yaw rate (deg/s)"),
                           (axes[0, 1], "ay_mps2", "a_y at the CoG (m/s²)"),
                           (axes[1, 0], "roll_deg", "roll (deg)"),
                           (axes[1, 1], "sideslip_deg", "sideslip at the CoG (deg)")):
        ax.plot(t, s[key], label="drake_car")
        ax.plot(t, s["mb_" + key], label="CommonRoad MB")
        ax.set(xlabel="time from 50 % steer (s)", ylabel=label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Step steer: drake_car against CommonRoad's multi-body model, same road-wheel "
                 "steer")
    _save(fig, out / "crosscheck" / "crosscheck_step.png")
    return {"crosscheck/crosscheck_ramp.png": "ramp steer, ours against CommonRoad's MB: "
                                              "understeer, roll, sideslip against a_y; yaw "
                                              "rate against steer",
            "crosscheck/crosscheck_step.png": "step steer, ours against CommonRoad's MB: yaw "
                                              "rate, a_y, roll, sideslip"}



# -- the report ------------------------------------------------------------------------------
