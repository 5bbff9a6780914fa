"""Pacejka's Magic Formula as in H. B. Pacejka, Tyre and Vehicle Dynamics, 2nd ed. (2006),
section 4.3.2 (steady state, eqs. 4.E1-4.E71), with the coefficient names of the .tir format.
Pure Python. The lateral and aligning camber terms follow the book (Kyγ via PKY6/PKY7, μy and
Kyα divided by 1 + P·γ*²), which is what the book's Table A3.1 coefficients were fitted to;
at zero camber this is the PAC2002 (MF 5.2) formula.

Conventions (ISO W-axis, as the coefficients expect): x along the wheel heading, y to its left,
z up. Longitudinal slip κ = -V_sx/|V_cx| (positive when driving); slip angle α with
tan α = V_cy/|V_cx| (positive when the wheel moves to its left; the force is then negative);
inclination γ: rotation of the wheel about its x axis (positive: top leaning to the right);
γ* = sin γ. Forces in N, moments in N m, Fz > 0 pressing the tyre on the road.
"""

import dataclasses
import math

from drake_car.law.tyre.tir import TirFileError, read_tir

# Coefficients that the book's Table A3.1 lists; the .tir must give them all.
REQUIRED = (
    "UNLOADED_RADIUS", "FNOMIN", "LONGVL",
    "PCX1", "PDX1", "PDX2", "PDX3", "PEX1", "PEX2", "PEX3", "PEX4", "PKX1", "PKX2", "PKX3",
    "PHX1", "PHX2", "PVX1", "PVX2", "RBX1", "RBX2", "RCX1", "REX1", "REX2", "RHX1",
    "PCY1", "PDY1", "PDY2", "PDY3", "PEY1", "PEY2", "PEY3", "PEY4", "PKY1", "PKY2", "PKY3",
    "PHY1", "PHY2", "PHY3", "PVY1", "PVY2", "PVY3", "PVY4", "RBY1", "RBY2", "RBY3", "RCY1",
    "REY1", "REY2", "RHY1", "RHY2", "RVY1", "RVY2", "RVY3", "RVY4", "RVY5", "RVY6",
    "QBZ1", "QBZ2", "QBZ3", "QBZ5", "QBZ9", "QBZ10", "QCZ1", "QDZ1", "QDZ2", "QDZ3",
    "QDZ4", "QDZ6", "QDZ7", "QDZ8", "QDZ9", "QEZ1", "QEZ2", "QEZ3", "QEZ4", "QEZ5", "QHZ1",
    "QHZ2", "QHZ3", "QHZ4", "SSZ1", "SSZ2", "SSZ3", "SSZ4", "QSY1", "QSY2", "QSY3", "QSY4")
# Coefficients of the book's formulas that may be absent (value when absent).
OPTIONAL = {"PKY4": 2.0, "PKY5": 0.0, "PKY6": 0.0, "PKY7": 0.0, "PEY5": 0.0, "RBX3": 0.0,
            "RBY4": 0.0, "QBZ6": 0.0, "QDZ10": 0.0, "QDZ11": 0.0}
# |F|/Fz above this is no road tyre (racing slicks reach about 1.8).
MAX_FRICTION_COEFFICIENT = 2.5
# Slip and cornering stiffness per unit load above this is no road tyre (they have 5-40 /rad).
MAX_STIFFNESS_PER_LOAD = 200.0
SCALING = ("LFZO", "LCX", "LMUX", "LEX", "LKX", "LHX", "LVX", "LCY", "LMUY", "LEY",
           "LKY", "LKYC", "LKZC", "LHY", "LVY", "LTR", "LRES", "LXAL", "LYKA", "LVYKA", "LS",
           "LMY")


