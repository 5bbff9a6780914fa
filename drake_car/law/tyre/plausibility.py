"""Is a tyre's Magic Formula a road tyre? Its coefficients checked as an engineer would, at read
time (so the tyre command and a scene refuse the same file with the same line), the formula
evaluated inside the file's own validity ranges.

Coefficients (``check_coefficients``): the scaling factors that divide or scale a friction
are positive (LFZO and LMUY divide: FNOMIN·LFZO is dfz's denominator, LMUY the aligning
moment's; LMUX >= 0, MF 6.x's degressive λμ' divides by 1 + 9 LMUX); the validity ranges are
ranges (FZMIN >= 0, each minimum below its maximum). Relaxation lengths (``check_relaxation``),
where the file gives their data (PAC2002: PTX1 or PTY1; MF 6.x: both carcass stiffnesses):
both > 0 at every load in FZMIN..FZMAX (without a range, up to 2 FNOMIN), sampled at
``RELAXATION_SAMPLES`` loads from FZMIN (or 0.001 FNOMIN where FZMIN is 0: at no load both are
0 by their formulas), and PTY2 != 0 (it divides).

Loads: FZMIN (at least 5 % of FNOMIN), FNOMIN and FZMAX when the file gives its
[VERTICAL_FORCE_RANGE], else 0.25, 1 and 2 FNOMIN (the book's file has no ranges); slips κ, α
and inclinations γ up to ±1, ±0.5 rad and ±0.17 rad, clipped to the file's KPUMIN..KPUMAX,
ALPMIN..ALPMAX, CAMMIN..CAMMAX. Refused (``TirFileError``): a shape factor C outside (0, 3],
non-finite forces, |F|/Fz above ``MAX_FRICTION_COEFFICIENT`` anywhere, or stiffnesses of the
wrong sign or size at FNOMIN (ISO: Kyα < 0 < Kx). The same stiffness test at the range's other
loads only warns (returned as text): a fit may extrapolate badly towards FZMAX (Chrono's
HMMWV tyre has Kx < 0 above about 2.4 FNOMIN), which matters only if the car gets there.
"""

import math
from pathlib import Path

from drake_car.law.tyre.property_file import TirFileError

MAX_FRICTION_COEFFICIENT = 2.5
MAX_STIFFNESS_PER_LOAD = 200.0
_PROBES = ((0.0, 0.0, 0.0), (0.1, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 0.1, 0.0),
           (0.0, -0.5, 0.0), (0.2, 0.2, 0.17), (-0.2, -0.2, -0.17))


RELAXATION_SAMPLES = 101
# The scaling factors that divide (must be > 0) and that scale a friction (must be >= 0).
_DIVIDING_SCALES = ("LFZO", "LMUY")
_FRICTION_SCALES = ("LMUX",)
_RANGES = (("FZMIN", "FZMAX"), ("KPUMIN", "KPUMAX"), ("ALPMIN", "ALPMAX"), ("CAMMIN", "CAMMAX"))


def check_coefficients(values, ranges, where):
    """Refuses (``TirFileError`` naming the file's line, the key and what is allowed) a scaling
    factor that divides by zero or makes a friction negative, and a validity range that is
    none. ``values``: the coefficients the formula reads; ``ranges``: FZMIN..CAMMAX (a file's,
    or the no-range defaults); ``where(key)``: "file:line"."""
    for key in _DIVIDING_SCALES:
        if not values[key] > 0:
            raise TirFileError(f"{where(key)}: {key} = {values[key]:g} must be > 0 (a scaling "
                               "factor; the formula divides by it)")
    for key in _FRICTION_SCALES:
        if not values[key] >= 0:
            raise TirFileError(f"{where(key)}: {key} = {values[key]:g} must be >= 0 (a "
                               "friction's scaling factor)")
    if not ranges["FZMIN"] >= 0:
        raise TirFileError(f"{where('FZMIN')}: FZMIN = {ranges['FZMIN']:g} N must be >= 0 (a "
                           "wheel load)")
    for low, high in _RANGES:
        if ranges[low] > ranges[high]:
            raise TirFileError(f"{where(high)}: {high} = {ranges[high]:g} is below "
                               f"{low} = {ranges[low]:g}")
        if ranges[low] == ranges[high]:
            raise TirFileError(f"{where(low)}: {low} = {ranges[low]:g} must be below {high} = "
                               f"{ranges[high]:g} (the range holds no value)")


