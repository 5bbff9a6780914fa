"""The Magic Formula and the .tir reader, tested alone against the formula's own landmarks."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from drake_car.data import resource
from drake_car.law.tyre.magic_formula import REQUIRED, MagicFormulaTyre, linear_tyre, magic_formula
from drake_car.law.tyre.tir import TirFileError, format_tir, parse_tir, read_tir

DEFAULT_TIR = str(resource("urdf/tyres/pacejka2006_205_60R15.tir"))
TYRE = MagicFormulaTyre.from_file(DEFAULT_TIR)
OFFSETS = ("PHX1", "PHX2", "PVX1", "PVX2", "PHY1", "PHY2", "PHY3", "PVY1", "PVY2", "RHX1",
           "RHY1", "RHY2", "QHZ1", "QHZ2", "QHZ3", "QHZ4", "RVY1", "RVY2", "RVY3", "PEX4",
           "PEY3", "PEY4", "QDZ6", "QDZ7", "SSZ1", "SSZ2", "RBY3", "QEZ4")


def symmetric():
    """The book's tyre with its asymmetries (ply steer, conicity, offsets) removed."""
    values = dict(TYRE.coefficients)
    for key in OFFSETS:
        values[key] = 0.0
    return MagicFormulaTyre(values, "symmetric")


def test_zero_slip_and_camber_gives_zero_force():
    f = magic_formula(symmetric(), 4000.0, 0.0, 0.0, 0.0, 0.0)
    assert (f.fx, f.fy, f.mz) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("fz", [2000.0, 4000.0, 6000.0])
def test_sign_symmetry(fz):
    tyre = symmetric()
    for kappa in (0.01, 0.05, 0.2):
        for alpha in (0.0, 0.02, 0.1):
            a = magic_formula(tyre, fz, kappa, alpha, 0.0, 10.0)
            b = magic_formula(tyre, fz, -kappa, -alpha, 0.0, 10.0)
            assert_allclose([b.fx, b.fy, b.mz], [-a.fx, -a.fy, -a.mz], atol=1e-9 * fz)


@pytest.mark.parametrize("fz", [2000.0, 4000.0, 6000.0])
def test_pure_slip_peaks_and_slopes_where_the_coefficients_put_them(fz):
    """D sin(C atan(...)) peaks at D when C > 1; the slope at zero slip is K."""
    tyre = symmetric()
    dfz = (fz - tyre.FNOMIN) / tyre.FNOMIN
    alphas = np.linspace(0.0, 0.6, 6001)
    fy = np.array([magic_formula(tyre, fz, 0.0, a, 0.0, 10.0, combined=False).fy
                   for a in alphas])
    assert_allclose(np.max(np.abs(fy)), abs((tyre.PDY1 + tyre.PDY2 * dfz) * fz), rtol=1e-6)
    kappas = np.linspace(0.0, 0.6, 6001)
    fx = np.array([magic_formula(tyre, fz, k, 0.0, 0.0, 10.0, combined=False).fx
                   for k in kappas])
    assert_allclose(np.max(fx), (tyre.PDX1 + tyre.PDX2 * dfz) * fz, rtol=1e-6)
    h = 1e-7
    ky = magic_formula(tyre, fz, 0.0, h, 0.0, 10.0).fy / h
    kx = magic_formula(tyre, fz, h, 0.0, 0.0, 10.0).fx / h
    assert_allclose(ky, tyre.PKY1 * tyre.FNOMIN * math.sin(2 * math.atan(
        fz / (tyre.PKY2 * tyre.FNOMIN))), rtol=1e-5)
    assert_allclose(kx, fz * (tyre.PKX1 + tyre.PKX2 * dfz) * math.exp(tyre.PKX3 * dfz),
                    rtol=1e-5)


def test_combined_slip_reduces_both_forces():
    for kappa, alpha in ((0.05, 0.05), (0.1, 0.03), (0.03, 0.1)):
        both = magic_formula(TYRE, 4000.0, kappa, alpha, 0.0, 16.0)
        assert abs(both.fx) < abs(magic_formula(TYRE, 4000.0, kappa, 0.0, 0.0, 16.0).fx)
        assert abs(both.fy) < abs(magic_formula(TYRE, 4000.0, 0.0, alpha, 0.0, 16.0).fy)
        pure = magic_formula(TYRE, 4000.0, kappa, alpha, 0.0, 16.0, combined=False)
        assert abs(both.fx) < abs(pure.fx) and abs(both.fy) < abs(pure.fy)


def test_load_sensitivity():
    """Peak friction falls with load (PDY2, PDX2); cornering stiffness grows less than load."""
    mu = [abs(magic_formula(TYRE, fz, 0.0, 0.3, 0.0, 16.0).fy) / fz for fz in (2e3, 4e3, 6e3)]
    assert mu[0] > mu[1] > mu[2]
    ky = [abs(magic_formula(TYRE, fz, 0.0, 0.0, 0.0, 16.0).cornering_stiffness)
          for fz in (2e3, 4e3, 6e3)]
    assert ky[0] < ky[1] < ky[2] and ky[2] / ky[0] < 3.0


def test_camber_thrust_points_where_the_wheel_leans():
    # ISO: γ > 0 leans the top to the right (-y); the thrust follows the lean.
    f = magic_formula(symmetric(), 4000.0, 0.0, 0.0, math.radians(2.0), 16.0)
    assert f.fy < 0


