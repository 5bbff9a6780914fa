"""The car that ran, as every report states it: its mass, centre of gravity and axle loads, its
front suspension (b, l, the rates, the strut's damping), its steering's rack gain, its drive and
its tyres (the file, its form, what combined slip does with that file), each from the scene that
ran and never from the shipped car's values; and whether it is the shipped car (the Ford Escort
of ``model.parameters`` on its shipped tyre: the car the paper's comparisons and the previous
version's verdicts are about)."""

import dataclasses

from drake_car.law.tyre.plausibility import COMBINED_SLIP_MEANING, combined_slip_note
from drake_car.model.geometry import design_axle_loads_N, whole_car_cog_to_front_m
from drake_car.model.loading import read_tyre, tir_path
from drake_car.model.parameters import CarParameters
from drake_car.scene.car_file import car_of_file
from drake_car.scene.borrowed import (
    drive_limit, drive_limit_words, relaxation, relaxation_words)
from drake_car.scene.scene import DEFAULT_TIR, LinearTyre, MagicFormula, PrescribedRotation


def _same_file(a, b):
    from pathlib import Path
    return Path(tir_path(a)).resolve() == Path(tir_path(b)).resolve()


def is_shipped_car(car, *, ignore_damping=True):
    """Whether ``car`` is the shipped car (``CarParameters()``), its front strut's damping
    aside when ``ignore_damping`` (the paper's friction sets set it)."""
    if ignore_damping:
        front = dataclasses.replace(car.front,
                                    strut_damping_Nspm=CarParameters().front.strut_damping_Nspm)
        car = dataclasses.replace(car, front=front)
    return car == CarParameters()


def on_shipped_tyre(scene):
    tir = getattr(scene.tyres, "tir_file", None)
    return tir is not None and _same_file(tir, DEFAULT_TIR)


def driven_axle(scene):
    """The axle the drive turns: the car's ``car.driven_axle`` (the paper's prescribed rotation
    too: a rear-drive car's rear wheels)."""
    return getattr(scene.car, "driven_axle", "front")


def drive_words(scene):
    """The drive in words, from the scene."""
    axle = driven_axle(scene)
    if isinstance(scene.drive, PrescribedRotation):
        return (f"the paper's drive: both {axle} wheels' rotation prescribed (a locked {axle} "
                "axle)")
    return (f"an open differential on the {axle} axle (one drive torque split equally between "
            "its wheels)")


def drive_short(scene):
    """The drive in a few words (a figure's title)."""
    axle = driven_axle(scene)
    if isinstance(scene.drive, PrescribedRotation):
        return f"prescribed {axle} wheels' rotation (locked {axle} axle)"
    return f"open differential, {axle}-driven"


def tyre_facts(scene):
    """{"model", "file", "form", "combined_slip", "combined_note", "relaxation"} of the
    scene's tyres ("relaxation": ``scene.borrowed.relaxation``, the lengths that ran and their
    source)."""
    tyres = scene.tyres
    if not isinstance(tyres, (MagicFormula, LinearTyre)):
        return {"model": type(tyres).__name__, "file": None, "form": None,
                "combined_slip": None, "combined_note": None, "relaxation": None}
    tyre = read_tyre(tyres.tir_file)
    combined = getattr(tyres, "combined_slip", None)
    return {"model": type(tyres).__name__, "file": tyres.tir_file, "form": tyre.form,
            "combined_slip": combined,
            "combined_note": combined_slip_note(tyre) if combined else None,
            "relaxation": relaxation(scene)}


def own_strut_damping(scenes):
    """(N s/m, its source in words) of the car's own front strut damping, for a study whose
    runs set it per friction set (the paper's): every run's where they agree (the user's scene
    gave it, as sets that differ in their friction do not), else the car file's, else the
    shipped Escort's (``CarParameters``). A study of one set says nothing of the car's own: its
    damping is the set's."""
    values = {s.car.front.strut_damping_Nspm for s in scenes}
    sets = {None if s.friction is None else (s.friction.law.mu_s, s.friction.law.mu_d)
            for s in scenes}
    if len(values) == 1 and len(sets) > 1:
        return values.pop(), "every run's scene"
    car_file = scenes[0].car_file
    if car_file:
        return car_of_file(car_file).front.strut_damping_Nspm, f"the car file `{car_file}`"
    return (CarParameters().front.strut_damping_Nspm,
            "the shipped Escort's, `drake_car/model/parameters.py`")