# The coefficients each relaxation length is made of, by its source, and its formula.
_RELAXATION_KEYS = {
    "PTX/PTY": (("σκ", ("PTX1", "PTX2", "PTX3", "LSGKP"),
                 "Fz (PTX1 + PTX2 dfz) exp(-PTX3 dfz) R0/Fz0 LSGKP"),
                ("σα", ("PTY1", "PTY2", "LFZO", "LSGAL"),
                 "PTY1 sin(2 atan(Fz / (PTY2 Fz0'))) R0 LFZO LSGAL")),
    "carcass": (("σκ", ("LONGITUDINAL_STIFFNESS", "PCFX1", "PCFX2", "PCFX3"),
                 "|Kxκ| / Cx, Cx = LONGITUDINAL_STIFFNESS (1 + PCFX1 dfz + PCFX2 dfz²)"
                 "(1 + PCFX3 dpi)"),
                ("σα", ("LATERAL_STIFFNESS", "PCFY1", "PCFY2", "PCFY3"),
                 "|Kyα| / Cy, Cy = LATERAL_STIFFNESS (1 + PCFY1 dfz + PCFY2 dfz²)"
                 "(1 + PCFY3 dpi)")),
}


def check_relaxation(tyre, source, relaxation_lengths_m, where):
    """Refuses (``TirFileError``) relaxation data (``source``: "PTX/PTY", "carcass" or None)
    that make a relaxation length <= 0 (or not finite) at a load in FZMIN..FZMAX;
    ``relaxation_lengths_m(tyre, fz)``: the lengths' law."""
    if source is None:
        return
    if source == "PTX/PTY" and tyre.PTY2 == 0 and tyre.PTY1 != 0:
        raise TirFileError(f"{where('PTY2')}: PTY2 = 0 divides by zero in σα = PTY1 sin(2 "
                           "atan(Fz / (PTY2 Fz0'))) R0 LFZO LSGAL; it must be != 0 where PTY1 "
                           f"= {tyre.PTY1:g} gives relaxation data")
    low = tyre.FZMIN if tyre.FZMIN > 0 else 1e-3 * tyre.FNOMIN
    high = tyre.FZMAX if math.isfinite(tyre.FZMAX) else 2.0 * tyre.FNOMIN
    for i in range(RELAXATION_SAMPLES):
        fz = low + (high - low) * i / (RELAXATION_SAMPLES - 1)
        for (name, keys, formula), value in zip(_RELAXATION_KEYS[source],
                                                relaxation_lengths_m(tyre, fz)):
            if not (math.isfinite(value) and value > 0):
                given = ", ".join(f"{k} = {getattr(tyre, k, 0.0):g}" for k in keys
                                  if where(k) != tyre.name or k == keys[0])
                raise TirFileError(
                    f"{where(keys[0])}: {given} give {name} = {value:.3g} m at Fz = {fz:.4g} "
                    f"N; relaxation lengths must be > 0 at every load in FZMIN..FZMAX = "
                    f"{tyre.FZMIN:g}..{tyre.FZMAX:g} N ({name} = {formula})")


def _clip(x, low, high):
    return min(max(x, low), high)


