"""The ride study's tables, linearity check and report text (``DIR/report.md`` is written by
``drake-car-ride`` from these). A run that did not hold its speed over the analysed window
(``analysis.held_speed``) is flagged at the report's top, in its Summary, on its rows of the
tables and on stderr (a logging warning): its numbers are not the ride at that speed."""

import csv
import logging
import math

import numpy as np

from drake_car.results.numbers import signed
from drake_car.scene.borrowed import (
    drive_limit, drive_limit_words, seat_place, seat_point, seat_point_words)
from drake_car.scene.launch import launch_limits
from drake_car.scene.manoeuvre_targets import SPEED_TOLERANCE_KPH
from drake_car.study.car.describe import car_facts, car_lines
from drake_car.study.ride.analysis import OUTCOMES, seat_psd
from drake_car.study.ride.figures import plot_against_mu, plot_psd
from drake_car.study.ride.grid import (
    SPEED_UP_KPH_PER_S, analysed_from_s, ride_timelines, speed_up_s)

log = logging.getLogger(__name__)

COLUMNS = (("aw_seat_mps2", "a_w seat [m/s²]", 3), ("pitch_acc_rms_radps2", "pitch acc. [rad/s²]", 3),
           ("roll_acc_rms_radps2", "roll acc. [rad/s²]", 3), ("dlc_front", "DLC front", 4),
           ("dlc_rear", "DLC rear", 4), ("stick_left", "stick L", 3),
           ("stick_right", "stick R", 3), ("friction_mean_N", "mean |F_fric| [N]", 0),
           ("normal_mean_N", "mean N [N]", 0))


def slope_words(slopes, classes):
    """What 0.1 of μs costs over the road ``classes`` (one slope each): one value for one
    class (or one value after rounding), else the range."""
    low, high = signed(min(slopes), 3), signed(max(slopes), 3)
    fit = "linear fit over μs 0-0.4"
    if len(slopes) == 1:
        return f"{low} m/s² per 0.1 of μs ({fit}, class {classes[0]})"
    if low == high:
        return f"{low} m/s² per 0.1 of μs ({fit}, the same in classes {', '.join(classes)})"
    return f"{low} to {high} m/s² per 0.1 of μs ({fit}, classes {', '.join(classes)})"


def _value(row, key, digits):
    return f"{row[key]:.{digits}f} ± {row['err_' + key]:.1g}"


def _range(row):
    """"48.50-59.80 km/h": the run's speed over its analysed window."""
    low, high = row["speed_min_kph"], row["speed_max_kph"]
    if not (math.isfinite(low) and math.isfinite(high)):
        return "speed not logged"
    return f"{low:.2f}-{high:.2f} km/h"


def _off(row):
    """" **OFF: 48.5-59.8 km/h**" after the speed of a run that did not hold it, else ""."""
    return "" if row["held_speed"] else f" **OFF: {_range(row)}**"


def off_speed(rows):
    """The rows whose run did not hold its speed over the analysed window, by name."""
    return sorted((r for r in rows if not r["held_speed"]), key=lambda r: r["name"])


def speed_flag(rows):
    """The report's warning lines (empty: every run held its speed)."""
    off = off_speed(rows)
    if not off:
        return []
    runs = "; ".join(f"{r['name']}: {_range(r)} (asked {r['speed_kph']:g})" for r in off)
    return [f"**Warning: not at constant speed.** {len(off)} of {len(rows)} runs did not hold "
            f"their speed within {SPEED_TOLERANCE_KPH:g} km/h over the analysed window: "
            f"{runs}. Their outcomes are not the ride at the asked speed (marked OFF below).",
            ""]


def seat_flag(seat):
    """The report's warning lines where the seat point is an estimate, not the car's (empty
    otherwise; ``seat``: ``scene.borrowed.seat_point``'s)."""
    if seat["source"] != "estimated":
        return []
    return [f"**Warning: the seat point is an estimate [EST], not this car's.** a_w is measured "
            f"at {seat_point_words(seat)}.", ""]


def warn_off_speed(rows):
    """One warning (stderr, through logging) per run that did not hold its speed."""
    for r in off_speed(rows):
        log.warning("ride run %s did not hold %g km/h over its analysed window: %s "
                    "(tolerance %g km/h); its outcomes are not the ride at that speed",
                    r["name"], r["speed_kph"], _range(r), SPEED_TOLERANCE_KPH)


