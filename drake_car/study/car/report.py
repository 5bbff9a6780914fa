"""The car checked on its own (``drake-car-car-checks``): the settled car against the real car's
axle loads, the kinematics' ranges, the jammed struts' settling; as Markdown."""

import numpy as np

from drake_car.results.provenance import provenance


def write_report(path, settled, sweep, stuck, wall):
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
    lines = [
        "# drake_car: the car on its own", "",
        f"Made by `{prov['command']}`; {prov['created_utc']}, drake {prov['drake']}, commit "
        f"{(prov['git_commit'] or 'unknown')[:10]}; {wall:.1f} s wall.", "",
        "## The settled car (lubricated struts)", "",
        "| quantity | model | real car [ESC] |", "|---|---|---|",
        f"| front axle load | {front:.0f} N | {design['front']:.0f} N "
        f"({100 * (front / design['front'] - 1):+.2f} %) |",
        f"| rear axle load | {rear:.0f} N | {design['rear']:.0f} N "
        f"({100 * (rear / design['rear'] - 1):+.2f} %) |",
        f"| total mass | {final['total_mass_kg']:.1f} kg | "
        f"{settled.scene.car.mass.total_mass_kg} kg |",
        f"| ride height front / rear | {final['ride_height_m']['front']:.4f} / "
        f"{final['ride_height_m']['rear']:.4f} m | design "
        f"{settled.scene.car.tyre.unloaded_radius_m} m |",
        f"| strut overlap d left / right | {final['strut_overlap_m']['left']:.5f} / "
        f"{final['strut_overlap_m']['right']:.5f} m | design "
        f"{settled.scene.car.front.guide_length_l_m} m |",
        f"| loop-closure error (SAP) | {final['loop_closure_error_m']:.1e} m | |", "",
        "[ESC]: Ford Escort data, see `drake_car/model/parameters.py`. The scene as it ran: "
        "`settle/scene.yaml`.", "",
        "## Kinematics (chassis fixed, ±80 mm, left wheel)", "",
        f"camber {span('camber_deg')} deg, toe-in {span('toe_deg')} deg, caster "
        f"{span('caster_deg')} deg, kingpin {span('kingpin_deg')} deg, strut length "
        f"{span('strut_length_m')} m, overlap d {span('overlap_m')} m; largest loop-closure "
        f"error {max(k['closure_error_m']):.1e} m (Newton). Plots: `kinematics/*.png`.", "",
        "## Jammed struts (μs = 0.4)", "",
        f"Settling from the design position, the rods move {1e6 * moved:.1f} µm after 0.8 s "
        "(the creep bound Δmax is 5 µm). Replay: `jammed/replay.html`; the Diagram with strut "
        "friction, as it ran: `jammed/diagram.svg`.", ""]
    path.write_text("\n".join(lines))
