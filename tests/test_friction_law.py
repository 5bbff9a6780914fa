"""The FRD friction law (paper eqs. 1-6) as pure functions."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from drake_car.law.checks import ParameterError
from drake_car.law.friction.frd import (
    KINETIC, NORMAL_FORCE_FORMS, STATIC, FrictionPairLaw, StrutFrictionParameters,
    advance_creep, beta, friction_coefficient, friction_moment, mu1, mu_kinetic, normal_force,
    shape, shape_max_slope, shape_slope)

PAPER = FrictionPairLaw(mu_s=0.2, mu_d=0.15, dv=1e-4, dmax=5e-6)
LAWS = [PAPER, FrictionPairLaw(0.4, 0.3, 1e-4, 5e-6, "linear", "linear"),
        FrictionPairLaw(0.3, 0.3, 1e-3, 1e-5, "cubic", "linear")]
# Round-off scale for evaluations of smooth polynomials of O(1) arguments.
EPS = 1e-12


@pytest.mark.parametrize("law", LAWS)
def test_continuity_at_threshold_and_end_of_stribeck_band(law):
    for creep in (-2 * law.dmax, -0.3 * law.dmax, 0.0, 0.7 * law.dmax, 3 * law.dmax):
        for sign in (1, -1):
            below = friction_coefficient(sign * law.dv * (1 - 1e-12), creep, law)[0]
            above = friction_coefficient(sign * law.dv * (1 + 1e-12), creep, law)[0]
            assert_allclose(below, above, atol=1e-9, err_msg=f"jump at |v| = dv, creep {creep}")
            assert_allclose(above, -sign * law.mu_s, atol=1e-9)
    for sign in (1, -1):
        a = friction_coefficient(sign * 1.5 * law.dv * (1 - 1e-12), 0.0, law)[0]
        b = friction_coefficient(sign * 1.5 * law.dv * (1 + 1e-12), 0.0, law)[0]
        assert_allclose(a, b, atol=1e-9, err_msg="jump at |v| = 1.5 dv")
        assert_allclose(b, -sign * law.mu_d, atol=1e-9)


def test_cubic_midpoint_of_stribeck_band():
    assert_allclose(mu_kinetic(1.25 * PAPER.dv, PAPER), (PAPER.mu_s + PAPER.mu_d) / 2, atol=EPS)


@pytest.mark.parametrize("law", LAWS)
def test_odd_symmetry(law):
    rng = np.random.default_rng(0)
    for _ in range(200):
        v = rng.uniform(-3, 3) * law.dv
        creep = rng.uniform(-2, 2) * law.dmax
        mu, b, m1, phase = friction_coefficient(v, creep, law)
        mu_m, b_m, m1_m, phase_m = friction_coefficient(-v, -creep, law)
        assert_allclose(mu_m, -mu, atol=EPS, err_msg=f"v {v}, creep {creep}")
        assert (b, m1, phase) == (b_m, m1_m, phase_m)


@pytest.mark.parametrize("law", LAWS)
def test_limits(law):
    assert friction_coefficient(0.0, 0.0, law)[0] == 0.0
    # At rest with creep at or beyond dmax: full static friction opposing the creep.
    assert_allclose(friction_coefficient(0.0, law.dmax, law)[0], -law.mu_s, atol=EPS)
    assert_allclose(friction_coefficient(0.0, -5 * law.dmax, law)[0], law.mu_s, atol=EPS)
    # Sliding fast: dynamic friction opposing the velocity, beta = 1, mu1 = 0.
    assert friction_coefficient(10 * law.dv, law.dmax, law) == (-law.mu_d, 1.0, 0.0, KINETIC)
    assert beta(0.0, law) == 0.0 and beta(law.dv, law) == 1.0
    assert mu1(0.0, law) == 0.0 and mu1(law.dmax, law) == law.mu_s
    # The static-phase coefficient never exceeds mu_s in magnitude.
    for v in np.linspace(-law.dv, law.dv, 41):
        for creep in np.linspace(-2 * law.dmax, 2 * law.dmax, 41):
            assert abs(friction_coefficient(v, creep, law)[0]) <= law.mu_s + EPS


def test_shapes():
    cubic, linear = PAPER, FrictionPairLaw(0.2, 0.15, 1e-4, 5e-6, "linear", "linear")
    assert_allclose(beta(0.5e-4, cubic), 0.5, atol=EPS)  # STEP midpoint
    assert_allclose(beta(0.25e-4, cubic), 0.25 ** 2 * (3 - 0.5), atol=EPS)
    assert_allclose(beta(0.25e-4, linear), 0.25, atol=EPS)
    assert_allclose(mu1(1.25e-6, linear), 0.05, atol=EPS)


@pytest.mark.parametrize("kind", ["cubic", "linear"])
def test_shape_slope_is_the_shapes_derivative(kind):
    """shape_slope (the fast scheme's tangents) against central differences of shape: the
    cubic's truncation error is h² (its third derivative is -12, so -2h² exactly); linear is
    exact. Zero outside [0, 1), and its maximum is shape_max_slope."""
    h = 1e-6
    xs = np.linspace(0.01, 0.99, 99)
    for x in xs:
        difference = (shape(x + h, kind) - shape(x - h, kind)) / (2 * h)
        assert_allclose(shape_slope(x, kind), difference, atol=2 * h * h + 1e-9)
    assert shape_slope(-0.1, kind) == shape_slope(1.0, kind) == shape_slope(1.5, kind) == 0.0
    assert_allclose(max(shape_slope(x, kind) for x in np.linspace(0, 0.999, 1999)),
                    shape_max_slope(kind), rtol=1e-6)


def test_lubricated_case_is_frictionless():
    law = FrictionPairLaw(0.0, 0.0)
    assert law.lubricated
    for v in (-1.0, -1e-4, 0.0, 5e-5, 1.0):
        assert friction_coefficient(v, 3e-6, law)[0] == 0.0


def test_creep_phase_logic():
    law = PAPER
    # Static: accumulates, bounded at +-dmax.
    assert advance_creep(1e-6, STATIC, 0.0, 2e-6, law) == (pytest.approx(3e-6, rel=1e-12), STATIC)
    assert advance_creep(4e-6, STATIC, 0.0, 3e-6, law) == (law.dmax, STATIC)
    # Static -> kinetic above dv: creep (so mu1) resets to zero.
    assert advance_creep(4e-6, STATIC, 2e-4, 1e-6, law) == (0.0, KINETIC)
    # Kinetic -> static below dv: creep starts again from zero.
    assert advance_creep(0.0, KINETIC, 5e-5, 1e-6, law) == (0.0, STATIC)


def test_contact_pair_normal_force():
    """F and M carried by two contact forces at guide and piston, d apart along û."""
    axis = np.array([0.0, 0.0, 1.0])
    f1, f2 = np.array([400.0, 0.0, 0.0]), np.array([-100.0, 0.0, 0.0])  # at +d/2, -d/2
    d = 0.1
    force = f1 + f2
    moment = np.cross(d / 2 * axis, f1) + np.cross(-d / 2 * axis, f2)
    assert_allclose(normal_force(force, moment, d, 0.0, 0.2, "contact_pair", axis=axis),
                    np.linalg.norm(f1) + np.linalg.norm(f2), rtol=1e-12)


def test_normal_force_of_a_mirror_image():
    """Eq. (4) of a strut's mirror image (in the plane y = 0: force and axis reflected, the
    moment, an axial vector, reflected and negated), evaluated ``mirrored``, equals the
    strut's own bit for bit in every form. The vector form unmirrored does not (it adds an
    axial vector to a polar one): |F - M/d| instead of |F + M/d|; the other two forms do not
    depend on ``mirrored`` at all."""
    reflect = np.array([1.0, -1.0, 1.0])
    rng = np.random.default_rng(3)
    for form in NORMAL_FORCE_FORMS:
        for _ in range(200):
            f, m = rng.uniform(-3000, 3000, 3), rng.uniform(-300, 300, 3)
            u = rng.uniform(-1, 1, 3)
            u /= np.linalg.norm(u)
            d, preload = rng.uniform(0.05, 0.2), rng.choice([0.0, 50.0])
            own = normal_force(f, m, d, preload, 0.2, form, axis=u)
            image = normal_force(reflect * f, -reflect * m, d, preload, 0.2, form,
                                 axis=reflect * u, mirrored=True)
            assert image == own, (form, image, own)
            if form == "vector":
                assert_allclose(normal_force(reflect * f, -reflect * m, d, preload, 0.2, form),
                                np.linalg.norm(f - m / d) + preload / 0.2 * (preload > 0),
                                rtol=1e-12)
            else:
                assert normal_force(f, m, d, preload, 0.2, form, axis=u, mirrored=True) == own


def test_normal_force_forms_and_moment():
    f = np.array([300.0, 0.0, 0.0])
    m = np.array([0.0, 30.0, 0.0])
    d = 0.1
    assert_allclose(normal_force(f, m, d, 0.0, 0.2), math.hypot(300.0, 300.0), rtol=EPS)
    assert_allclose(normal_force(f, m, d, 0.0, 0.2, "magnitude_sum"), 600.0, rtol=EPS)
    assert_allclose(normal_force(f, -m, d, 50.0, 0.2), math.hypot(300, 300) + 250.0, rtol=EPS)
    assert_allclose(friction_moment(-0.2, 1000.0, 0.011, 2.0, 0.2), -0.2 * (11.0 + 10.0),
                    rtol=EPS)
    with pytest.raises(ParameterError, match="overlap"):
        normal_force(f, m, 0.0, 0.0, 0.2)
    with pytest.raises(ParameterError, match="form"):
        normal_force(f, m, d, 0.0, 0.2, "sum")


@pytest.mark.parametrize("kwargs, match", [
    (dict(mu_s=0.1, mu_d=0.2), "mu_d"),
    (dict(mu_s=0.2, mu_d=-0.1), "mu_d"),
    (dict(mu_s=0.2, mu_d=0.1, dv_translation_mps=0.0), "dv_translation_mps"),
    (dict(mu_s=0.2, mu_d=0.1, dmax_translation_m=-1e-6), "dmax_translation_m"),
    (dict(mu_s=0.2, mu_d=0.1, beta_shape="sine"), "beta_shape"),
    (dict(mu_s=0.2, mu_d=0.1, creep_shape="quad"), "creep_shape"),
    (dict(mu_s=float("nan"), mu_d=0.1), "mu_s"),
    (dict(mu_s=5.0, mu_d=0.1), "mu_s"),
    (dict(preload_force_N=-1.0), "preload_force_N"),
    (dict(preload_moment_Nm=-1.0), "preload_moment_Nm"),
    (dict(mu_s=0.0, mu_d=0.0, preload_force_N=10.0), "preload_force_N"),
    (dict(mu_s=0.0, mu_d=0.0, preload_moment_Nm=1.0), "preload_moment_Nm"),
    (dict(normal_force_form="adams"), "normal_force_form"),
    (dict(dv_rotation_radps=-1.0), "dv"),
    (dict(dmax_translation_m=0.0), "dmax"),
])
def test_strut_parameter_errors(kwargs, match):
    """Checked once, where they enter (``check()``, which a scene's load runs); the pairs' laws
    made from them trust them."""
    with pytest.raises(ParameterError, match=match):
        StrutFrictionParameters(**kwargs).check()