def test_no_force_without_load_and_finite_at_standstill():
    assert magic_formula(TYRE, 0.0, 0.1, 0.1, 0.0, 0.0).fx == 0.0
    f = magic_formula(TYRE, 4000.0, 0.0, 0.0, 0.0, 0.0)
    assert all(math.isfinite(v) for v in (f.fx, f.fy, f.mz, f.my))


def test_tir_round_trip(tmp_path):
    tir = read_tir(DEFAULT_TIR)
    path = tmp_path / "copy.tir"
    path.write_text(format_tir(tir, header="copy"))
    again = read_tir(path)
    assert again.sections == tir.sections and again.tables == tir.tables
    assert MagicFormulaTyre.from_file(path).coefficients == TYRE.coefficients


@pytest.mark.parametrize("text, match", [
    ("[MODEL]\nLONGVL = fast\n", r"copy.tir:2: LONGVL = 'fast' is not a number"),
    ("[MODEL]\nLONGVL 16.7\n", r"copy.tir:2: cannot read line"),
    ("LONGVL = 16.7\n", r"copy.tir:1: entry LONGVL before any \[SECTION\]"),
    ("[MODEL]\nLONGVL = 1\nLONGVL = 2\n", r"copy.tir:3: LONGVL is given twice"),
    ("[MODEL]\nLONGVL = 1\n[DIMENSION]\nLONGVL = 2\n",
     r"copy.tir:4: LONGVL is given twice \(in \[MODEL\] and \[DIMENSION\]\)"),
    ("[SHAPE]\n{radial width}\n1.0 0.0\n1.0 wide\n", r"copy.tir:4: cannot read line .*\[SHAPE\]"),
    ("[UNITS]\nLENGTH = 'furlong'\n", r"copy.tir:2: \[UNITS\] LENGTH = 'furlong' is not a unit"),
    ("[MODEL]\nNAME = 'open\n", r"copy.tir:2: unterminated string"),
    ("[MODEL]\nLONGVL = nan\n", r"copy.tir:2: LONGVL = 'nan' is not a number"),
    ("[MODEL]\nLONGVL = 1e999\n", r"copy.tir:2: LONGVL = '1e999' is not finite"),
])
def test_malformed_tir_names_the_line(tmp_path, text, match):
    path = tmp_path / "copy.tir"
    path.write_text(text)
    with pytest.raises(TirFileError, match=match):
        read_tir(path)


def test_tir_missing_coefficient_and_file(tmp_path):
    tir = read_tir(DEFAULT_TIR)
    del tir.sections["LATERAL_COEFFICIENTS"]["PKY1"]
    path = tmp_path / "short.tir"
    path.write_text(format_tir(tir))
    with pytest.raises(TirFileError, match=r"short.tir: missing .*PKY1"):
        MagicFormulaTyre.from_file(path)
    with pytest.raises(TirFileError, match="nowhere.tir: tyre property file not found"):
        MagicFormulaTyre.from_file(tmp_path / "nowhere.tir")
    assert set(REQUIRED) <= set(read_tir(DEFAULT_TIR).coefficients())


def test_comments_and_strings_parse():
    tir = parse_tir("$ header\n[MODEL]\nNAME = 'a $ b' ! note\nLONGVL = 16.7 $ m/s\n"
                    "[UNITS]\nMASS = 'kg'\nLENGTH='mm'\n[INERTIA]\nMASS = 9.0\n"
                    "[DIMENSION]\nUNLOADED_RADIUS = 313.0\n")
    assert tir.coefficients() == {"NAME": "a $ b", "LONGVL": 16.7 * 1e-3, "MASS": 9.0,
                                  "UNLOADED_RADIUS": 0.313}


def test_linear_tyre_is_the_magic_formula_to_first_order():
    """The linear tyre shares the Magic Formula's value and slope at zero slip, so their
    difference is O(ε²) in the slips: halving ε divides it by about 4 (at least 3 allows for
    the ε³ term). Away from zero slip it does not saturate."""
    tyre = MagicFormulaTyre.from_file(DEFAULT_TIR)
    fz, gamma, vx = 3800.0, 0.01, 16.0

    def difference(eps):
        mf = magic_formula(tyre, fz, eps, eps, gamma, vx, combined=False)
        lin = linear_tyre(tyre, fz, eps, eps, gamma, vx)
        return np.array([mf.fx - lin.fx, mf.fy - lin.fy, mf.mz - lin.mz])

    coarse, fine = np.abs(difference(5e-3)), np.abs(difference(2.5e-3))
    assert np.all(coarse / fine >= 3.0), coarse / fine
    at_zero = magic_formula(tyre, fz, 0.0, 0.0, gamma, vx, combined=False)
    lin = linear_tyre(tyre, fz, 0.0, 0.0, gamma, vx)
    assert (lin.fx, lin.fy, lin.mz, lin.my) == (at_zero.fx, at_zero.fy, at_zero.mz, at_zero.my)
    peak = max(abs(magic_formula(tyre, fz, 0.0, a, gamma, vx).fy) for a in np.radians(
        np.arange(1.0, 20.0)))
    assert abs(linear_tyre(tyre, fz, 0.0, np.radians(15.0), gamma, vx).fy) > 2 * peak
