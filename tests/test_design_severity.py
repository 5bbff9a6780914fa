"""The design study's severity on the user's car: the shipped spec states the rack amplitude's
range (3 ... 9 mm: half to one and a half times the lane change) for the shipped Escort's
calibrated rack (its ``rack_reference_m``, 5.91 mm); on another car, whose rack is calibrated
for it or stated by its scene, every run that varies the severity runs the car's own rack times
the spec's fractions (a newcomer's 1500 kg sedan, calibrated to 9.08 mm, ran 0.33 ... 0.99 of
its lane change and its own value "outside the range"). The shipped car's study is unchanged,
and a spec of the user's own without ``rack_reference_m`` runs its amplitudes as given."""

import dataclasses
import math

import pytest

from drake_car.data import resource
from drake_car.scene.load import SceneError
from drake_car.study.design import answers, base_car
from drake_car.study.design import runs as design_runs
from drake_car.study.design.report import factor_rows
from drake_car.study.design.spec import Line, factor, load_study

DESIGN = resource("scenes/studies/design.yaml")
AMPLITUDE = "manoeuvre.amplitude_m"
# A made-up car (not the shipped one: another mass, its own ball-joint offset) with its own
# launch, so that no simulation is needed where its rack is stated.
MINE = """
car:
  name: made_up
  car: {mass: {total_mass_kg: 1400.0}, front: {ball_joint_offset_b_m: 0.07}}
  manoeuvre: !LaneChange {timeline: {speed_up_s: 5.0}}
"""


@pytest.fixture(scope="module")
def mine(tmp_path_factory):
    path = tmp_path_factory.mktemp("car") / "mine.yaml"
    path.write_text(MINE)
    return path


def _spec_fractions():
    """The shipped spec's severity range as fractions of its reference rack."""
    spec = load_study(DESIGN, "study")
    f = factor(spec, AMPLITUDE)
    return f.low / spec.rack_reference_m, f.high / spec.rack_reference_m


def _amplitudes(parts):
    return [scene.manoeuvre.amplitude_m for scene, _ in parts.values()]


def _check_scaled(study, rack_m):
    """Every severity value the study builds is ``rack_m`` times the spec's fractions."""
    low, high = _spec_fractions()
    f = factor(study, AMPLITUDE)
    assert math.isclose(f.low, rack_m * low, rel_tol=1e-12)
    assert math.isclose(f.high, rack_m * high, rel_tol=1e-12)
    spec = [m for m in study.maps if AMPLITUDE in (m.x, m.y)][0]
    i = study.maps.index(spec)
    varied = {name: entry for name, entry in design_runs.map_scenes(study).items()
              if name.startswith(f"map{i}_")}
    n = spec.points - 1
    want = sorted({round(low + k * (high - low) / n, 12) for k in range(n + 1)})
    got = sorted({round(a / rack_m, 12) for a in _amplitudes(varied)})
    assert got == want, (got, want)
    for a in _amplitudes(design_runs.sobol_scenes(study)):
        assert low * (1 - 1e-12) <= a / rack_m <= high * (1 + 1e-12)
    # The runs that do not vary it share the car's rack.
    assert set(_amplitudes(design_runs.monte_carlo_scenes(study))) == {rack_m}
    row = {r["key"]: r for r in factor_rows(study)}[AMPLITUDE]
    assert row["low"] <= row["car"] == rack_m <= row["high"]  # the star inside, not outside
    assert f"{1e3 * f.low:.2f} ... {1e3 * f.high:.2f} mm on this car" in row["reason"]
    assert f"{low:.2f} ... {high:.2f} times" in row["reason"]
    assert f"scaled by {1e3 * rack_m:.2f} / 5.91 = {rack_m / study.rack_reference_m:.3f}" \
        in row["reason"]
    text = " ".join(answers.method(study))
    assert f"{1e3 * f.low:.2f} ... {1e3 * f.high:.2f} mm: {low:.2f} ... {high:.2f} times" in text


def test_a_rack_the_user_states_sets_the_severity_range(mine):
    study = load_study(DESIGN, "study", scene=(mine, "car"),
                       scene_text="manoeuvre: !LaneChange {amplitude_m: 0.0084, second_lobe: 1.0}")
    adapted, words = base_car.adapted_base(study, stated={"speed_up_s", "amplitude_m",
                                                          "second_lobe"})
    assert adapted.base == study.base  # the rack and launch as stated
    _check_scaled(adapted, 0.0084)
    assert len(words) == 1 and words[0].startswith("the severity range")
    assert "the rack amplitude its scene gives (8.40 mm)" in words[0]