def outcome_table(rows):
    """A markdown table: one line per run (cell, μs), each outcome ± its numerical error; a
    run that did not hold its speed marked OFF with its speed range."""
    head = "| class | km/h | strut | μs | " + " | ".join(c[1] for c in COLUMNS) + " |"
    lines = [head, "|" + "---|" * (4 + len(COLUMNS))]
    for r in sorted(rows, key=lambda r: (r["speed_kph"], r["road_class"], r["strut"] != "lubricated",
                                         r["strut"], r["mu_s"])):
        cells = [r["road_class"], f"{r['speed_kph']:g}{_off(r)}", r["strut"],
                 f"{r['mu_s']:.2f}"]
        cells += [_value(r, key, digits) for key, _, digits in COLUMNS]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def cells_of(rows):
    """{(class, speed, strut): [rows by μs, the lubricated run first]} (the lubricated run is
    every strut's μs = 0)."""
    cells = {}
    for r in rows:
        if r["strut"] == "lubricated":
            continue
        cells.setdefault((r["road_class"], r["speed_kph"], r["strut"]), []).append(r)
    out = {}
    for key, sel in cells.items():
        lubricated = [r for r in rows if r["strut"] == "lubricated"
                      and (r["road_class"], r["speed_kph"]) == key[:2]]
        out[key] = lubricated + sorted(sel, key=lambda r: r["mu_s"])
    return out


def linearity(sel, x_key, y_key="aw_seat_mps2"):
    """A straight line y = a + b x through the rows ``sel``: (a, b, R², the largest deviation
    from the line over the total change of y, the largest numerical error of y)."""
    x = np.array([r[x_key] for r in sel], dtype=float)
    y = np.array([r[y_key] for r in sel], dtype=float)
    b, a = np.polyfit(x, y, 1)
    fitted = a + b * x
    total = np.ptp(y)
    ss = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(np.sum((y - fitted) ** 2)) / ss if ss > 0 else math.nan
    deviation = float(np.max(np.abs(y - fitted)) / total) if total > 0 else math.nan
    return a, b, r2, deviation, max(r[f"err_{y_key}"] for r in sel)


def cost_table(rows):
    """Per cell: the lubricated car's values and what each μs adds (relative change), with
    the linear fits of a_w against μs and against the mean friction force."""
    lines = ["| class | km/h | strut | a_w lubricated [m/s²] | Δa_w at μs 0.1 / 0.2 / 0.3 / 0.4 "
             "| ΔDLC front at μs 0.1 / 0.2 / 0.3 / 0.4 | line a_w(μs): slope [m/s² per 0.1], R², "
             "max dev. | line a_w(rig friction μd·N̄): slope [m/s² per 100 N], R² |",
             "|---|---|---|---|---|---|---|---|"]
    for (road_class, speed, strut), sel in sorted(cells_of(rows).items()):
        base = sel[0]
        if base["strut"] != "lubricated":
            continue
        dry = sel[1:]
        da = " / ".join(f"{signed(100 * (r['aw_seat_mps2'] / base['aw_seat_mps2'] - 1))} %"
                        for r in dry)
        dd = " / ".join(f"{signed(100 * (r['dlc_front'] / base['dlc_front'] - 1))} %"
                        for r in dry)
        _, b, r2, dev, _ = linearity(sel, "mu_s")
        if len(dry) >= 2:
            _, bf, r2f, _, _ = linearity(sel, "rig_friction_N")
            force = f"{100 * bf:.3f}, {r2f:.3f}"
        else:
            force = "-"
        off = " **OFF**" if any(not r["held_speed"] for r in sel) else ""
        lines.append(f"| {road_class} | {speed:g}{off} | {strut} | {base['aw_seat_mps2']:.3f} | {da} | "
                     f"{dd} | {signed(0.1 * b, 3)}, {r2:.3f}, {100 * dev:.0f} % | {force} |")
    return "\n".join(lines)