def check_forces(tyre, magic_formula):
    """Raises ``TirFileError`` if ``tyre`` (``MagicFormulaTyre``) is no road tyre by
    ``magic_formula`` (its law); returns the warnings (a tuple of text)."""
    for key, scale in (("PCX1", "LCX"), ("PCY1", "LCY")):
        shape_factor = getattr(tyre, key) * getattr(tyre, scale)
        if not 0 < shape_factor <= 3:
            given = (f"{key} (absent, so 0)" if key in tyre.defaulted
                     else f"{key} = {getattr(tyre, key):g}")
            if getattr(tyre, scale) != 1.0:
                given += f" with {scale} = {getattr(tyre, scale):g}"
            raise TirFileError(f"{tyre.name}: {given} gives the shape factor C = "
                               f"{shape_factor:.4g}; it must lie in (0, 3] "
                               "(Pacejka 2006: about 1.3-1.7 for a road tyre)")
    nominal = tyre.FNOMIN
    if math.isfinite(tyre.FZMAX):
        loads = (max(tyre.FZMIN, 0.05 * nominal), nominal, tyre.FZMAX)
    else:
        loads = (0.25 * nominal, nominal, 2.0 * nominal)
    warnings = []
    for fz in loads:
        for kappa, alpha, gamma in _PROBES:
            kappa = _clip(kappa, tyre.KPUMIN, tyre.KPUMAX)
            alpha = _clip(alpha, tyre.ALPMIN, tyre.ALPMAX)
            gamma = _clip(gamma, tyre.CAMMIN, tyre.CAMMAX)
            at = f"at Fz = {fz:g} N, κ = {kappa:g}, α = {alpha:g} rad, γ = {gamma:g} rad"
            try:
                f = magic_formula(tyre, fz, kappa, alpha, gamma, 16.7)
            except (ArithmeticError, ValueError) as e:
                raise TirFileError(f"{tyre.name}: the Magic Formula fails {at}: {e}") from None
            values = (f.fx, f.fy, f.mz, f.my, f.cornering_stiffness, f.slip_stiffness)
            if not all(math.isfinite(v) for v in values):
                raise TirFileError(f"{tyre.name}: the Magic Formula gives non-finite forces "
                                   f"{at} (a coefficient is out of range)")
            ratio = max(abs(f.fx), abs(f.fy)) / fz
            if ratio > MAX_FRICTION_COEFFICIENT:
                raise TirFileError(
                    f"{tyre.name}: the Magic Formula gives |F|/Fz = {ratio:.3g} {at}; a road "
                    f"tyre stays below {MAX_FRICTION_COEFFICIENT} (a coefficient is out of "
                    "range)")
            if kappa == alpha == gamma == 0.0 and not (
                    -MAX_STIFFNESS_PER_LOAD * fz < f.cornering_stiffness < 0
                    < f.slip_stiffness < MAX_STIFFNESS_PER_LOAD * fz):
                text = (f"at Fz = {fz:g} N the cornering stiffness "
                        f"{f.cornering_stiffness:.4g} N/rad must lie in "
                        f"(-{MAX_STIFFNESS_PER_LOAD:g} Fz, 0) and the slip stiffness "
                        f"{f.slip_stiffness:.4g} N in (0, {MAX_STIFFNESS_PER_LOAD:g} Fz) (ISO "
                        "signs: PKY1 < 0, PKX1 > 0; road tyres have 5-40 Fz)")
                if fz == nominal:
                    raise TirFileError(f"{tyre.name}: {text}")
                warnings.append(text + " -- inside the file's load range")
    return tuple(warnings)


# [EST] The loads a tyre's fit rests on: tyre test programmes measure at about 0.25 to 2 times
# the nominal load (the tyre command's curves span 0.5-2 FNOMIN); a car whose wheels rest
# outside that band runs on the fit's load dependence extrapolated, whatever FZMIN..FZMAX say.
FIT_LOAD_BAND = (0.25, 2.0)


def wheel_load_note(tyre, wheel_loads_N):
    """One line when a static wheel load of the car (``wheel_loads_N``: {"front": N, "rear": N}
    per wheel) lies outside ``FIT_LOAD_BAND`` x FNOMIN -- the file's FZMIN..FZMAX and FNOMIN
    against the car's loads -- else None. (Loads outside FZMIN..FZMAX are refused where the
    car is built.)"""
    low, high = (r * tyre.FNOMIN for r in FIT_LOAD_BAND)
    if all(low <= load <= high for load in wheel_loads_N.values()):
        return None
    loads = ", ".join(f"{load:.0f} N {axle} ({load / tyre.FNOMIN:.2f} FNOMIN)"
                      for axle, load in wheel_loads_N.items())
    return (f"{tyre.name}: FNOMIN {tyre.FNOMIN:g} N, valid for {tyre.FZMIN:g}..{tyre.FZMAX:g} N; "
            f"this car's static wheel loads are {loads}, outside the {FIT_LOAD_BAND[0]:g}.."
            f"{FIT_LOAD_BAND[1]:g} FNOMIN a fit is measured over [EST]: a tyre for another "
            "vehicle, its forces here extrapolate the fit's load dependence")