def test_a_rack_calibrated_for_the_car_sets_the_severity_range(mine, monkeypatch):
    # The calibration stood in for (its own tests calibrate): the car's rack 9.075 mm, the
    # newcomer's sedan's.
    def calibrated(scene, run):
        m = scene.manoeuvre
        assert m.amplitude_m is None  # the shipped rack is not kept on another car
        return dataclasses.replace(scene, manoeuvre=dataclasses.replace(
            m, amplitude_m=0.009075232, second_lobe=1.005)), {"source": "test"}
    monkeypatch.setattr(base_car, "adapted", calibrated)
    study = load_study(DESIGN, "study", scene=(mine, "car"))
    adapted, words = base_car.adapted_base(study, stated={"speed_up_s"})
    _check_scaled(adapted, 0.009075232)
    assert words[0].startswith("the rack calibrated for this car: 9.08 mm")
    assert "times its rack calibrated for this car's 3.7 m lane change (9.08 mm)" in words[1]
    # Before: 3 ... 9 mm for this car, 0.33 ... 0.99 of its lane change.
    assert math.isclose(factor(adapted, AMPLITUDE).low, 0.003 * 0.009075232
                        / 0.005908525382359731, rel_tol=1e-12)


def test_the_bmw_s_calibrated_rack_sets_its_severity_range():
    # The shipped BMW 320i: its rack calibrated on the study's base (cached by content; about
    # 10 s of CPU where the code changed since).
    study = load_study(DESIGN, "study", scene=(resource("scenes/bmw_320i.yaml"), "car"))
    adapted, words = base_car.adapted_base(study, stated=set())
    rack_m = adapted.base.manoeuvre.amplitude_m
    assert rack_m != base_car.shipped_profile()[0]
    _check_scaled(adapted, rack_m)
    assert words[0].startswith("the rack calibrated for this car")
    assert words[1].startswith("the severity range (manoeuvre.amplitude_m) ")


def test_the_shipped_car_s_severity_is_the_spec_s():
    shipped = load_study(DESIGN, "study")
    assert shipped.rack_reference_m == shipped.base.manoeuvre.amplitude_m \
        == base_car.shipped_profile()[0]
    assert base_car.adapted_base(shipped) == (shipped, [])
    f = factor(shipped, AMPLITUDE)
    assert (f.low, f.high) == (0.003, 0.009)
    assert "3.00 ... 9.00 mm: 0.51 ... 1.52 times this one" in " ".join(answers.method(shipped))
    row = {r["key"]: r for r in factor_rows(shipped)}[AMPLITUDE]
    assert row["reason"].startswith("severity: half to one and a half times the lane change "
                                    "calibrated for the shipped car")


def test_a_spec_without_a_reference_runs_its_amplitudes_as_given(mine, tmp_path):
    text = DESIGN.read_text() if hasattr(DESIGN, "read_text") else open(DESIGN).read()
    assert "\n  rack_reference_m: " in text
    own = tmp_path / "design.yaml"
    own.write_text("\n".join(line for line in text.splitlines()
                             if not line.startswith("  rack_reference_m:")))
    study = load_study(own, "study", scene=(mine, "car"),
                       scene_text="manoeuvre: !LaneChange {amplitude_m: 0.0084, second_lobe: 1.0}")
    assert study.rack_reference_m is None
    adapted, words = base_car.adapted_base(study, stated={"speed_up_s", "amplitude_m",
                                                          "second_lobe"})
    assert words == [] and adapted == study
    assert (factor(adapted, AMPLITUDE).low, factor(adapted, AMPLITUDE).high) == (0.003, 0.009)
    bad = tmp_path / "bad.yaml"
    bad.write_text(text.replace("\n  rack_reference_m: ", "\n  rack_reference_m: -"))
    with pytest.raises(SceneError, match="rack_reference_m = -0.0059.* must be a rack amplitude"):
        load_study(bad, "study")


def test_a_line_of_the_amplitude_is_scaled_alike(mine):
    study = load_study(DESIGN, "study", scene=(mine, "car"),
                       scene_text="manoeuvre: !LaneChange {amplitude_m: 0.0084, second_lobe: 1.0}")
    ref = study.rack_reference_m
    study = dataclasses.replace(study, lines=[Line(key=AMPLITUDE, label="rack", values=[
        0.004, 0.006], reason="two severities")])
    scaled, words = base_car.severity_scaled(study, "the rack amplitude its scene gives")
    assert scaled.lines[0].values == pytest.approx([0.004 * 0.0084 / ref, 0.006 * 0.0084 / ref],
                                                   rel=1e-12)
    assert "two severities" in scaled.lines[0].reason and "on this car" in scaled.lines[0].reason
    assert words[-1] == "the line of manoeuvre.amplitude_m scaled alike: 5.69, 8.53 mm"
    built = {s.manoeuvre.amplitude_m for s, _ in design_runs.line_scenes(scaled).values()}
    assert built == set(scaled.lines[0].values)
