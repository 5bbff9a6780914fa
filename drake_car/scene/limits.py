"""What a scene's parts must satisfy together, asked of the law and the model once, where the
scene is loaded (``scene.load.check_scene``); the build, the systems and the law's constructors
trust a checked scene.

- The plant: discrete, SAP, sampled output ports, a step in (0, 10 ms], nothing that has no
  effect on this car (``check_plant``).
- The step against the stability limit of every part applied explicitly (``check_limits``): the
  anti-roll bars (``model.anti_roll_bar.time_step_limit_s``), the reference friction scheme (the
  law's ``explicit_time_step_limit_s`` on the car's strut: ``model.struts``), the tyres' spin
  coupling (``law.tyre.slip.explicit_time_step_limit_s``).
- The tyre file against the car: its FZMIN..FZMAX holds the car's wheel load at rest, and it
  has relaxation data when the scene takes them from the file (the file's own values, e.g.
  relaxation lengths > 0 over its load range, are checked once, when it is read:
  ``law.tyre.plausibility``). A ``combined_slip: true`` on a file without a combined-slip fit
  (RBX1/RBY1 zero or absent) runs (it still acts through the aligning moment) but is said:
  a note (information: what it means for the results and what to do,
  ``law.tyre.plausibility.combined_slip_said``), once per file in a process, and a line in
  every report.
- The driver against the manoeuvre (``check_driver``): a ``!PathFollower`` only on a manoeuvre
  defined by a path, such a manoeuvre only with it, its chassis channels logged (its outcome is
  judged from them), the driver's period no shorter than the step, the body no narrower than
  the car's wheels.

Every refusal is a ``ParameterError`` naming the key; ``check_scene`` adds where the scene came
from.
"""

import logging
import math

from pydrake.multibody.plant import MultibodyPlantConfig

from drake_car.law.checks import ParameterError
from drake_car.law.tyre.magic_formula import magic_formula, relaxation_lengths_m
from drake_car.law.tyre.plausibility import combined_slip_said
from drake_car.law.tyre.slip import explicit_time_step_limit_s as tyre_time_step_limit_s
from drake_car.model.anti_roll_bar import time_step_limit_s as bar_time_step_limit_s
from drake_car.model.drive import explicit_time_step_limit_s as drive_time_step_limit_s
from drake_car.model.loading import read_tyre
from drake_car.model.parameters import GRAVITY_MPS2
from drake_car.model.struts import reference_time_step_limit_s
from drake_car.scene.scene import (
    LinearTyre, MagicFormula, OpenDifferential, PathFollower, default_plant_config)

# Plant-config fields that have no effect on this car (it has no collision geometry): they
# must keep their defaults, so that every value of a scene changes its run.
INERT_PLANT_FIELDS = ("penetration_allowance", "stiction_tolerance", "contact_model",
                      "contact_surface_representation", "adjacent_bodies_collision_filters")
# The largest step: the tyres' explicit coupling needs less (``check_limits`` gives the limit).
MAX_TIME_STEP_S = 0.01
log = logging.getLogger(__name__)
_SAID = set()  # the combined-slip notes already given in this process


def check_plant(plant: MultibodyPlantConfig):
    default = default_plant_config()
    step = plant.time_step
    if not (isinstance(step, float) and math.isfinite(step) and 0 < step <= MAX_TIME_STEP_S):
        raise ParameterError("plant.time_step", step,
                             f"must lie in (0, {MAX_TIME_STEP_S:g}] s (the plant is discrete)")
    if plant.discrete_contact_approximation != "sap":
        raise ParameterError("plant.discrete_contact_approximation",
                             plant.discrete_contact_approximation,
                             "must be sap: the car's servos and friction are SAP PD actuators")
    if not plant.use_sampled_output_ports:
        raise ParameterError("plant.use_sampled_output_ports", False,
                             "must be true: the friction and tyres read the sampled outputs")
    for name in INERT_PLANT_FIELDS:
        if getattr(plant, name) != getattr(default, name):
            raise ParameterError(f"plant.{name}", getattr(plant, name),
                                 "has no effect on this car (it has no collision geometry); "
                                 "leave it out")
    if not plant.sap_near_rigid_threshold >= 0:
        raise ParameterError("plant.sap_near_rigid_threshold", plant.sap_near_rigid_threshold,
                             "must be >= 0")