def car_facts(scene, *, strut_damping=None):
    """JSON-ready facts of the car that ran (``scene``). ``strut_damping``: (N s/m, its source
    in words) of the car's own strut damping where the runs' damping is a study's (the paper's
    friction sets: ``own_strut_damping``); None: the scene's."""
    car = scene.car
    loads = design_axle_loads_N(car)
    f, r = car.front, car.rear
    return {
        "shipped": is_shipped_car(car) and on_shipped_tyre(scene),
        "driven_axle": driven_axle(scene),
        "car_file": getattr(scene, "car_file", None) or None,
        "mass_kg": car.mass.total_mass_kg,
        "cog_behind_front_axle_m": whole_car_cog_to_front_m(car),
        "wheelbase_m": car.wheelbase_m,
        "corner_load_N": {"front": loads["front"] / 2, "rear": loads["rear"] / 2},
        "track_m": {"front": f.track_m, "rear": r.track_m},
        "ball_joint_offset_b_m": f.ball_joint_offset_b_m,
        "guide_length_l_m": f.guide_length_l_m,
        "wheel_rate_Npm": {"front": f.wheel_rate_Npm, "rear": r.wheel_rate_Npm},
        "strut_damping_Nspm": f.strut_damping_Nspm if strut_damping is None
        else strut_damping[0],
        "strut_damping_source": None if strut_damping is None else strut_damping[1],
        "rear_wheel_damping_Nspm": r.wheel_damping_Nspm,
        "anti_roll_bar_Nm_per_rad": {"front": f.anti_roll_bar_Nm_per_rad,
                                     "rear": r.anti_roll_bar_Nm_per_rad},
        "top_mount_stiffness_Npm": f.top_mount_stiffness_Npm,
        "rack_gain_m_per_rad": f.rack_gain_m_per_rad,
        "drive": drive_words(scene),
        "drive_limit": drive_limit(scene),
        "tyres": tyre_facts(scene),
    }


def car_lines(facts, *, damping=True):
    """The report's lines about the car (Markdown bullets); ``damping``: also the strut's
    damping (a study whose runs vary it says it per run instead)."""
    which = ("the shipped car (the Ford Escort of `drake_car/model/parameters.py`, every "
             "number with its source there), on its shipped tyre" if facts["shipped"] else
             "not the shipped car" + (f": the car file `{facts['car_file']}` under the scene's "
                                      "car values" if facts["car_file"] else
                                      ": the scene's car values (each run's saved "
                                      "`scene.yaml`)"))
    corner, rate = facts["corner_load_N"], facts["wheel_rate_Npm"]
    bar = facts["anti_roll_bar_Nm_per_rad"]
    mount = facts["top_mount_stiffness_Npm"]
    lines = [
        f"- **the car**: {which}; {facts['mass_kg']:g} kg, its centre of gravity "
        f"{facts['cog_behind_front_axle_m']:.3f} m behind the front axle of a "
        f"{facts['wheelbase_m']:.3f} m wheelbase; static corner loads "
        f"{corner['front']:.0f} N front, {corner['rear']:.0f} N rear; tracks "
        f"{facts['track_m']['front']:g} / {facts['track_m']['rear']:g} m.",
        f"- **front struts** (McPherson): ball-joint offset b = "
        f"{1e3 * facts['ball_joint_offset_b_m']:.1f} mm, guide length l = "
        f"{1e3 * facts['guide_length_l_m']:.0f} mm, wheel rate {rate['front'] / 1e3:.1f} kN/m"
        + (f", the car's own viscous damping in the strut {facts['strut_damping_Nspm']:g} N "
           f"s/m ({facts['strut_damping_source']}; the friction sets run with their own)"
           if facts.get("strut_damping_source") else
           f", viscous damping {facts['strut_damping_Nspm']:g} N s/m in the strut"
           if damping and facts["strut_damping_Nspm"] else
           ", no viscous damping in the strut" if damping else "")
        + f"; top mount {'rigid' if mount == 0 else f'elastic, {mount / 1e6:g} MN/m'}; "
        f"anti-roll bars {bar['front']:g} / {bar['rear']:g} N m/rad (front / rear); rear "
        f"wheel rate {rate['rear'] / 1e3:.1f} kN/m, damping "
        f"{facts['rear_wheel_damping_Nspm']:g} N s/m.",
        f"- **drive**: {facts['drive']}"
        + ("" if "drive_limit" not in facts else
           f", its torque limit {drive_limit_words(facts['drive_limit'])}")
        + f"; **steering**: rack gain c = "
        f"{1e3 * facts['rack_gain_m_per_rad']:g} mm of rack per steering-wheel radian "
        "(`car.front.rack_gain_m_per_rad`: the steering-wheel torque is the rack force times "
        "c).",
        "- **tyres**: " + tyre_words(facts["tyres"]) + "."]
    return lines


def tyre_words(t):
    if t["file"] is None:
        return f"{t['model']} (no horizontal forces)" if t["model"] == "VerticalOnly" \
            else t["model"]
    how = {"MagicFormula": "Magic Formula", "LinearTyre": "Magic Formula linearised at zero "
           "slip"}[t["model"]]
    slip = ("" if t["combined_slip"] is None else
            ", combined slip" if t["combined_slip"] else ", pure slip (combined_slip: false)")
    text = f"{how} of `{t['file']}` ({t['form']}{slip})"
    if t["combined_note"]:
        text += (f"; **combined_slip: true acts less than its name says**: "
                 f"{t['combined_note']}. For the results: {COMBINED_SLIP_MEANING}")
    if t.get("relaxation"):
        text += "; " + relaxation_words(t["relaxation"])
    return text