def linear_verdict(sel):
    """Whether a_w grows about linearly with the strut's friction force as a rig measures it
    (``rig_friction_N`` = μd·N̄; the lubricated run at 0): R² >= 0.95 and no point off the
    line by more than 10 % of the total change (the runs' numerical errors are far smaller)."""
    a, b, r2, dev, err = linearity(sel, "rig_friction_N")
    linear = r2 >= 0.95 and dev <= 0.10
    return linear, b, r2, dev, err


def literature_text(rows, seat):
    """The lubricated car's a_w against the literature (the sources as given; [EST] where a
    value could not be checked here); ``seat``: ``scene.borrowed.seat_point``'s."""
    lubricated = sorted((r for r in rows if r["strut"] == "lubricated"),
                        key=lambda r: (r["speed_kph"], r["road_class"]))
    values = ", ".join(f"class {r['road_class']} at {r['speed_kph']:g} km/h "
                       f"{r['aw_seat_mps2']:.2f} m/s²" for r in lubricated)
    return (
        "The lubricated car's Wk-weighted RMS vertical acceleration at the seat point "
        f"({seat_place(seat['seat_point_m'])}; the car's section says its source): {values}."
        "\n\nAgainst what is known of passenger cars:\n\n"
        "- ISO 2631-1:1997, Annex C (C.2.3), the likely reactions to a_w in public transport: "
        "< 0.315 m/s² not uncomfortable; 0.315-0.63 a little uncomfortable; 0.5-1 fairly "
        "uncomfortable; 0.8-1.6 uncomfortable; 1.25-2.5 very uncomfortable; > 2 extremely "
        "uncomfortable.\n"
        "- Passenger cars measured on public roads: seat-surface vertical a_w of the order of "
        "0.2-0.6 m/s² (Paddan & Griffin, \"Evaluation of whole-body vibration in vehicles\", "
        "J. Sound Vib. 253(1), 2002, 195-213, cars among 100 vehicles) [EST: the range is "
        "recalled, not checked against the paper here]. Their roads were ordinary roads, "
        "mostly ISO 8608 class A-B.\n"
        "- The model's point is the floor under the seat (no cushion): a seat's cushion "
        "transmits about 1 near 4 Hz and amplifies somewhat there (a SEAT value of ~0.8-1.1 "
        "for car seats [EST]), so the floor value is comparable to the seat-surface value "
        "within some tens of per cent; the model's tyres touch the road at a point (no "
        "enveloping of the contact patch), which overstates the excitation of wavelengths "
        "shorter than ~0.5 m, i.e. above ~8 Hz at 60 km/h.")


def summary_text(rows):
    """The answers in numbers: per strut model and speed, what 0.1 of μs costs in a_w and in
    the front DLC over the road classes, and how many cells are about linear."""
    lines = []
    cells = cells_of(rows)
    for strut in sorted({k[2] for k in cells}):
        for speed in sorted({k[1] for k in cells}):
            sel = {k: v for k, v in cells.items() if k[1] == speed and k[2] == strut
                   and v[0]["strut"] == "lubricated" and len(v) >= 3}
            if not sel:
                continue
            slopes = [0.1 * linearity(v, "mu_s")[1] for v in sel.values()]
            worst = {k[0]: (v[-1]["aw_seat_mps2"] / v[0]["aw_seat_mps2"] - 1,
                            v[-1]["dlc_front"] / v[0]["dlc_front"] - 1,
                            v[-1]["dlc_rear"] / v[0]["dlc_rear"] - 1, v[-1]["mu_s"])
                     for k, v in sel.items()}
            linear = sum(linear_verdict(v)[0] for v in sel.values())
            off = sum(not r["held_speed"] for v in sel.values() for r in v)
            parts = "; ".join(f"class {c}: a_w {signed(100 * a)} %, DLC front "
                              f"{signed(100 * f)} %, rear {signed(100 * r)} % at μs {m:g}"
                              for c, (a, f, r, m) in sorted(worst.items()))
            lines.append(f"- {strut} strut, {speed:g} km/h: a_w changes by "
                         f"{slope_words(slopes, sorted(k[0] for k in sel))}; {parts}; about "
                         f"linear in the rig friction force in {linear} of {len(sel)} classes"
                         + (f" (**not at constant speed**: {off} of "
                            f"{sum(len(v) for v in sel.values())} runs did not hold "
                            f"{speed:g} km/h)." if off else "."))
    return "\n".join(lines)