def check_limits(scene):
    """The scene's step against every explicit part's stability limit, and its tyre file
    against its car; raises ParameterError naming the key."""
    check_driver(scene)
    step = scene.time_step_s
    bar = bar_time_step_limit_s(scene.car)
    if step > bar:
        raise ParameterError("plant.time_step", step, f"is above the anti-roll bars' explicit "
                             f"stability limit {bar:.2g} s")
    friction = scene.friction
    if friction is not None and friction.scheme == "reference":
        limit = reference_time_step_limit_s(scene.car, friction.law)
        if step > limit:
            raise ParameterError(
                "plant.time_step", step,
                f"is above the explicit (reference) friction scheme's stability limit "
                f"{limit:.2g} s on this car (2 m Δv / (1.5 μs N) with the strut's moving mass "
                "and its normal force at rest); use a smaller step or friction.scheme: fast")
    if isinstance(scene.tyres, (MagicFormula, LinearTyre)):
        _check_tyre_file(scene)
    _check_drive_loops(scene)


def _check_drive_loops(scene):
    """The open differential's rev limit (explicit feedback on the wheels' spin) against the
    step (``model.drive.explicit_time_step_limit_s``)."""
    drive, step = scene.drive, scene.time_step_s
    if not isinstance(drive, OpenDifferential) or not scene.manoeuvre.drives:
        return
    gain = drive.governor_gain_Nm_per_radps
    limit = drive_time_step_limit_s(scene.car, gain)
    if step > limit:
        raise ParameterError(
            "drive.governor_gain_Nm_per_radps", gain,
            f"makes the rev limit's loop stable only for steps below {limit:.2g} s (4 I / K, "
            f"the wheels' spin inertia I {scene.car.mass.wheel_spin_inertia_kgm2:g} kg m²); "
            f"plant.time_step is {step:g} s: a gain of at most "
            f"{4 * scene.car.mass.wheel_spin_inertia_kgm2 / step:.0f} N m s/rad, or a step "
            f"below {limit:.2g} s")


def wheel_load_at_rest_N(car):
    """The car's weight over four wheels (N): what a tyre file's load range must hold."""
    return car.mass.total_mass_kg * GRAVITY_MPS2 / 4.0


# A tyre file's unloaded radius this far (relative) from the car's is said once per pair
# [EST]: 2 %, a tyre size step (205/60R15 0.3135 m, 205/65R15 0.3238 m) is 3.3 %.
RADIUS_NOTE = 0.02


def radius_note(tir_file, car):
    """What a tyre file whose UNLOADED_RADIUS is more than ``RADIUS_NOTE`` from the car's
    ``tyre.unloaded_radius_m`` means for a run (None when they agree)."""
    tyre = read_tyre(tir_file)
    if abs(tyre.UNLOADED_RADIUS / car.tyre.unloaded_radius_m - 1) <= RADIUS_NOTE:
        return None
    return (f"tyres.tir_file {tir_file}: UNLOADED_RADIUS {tyre.UNLOADED_RADIUS:.3f} m, the car's "
            f"tyre.unloaded_radius_m {car.tyre.unloaded_radius_m:.3f} m: the wheels are placed, "
            "driven and rolled on the car's; the Magic Formula's rolling-resistance and aligning "
            "moments (and relaxation lengths taken from the file) take the file's")


def warn_radius(tir_file, car):
    """``radius_note`` on stderr (once per file and radius in a process); returns it."""
    note = radius_note(tir_file, car)
    if note is not None and note not in _SAID:
        _SAID.add(note)
        log.warning("%s", note)
    return note


