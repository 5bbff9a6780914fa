"""Is a tyre's Magic Formula a road tyre? Evaluated inside the file's own validity ranges.

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


def _clip(x, low, high):
    return min(max(x, low), high)


def check_forces(tyre, magic_formula):
    """Raises ``TirFileError`` if ``tyre`` (``MagicFormulaTyre``) is no road tyre by
    ``magic_formula`` (its law); returns the warnings (a tuple of text)."""
    for key, scale in (("PCX1", "LCX"), ("PCY1", "LCY")):
        shape_factor = getattr(tyre, key) * getattr(tyre, scale)
        if not 0 < shape_factor <= 3:
            raise TirFileError(f"{tyre.name}: {key} = {getattr(tyre, key)} gives the shape "
                               f"factor C = {shape_factor:.4g}; it must lie in (0, 3] "
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


def combined_slip_note(tyre):
    """One line when the file has no combined-slip fit for Fx or Fy (RBX1 or RBY1 zero, or
    absent and so 0), else None: combined slip then leaves that force at its pure-slip value
    (the weighting G = 1), so ``combined_slip: true`` changes only what the file fits (the
    other force's weighting, the κ-induced side force RVY*, the aligning moment's combined
    terms) -- for a file with neither, the aligning moment alone."""
    missing = [f"{key} ({'absent' if key in tyre.defaulted else 'given as 0'})"
               for key in ("RBX1", "RBY1") if getattr(tyre, key) == 0.0]
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