@dataclasses.dataclass(frozen=True)
class MagicFormulaTyre:
    """Coefficients of one tyre: a {KEY: float} mapping as read from a .tir file."""

    coefficients: dict
    name: str = "<tyre>"

    def __post_init__(self):
        missing = [k for k in REQUIRED if k not in self.coefficients]
        if missing:
            raise TirFileError(f"{self.name}: missing Magic Formula coefficients {missing}")
        for key in REQUIRED + tuple(k for k in SCALING if k in self.coefficients):
            if isinstance(self.coefficients[key], str):
                raise TirFileError(f"{self.name}: {key} must be a number")
        for key in ("UNLOADED_RADIUS", "FNOMIN", "LONGVL"):
            if not self.coefficients[key] > 0:
                raise TirFileError(f"{self.name}: {key} = {self.coefficients[key]} must be > 0")
        if not 0.1 <= self.coefficients["UNLOADED_RADIUS"] <= 2.0:
            raise TirFileError(f"{self.name}: UNLOADED_RADIUS = "
                               f"{self.coefficients['UNLOADED_RADIUS']} m must lie in [0.1, 2]")
        # Coefficients as attributes (fast to read in the per-step formulas); scaling factors
        # default to 1.
        for key in SCALING:
            object.__setattr__(self, key, float(self.coefficients.get(key, 1.0)))
        for key, default in OPTIONAL.items():
            object.__setattr__(self, key, float(self.coefficients.get(key, default)))
        for key in REQUIRED:
            object.__setattr__(self, key, float(self.coefficients[key]))

        self._check_forces()

    def _check_forces(self):
        """The coefficients must give a road tyre: over loads 0.25 ... 2 FNOMIN and slips up to
        κ = ±1, α = ±30 deg, γ = ±10 deg the forces are finite, the friction coefficients
        |F|/Fz stay below ``MAX_FRICTION_COEFFICIENT`` and the cornering and slip stiffnesses
        have the signs of the ISO convention (Kyα < 0, Kx > 0). Catches a mistyped exponent
        (1e300) before it reaches a simulation as a NaN."""
        for key, scale in (("PCX1", "LCX"), ("PCY1", "LCY")):
            shape_factor = self.coefficients[key] * getattr(self, scale)
            if not 0 < shape_factor <= 3:
                raise TirFileError(f"{self.name}: {key} = {self.coefficients[key]} gives the shape "
                                   f"factor C = {shape_factor:.4g}; it must lie in (0, 3] "
                                   "(Pacejka 2006: about 1.3-1.7 for a road tyre)")
        for load_ratio in (0.25, 1.0, 2.0):
            fz = load_ratio * self.FNOMIN
            for kappa, alpha, gamma in ((0.0, 0.0, 0.0), (0.1, 0.0, 0.0), (-1.0, 0.0, 0.0),
                                        (0.0, 0.1, 0.0), (0.0, -0.5, 0.0), (0.2, 0.2, 0.17),
                                        (-0.2, -0.2, -0.17)):
                try:
                    f = magic_formula(self, fz, kappa, alpha, gamma, 16.7)
                except (ArithmeticError, ValueError) as e:
                    raise TirFileError(f"{self.name}: the Magic Formula fails at Fz = {fz:g} N,"
                                       f" κ = {kappa}, α = {alpha} rad: {e}") from None
                values = (f.fx, f.fy, f.mz, f.my, f.cornering_stiffness, f.slip_stiffness)
                if not all(math.isfinite(v) for v in values):
                    raise TirFileError(f"{self.name}: the Magic Formula gives non-finite forces "
                                       f"at Fz = {fz:g} N, κ = {kappa}, α = {alpha} rad "
                                       "(a coefficient is out of range)")
                ratio = max(abs(f.fx), abs(f.fy)) / fz
                if ratio > MAX_FRICTION_COEFFICIENT:
                    raise TirFileError(
                        f"{self.name}: the Magic Formula gives |F|/Fz = {ratio:.3g} at Fz = "
                        f"{fz:g} N, κ = {kappa}, α = {alpha} rad; a road tyre stays below "
                        f"{MAX_FRICTION_COEFFICIENT} (a coefficient is out of range)")
                if kappa == alpha == gamma == 0.0 and not (
                        -MAX_STIFFNESS_PER_LOAD * fz < f.cornering_stiffness < 0
                        < f.slip_stiffness < MAX_STIFFNESS_PER_LOAD * fz):
                    raise TirFileError(
                        f"{self.name}: at Fz = {fz:g} N the cornering stiffness "
                        f"{f.cornering_stiffness:.4g} N/rad must lie in (-{MAX_STIFFNESS_PER_LOAD:g}"
                        f" Fz, 0) and the slip stiffness {f.slip_stiffness:.4g} N in (0, "
                        f"{MAX_STIFFNESS_PER_LOAD:g} Fz) (ISO signs: PKY1 < 0, PKX1 > 0; road "
                        "tyres have 5-40 Fz)")

    @classmethod
    def from_file(cls, path):
        values, _ = read_tir(path)
        return cls(values, str(path))


def _sign(x):
    return 1.0 if x >= 0 else -1.0


def _mf(b, c, d, e, x):
    """D sin(C atan(B x - E (B x - atan(B x))))."""
    bx = b * x
    return d * math.sin(c * math.atan(bx - e * (bx - math.atan(bx))))


def _weight(b, c, e, x, shift):
    """Combined-slip weighting cos(C atan(B x_s - E(...))) / cos(C atan(B S - E(...)))."""
    def g(u):
        bu = b * u
        return math.cos(c * math.atan(bu - e * (bu - math.atan(bu))))
    return g(x + shift) / g(shift)


