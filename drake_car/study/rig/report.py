"""The strut rig study's report (``drake-car-strut-rig``'s report.md): the car's strut at rest
and the rig loaded as it, every rig run's break-away and sliding, and the synthetic loop's
fit; the numbers of at_rest.json, rig.csv and fit.json, as Markdown (pure: no files)."""

import math


def report(*, scene_name, at_rest, rows, law, fit, runs, prov):
    """Markdown of the rig study: ``at_rest`` (``StrutAtRest.summary()``), ``rows`` (one per
    rig run, ``loops.rig_study``), ``law`` the synthetic loop's law, ``fit`` its ``LoopFit``,
    ``runs`` how the rig's runs went, ``prov`` the provenance."""
    shares = ", ".join(f"{name} {value:+.1f} N" for name, value in at_rest["shares_N"].items())
    lines = [
        f"# The strut side-load rig: the front strut of the car of scene `{scene_name}`", "",
        f"Made by `{prov['command']}`, commit {prov['git_commit']}"
        f"{' (uncommitted changes)' if prov['dirty'] else ''}, drake {prov['drake']}, "
        f"{prov['created_utc']}; {runs['runs']} rig runs, {runs['cpu_s']:.0f} s of CPU.", "",
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