def launch_text(rows, scene):
    """The runs' launches: the asked 0.57 g, or longer where the car's drive cannot follow it
    (``grid.ride_timeline``)."""
    launches = sorted({(r["speed_kph"], r["launch_s"]) for r in rows})
    longer = [(v, t) for v, t in launches if t != speed_up_s(v)]
    text = (f"The launch asks {SPEED_UP_KPH_PER_S / 3.6 / 9.81:.2f} g up to the speed (the "
            "paper's) where the car is predicted to hold its speed over the analysed window "
            "(`scene/launch.py`), else the shortest launch its drive allows that it holds: "
            + "; ".join(f"{v:g} km/h in {t:g} s" for v, t in launches))
    if longer:
        limits = launch_limits(scene)
        text += (f" (longer than the asked {', '.join(f'{speed_up_s(v):g}' for v, _ in longer)}"
                 f" s: the car allows {limits.max_accel_mps2:.2f} m/s² with its drive and tyres, "
                 f"limited by {limits.limited_by}; the drive's torque limit "
                 f"{drive_limit_words(drive_limit(scene))})")
    return text


def _track_m(study, runs):
    """The road's tracks' distance: the study's, or the car's front track."""
    if study.track_m is not None or not runs:
        return study.track_m
    return next(iter(runs.values())).scene.car.front.track_m


