"""The hard-point table: a car's inputs beside what the model derives from them, each row with
its unit, whether it was entered or derived, and how it is derived (used by
``drake-car-car-checks``' report and its ``hard_points.csv``).

A car given by a car file (``model.hard_points``) has its points as inputs and its angles
derived; a car given by today's parameters the other way round. Both get every row. Points are
the left front corner's, in the model's vehicle frame V (origin on the ground under the front
axle, the tyres touching it unloaded; x forward, y left, z up).

Derived, with the steering axis through the ball joint B and the top mount T, the strut axis
from T to the strut's lower mount S, the wheel centre W, the ground z = 0:

- kingpin inclination atan((y_B - y_T) / (z_T - z_B)), caster atan((x_B - x_T) / (z_T - z_B));
- the steering axis meets the ground at G = B - z_B (T - B) / (z_T - z_B): scrub radius
  y_W - y_G (positive: the axis meets the ground inboard of the tyre's centre), caster trail
  x_G - x_W (positive: ahead of it), the kingpin offset at the wheel centre y_W - y_axis(z_W);
- b = y_W - y_B (the paper's Fig. 4: the ball joint's lateral distance from the wheel plane);
- strut inclination atan((y_T - y_S) / (z_T - z_S)) and its lean back atan((x_S - x_T) /
  (z_T - z_S)); the spring's offsets and inclinations against the strut axis
  (``FrontSuspensionParameters``);
- the whole car's centre of gravity from the body's and the parts' (``geometry.centre_of_mass``)
  or the body's from the whole car's (``hard_points.sprung_mass_of``), the axle loads, the
  corners' sprung masses and ride frequencies (``model.corners``); with the springs
  (``model.car.spring_settings``) the motion ratio and the spring rate K_w / MR².

Given ``base``, the car the scene's car was made from (its car file's, or the shipped car's
parameters), every row whose value differs from the base's says so and why: a value the scene's
``car:`` set is "input (scene)", a point or entered value it moved is "moved (scene)" (no longer
as entered), a derived value keeps "derived"; each with the base's value in its "how".
"""

import dataclasses

import numpy as np

from drake_car.law.numerics.round_off import cleaned
from drake_car.model.corners import corner_sprung_mass_kg, ride_frequency_hz
from drake_car.model.geometry import centre_of_mass, design_axle_loads_N, front_corner_points
from drake_car.model.hard_points import frame_shift_m, whole_car_inertia_kgm2
from drake_car.model.parameters import CarParameters


@dataclasses.dataclass
class Row:
    group: str
    quantity: str
    value: tuple  # one number, or a point's (x, y, z)
    unit: str
    kind: str  # "input", "derived", or (with a base car) "input (scene)", "moved (scene)"
    how: str = ""
    field: str = ""  # the CarParameters value the row shows, when it shows one

    def text(self, digits=4):
        """The values as the report prints them (round-off of zero as 0: ``cleaned``)."""
        shown = [cleaned(v) for v in self.value]
        return ", ".join(f"{v:.{digits}g}" if abs(v) >= 1e-3 or v == 0 else f"{v:.3e}"
                         for v in shown)


POINTS = (("wheel centre", "wheel_centre"), ("lower arm front pivot", "arm_front_pivot"),
          ("lower arm rear pivot", "arm_rear_pivot"), ("ball joint", "ball_joint"),
          ("strut top mount", "top_mount"), ("strut lower mount", "strut_lower_mount"),
          ("spring upper seat", "spring_upper_seat"), ("spring lower seat", "spring_lower_seat"),
          ("tie rod inner end", "tie_rod_inner"), ("tie rod outer end", "tie_rod_outer"),
          ("rod guide", "guide"), ("piston", "piston"))


def differences(base, car, key=""):
    """[(dotted name, base value, car value)] of every value in which ``car`` differs from
    ``base`` (two ``CarParameters``, or parts of them)."""
    out = []
    for field in dataclasses.fields(car):
        name = f"{key}.{field.name}" if key else field.name
        mine, theirs = getattr(car, field.name), getattr(base, field.name)
        if dataclasses.is_dataclass(mine):
            out += differences(theirs, mine, name)
        elif mine != theirs:
            out.append((name, theirs, mine))
    return out


def value_text(value):
    """A parameter's value as a report gives it (6 significant digits)."""
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(value_text(v) for v in value) + "]"
    return repr(value)


def hard_point_table(car: CarParameters, given=None, springs=None, base=None):
    """Rows (``Row``) of ``car`` (what runs); ``given``: the ``HardPointCar`` it was made from
    (its points then are the inputs), or None; ``springs``: ``model.car.spring_settings`` of the
    car, for its motion ratios and spring rates; ``base``: the ``CarParameters`` the scene's
    car values were laid over (the car file's car, or the shipped car's), whose differing rows
    are marked (the module's docstring)."""
    rows = _rows(car, given, springs)
    if base is None:
        return rows
    return _marked(rows, {(r.group, r.quantity): r for r in _rows(base, given, None)},
                   differences(base, car), "the car file's" if given is not None else
                   "the shipped car's")