# What a file without a combined-slip fit means for a run, and what to do (said with the note).
# Measured: the reviewer's hatch (1350 kg) on Sedan_Pac02Tire.tir in the paper's lane changes at
# 60 km/h (a_1, a_3: history.csv's kappa_f*, alpha_f*) had front |κ| <= 0.0022 at |α| <= 0.033
# rad once the speed was held, |κ| <= 0.042 at |α| <= 0.006 rad in the launch; the shipped
# tyre's fit (tyres/pacejka2006_205_60R15.tir, Fz 3500 N) weakens Fy at κ 0.0022, α 0.033 rad
# by 0.6 % (magic_formula(..., combined=True) against combined=False).
COMBINED_SLIP_MEANING = (
    "grip while the tyre drives or brakes hard in a turn is overstated; a run at held speed "
    "hardly changes (a 60 km/h lane change: front |κ| < 0.003, where the shipped tyre's fit "
    "takes 0.6 % off Fy); to model it, add the tyre's combined-slip coefficients (RBX*, RCX1, "
    "RBY*, RCY1, ...) to the file")


def _no_combined_fit(tyre):
    """The combined-slip fit's keys a file leaves at 0 (given so, or absent): RBX1 for Fx under
    a slip angle, RBY1 for Fy under longitudinal slip."""
    return [key for key in ("RBX1", "RBY1") if getattr(tyre, key) == 0.0]


def combined_slip_said(tyre):
    """The one line said at scene load when the file has no combined-slip fit for Fx or Fy
    (``combined_slip_note``): what it lacks, what that means for the results, what to do;
    None when it has both."""
    missing = _no_combined_fit(tyre)
    if not missing:
        return None
    forces = " and ".join({"RBX1": "Fx", "RBY1": "Fy"}[k] for k in missing)
    return (f"no combined-slip fit for {forces} ({', '.join(missing)} absent or 0): "
            f"{forces} {'keep their' if len(missing) == 2 else 'keeps its'} pure-slip value "
            f"under combined slip, so {COMBINED_SLIP_MEANING}")


def combined_slip_note(tyre):
    """One line when the file has no combined-slip fit for Fx or Fy (RBX1 or RBY1 zero, or
    absent and so 0), else None: combined slip then leaves that force at its pure-slip value
    (the weighting G = 1), so ``combined_slip: true`` changes only what the file fits (the
    other force's weighting, the κ-induced side force RVY*, the aligning moment's combined
    terms) -- for a file with neither, the aligning moment alone."""
    missing = [f"{key} ({'absent' if key in tyre.defaulted else 'given as 0'})"
               for key in _no_combined_fit(tyre)]
    if not missing:
        return None
    weakened = {"RBX1": "the weakening of Fx by the slip angle",
                "RBY1": "the weakening of Fy by the longitudinal slip"}
    left = [weakened[k] for k in ("RBX1", "RBY1") if getattr(tyre, k) != 0.0]
    side_force = any(getattr(tyre, k) != 0.0 for k in ("RVY1", "RVY2", "RVY3"))
    acts = left + (["the κ-induced side force (RVY*)"] if side_force else []) + [
        "the aligning moment's combined-slip terms"]
    return (f"{Path(tyre.name).name} has no combined-slip fit for "
            + " or ".join({"RBX1": "Fx", "RBY1": "Fy"}[m.split()[0]] for m in missing)
            + f" ({', '.join(missing)}): combined slip leaves "
            + ("them" if len(missing) == 2 else "it")
            + " at the pure-slip value, so combined_slip: true acts only through "
            + ", ".join(acts))