def write_outputs(out, rows, runs, study, wall_s):
    """DIR/outcomes.csv, the figures and DIR/report.md of ``rows`` (``analysis.collect``);
    ``runs``: name -> a finished run (.scene, .history) for the spectra."""
    fields = ["name", "road_class", "speed_kph", "strut", "mu_s", "rig_friction_N", "wall_s",
              "wall_half_s", "launch_s", "speed_min_kph", "speed_max_kph", "held_speed",
              *OUTCOMES, *[f"err_{k}" for k in OUTCOMES]]
    with open(out / "outcomes.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fields)
        writer.writeheader()
        writer.writerows(rows)
    for strut in sorted({r["strut"] for r in rows} - {"lubricated"}):
        sel = [r for r in rows if r["strut"] in ("lubricated", strut)]
        plot_against_mu(sel, out / f"ride_vs_mu_{strut}.png",
                        f"Ride on ISO 8608 roads against strut friction ({strut} strut)")
    figures = []
    for (road_class, speed, strut), sel in sorted(cells_of(rows).items()):
        curves = []
        for r in sel:
            if r["mu_s"] in (0.0, 0.2, 0.4):
                run = runs[r["name"]]
                f, p = seat_psd(run.history, analysed_from_s(run.scene, study))
                curves.append((f"μs {r['mu_s']:g} ({r['strut']})", f, p))
        name = f"psd_{road_class}_{speed:g}_{strut}.png"
        plot_psd(curves, out / name, f"Seat vertical acceleration, class {road_class}, "
                                     f"{speed:g} km/h, {strut} strut")
        figures.append(name)
    verdicts = []
    for (road_class, speed, strut), sel in sorted(cells_of(rows).items()):
        if sel[0]["strut"] != "lubricated" or len(sel) < 3:
            continue
        linear, b, r2, dev, err = linear_verdict(sel)
        verdicts.append(f"- class {road_class}, {speed:g} km/h, {strut} strut: "
                        f"{'about linear' if linear else 'not linear'} (a_w against the rig "
                        f"friction force μd·N̄: slope {100 * b:.3f} m/s² per 100 N, R² {r2:.3f}, "
                        f"largest deviation from the line {100 * dev:.0f} % of the change; "
                        f"numerical error of a_w ≤ {err:.1g} m/s²)"
                        + (" **OFF: not at constant speed**" if any(not r["held_speed"]
                                                                   for r in sel) else ""))
    first = next(iter(runs.values()))
    scene, lubricated = first.scene, [r for r in runs.values() if r.scene.friction is None]
    car = car_facts(lubricated[0].scene if lubricated else scene)
    seat = seat_point(scene)  # the car's: the grid's scenes share it
    steps = sorted({r.scene.plant.time_step for r in runs.values()})
    track = _track_m(study, runs)
    held = [(r["speed_min_kph"], r["speed_max_kph"], r["speed_kph"]) for r in rows]
    worst = max((max(abs(lo - v), abs(hi - v)) for lo, hi, v in held
                 if math.isfinite(lo)), default=math.nan)
    warn_off_speed(rows)
    flag = speed_flag(rows)
    # Every speed's launch, as the scenes were made (a speed without a finished run too).
    launches = {v: t.speed_up_s for v, t in ride_timelines(study, scene).items()}
    text = [
        "# Ride comfort and road holding on rough roads against strut friction", "",
        *flag, *seat_flag(seat),
        f"{len(rows)} runs, each with its half-step twin ({2 * len(rows)} simulations); "
        f"analysis wall time {wall_s:.0f} s. Road: ISO 8608 (law/road/iso8608.py), one seed "
        f"({study.seed}) for every class and speed (class B is class A's road doubled, C is "
        f"B's doubled), {study.road_m(launches):g} m, 0.05 m samples, 0.011-2.83 cycles/m, "
        f"two tracks {track:g} m apart (the car's front track) with the isotropic coherence. "
        f"{launch_text(rows, scene)}; then {study.settle_window_s:g} s settles and "
        f"{study.window_s:g} s is analysed; in the analysed windows the car held its speed "
        f"within {worst:.2f} km/h"
        + (f" (**not at constant speed**: beyond the {SPEED_TOLERANCE_KPH:g} km/h asked, see "
           "the warning above)" if flag else "") + "; logged every "
        f"{1e3 * scene.logging.record_period_s:g} ms (Nyquist "
        f"{0.5 / scene.logging.record_period_s:.0f} Hz against Wk's 80 Hz); step "
        f"{1e3 * steps[-1]:g} ms, twin at {1e3 * steps[0]:g} ms. μd = {study.mu_d_ratio:g} μs.",
        "", "## The car", "", *car_lines(car),
        "- **strut models**: *lubricated* is the car as it is (μs = 0: no dry friction, its "
        f"own damper of {car['strut_damping_Nspm']:g} N s/m); *damper* adds the dry friction "
        "to the car's damper (a real strut); *paper* removes the viscous damping (the paper's "
        "dry strut).",
        f"- **seat point** (where a_w is measured; `car.seat_point_m`): {seat_point_words(seat)}.",
        "",
        "## Summary", "", *flag, *seat_flag(seat), summary_text(rows), "",
        "## What each μs costs", "", cost_table(rows), "",
        "## Is the worsening linear in the friction force?", "",
        "Deubel, Schneider & Prokop (SAE J. Veh. Dyn. 8(2), 2024) measured vertical ride "
        "comfort worsening about linearly with the strut's friction force. The model, cell by "
        "cell (a_w against the friction force a rig would measure at the car's mean side load, "
        "μd·N̄, the lubricated car at 0; \"about linear\": R² >= 0.95 and no point off the line "
        "by more than 10 % of the change):", "", *verdicts, "",
        "## Limits", "",
        "- One road realisation (seed) and 6 s per run: the absolute a_w of one run scatters "
        "with the road sample (a 6 s record of a ~1.5 Hz response holds few independent "
        "cycles); the differences between μs are paired (the same road under every μs) and "
        "much more certain than the absolute values. Not estimated here: a second seed.",
        "- The tyres touch the road at a point (no contact-patch enveloping): wavelengths below "
        "~0.5 m excite the wheels more than on a real tyre.",
        "- The seat point is the floor under the seat; the seat cushion is not modelled. a_w "
        "depends on where it lies (the body's pitch moves a point over an axle unlike one at "
        "mid-wheelbase): " + ("**an estimate, not this car's** (above)" if seat["source"] ==
                              "estimated" else "see the car's section for its source") + ".",
        "- Only the front struts carry dry friction (the rear suspension is lubricated).", "",
        "## The lubricated car against measured cars", "", literature_text(rows, seat), "",
        "## Every run (value ± numerical error: |run(1 ms) - run(0.5 ms)|)", "",
        outcome_table(rows), "",
        "## Figures", "", *[f"![]({p.name})" for p in sorted(out.glob("ride_vs_mu_*.png"))],
        *[f"![]({name})" for name in figures], ""]
    (out / "report.md").write_text("\n".join(text))