def _marked(rows, base_rows, changed, whose):
    """``rows`` with those differing from ``base_rows`` marked (``changed``: ``differences``)."""
    set_by_scene = {name for name, _, _ in changed}
    geometry = ", ".join(f"{name} = {value_text(mine)} ({whose} {value_text(theirs)})"
                         for name, theirs, mine in changed
                         if name.startswith(("front.", "tyre.")))
    out = []
    for r in rows:
        b = base_rows.get((r.group, r.quantity))
        if b is None or np.allclose(r.value, b.value, rtol=1e-12, atol=1e-15):
            out.append(r)
            continue
        was = f"{whose}: {b.text()}"
        if set_by_scene.intersection(r.field.split()):
            r = dataclasses.replace(r, kind="input (scene)",
                                    how=f"set by the scene's car: {' and '.join(r.field.split())}"
                                        f" ({was})")
        elif r.kind == "input" and r.group == "point":
            r = dataclasses.replace(r, kind="moved (scene)",
                                    how=f"not as entered: {was}, moved by the scene's car: "
                                        f"{geometry or 'values'}")
        elif r.kind == "input":
            r = dataclasses.replace(r, kind="moved (scene)",
                                    how=f"{r.how}; not as entered ({was}): the scene's car: "
                                        "values")
        else:
            r = dataclasses.replace(r, how=f"{r.how}; {was}" if r.how else was)
        out.append(r)
    return out


