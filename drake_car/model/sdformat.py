"""Generates the car's SDFormat model (with Drake's extensions) from ``CarParameters``.

The committed file ``urdf/car.sdf`` is this generator's output for the default parameters
(``python -m drake_car.model.sdformat`` rewrites it; a test checks they agree). A scene that
changes a parameter gets its own file generated the same way.

Topology (per front side): chassis -(revolute)- lower arm; chassis -(universal, top mount)-
piston rod -(revolute, strut axis)- strut slider -(prismatic, strut axis)- knuckle (carries the
strut cylinder); the knuckle closes the loop to the lower arm at the ball joint. The rack is a
prismatic joint; each tie rod hangs on a universal joint at the rack end and closes the second
loop at the steering arm. The rear is two trailing arms. The file declares the hard points as
named frames (``ball_joint_arm_left`` on the arm, ``ball_joint_knuckle_left`` on the knuckle,
...); the loop closures (ball constraints) and the springs are added in code
(``drake_car.model.car``) between those frames, so the frames are the one statement of where
the loops close.

Why the loop closes at the ball joint and not at the top mount: SAP caps the impedance of a
PD-controlled joint at about 4π²·I/dt², I the joint's own tree inertia (its child subtree).
With the rod as the leaf of the cylindrical pair, the rotation pair's I is the rod's spin
inertia (6e-5 kg m²): the cap (≈2e3 N m s/rad at 1 ms) is far below the friction law's
slope μs·N·r/Δv (≈1e5 N m s/rad), and the strut friction's rotation pair chattered at
±1e-3 rad/s on the settled car. With the knuckle and wheel as the child, I ≈ 0.5 kg m² about
the strut axis and the cap is ≈2e7. The mechanism is the same: the rod does not spin against the
body (universal top mount), the cylinder turns with the knuckle when steering.
"""

import argparse
import math
from pathlib import Path

import numpy as np

from drake_car.data import resource
from drake_car.model.geometry import (
    PART_INERTIA_KGM2, SIDES, chassis_mass_and_com, front_corner_points, rear_corner_points,
    rod_inertia_kgm2, rpy_z_to, tie_rod_inertia_kgm2, wheel_inertia_kgm2)
from drake_car.model.parameters import CarParameters

# The committed model file, in the project's urdf/ folder (the package's data).
DEFAULT_MODEL_PATH = Path(str(resource("urdf").joinpath("car.sdf")))


def _v(p):
    return " ".join(f"{float(x):.15g}" for x in p)


def _inertial(origin, mass, com, ixx, iyy, izz, rpy=(0.0, 0.0, 0.0)):
    """Inertial element of a link whose frame is at ``origin`` (in V) and aligned with V."""
    return f"""
    <inertial>
      <pose>{_v(np.asarray(com) - np.asarray(origin))} {_v(rpy)}</pose>
      <mass>{mass:.6g}</mass>
      <inertia><ixx>{ixx:.6g}</ixx><iyy>{iyy:.6g}</iyy><izz>{izz:.6g}</izz>
        <ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>
    </inertial>"""


def _visual(name, pose, geometry, rgba):
    return f"""
    <visual name="{name}">
      <pose relative_to="__model__">{_v(pose)}</pose>
      <geometry>{geometry}</geometry>
      <material><diffuse>{_v(rgba)}</diffuse></material>
    </visual>"""


def _cylinder_between(name, a, b, radius, rgba):
    a, b = np.asarray(a), np.asarray(b)
    length = float(np.linalg.norm(b - a))
    pose = list((a + b) / 2) + list(rpy_z_to(b - a))
    return _visual(name, pose, f"<cylinder><radius>{radius}</radius>"
                   f"<length>{length:.6g}</length></cylinder>", rgba)


def _link(name, origin, body):
    return f"""
  <link name="{name}">
    <pose relative_to="__model__">{_v(origin)} 0 0 0</pose>{body}
  </link>"""


