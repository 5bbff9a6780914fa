"""The design study's manoeuvre on the user's car: the shipped study's base scene
gives the shipped Escort's launch (3 s) and lane-change rack (its calibration), which another
car does not follow to 60 km/h or moves by another shift than 3.7 m. Where the base car is not
the shipped one and the user left the shipped values in place, the launch is the one its drive
allows (``scene.launch``) and the rack is calibrated for that car (``sim.lane_change_
calibration``, cached by content), once, on the base scene: every run of the study that does not
vary the rack shares it, as every point shared the Escort's. A launch or a rack the user's scene
states is run as given.

The severity factor sets the rack amplitude itself (``manoeuvre.amplitude_m``), in metres. The
shipped spec states its range (3 ... 9 mm: half to one and a half times the lane change) for the
Escort's calibrated 5.91 mm (its ``rack_reference_m``); on another car every amplitude the spec
states in that reference is scaled by the car's own rack over it (``severity_scaled``), so that
the range is the same share of this car's lane change. A spec without ``rack_reference_m`` runs
its amplitudes as given."""

import dataclasses

from drake_car.scene.borrowed import drive_limit, drive_limit_words
from drake_car.scene.manoeuvres import Timeline
from drake_car.sim import lane_change_cache
from drake_car.sim.lane_change_calibration import adapted
from drake_car.sim.simulate import simulate
from drake_car.study.design.spec import check_values, is_paper_car

AMPLITUDE = "manoeuvre.amplitude_m"


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
    source = (f"its rack calibrated for this car's {new.shift_m:g} m lane change"
              if found is not None else "the rack amplitude its scene gives")
    study, words = severity_scaled(dataclasses.replace(study, base=base), source)
    return study, changes + words


def severity_scaled(study, source):
    """(``study`` with every amplitude its spec states in ``rack_reference_m`` (the severity
    factor's range, a line's values) scaled by the base scene's rack over that reference, what
    was scaled: a list of words, empty when nothing was). ``source``: where the base's rack
    comes from, in words. The paper's value of the factor stays the paper's car's."""
    ref, amplitude = study.rack_reference_m, study.base.manoeuvre.amplitude_m
    if ref is None or amplitude is None or amplitude == ref:
        return study, []
    ratio = amplitude / ref

    def why(low, high, reason):
        return (f"{1e3 * low * ratio:.2f} ... {1e3 * high * ratio:.2f} mm on this car: "
                f"{low / ref:.2f} ... {high / ref:.2f} times {source} ({1e3 * amplitude:.2f} mm)."
                f" The spec's {1e3 * low:g} ... {1e3 * high:g} mm are stated for the shipped "
                f"car's calibrated {1e3 * ref:.2f} mm (\"{' '.join(reason.split())}\"), here "
                f"scaled by {1e3 * amplitude:.2f} / {1e3 * ref:.2f} = {ratio:.3f} so that they "
                "are the same share of this car's lane change (its lateral accelerations on "
                "this car not measured)")
    factors = [dataclasses.replace(f, low=f.low * ratio, high=f.high * ratio,
                                   reason="severity: " + why(f.low, f.high, f.reason))
               if f.key == AMPLITUDE else f for f in study.factors]
    lines = [dataclasses.replace(line, values=[v * ratio for v in line.values],
                                 reason=why(min(line.values), max(line.values), line.reason))
             if line.key == AMPLITUDE and line.values else line for line in study.lines]
    if factors == study.factors and lines == study.lines:
        return study, []
    scaled = dataclasses.replace(study, factors=factors, lines=lines)
    check_values(scaled)
    words = [f"the severity range ({AMPLITUDE}) {why(f.low, f.high, f.reason)}"
             for f in study.factors if f.key == AMPLITUDE]
    words += [f"the line of {AMPLITUDE} scaled alike: "
              + ", ".join(f"{1e3 * v:.2f}" for v in line.values) + " mm"
              for line in lines if line.key == AMPLITUDE]
    return scaled, words


def _states(stated, key):
    return bool(stated) and key in stated
