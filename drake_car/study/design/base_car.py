"""The design study's manoeuvre on the user's car (issue 31): the shipped study's base scene
gives the shipped Escort's launch (3 s) and lane-change rack (its calibration), which another
car does not follow to 60 km/h or moves by another shift than 3.7 m. Where the base car is not
the shipped one and the user left the shipped values in place, the launch is the one its drive
allows (``scene.launch``) and the rack is calibrated for that car (``sim.lane_change_
calibration``, cached by content), once, on the base scene: every run of the study shares it
(the severity factor scales it), as every point shared the Escort's. A launch or a rack the
user's scene states is run as given."""

import dataclasses

from drake_car.scene.borrowed import drive_limit, drive_limit_words
from drake_car.scene.manoeuvres import Timeline
from drake_car.sim import lane_change_cache
from drake_car.sim.lane_change_calibration import adapted
from drake_car.sim.simulate import simulate
from drake_car.study.design.spec import is_paper_car


def shipped_profile():
    """(amplitude_m, second_lobe) of the shipped Escort's calibration."""
    profile = lane_change_cache.shipped()["profile"]
    return float(profile["amplitude_m"]), float(profile["second_lobe"])


def adapted_base(study, *, stated=None):
    """(the study with its base manoeuvre adapted to its car, what was adapted: a list of
    words, empty when nothing was). ``stated``: the user's scene as YAML text and/or the
    manoeuvre keys it states, so that a value the user gave is kept."""
    if is_paper_car(study):
        return study, []
    m = study.base.manoeuvre
    changes = []
    timeline = m.timeline
    if timeline.speed_up_s == Timeline().launch_s and not _states(stated, "speed_up_s"):
        timeline = dataclasses.replace(timeline, speed_up_s=None)
    rack = (m.amplitude_m, m.second_lobe)
    if rack == shipped_profile() and not _states(stated, "amplitude_m"):
        m = dataclasses.replace(m, amplitude_m=None, second_lobe=None)
    m = dataclasses.replace(m, timeline=timeline)
    base, found = adapted(dataclasses.replace(study.base, manoeuvre=m), run=simulate)
    new = base.manoeuvre
    if new.timeline.speed_up_s != study.base.manoeuvre.timeline.speed_up_s:
        changes.append(f"the launch {new.timeline.speed_up_s:g} s, what the car allows with the "
                       f"drive's torque limit {drive_limit_words(drive_limit(base))} (the "
                       f"shipped study's {study.base.manoeuvre.timeline.speed_up_s:g} s)")
    if found is not None:
        changes.append(f"the rack calibrated for this car: {1e3 * new.amplitude_m:.2f} mm, "
                       f"second lobe {new.second_lobe:.3f} ({found.get('source', 'calibrated')})")
    return dataclasses.replace(study, base=base), changes


def _states(stated, key):
    return bool(stated) and key in stated
