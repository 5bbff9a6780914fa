"""The car and its lane changes are mirror images (issue 32): driving straight, the left and
right struts of the dry-strut runs agree to round-off, and case b mirrors case a.

What broke it: eq. (4)'s vector form |M/d + F| adds the reaction's moment (an axial vector) to
its force (a polar vector), so the right strut, evaluated in the same frame as the left, took
|F - M/d| (``law.friction.frd``; 0.23 N of 1414 N at rest): a_3's rods were 1.5e-10 m apart at
rest and 64 µm in the launch, and b_3 ended 3.5 mm from a_3 mirrored.

The bound for "round-off": the plant's positions are of the order of 1 m and carry ε·1 m ≈
2e-16 m; the friction's stick-slip decisions amplify it somewhat (measured on the translation
pairs through the launch: 6e-14 m), and 1e-12 m (2e-7 of the creep Δmax) leaves a margin of 16
below which no physical asymmetry hides (the broken law's at rest: 1.5e-10 m). A corner load's
round-off is the tyre's radial stiffness times that.

What remains at the default 1 ms step, and is not round-off: in the launch (0.86 s) the rotation
pairs of a_2 and a_3 reach the Stribeck band (Δv < |ω| < 1.5 Δv), where the fast scheme's effort
limit μk(|ω_k|)·S lags one step and an antisymmetric difference grows about 30-fold per step: a
symmetric state breaks to one of two mirror-image states, ±2.5 µm of rod at 1.1 s, whichever
sign the round-off has (an antisymmetric seed of 1e-14 m on the rack gives the same size). At
0.5 ms and finer the pairs stay static there and a 1e-12 m seed stays below 1.3e-13 m. So the
straight-drive test leaves the rotation pairs out after the car has settled, and the mirror
test bounds the whole law's residual by claim 4's tolerance. The strut's own viscous damper
beside the dry friction (a user's sets) keeps the mirror too; what a 1 ms launch's break leaves
at place a depends on the later break-aways it passes through (0.004 N of rack force with the
damper 0, 8.8 N with 2200 N s/m on the hatch car: docs/accuracy.md "The mirror").
"""

import numpy as np
import pytest

from conftest import paper_scene
from drake_car.sim.simulate import simulate
from drake_car.study.paper.outcomes import TOLERANCES

ROUND_OFF_M = 1e-12


def _left_right(history):
    return (np.max(np.abs(history["d_left_m"] - history["d_right_m"])),
            np.max(np.abs(history["Fz_fl_N"] - history["Fz_fr_N"])))


@pytest.mark.parametrize("name, pairs, end_s, damper_Nspm", [
    ("a_2", "translation", 1.5, 0.0),  # settling, then the launch to 0.7 s into the speed-up
    ("a_3", "translation", 1.5, 0.0),
    ("a_3", "translation_rotation", 0.8, 0.0),  # the whole law: at rest, to the launch
    # a user's set keeping the strut's own viscous damper beside the dry friction
    ("a_3", "translation_rotation", 0.8, 2200.0)])
def test_left_and_right_struts_agree_driving_straight(name, pairs, end_s, damper_Nspm):
    scene = paper_scene(name, f"{{friction: {{pairs: {pairs}}}, "
                              f"car: {{front: {{strut_damping_Nspm: {damper_Nspm}}}}}, "
                              f"simulator: {{end_time_s: {end_s}}}}}")
    run = simulate(scene)
    rods, loads = _left_right(run.history)
    stiffness = scene.car.tyre.radial_stiffness_Npm
    assert rods <= ROUND_OFF_M, f"{name} ({pairs}): rods {rods:.3g} m apart left to right"
    assert loads <= stiffness * ROUND_OFF_M, (
        f"{name} ({pairs}): front corner loads {loads:.3g} N apart left to right")


@pytest.mark.slow
@pytest.mark.parametrize("pairs, bound_m, why", [
    ("translation", ROUND_OFF_M, "round-off"),
    ("translation_rotation", TOLERANCES["mirror_residual_m"][0],
     "claim 4's tolerance (the 1 ms launch's symmetry break, 4.7 µm measured, stays in it)")])
def test_case_b_mirrors_case_a(pairs, bound_m, why):
    """a_3 and b_3 at the default step, the whole lane change: claim 4's residual,
    max |Δd(a, side) - Δd(b, other side)|."""
    runs = {case: simulate(paper_scene(f"{case}_3", f"{{friction: {{pairs: {pairs}}}}}"))
            for case in "ab"}
    a, b = (runs[c].history for c in "ab")
    residual = max(np.max(np.abs((a[f"d_{s}_m"] - a[f"d_{s}_m"][0])
                                 - (b[f"d_{o}_m"] - b[f"d_{o}_m"][0])))
                   for s, o in (("left", "right"), ("right", "left")))
    assert residual <= bound_m, f"{pairs}: mirror residual {residual:.3g} m above {why}"


def test_the_reports_torques_at_the_places_have_no_negative_zero():
    """The paper report's torque line: a torque that rounds to zero reads 0.000, not -0.000."""
    from drake_car.study.paper.report_sections import _torque_at_places
    (line, _) = _torque_at_places({"wheel_torque_at_places_Nm": {"a_1": (-4e-6, 0.0391),
                                                                 "b_3": (1e-4, -0.17)}})
    assert "a_1 0.000 / +0.039, b_3 0.000 / -0.170" in line and "-0.000" not in line