def _rows(car, given, springs):
    by_points = given is not None
    point_kind, angle_kind = ("input", "derived") if by_points else ("derived", "input")
    f, m = car.front, car.mass
    p = front_corner_points(car, 1.0)
    rows = []

    def add(group, quantity, value, unit, kind, how="", field=""):
        values = tuple(float(v) for v in np.atleast_1d(value))
        rows.append(Row(group, quantity, values, unit, kind, how, field))

    shift = frame_shift_m(given) if by_points else np.zeros(3)
    if by_points:
        add("frame", "car file's frame moved by (x, z) into V", shift[[0, 2]] + 0.0, "m",
            "derived", "(-x_W, R0 - z_W): the wheel centre to x = 0 and the tyre's unloaded "
            "radius R0")
    entered = ("as entered, in the car file's frame (in V: plus the frame row's shift)"
               if by_points else "in V")
    for label, name in POINTS:
        inner = name in ("guide", "piston")
        add("point", label, getattr(p, name) - (0.0 if inner else shift),
            "m", "derived" if inner else point_kind,
            "in V, along the strut: guide_below_top_mount_m, + l" if inner else entered)
    top, ball, wheel = p.top_mount, p.ball_joint, p.wheel_centre
    rise = top[2] - ball[2]
    ground = ball - ball[2] / rise * (top - ball)
    at_wheel = ball + (wheel[2] - ball[2]) / rise * (top - ball)
    add("steering axis", "ball-joint offset b", f.ball_joint_offset_b_m, "m", angle_kind,
        "y_W - y_B", "front.ball_joint_offset_b_m")
    add("steering axis", "kingpin inclination", f.kingpin_inclination_deg, "deg", angle_kind,
        "atan((y_B - y_T) / (z_T - z_B))", "front.kingpin_inclination_deg")
    add("steering axis", "caster", f.caster_deg, "deg", angle_kind,
        "atan((x_B - x_T) / (z_T - z_B))", "front.caster_deg")
    add("steering axis", "scrub radius", wheel[1] - ground[1], "m", "derived",
        "y_W - y_G, G the axis at the ground")
    add("steering axis", "caster trail", ground[0] - wheel[0], "m", "derived", "x_G - x_W")
    add("steering axis", "kingpin offset at the wheel centre", wheel[1] - at_wheel[1], "m",
        "derived", "y_W - y of the axis at z_W")
    add("strut", "strut inclination", f.strut_inclination_deg, "deg", angle_kind,
        "atan((y_T - y_S) / (z_T - z_S))", "front.strut_inclination_deg")
    add("strut", "strut lean back", f.strut_lean_back_deg(), "deg", angle_kind,
        "atan((x_S - x_T) / (z_T - z_S))", "front.strut_caster_deg")
    add("strut", "strut length (top to lower mount)", f.strut_lower_mount_below_top_m, "m",
        angle_kind, "length of S - T", "front.strut_lower_mount_below_top_m")
    add("strut", "guide length l", f.guide_length_l_m, "m", "input", "the damper's drawing",
        "front.guide_length_l_m")
    add("strut", "rod radius r", f.rod_radius_r_m, "m", "input", "the damper's drawing",
        "front.rod_radius_r_m")
    add("strut", "rod guide below the top mount", f.guide_below_top_mount_m, "m", "input",
        "", "front.guide_below_top_mount_m")
    seat_how = "about the strut axis (lateral: outboard +, top inboard +; fore-aft: " \
               "forward +, top rearward +)"
    add("spring", "spring offset, lateral / fore-aft", (f.spring_offset_m,
        f.spring_offset_fore_aft_m), "m", angle_kind, seat_how,
        "front.spring_offset_m front.spring_offset_fore_aft_m")
    add("spring", "spring inclination, lateral / fore-aft", (f.spring_inclination_deg,
        f.spring_inclination_fore_aft_deg), "deg", angle_kind, seat_how,
        "front.spring_inclination_deg front.spring_inclination_fore_aft_deg")
    add("spring", "spring length at design", np.linalg.norm(p.spring_upper_seat
                                                             - p.spring_lower_seat),
        "m", "derived", "length of upper seat - lower seat")
    axis = p.arm_rear_pivot - p.arm_front_pivot
    reach = ball - p.arm_front_pivot
    unit_axis = axis / np.linalg.norm(axis)
    add("arms", "lower arm's reach (ball joint to pivot axis)",
        np.linalg.norm(reach - (reach @ unit_axis) * unit_axis), "m", "derived")
    add("arms", "tie rod length", np.linalg.norm(p.tie_rod_outer - p.tie_rod_inner), "m",
        "derived")
    add("car", "front track", f.track_m, "m", angle_kind, "2 y_W", "front.track_m")
    add("car", "rear track", car.rear.track_m, "m", "input", "", "rear.track_m")
    add("car", "wheelbase", car.wheelbase_m, "m", "input" if by_points else "derived",
        "" if by_points else "cog_to_front_axle_m + cog_to_rear_axle_m")
    add("car", "driven axle (0 front, 1 rear)", 0.0 if car.driven_axle == "front" else 1.0,
        "", "input", "", "driven_axle")
    whole = centre_of_mass(car)
    add("mass", "total mass", m.total_mass_kg, "kg", "input", "", "mass.total_mass_kg")
    add("mass", "whole car's CoG behind the front axle, height", (-whole[0],
        whole[2] - shift[2]), "m", point_kind, (entered if by_points else "in V") +
        "; the body's and the parts'")
    add("mass", "sprung mass", m.total_mass_kg - car.parts_mass_kg(), "kg", "derived",
        "total less the parts")
    add("mass", "sprung mass's CoG behind the front axle, height", (m.cog_to_front_axle_m,
        m.sprung_cog_height_m - shift[2]), "m", angle_kind, "(M G - Σ m_i c_i) / m_s, "
        + ("in the car file's frame as the row above" if by_points else "in V"))
    add("mass", "whole car's inertia (roll, pitch, yaw)", whole_car_inertia_kgm2(car), "kg m²",
        point_kind, "about its CoG; the body's and the parts' (parallel axes)")
    add("mass", "sprung mass's inertia (roll, pitch, yaw)", m.sprung_inertia_kgm2, "kg m²",
        angle_kind, "the whole car's less the parts' (parallel axes), diagonal")
    loads = design_axle_loads_N(car)
    add("mass", "axle loads at rest, front / rear", (loads["front"], loads["rear"]), "N",
        "derived", "weight shared by the whole car's CoG")
    for axle in ("front", "rear"):
        group = getattr(car, axle)
        add("rates", f"{axle} wheel rate", group.wheel_rate_Npm, "N/m", "input", "",
            f"{axle}.wheel_rate_Npm")
        if springs is not None:
            setting = springs[(axle, "left")]
            add("rates", f"{axle} motion ratio dL_spring/dz_wheel", setting.motion_ratio,
                "", "derived", "the kinematics (chassis fixed)")
            add("rates", f"{axle} spring rate", setting.stiffness_Npm, "N/m", "derived",
                "wheel rate / MR²")
        add("rates", f"{axle} corner sprung mass", corner_sprung_mass_kg(car, axle), "kg",
            "derived", "axle load / 2g less the unsprung mass")
        add("rates", f"{axle} ride frequency", ride_frequency_hz(car, axle), "Hz", "derived",
            "sqrt(K_w K_t / (K_w + K_t) / m) / 2π")
        add("rates", f"{axle} anti-roll bar", group.anti_roll_bar_Nm_per_rad, "N m/rad",
            "input", "", f"{axle}.anti_roll_bar_Nm_per_rad")
    add("rates", "front strut damping", f.strut_damping_Nspm, "N s/m", "input",
        "along the strut", "front.strut_damping_Nspm")
    add("rates", "rear damping at the wheel", car.rear.wheel_damping_Nspm, "N s/m", "input",
        "", "rear.wheel_damping_Nspm")
    add("rates", "tyre radial stiffness", car.tyre.radial_stiffness_Npm, "N/m", "input",
        "", "tyre.radial_stiffness_Npm")
    return rows


def table_columns(rows):
    """The table as CSV columns."""
    return {"group": [r.group for r in rows], "quantity": [r.quantity for r in rows],
            "value": [" ".join(repr(v) for v in r.value) for r in rows],
            "unit": [r.unit for r in rows], "kind": [r.kind for r in rows],
            "how": [r.how for r in rows]}


def table_markdown(rows):
    """The table as Markdown lines."""
    lines = ["| group | quantity | value | unit | entered or derived | how |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r.group} | {r.quantity} | {r.text()} | {r.unit} | {r.kind} | "
                     f"{r.how} |")
    return lines