def _joint(name, kind, parent, child, origin, axis=None, damping=0.0, axis2=None):
    text = f"""
  <joint name="{name}" type="{kind}">
    <parent>{parent}</parent><child>{child}</child>
    <pose relative_to="__model__">{_v(origin)} 0 0 0</pose>"""
    # Effort 0: no actuator from the file; actuators are added in code where they are wanted.
    if axis is not None:
        text += f"""
    <axis><xyz expressed_in="__model__">{_v(axis)}</xyz>
      <dynamics><damping>{damping:.6g}</damping></dynamics>
      <limit><effort>0</effort></limit></axis>"""
    if axis2 is not None:
        text += f"""
    <axis2><xyz expressed_in="__model__">{_v(axis2)}</xyz>
      <limit><effort>0</effort></limit></axis2>"""
    return text + "\n  </joint>"


def _frame(name, link, point):
    return f"""
  <frame name="{name}" attached_to="{link}">
    <pose relative_to="__model__">{_v(point)} 0 0 0</pose>
  </frame>"""


def generate_sdformat(params: CarParameters) -> str:
    """Returns the SDFormat text of the car for ``params`` (checked where they entered: a
    scene's load)."""
    m = params.mass
    radius = params.tyre.unloaded_radius_m
    chassis_mass, chassis_com = chassis_mass_and_com(params)
    ixx, iyy, izz = m.sprung_inertia_kgm2
    body = _inertial([0, 0, 0], chassis_mass, chassis_com, ixx, iyy, izz)
    body += _visual("body", [-1.2, 0, 0.78, 0, 0, 0],
                    "<box><size>3.9 1.62 0.55</size></box>", [0.2, 0.4, 0.8, 0.25])
    parts = [_link("chassis", [0, 0, 0], body)]
    frames = []
    wheel_geometry = (f"<cylinder><radius>{radius}</radius>"
                      f"<length>{params.tyre.width_m}</length></cylinder>")
    wheel_inertia = wheel_inertia_kgm2(params)

    # Rack.
    f = params.front
    rack_origin = np.array([f.rack_x_m, 0.0, f.rack_height_m])
    parts.append(_link("steering_rack", rack_origin,
                       _inertial(rack_origin, m.rack_kg, rack_origin, *PART_INERTIA_KGM2["steering_rack"])
                       + _cylinder_between("rack", rack_origin - [0, f.rack_half_length_m, 0],
                                           rack_origin + [0, f.rack_half_length_m, 0], 0.015,
                                           [0.5, 0.5, 0.5, 1])))
    parts.append(_joint("rack_slide", "prismatic", "chassis", "steering_rack", rack_origin,
                        axis=[0, 1, 0]))

    for side_name, s in SIDES.items():
        p = front_corner_points(params, s)
        wheel = f"wheel_front_{side_name}"
        arm, knuckle = f"lower_arm_{side_name}", f"knuckle_{side_name}"
        slider, rod = f"strut_slider_{side_name}", f"piston_rod_{side_name}"
        tie = f"tie_rod_{side_name}"
        arm_com = (p.arm_front_pivot + p.arm_rear_pivot + p.ball_joint) / 3
        parts.append(_link(arm, p.arm_front_pivot,
                           _inertial(p.arm_front_pivot, m.front_lower_arm_kg, arm_com,
                                     *PART_INERTIA_KGM2["lower_arm"])
                           + _cylinder_between("front_leg", p.arm_front_pivot, p.ball_joint, 0.015,
                                               [0.3, 0.3, 0.3, 1])
                           + _cylinder_between("rear_leg", p.arm_rear_pivot, p.ball_joint, 0.015,
                                               [0.3, 0.3, 0.3, 1])))
        knuckle_com = 0.6 * p.wheel_centre + 0.4 * p.strut_lower_mount
        parts.append(_link(knuckle, p.ball_joint,
                           _inertial(p.ball_joint, m.front_knuckle_kg, knuckle_com,
                                     *PART_INERTIA_KGM2["knuckle"])
                           + _cylinder_between("cylinder", p.guide, p.strut_lower_mount, 0.025,
                                               [0.8, 0.3, 0.1, 1])
                           + _cylinder_between("upright", p.ball_joint, p.strut_lower_mount,
                                               0.02, [0.8, 0.3, 0.1, 1])))
        parts.append(_link(slider, p.guide,
                           _inertial(p.guide, m.strut_slider_kg, p.guide, *PART_INERTIA_KGM2["strut_slider"])))
        rod_com = (p.top_mount + p.piston) / 2
        rod_transverse, _, rod_axial = rod_inertia_kgm2(params)
        parts.append(_link(rod, p.top_mount,
                           _inertial(p.top_mount, m.piston_rod_kg, rod_com, rod_transverse, rod_transverse,
                                     rod_axial, rpy=rpy_z_to(p.strut_axis_up))
                           + _cylinder_between("rod", p.top_mount, p.piston, f.rod_radius_r_m,
                                               [0.85, 0.85, 0.85, 1])))
        parts.append(_link(wheel, p.wheel_centre,
                           _inertial(p.wheel_centre, m.front_wheel_kg, p.wheel_centre, *wheel_inertia)
                           + _visual("tyre", list(p.wheel_centre) + [math.pi / 2, 0, 0],
                                     wheel_geometry, [0.1, 0.1, 0.1, 1])))
        tie_inner, tie_outer = p.tie_rod_inner, p.tie_rod_outer
        tie_length = float(np.linalg.norm(tie_outer - tie_inner))
        parts.append(_link(tie, tie_inner,
                           _inertial(tie_inner, m.tie_rod_kg, (tie_inner + tie_outer) / 2,
                                     *tie_rod_inertia_kgm2(params, p))
                           + _cylinder_between("tie_rod", tie_inner, tie_outer, 0.008,
                                               [0.5, 0.5, 0.5, 1])))
        arm_axis = p.arm_rear_pivot - p.arm_front_pivot
        parts.append(_joint(f"lower_arm_pivot_{side_name}", "revolute", "chassis", arm,
                            p.arm_front_pivot, axis=arm_axis / np.linalg.norm(arm_axis)))
        # The strut hangs from the top mount: a universal joint (the mount tilts, the rod does
        # not spin against the body), then the cylindrical pair with the cylinder (knuckle) as
        # the child, so the pair's tree inertia is the knuckle's and the wheel's (see module doc).
        mount_parent = "chassis"
        if f.top_mount_stiffness_Npm > 0:
            # Compliant mount: chassis -x- link -y- link -z- mount body, three prismatic joints
            # (their spring-dampers are SAP PD actuators, drake_car/model/car.py).
            parent = "chassis"
            for axis_name, axis, mass in (("x", [1, 0, 0], f.top_mount_link_kg),
                                          ("y", [0, 1, 0], f.top_mount_link_kg),
                                          ("z", [0, 0, 1], f.top_mount_body_kg)):
                child = (f"top_mount_body_{side_name}" if axis_name == "z"
                         else f"top_mount_link_{axis_name}_{side_name}")
                parts.append(_link(child, p.top_mount, _inertial(
                    p.top_mount, mass, p.top_mount, *PART_INERTIA_KGM2["top_mount"])))
                parts.append(_joint(f"top_mount_{axis_name}_{side_name}", "prismatic", parent,
                                    child, p.top_mount, axis=axis))
                parent = child
            mount_parent = parent
        parts.append(_joint(f"top_mount_joint_{side_name}", "universal", mount_parent, rod,
                            p.top_mount, axis=p.top_mount_axes[0], axis2=p.top_mount_axes[1]))
        parts.append(_joint(f"strut_revolute_{side_name}", "revolute", rod, slider, p.guide,
                            axis=p.strut_axis_up))
        parts.append(_joint(f"strut_prismatic_{side_name}", "prismatic", slider, knuckle,
                            p.guide, axis=-p.strut_axis_up, damping=f.strut_damping_Nspm))
        parts.append(_joint(f"{wheel}_spin", "revolute", knuckle, wheel, p.wheel_centre,
                            axis=[0, 1, 0]))
        tie_direction = (tie_outer - tie_inner) / tie_length
        second = np.cross(tie_direction, [1.0, 0.0, 0.0])
        parts.append(_joint(f"tie_rod_inner_{side_name}", "universal", "steering_rack", tie,
                            tie_inner, axis=[1, 0, 0], axis2=second / np.linalg.norm(second)))
        frames += [
            _frame(f"top_mount_{side_name}", "chassis", p.top_mount),
            _frame(f"ball_joint_arm_{side_name}", arm, p.ball_joint),
            _frame(f"ball_joint_knuckle_{side_name}", knuckle, p.ball_joint),
            _frame(f"spring_upper_seat_{side_name}", "chassis", p.spring_upper_seat),
            _frame(f"spring_lower_seat_{side_name}", knuckle, p.spring_lower_seat),
            _frame(f"strut_lower_mount_{side_name}", knuckle, p.strut_lower_mount),
            _frame(f"piston_{side_name}", rod, p.piston),
            _frame(f"guide_{side_name}", knuckle, p.guide),
            _frame(f"tie_rod_outer_{side_name}", knuckle, tie_outer),
            _frame(f"tie_rod_end_{side_name}", tie, tie_outer),
        ]

        r = rear_corner_points(params, s)
        rear_arm, rear_wheel = f"trailing_arm_{side_name}", f"wheel_rear_{side_name}"
        lever = float(np.hypot(r.wheel_centre[0] - r.pivot[0], r.wheel_centre[2] - r.pivot[2]))
        parts.append(_link(rear_arm, r.pivot,
                           _inertial(r.pivot, m.rear_carrier_kg, 0.3 * r.pivot + 0.7 * r.wheel_centre,
                                     *PART_INERTIA_KGM2["trailing_arm"])
                           + _cylinder_between("arm", r.pivot, r.wheel_centre, 0.03,
                                               [0.3, 0.3, 0.3, 1])))
        parts.append(_link(rear_wheel, r.wheel_centre,
                           _inertial(r.wheel_centre, m.rear_wheel_kg, r.wheel_centre, *wheel_inertia)
                           + _visual("tyre", list(r.wheel_centre) + [math.pi / 2, 0, 0],
                                     wheel_geometry, [0.1, 0.1, 0.1, 1])))
        parts.append(_joint(f"trailing_arm_pivot_{side_name}", "revolute", "chassis", rear_arm, r.pivot, axis=[0, 1, 0],
                            damping=params.rear.wheel_damping_Nspm * lever ** 2))
        parts.append(_joint(f"{rear_wheel}_spin", "revolute", rear_arm, rear_wheel, r.wheel_centre,
                            axis=[0, 1, 0]))
        frames += [
            _frame(f"rear_spring_upper_seat_{side_name}", "chassis", r.spring_upper_seat),
            _frame(f"rear_spring_lower_seat_{side_name}", rear_arm, r.spring_lower_seat),
        ]

    about = ("     Car: Ford Escort (NA, 1981-90) mass data; McPherson hard points estimated\n"
             "     (see drake_car/model/parameters.py for every number's source). -->\n"
             if params == CarParameters() else
             "     Car: the scene's (its car file or car: values say where each number is\n"
             "     from). -->\n")
    header = (
        "<?xml version=\"1.0\"?>\n"
        "<!-- Generated by drake_car.model.sdformat from CarParameters; do not edit by hand.\n"
        + about +
        "<sdf version=\"1.9\" xmlns:drake=\"http://drake.mit.edu\">\n"
        "<model name=\"car\">")
    return header + "".join(parts + frames) + "\n</model>\n</sdf>\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=DEFAULT_MODEL_PATH,
                        help="where to write the SDFormat file (default: %(default)s)")
    args = parser.parse_args()
    args.out.write_text(generate_sdformat(CarParameters()))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