def _check_tyre_file(scene):
    tyres, car = scene.tyres, scene.car
    tyre = read_tyre(tyres.tir_file)
    wheel_N = wheel_load_at_rest_N(car)
    if not tyre.FZMIN <= wheel_N <= tyre.FZMAX:
        raise ParameterError(
            "tyres.tir_file", tyres.tir_file,
            f"is valid for wheel loads {tyre.FZMIN:g}..{tyre.FZMAX:g} N (FNOMIN "
            f"{tyre.FNOMIN:g} N); this car rests on about {wheel_N:.0f} N per wheel "
            f"({4 * wheel_N:.0f} N over four) and runs at about 0..{2 * wheel_N:.0f} N in a "
            "lane change: a tyre for a "
            + ("heavier" if wheel_N < tyre.FZMIN else "lighter") + " vehicle")
    warn_radius(tyres.tir_file, car)
    note = combined_slip_said(tyre) if getattr(tyres, "combined_slip", False) else None
    if note and (tyres.tir_file, note) not in _SAID:  # information: the run is the file's
        _SAID.add((tyres.tir_file, note))
        log.info("tyres.tir_file %s: %s", tyres.tir_file, note)
    slip = tyres.slip
    if slip.relaxation and slip.relaxation_lengths_from_file:
        sigma = relaxation_lengths_m(tyre, wheel_N)
        if sigma is None:
            raise ParameterError(
                "tyres.slip.relaxation_lengths_from_file", True,
                f"needs relaxation data: {tyre.name} ({tyre.form}) has no relaxation data "
                "(PAC2002: PTX*/PTY*; MF 6.x: LONGITUDINAL_STIFFNESS and LATERAL_STIFFNESS)")
        slip_lengths = sigma  # > 0 at every load in FZMIN..FZMAX: checked when the file is read
    else:
        slip_lengths = (slip.relaxation_length_long_m, slip.relaxation_length_lat_m)
    stiffness = magic_formula(tyre, tyre.FNOMIN, 0.0, 0.0, 0.0, 0.0).slip_stiffness
    limit = tyre_time_step_limit_s(stiffness, slip, slip_lengths[0],
                                   car.tyre.unloaded_radius_m, car.mass.wheel_spin_inertia_kgm2)
    if scene.time_step_s > limit:
        raise ParameterError(
            "plant.time_step", scene.time_step_s,
            f"is above the tyres' explicit stability limit {limit:.2g} s (wheel spin inertia "
            f"{car.mass.wheel_spin_inertia_kgm2:g} kg m²); use a smaller step")


def check_driver(scene):
    """A path follower and a path manoeuvre come together (module docstring)."""
    follows = isinstance(scene.steering, PathFollower)
    manoeuvre = scene.manoeuvre
    has_path = getattr(manoeuvre, "follows_path", False)
    kind = type(manoeuvre).__name__
    if follows and not has_path:
        raise ParameterError("steering", "!PathFollower",
                             f"needs a manoeuvre defined by a path (!DoubleLaneChange, "
                             f"!ConstantRadius); !{kind} has none")
    if has_path and not follows:
        raise ParameterError("steering", f"!{type(scene.steering).__name__}",
                             f"cannot drive !{kind}, a manoeuvre defined by a path; use "
                             "steering: !PathFollower {}")
    if not has_path:
        return
    channels = scene.logging.channels
    if channels is not None and "chassis" not in channels:
        raise ParameterError("logging.channels", channels,
                             f"must hold chassis: !{kind}'s outcome is judged from it")
    if scene.steering.period_s < scene.time_step_s:
        raise ParameterError("steering.period_s", scene.steering.period_s,
                             f"must be >= plant.time_step = {scene.time_step_s:g} s")
    width = getattr(manoeuvre, "vehicle_width_m", None)
    car = scene.car
    wheels = max(car.front.track_m, car.rear.track_m) + car.tyre.width_m
    if width is not None and width < wheels:
        raise ParameterError("manoeuvre.vehicle_width_m", width,
                             f"must be >= the car's width over its tyres, {wheels:.3g} m "
                             "(track + tyre width)")
