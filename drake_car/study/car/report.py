"""The car checked on its own (``drake-car-car-checks``): the settled car against the real car's
axle loads, the kinematics' ranges, the jammed struts' settling; as Markdown."""

import numpy as np

from drake_car.model.car import model_source, spring_settings
from drake_car.model.hard_point_table import hard_point_table, table_markdown
from drake_car.results.provenance import provenance
from drake_car.scene.car_file import read_car_file


def hard_point_rows(scene):
    """The hard-point table (``model.hard_point_table``) of the scene's car, with its car
    file's points as the inputs when it has one, and its springs' motion ratios and rates."""
    given = read_car_file(scene.car_file) if scene.car_file else None
    return hard_point_table(scene.car, given,
                            springs=spring_settings(scene.car, model_source(scene.car)))


def _hard_point_section(scene, rows):
    source = (f"the car file `{scene.car_file}` (its points entered, its angles derived)"
              if scene.car_file else "today's parameters (its angles entered, its points "
              "derived)")
    return ["## Hard points: inputs and what the model derives", "",
            f"The car as it ran, given by {source}; every row also in `hard_points.csv` "
            "(full precision). Points are the left front corner's; V is the model's frame "
            "(origin on the ground under the front axle, the tyres touching it unloaded). "
            "How each is derived: `drake_car/model/hard_point_table.py`.", "",
            *table_markdown(rows), ""]


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
        f"| ride height front / rear | {final['ride_height_m']['front']:.4f} / "
        f"{final['ride_height_m']['rear']:.4f} m | design "
        f"{settled.scene.car.tyre.unloaded_radius_m} m (the model's: wheel centres at the "
        "tyre's unloaded radius; the settled tyres and springs lower it) |",
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
        "## Jammed struts (μs = 0.4)", "",
        f"Settling from the design position, the rods move {1e6 * moved:.1f} µm after 0.8 s "
        "(the creep bound Δmax is 5 µm). Replay: `jammed/replay.html`; the Diagram with strut "
        "friction, as it ran: `jammed/diagram.svg`.", ""]
    if rows is not None:
        lines += _hard_point_section(settled.scene, rows)
    path.write_text("\n".join(lines))
