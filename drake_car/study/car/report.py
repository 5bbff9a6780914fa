"""The car checked on its own (``drake-car-car-checks``): the settled car against the real car's
axle loads, the kinematics' ranges, the jammed struts' settling; as Markdown."""

import numpy as np

from drake_car.model.car import model_source, spring_settings
from drake_car.model.hard_point_table import (
    differences, hard_point_table, table_markdown, value_text)
from drake_car.model.parameters import CarParameters
from drake_car.results.provenance import provenance
from drake_car.scene.car_file import car_of_file, read_car_file


def base_car(scene):
    """The car the scene's ``car:`` values were laid over: its car file's, or the shipped
    car's parameters."""
    return car_of_file(scene.car_file) if scene.car_file else CarParameters()


def hard_point_rows(scene):
    """The hard-point table (``model.hard_point_table``) of the scene's car, with its car
    file's points as the inputs when it has one, its springs' motion ratios and rates, and
    the rows the scene's ``car:`` values changed against the car file's (or the shipped car's)
    marked."""
    given = read_car_file(scene.car_file) if scene.car_file else None
    return hard_point_table(scene.car, given,
                            springs=spring_settings(scene.car, model_source(scene.car)),
                            base=base_car(scene))


def overrides_sentence(scene):
    """What the scene's ``car:`` values change against the car it lays them over ('' for
    nothing)."""
    changed = differences(base_car(scene), scene.car)
    if not changed:
        return ""
    whose = "the car file's" if scene.car_file else "the shipped car's"
    return ("The scene's `car:` values laid over it: " + ", ".join(
        f"`{name}` = {value_text(mine)} ({whose} {value_text(theirs)})"
        for name, theirs, mine in changed)
        + "; the rows they change are marked \"input (scene)\" (a value the scene set), "
        "\"moved (scene)\" (an entered point or value it moved: no longer as entered) or keep "
        f"\"derived\" with {whose} value beside.")


def _hard_point_section(scene, rows):
    source = (f"the car file `{scene.car_file}` (its points entered, its angles derived)"
              if scene.car_file else "today's parameters (its angles entered, its points "
              "derived)")
    more = overrides_sentence(scene)
    return ["## Hard points: inputs and what the model derives", "",
            f"The car as it ran, given by {source}." + (f" {more}" if more else "")
            + " Every row is also in `hard_points.csv` "
            "(full precision). Points are the left front corner's; V is the model's frame "
            "(origin on the ground under the front axle, the tyres touching it unloaded). "
            "How each is derived: `drake_car/model/hard_point_table.py`.", "",
            *table_markdown(rows), ""]


def _ride_height_row(scene, ride):
    """The settled ride heights beside the car's own: as drawn in its car file (the wheel
    centre's height there: ``model.hard_points`` places the car's points so that it settles
    back onto them) and the model's unloaded design position (wheel centres at the tyre's
    unloaded radius R0: the heights the car sinks from)."""
    r0 = scene.car.tyre.unloaded_radius_m
    front, rear = ride["front"], ride["rear"]
    sank = (f"at the unloaded design position (tyres touching, unloaded: R0) {r0:.4f} m, so the "
            f"car sank {1e3 * (r0 - front):.1f} / {1e3 * (r0 - rear):.1f} mm under its weight")
    if scene.car_file:
        drawn = float(read_car_file(scene.car_file).front.wheel_centre_m[2])
        ours = (f"as drawn in the car file: {drawn:.4f} m (its wheel centre's height; the "
                f"settled car sits {1e3 * (front - drawn):+.1f} / {1e3 * (rear - drawn):+.1f} mm "
                f"from it); {sank}")
    else:
        ours = f"no ride height as drawn in the car's data; {sank}"
    return (f"| ride height front / rear (the body's height above the road at each axle, at the "
            f"design wheel-centre height) | {front:.4f} / {rear:.4f} m | {ours} |")


