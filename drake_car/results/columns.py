"""What a results folder's columns mean: ``folder_readme(folder)`` describes every CSV file in
it (its columns' quantities, units, frames and signs) beside the conventions they follow, as
the folder's README.md. Units are in the column names (SI; angles of time histories in rad,
reported gradients and kinematic tables in deg); the meanings come from the patterns below."""

import csv
import re
from pathlib import Path

CONVENTIONS = """\
## Conventions

- **Units**: SI, the unit at the end of each column name (`_m`, `_N`, `_Nm`, `_mps`, `_mps2`,
  `_rad`, `_radps`, `_J`, `_s`; `_deg`, `_pct` where a number is reported for reading). Angles
  of time histories are in radians; handling gradients (deg/g) and kinematic tables are in
  degrees.
- **Vehicle and world axes (ISO 8855)**: x forward, y to the left, z up; the world's x is the
  car's heading at the start (along the road), its z up. Roll is positive
  with the right side down, pitch with the nose down, yaw and yaw rate counterclockwise seen
  from above (a left turn); lateral acceleration and the rack (`rack_m`) positive to the left;
  road-wheel steer angles positive to the left.
- **Tyre axes (ISO-W, per wheel)**: x along the wheel's heading on the road, y to its left, z
  up; `Fz` > 0 presses the tyre on the road; slip ratio κ = -V_sx/|V_cx| (> 0 driving);
  slip angle α with tan α = V_cy/|V_cx| (> 0 when the wheel moves to its left: the force `Fy`
  is then negative); inclination γ positive with the wheel's top leaning to the right.
- **Struts**: `d` is the overlap of rod and cylinder (d = l - s, s the rod's extension), `Δd`
  (`dd_`) its change from the static equilibrium at rest, + = the rod goes in (the body comes
  down); `rot_` the rod's rotation in its cylinder.
- **Wheels**: `fl`, `fr`, `rl`, `rr` = front left, front right, rear left, rear right.
"""

# (pattern over a column name, meaning); the first match wins.
MEANINGS = [
    (r"^t$", "time (s)"),
    (r"^phase$", "the manoeuvre's phase (I start and speed-up, II straight, III manoeuvre, IV "
                 "calming down)"),
    (r"^[xyz]_m$", "position of the body's origin in the world (m)"),
    (r"^(roll|pitch|yaw)_rad$", "the body's attitude (rad, fixed-axis x-y-z)"),
    (r"^yaw_rate_radps$", "yaw rate about the world's z (rad/s)"),
    (r"^speed_mps$", "horizontal speed of the body's origin (m/s)"),
    (r"^sideslip_rad$", "sideslip angle at the body's origin (rad; 0 below 0.5 m/s)"),
    (r"^a[xy]_mps2$", "acceleration of the body's origin in its heading frame (m/s²)"),
    (r"^az_seat_mps2$", "world-vertical acceleration of the body at the car's seat point "
                        "(car.seat_point_m in the run's scene.yaml; m/s², gravity not included)"),
    (r"^aw_seat_mps2$", "ISO 2631-1 Wk-weighted RMS vertical acceleration at the car's seat "
                        "point (report.md says where it lies and its source; m/s²)"),
    (r"^rack_m$", "rack position (m, left +)"),
    (r"^rack_force_N$", "force the steering servo applies to the rack (N)"),
    (r"^steering_wheel_torque_Nm$", "torque the driver holds at the steering wheel: the rack "
                                    "servo's force times car.front.rack_gain_m_per_rad (N m, "
                                    "towards a left turn +; no power assistance)"),
    (r"^steer_\w+_rad$", "road-wheel steer angle relative to the body (rad, left +)"),
    (r"^d_(left|right)_m$", "strut overlap d = l - s (m)"),
    (r"^dd_(left|right)_m$", "Δd: the strut overlap's change from static equilibrium (m, rod in +)"),
    (r"^rot_(left|right)_rad$", "the rod's rotation in its cylinder (rad)"),
    (r"^kinetic_J$", "the car's kinetic energy (J)"),
    (r"^potential_J$", "potential energy of gravity and the coil springs (J)"),
    (r"^F[xyz]_\w+_N$", "tyre force in the wheel's ISO-W axes (N)"),
    (r"^Mz_\w+_Nm$", "tyre aligning moment about the wheel's z (N m)"),
    (r"^kappa_\w+$", "longitudinal slip ratio κ (-)"),
    (r"^alpha_\w+_rad$", "slip angle α (rad)"),
    (r"^gamma_\w+_rad$", "inclination γ (rad)"),
    (r"^vx_\w+_mps$", "the wheel centre's forward speed (m/s)"),
    (r"^deflection_\w+_m$", "the tyre's radial deflection (m)"),
    (r"^friction_\w+_v$", "friction pair: relative velocity (m/s, or rad/s for a rotation pair)"),
    (r"^friction_\w+_creep$", "friction pair: creep Δ (m, or rad)"),
    (r"^friction_\w+_beta$", "friction pair: β of eq. (1) (-)"),
    (r"^friction_\w+_mu1$", "friction pair: μ1 of eq. (1) (-)"),
    (r"^friction_\w+_mu$", "friction pair: the signed friction coefficient μ (-)"),
    (r"^friction_\w+_phase$", "friction pair: 0 static, 1 kinetic"),
    (r"^friction_\w+_N$", "friction pair: normal force N of eq. (4) (N)"),
    (r"^friction_\w+_friction$", "friction pair: friction of the law (N, or N m)"),
    (r"^(creep|beta|mu1|N|Ffric|v)_(left|right)(_\w+)?$", "the friction's translation pair, "
                                                           "per strut (as friction_…)"),
    (r"^top_mount_[xyz]_\w+_m$", "the compliant top mount's deflection (m)"),
    (r"_m$", "a length (m)"), (r"_N$", "a force (N)"), (r"_Nm$", "a moment (N m)"),
    (r"_rad$", "an angle (rad)"), (r"_deg$", "an angle (deg)"), (r"_mps$", "a speed (m/s)"),
    (r"_mps2$", "an acceleration (m/s²)"), (r"_s$", "a time (s)"), (r"_J$", "an energy (J)"),
    (r"_pct$", "a percentage (%)"), (r"_radps$", "an angular rate (rad/s)"),
]


def meaning(column):
    for pattern, text in MEANINGS:
        if re.search(pattern, column):
            return text
    return "see the report"


def _header(path):
    try:
        with open(path, newline="") as f:
            return next(csv.reader(f), [])
    except (OSError, UnicodeDecodeError, csv.Error):
        return []


def folder_readme(folder, title=None):
    """README.md text for ``folder``: the conventions, then each CSV file's columns (files with
    the same columns described once)."""
    folder = Path(folder)
    groups = {}
    for path in sorted(folder.rglob("*.csv")):
        header = tuple(_header(path))
        if header:
            groups.setdefault(header, []).append(path.relative_to(folder).as_posix())
    lines = [f"# {title or folder.name}: what the files' columns mean", "",
             "Written by drake_car with the results; `report.md` (where there is one) says what "
             "they show.", "", CONVENTIONS]
    for header, files in groups.items():
        shown = ", ".join(f"`{f}`" for f in files[:6]) + (f" and {len(files) - 6} more"
                                                          if len(files) > 6 else "")
        lines += [f"## {shown}", "", "| column | meaning |", "|---|---|"]
        lines += [f"| `{c}` | {meaning(c)} |" for c in header]
        lines.append("")
    return "\n".join(lines)