@dataclasses.dataclass
class TyreForces:
    fx: float
    fy: float
    mz: float
    my: float
    fx0: float  # pure-slip values, for diagnostics and tests
    fy0: float
    cornering_stiffness: float  # Ky (N/rad) at this load and camber
    slip_stiffness: float  # Kx (N per unit slip)
    pneumatic_trail: float = 0.0  # t (m) at this slip: Mz = -t Fy + Mzr


def magic_formula(t: MagicFormulaTyre, fz, kappa, alpha, gamma, vx, combined=True):
    """Steady-state tyre forces for vertical load ``fz`` (N), longitudinal slip ``kappa``,
    slip angle ``alpha`` (rad), inclination ``gamma`` (rad), forward speed ``vx`` (m/s, for
    rolling resistance only). ``combined=False`` drops the combined-slip weighting.
    ``cornering_stiffness`` is Kyα (negative in the ISO convention: Fy ≈ Kyα·α)."""
    if fz <= 0.0:
        return TyreForces(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    fz0 = t.FNOMIN * t.LFZO
    dfz = (fz - fz0) / fz0
    r0 = t.UNLOADED_RADIUS

    gs = math.sin(gamma)  # γ*

    # Longitudinal, pure slip (4.E9-4.E18).
    shx = (t.PHX1 + t.PHX2 * dfz) * t.LHX
    kx_ = kappa + shx
    cx = t.PCX1 * t.LCX
    mux = (t.PDX1 + t.PDX2 * dfz) * (1.0 - t.PDX3 * gamma * gamma) * t.LMUX
    dx = mux * fz
    ex = min(1.0, (t.PEX1 + t.PEX2 * dfz + t.PEX3 * dfz * dfz)
             * (1.0 - t.PEX4 * _sign(kx_)) * t.LEX)
    kx = fz * (t.PKX1 + t.PKX2 * dfz) * math.exp(t.PKX3 * dfz) * t.LKX
    bx = kx / (cx * dx) if cx * dx != 0 else 0.0
    svx = fz * (t.PVX1 + t.PVX2 * dfz) * t.LVX * t.LMUX
    fx0 = _mf(bx, cx, dx, ex, kx_) + svx

    # Lateral, pure slip (4.E19-4.E30).
    ky = (t.PKY1 * fz0 * math.sin(t.PKY4 * math.atan(fz / ((t.PKY2 + t.PKY5 * gs * gs) * fz0)))
          / (1.0 + t.PKY3 * gs * gs) * t.LKY)
    kyg = fz * (t.PKY6 + t.PKY7 * dfz) * t.LKYC
    svyg = fz * (t.PVY3 + t.PVY4 * dfz) * gs * t.LKYC * t.LMUY
    svy = fz * (t.PVY1 + t.PVY2 * dfz) * t.LVY * t.LMUY + svyg
    shy = (t.PHY1 + t.PHY2 * dfz) * t.LHY + ((kyg * gs - svyg) / ky if ky != 0 else 0.0)
    ay = alpha + shy
    cy = t.PCY1 * t.LCY
    muy = (t.PDY1 + t.PDY2 * dfz) / (1.0 + t.PDY3 * gs * gs) * t.LMUY
    dy = muy * fz
    ey = min(1.0, (t.PEY1 + t.PEY2 * dfz)
             * (1.0 + t.PEY5 * gs * gs - (t.PEY3 + t.PEY4 * gs) * _sign(ay)) * t.LEY)
    by = ky / (cy * dy) if cy * dy != 0 else 0.0
    fy0 = _mf(by, cy, dy, ey, ay) + svy

    # Aligning moment, pure slip (4.E31-4.E49).
    sht = t.QHZ1 + t.QHZ2 * dfz + (t.QHZ3 + t.QHZ4 * dfz) * gs
    bt = ((t.QBZ1 + t.QBZ2 * dfz + t.QBZ3 * dfz * dfz)
          * (1.0 + t.QBZ5 * abs(gs) + t.QBZ6 * gs * gs) * t.LKY / t.LMUY)
    ct = t.QCZ1
    dt = (fz * (t.QDZ1 + t.QDZ2 * dfz) * (1.0 + t.QDZ3 * abs(gs) + t.QDZ4 * gs * gs)
          * (r0 / fz0) * t.LTR)
    at = alpha + sht
    et = min(1.0, (t.QEZ1 + t.QEZ2 * dfz + t.QEZ3 * dfz * dfz)
             * (1.0 + (t.QEZ4 + t.QEZ5 * gs) * (2.0 / math.pi) * math.atan(bt * ct * at)))
    shf = shy + (svy / ky if ky != 0 else 0.0)
    ar = alpha + shf
    br = t.QBZ9 * t.LKY / t.LMUY + t.QBZ10 * by * cy
    cos_a = math.cos(alpha)
    dr = (fz * r0 * ((t.QDZ6 + t.QDZ7 * dfz) * t.LRES
                     + ((t.QDZ8 + t.QDZ9 * dfz) + (t.QDZ10 + t.QDZ11 * dfz) * abs(gs))
                     * gs * t.LKZC) * t.LMUY * cos_a)

    if combined:
        # Combined slip (4.E50-4.E67).
        bxa = (t.RBX1 + t.RBX3 * gs * gs) * math.cos(math.atan(t.RBX2 * kappa)) * t.LXAL
        exa = min(1.0, t.REX1 + t.REX2 * dfz)
        fx = _weight(bxa, t.RCX1, exa, alpha, t.RHX1) * fx0
        shyk = t.RHY1 + t.RHY2 * dfz
        byk = ((t.RBY1 + t.RBY4 * gs * gs) * math.cos(math.atan(t.RBY2 * (alpha - t.RBY3)))
               * t.LYKA)
        eyk = min(1.0, t.REY1 + t.REY2 * dfz)
        dvyk = (muy * fz * (t.RVY1 + t.RVY2 * dfz + t.RVY3 * gs)
                * math.cos(math.atan(t.RVY4 * alpha)))
        svyk = dvyk * math.sin(t.RVY5 * math.atan(t.RVY6 * kappa)) * t.LVYKA
        fy = _weight(byk, t.RCY1, eyk, kappa, shyk) * fy0 + svyk
        ratio = (kx / ky) if ky != 0 else 0.0
        at_eq = math.sqrt(at * at + (ratio * kappa) ** 2) * _sign(at)
        ar_eq = math.sqrt(ar * ar + (ratio * kappa) ** 2) * _sign(ar)
        trail = _mf_cos(bt, ct, dt, et, at_eq) * cos_a
        mzr = dr * math.cos(math.atan(br * ar_eq))
        s = (t.SSZ1 + t.SSZ2 * (fy / fz0) + (t.SSZ3 + t.SSZ4 * dfz) * gs) * r0 * t.LS
        mz = -trail * (fy - svyk) + mzr + s * fx
    else:
        fx, fy = fx0, fy0
        trail = _mf_cos(bt, ct, dt, et, at) * cos_a
        mz = -trail * fy0 + dr * math.cos(math.atan(br * ar))

    # Rolling resistance (4.E70), opposing the rolling direction.
    v = vx / t.LONGVL
    my = -r0 * fz * (t.QSY1 + t.QSY2 * fx / fz0 + t.QSY3 * abs(v) + t.QSY4 * v ** 4) * t.LMY
    my *= math.tanh(vx / 0.1)  # smooth sign through standstill
    return TyreForces(fx, fy, mz, my, fx0, fy0, ky, kx, trail)


def linear_tyre(t: MagicFormulaTyre, fz, kappa, alpha, gamma, vx):
    """The same tyre linearised in the slips about zero slip, at this load and camber (the
    "linear tyre" of handling analyses): Fx = Fx(0) + Kx κ, Fy = Fy(0) + Ky α,
    Mz = Mz(0) - t0 Ky α, with Kx, Ky and the pneumatic trail t0 the Magic Formula's at zero
    slip (so it agrees with ``magic_formula`` to first order in κ and α) and My its rolling
    resistance; no saturation, no combined-slip interaction. Fy(0), Mz(0) are the data's
    offsets (ply-steer, conicity, camber thrust)."""
    f = magic_formula(t, fz, 0.0, 0.0, gamma, vx, combined=False)
    fx = f.fx + f.slip_stiffness * kappa
    fy = f.fy + f.cornering_stiffness * alpha
    my = f.my
    if fz > 0.0:  # rolling resistance at this Fx (4.E70's QSY2 term)
        my += -t.UNLOADED_RADIUS * fz * t.QSY2 * (fx - f.fx) / (t.FNOMIN * t.LFZO) * t.LMY \
            * math.tanh(vx / 0.1)
    mz = f.mz - f.pneumatic_trail * f.cornering_stiffness * alpha
    return TyreForces(fx, fy, mz, my, fx, fy, f.cornering_stiffness, f.slip_stiffness,
                      f.pneumatic_trail)


def _mf_cos(b, c, d, e, x):
    bx = b * x
    return d * math.cos(c * math.atan(bx - e * (bx - math.atan(bx))))