def _jammed_section(lubricated, scene, moved):
    """The jammed run's section: its friction law and the strut damping it ran with (the
    scene's, against the lubricated run's)."""
    law = scene.friction.law if scene.friction is not None else None
    damping, before = (scene.car.front.strut_damping_Nspm,
                       lubricated.car.front.strut_damping_Nspm)
    title = ("## Jammed struts" + (f" (μs = {law.mu_s:g}, μd = {law.mu_d:g})" if law else ""))
    if damping == 0.0:
        how = (f"This run sets the front struts' viscous damping to 0 (the lubricated run above: "
               f"{before:g} N s/m): a dry strut has only its friction.")
    else:
        how = (f"This run keeps {damping:g} N s/m of viscous damping in the front struts beside "
               "the friction (the scene's `car.front.strut_damping_Nspm`).")
    dmax = f"{1e6 * law.dmax_translation_m:g} µm" if law else "none"
    return [title, "", f"{how} Settling from the design position, the rods move "
            f"{1e6 * moved:.1f} µm after 0.8 s (the creep bound Δmax is {dmax}). Replay: "
            "`jammed/replay.html`; the Diagram with strut friction, as it ran: "
            "`jammed/diagram.svg`.", ""]


def write_report(path, settled, sweep, stuck, wall, rows=None):
    final = settled.final
    loads, design = final["corner_loads_N"], final["design_axle_loads_N"]
    front, rear = loads["fl"] + loads["fr"], loads["rl"] + loads["rr"]
    k = sweep.kinematics
    left = np.array(k["side"]) == "left"

    def span(name):
        values = np.array(k[name])[left]
        return f"{values.min():.2f} … {values.max():.2f}"

    h = stuck.history
    late = h["t"] >= 0.8
    moved = max(float(np.ptp(h[f"d_{s}_m"][late])) for s in ("left", "right"))
    prov = provenance()
    scene = settled.scene
    data = (f"the car file `{scene.car_file}`" if scene.car_file else
            "Ford Escort data [ESC], see `drake_car/model/parameters.py`")
    if scene.car_file is None and scene.car != type(scene.car)():
        data = "the scene's car parameters (`car:` in the scene)"
    lines = [
        "# drake_car: the car on its own", "",
        f"Made by `{prov['command']}`; {prov['created_utc']}, drake {prov['drake']}, commit "
        f"{(prov['git_commit'] or 'unknown')[:10]}; {wall:.1f} s wall.", "",
        "## The settled car (lubricated struts)", "",
        "| quantity | model | the car's data |", "|---|---|---|",
        f"| front axle load | {front:.0f} N | {design['front']:.0f} N "
        f"({100 * (front / design['front'] - 1):+.2f} %) |",
        f"| rear axle load | {rear:.0f} N | {design['rear']:.0f} N "
        f"({100 * (rear / design['rear'] - 1):+.2f} %) |",
        f"| total mass | {final['total_mass_kg']:.1f} kg | "
        f"{settled.scene.car.mass.total_mass_kg} kg |",
        _ride_height_row(scene, final["ride_height_m"]),
        f"| strut overlap d left / right | {final['strut_overlap_m']['left']:.5f} / "
        f"{final['strut_overlap_m']['right']:.5f} m | design "
        f"{settled.scene.car.front.guide_length_l_m} m |",
        f"| loop-closure error (SAP) | {final['loop_closure_error_m']:.1e} m | |", "",
        f"The car's data: {data}. The scene as it ran: `settle/scene.yaml`.", "",
        "## Kinematics (chassis fixed, ±80 mm, left wheel)", "",
        f"camber {span('camber_deg')} deg, toe-in {span('toe_deg')} deg, caster "
        f"{span('caster_deg')} deg, kingpin {span('kingpin_deg')} deg, strut length "
        f"{span('strut_length_m')} m, overlap d {span('overlap_m')} m; largest loop-closure "
        f"error {max(k['closure_error_m']):.1e} m (Newton). Plots: `kinematics/*.png`.", "",
        *_jammed_section(scene, stuck.scene, moved)]
    if rows is not None:
        lines += _hard_point_section(settled.scene, rows)
    path.write_text("\n".join(lines))
