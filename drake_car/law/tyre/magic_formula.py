"""Pacejka's Magic Formula, steady state, in the form the tyre's property file asks for
(``law.tyre.formats``): the book's 2006 form (H. B. Pacejka, Tyre and Vehicle Dynamics, 2nd
ed. 2006, section 4.3.2, eqs. 4.E1-4.E71: the file drake_car ships), PAC2002 (MF 5.2, MSC
Adams/Tire) and MF 6.1/6.2 (TNO; Pacejka and Besselink, 3rd ed. 2012, 4.E1-4.E78, with the
inflation-pressure terms). Pure Python; ``law.tyre.compiled`` is its numba twin.

Where the forms differ (``FORM``: 0 book, 1 PAC2002, 2 MF 6.x):
- slip angle: the book's α; PAC2002 and MF 6.x use α* = tan α (4.E3) in every slip term;
- camber: the book divides μy and Kyα by 1 + P·γ*² and shifts Fy by Kyγ (PKY6/PKY7);
  PAC2002 multiplies by (1 - PDY3 γy²), (1 - PKY3 |γy|), shifts by PHY3 γy, uses QBZ4 and
  QDZ3 γz, with γx,y,z = γ* LGAX,Y,Z; MF 6.x multiplies as PAC2002 but shifts by Kyγ as the
  book, and its aligning moment takes the side force without camber (4.E74, as the TNO solver);
- MF 6.x's pressure terms with dpi = (p - NOMPRES)/NOMPRES; its rolling resistance
  Fz0 R0 (...) (Fz/Fz0)^QSY7 (p/p0)^QSY8 (4.E70, 3rd ed.).
Inputs are clipped to the file's ranges (FZMAX, KPUMIN..KPUMAX, ALPMIN..ALPMAX, CAMMIN..CAMMAX)
when ``CLIP`` (as Adams does); a file without ranges is not clipped.

Conventions (ISO W-axis, as the coefficients expect): x along the wheel heading, y to its left,
z up. Longitudinal slip κ = -V_sx/|V_cx| (positive when driving); slip angle α with
tan α = V_cy/|V_cx| (positive when the wheel moves to its left; the force is then negative);
inclination γ: rotation of the wheel about its x axis (positive: top leaning to the right);
γ* = sin γ. Forces in N, moments in N m, Fz > 0 pressing the tyre on the road. The data are
of a tyre on the file's TYRESIDE; the tyre system mirrors them for the other side.
"""

import dataclasses
import math

from drake_car.law.tyre import formats
from drake_car.law.tyre.plausibility import check_coefficients, check_forces, check_relaxation
from drake_car.law.tyre.property_file import TirFileError
from drake_car.law.tyre.tir import read_tir

# The book form's required coefficients (kept under this name for its callers).
REQUIRED = formats.BOOK_REQUIRED
# Numbers the formula reads besides the coefficients: the form's code, the inflation
# pressure's dpi and p/p0, the shift scalings λμ' (4.E8), Fz0 of the scrub and rolling
# resistance terms, the clip flag and the ranges.
DERIVED = ("FORM", "DPI", "P_RATIO", "LMUX_S", "LMUY_S", "FZ0_S", "CLIP") + formats.RANGES
_NO_RANGE = {"FZMIN": 0.0, "FZMAX": math.inf, "KPUMIN": -math.inf, "KPUMAX": math.inf,
             "ALPMIN": -math.pi / 2, "ALPMAX": math.pi / 2, "CAMMIN": -math.pi / 2,
             "CAMMAX": math.pi / 2}


@dataclasses.dataclass(frozen=True)
class MagicFormulaTyre:
    """One tyre: ``coefficients`` {KEY: value} as read from a .tir file (the book form unless
    ``form`` says otherwise), at inflation pressure ``pressure_Pa`` (MF 6.x; default the
    file's INFLPRES), inputs clipped to the file's ranges when ``clip``. After construction:
    ``defaulted`` (the coefficients the form reads that took defaults), ``side`` (TYRESIDE),
    ``format_note`` (how the form was chosen), ``warnings`` (the plausibility check's findings
    outside the nominal load)."""

    coefficients: dict
    name: str = "<tyre>"
    form: str = formats.BOOK
    pressure_Pa: float | None = None
    clip: bool = True
    side: str = "LEFT"
    format_note: str = ""
    location: object = None  # key -> "file:line" for messages

    def __post_init__(self):
        where = self.location or (lambda key: self.name)
        values, defaulted = formats.effective(self.coefficients, self.form, self.name, where)
        object.__setattr__(self, "defaulted", defaulted)
        for key in ("UNLOADED_RADIUS", "FNOMIN", "LONGVL"):
            if not values[key] > 0:
                raise TirFileError(f"{where(key)}: {key} = {values[key]} must be > 0")
        if not 0.1 <= values["UNLOADED_RADIUS"] <= 2.0:
            raise TirFileError(f"{where('UNLOADED_RADIUS')}: UNLOADED_RADIUS = "
                               f"{values['UNLOADED_RADIUS']} m must lie in [0.1, 2]")
        ranges = {k: values.get(k, _NO_RANGE[k]) for k in formats.RANGES}
        check_coefficients(values, ranges, where)
        for key, value in values.items():  # coefficients as attributes (fast to read)
            object.__setattr__(self, key, value)
        self._derive(values, ranges, where)
        object.__setattr__(self, "warnings", ())
        object.__setattr__(self, "warnings", check_forces(self, magic_formula))
        check_relaxation(self, relaxation_source(self), relaxation_lengths_m, where)

    def _derive(self, values, ranges, where):
        mf6 = self.form in (formats.MF61, formats.MF62)
        fz0_scaled = values["FNOMIN"] * values["LFZO"]
        dpi, p_ratio = 0.0, 1.0
        asked = self.pressure_Pa
        if asked is not None and not mf6:
            raise TirFileError(f"{self.name}: pressure_Pa = {asked:g} has no effect: the file is "
                               f"{self.form}, which has no inflation-pressure terms (MF 6.x has)")
        if asked is not None and not 0 < asked < math.inf:
            raise TirFileError(f"{self.name}: pressure_Pa = {asked:g} must be a finite number > 0")
        if mf6:
            nominal = values.get("NOMPRES")
            pressure = asked if asked is not None else values.get("INFLPRES", nominal)
            if nominal is not None and pressure is not None:
                if not (nominal > 0 and pressure > 0):
                    raise TirFileError(f"{where('NOMPRES')}: NOMPRES and INFLPRES must be > 0")
                dpi, p_ratio = (pressure - nominal) / nominal, pressure / nominal
            elif asked is not None:
                raise TirFileError(f"{self.name}: no NOMPRES; the pressure terms cannot be used")
            low, high = values.get("PRESMIN", 0.0), values.get("PRESMAX", math.inf)
            if asked is not None and not low <= asked <= high:
                raise TirFileError(f"{where('PRESMAX')}: pressure_Pa = {asked:g} lies outside "
                                   f"the file's PRESMIN..PRESMAX = {low:g}..{high:g} Pa")

        def degressive(scale):  # λμ' = Aμ λμ* / (1 + (Aμ - 1) λμ*), Aμ = 10 (4.E8)
            return 10.0 * scale / (1.0 + 9.0 * scale) if mf6 else scale
        derived = {"FORM": formats.FORM_CODE[self.form], "DPI": dpi, "P_RATIO": p_ratio,
                   "LMUX_S": degressive(values["LMUX"]), "LMUY_S": degressive(values["LMUY"]),
                   "FZ0_S": values["FNOMIN"] if mf6 else fz0_scaled,
                   "CLIP": 1.0 if self.clip else 0.0, **ranges}
        for key, value in derived.items():
            object.__setattr__(self, key, float(value))

    @classmethod
    def from_file(cls, path, *, pressure_Pa=None, clip=True):
        tir = read_tir(path)
        form, note = formats.detect(tir)
        side, read_as = tyre_side(tir)
        return cls(tir.coefficients(), str(path), form, pressure_Pa, clip, read_as,
                   note + ("" if side == read_as else f"; TYRESIDE '{side}' read as LEFT"),
                   tir.where)


# TYRESIDE: the side the data were measured on (mirrored for the other). 'UNKNOWN' (files that
# did not record it, e.g. OpenTire's exports; Chrono's ChPac02Tire reads it as LEFT) and
# 'SYMMETRIC' (no side) are read as LEFT; a file without TYRESIDE is LEFT's.
TYRESIDES = {"LEFT": "LEFT", "RIGHT": "RIGHT", "UNKNOWN": "LEFT", "SYMMETRIC": "LEFT"}


def tyre_side(tir):
    """(TYRESIDE as written, upper case; the side it is read as) of a ``PropertyFile``."""
    side = tir.header("TYRESIDE")
    if side is None:
        return "LEFT", "LEFT"
    written = side.strip().upper() if isinstance(side, str) else side
    if written not in TYRESIDES:
        shown = f"'{side}'" if isinstance(side, str) else f"{side:g}"
        raise TirFileError(f"{tir.where('TYRESIDE')}: TYRESIDE = {shown} must be LEFT or RIGHT "
                           "('UNKNOWN' and 'SYMMETRIC', no side, are read as LEFT)")
    return written, TYRESIDES[written]



def _sign(x):
    return 1.0 if x >= 0 else -1.0


def _clip(x, low, high):
    return low if x < low else (high if x > high else x)


def _mf(b, c, d, e, x):
    """D sin(C atan(B x - E (B x - atan(B x))))."""
    bx = b * x
    return d * math.sin(c * math.atan(bx - e * (bx - math.atan(bx))))


def _mf_cos(b, c, d, e, x):
    bx = b * x
    return d * math.cos(c * math.atan(bx - e * (bx - math.atan(bx))))


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


def _lateral(t, fz, dfz, fz0, a, gs, gy):
    """Pure-slip side force at α* = ``a``: (Fy0, Kyα, By, Cy, μy, SHy, SVy) (4.E19-4.E30)."""
    dpi = t.DPI
    if t.FORM == 0.0:
        ky = (t.PKY1 * fz0 * math.sin(t.PKY4 * math.atan(fz / ((t.PKY2 + t.PKY5 * gs * gs)
                                                               * fz0)))
              / (1.0 + t.PKY3 * gs * gs) * t.LKY)
        muy = (t.PDY1 + t.PDY2 * dfz) / (1.0 + t.PDY3 * gs * gs) * t.LMUY
    else:
        ky = (t.PKY1 * fz0 * (1.0 + t.PPY1 * dpi) * (1.0 - t.PKY3 * abs(gy))
              * math.sin(t.PKY4 * math.atan(fz / ((t.PKY2 + t.PKY5 * gy * gy)
                                                  * (1.0 + t.PPY2 * dpi) * fz0))) * t.LKY)
        muy = ((t.PDY1 + t.PDY2 * dfz) * (1.0 + t.PPY3 * dpi + t.PPY4 * dpi * dpi)
               * (1.0 - t.PDY3 * gy * gy) * t.LMUY)
    svyg = fz * (t.PVY3 + t.PVY4 * dfz) * gy * t.LKYC * t.LMUY_S
    svy = fz * (t.PVY1 + t.PVY2 * dfz) * t.LVY * t.LMUY_S + svyg
    shy = (t.PHY1 + t.PHY2 * dfz) * t.LHY
    if t.FORM == 1.0:
        shy += t.PHY3 * gy
    else:
        kyg = fz * (t.PKY6 + t.PKY7 * dfz) * (1.0 + t.PPY5 * dpi) * t.LKYC
        shy += (kyg * gs - svyg) / ky if ky != 0 else 0.0
    ay = a + shy
    cy = t.PCY1 * t.LCY
    dy = muy * fz
    ey = min(1.0, (t.PEY1 + t.PEY2 * dfz)
             * (1.0 + t.PEY5 * gy * gy - (t.PEY3 + t.PEY4 * gy) * _sign(ay)) * t.LEY)
    by = ky / (cy * dy) if cy * dy != 0 else 0.0
    return _mf(by, cy, dy, ey, ay) + svy, ky, by, cy, muy, shy, svy


def _rolling(t, fz, fx, gamma, vx):
    """Rolling resistance moment My (4.E70), opposing the rolling direction."""
    v = vx / t.LONGVL
    bracket = t.QSY1 + t.QSY2 * fx / t.FZ0_S + t.QSY3 * abs(v) + t.QSY4 * v ** 4
    if t.FORM == 2.0:
        ratio = fz / t.FNOMIN
        my = (-t.UNLOADED_RADIUS * t.FNOMIN * t.LMY
              * (bracket + (t.QSY5 + t.QSY6 * ratio) * gamma * gamma)
              * ratio ** t.QSY7 * t.P_RATIO ** t.QSY8)
    else:
        my = -t.UNLOADED_RADIUS * fz * bracket * t.LMY
    return my * math.tanh(vx / 0.1)  # smooth sign through standstill


def magic_formula(t: MagicFormulaTyre, fz, kappa, alpha, gamma, vx, combined=True):
    """Steady-state tyre forces for vertical load ``fz`` (N), longitudinal slip ``kappa``,
    slip angle ``alpha`` (rad), inclination ``gamma`` (rad), forward speed ``vx`` (m/s, for
    rolling resistance only). ``combined=False`` drops the combined-slip weighting.
    ``cornering_stiffness`` is Kyα (negative in the ISO convention: Fy ≈ Kyα·α)."""
    if t.CLIP != 0.0:
        fz = min(fz, t.FZMAX)
        kappa = _clip(kappa, t.KPUMIN, t.KPUMAX)
        alpha = _clip(alpha, t.ALPMIN, t.ALPMAX)
        gamma = _clip(gamma, t.CAMMIN, t.CAMMAX)
    if fz <= 0.0:
        return TyreForces(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    fz0 = t.FNOMIN * t.LFZO
    dfz = (fz - fz0) / fz0
    r0 = t.UNLOADED_RADIUS
    dpi = t.DPI
    form = t.FORM
    gs = math.sin(gamma)  # γ*
    a = alpha if form == 0.0 else math.tan(alpha)  # α* (4.E3)
    if form == 1.0:
        gx, gy, gz = gs * t.LGAX, gs * t.LGAY, gs * t.LGAZ
    else:
        gx, gy, gz = (gamma if form == 0.0 else gs), gs, gs

    # Longitudinal, pure slip (4.E9-4.E18).
    shx = (t.PHX1 + t.PHX2 * dfz) * t.LHX
    kx_ = kappa + shx
    cx = t.PCX1 * t.LCX
    mux = ((t.PDX1 + t.PDX2 * dfz) * (1.0 + t.PPX3 * dpi + t.PPX4 * dpi * dpi)
           * (1.0 - t.PDX3 * gx * gx) * t.LMUX)
    dx = mux * fz
    ex = min(1.0, (t.PEX1 + t.PEX2 * dfz + t.PEX3 * dfz * dfz)
             * (1.0 - t.PEX4 * _sign(kx_)) * t.LEX)
    kx = (fz * (t.PKX1 + t.PKX2 * dfz) * math.exp(t.PKX3 * dfz)
          * (1.0 + t.PPX1 * dpi + t.PPX2 * dpi * dpi) * t.LKX)
    bx = kx / (cx * dx) if cx * dx != 0 else 0.0
    svx = fz * (t.PVX1 + t.PVX2 * dfz) * t.LVX * t.LMUX_S
    fx0 = _mf(bx, cx, dx, ex, kx_) + svx

    # Lateral, pure slip (4.E19-4.E30).
    fy0, ky, by, cy, muy, shy, svy = _lateral(t, fz, dfz, fz0, a, gs, gy)
    # MF 6.x's aligning moment takes the side force without camber (4.E74).
    fy0_trail = _lateral(t, fz, dfz, fz0, a, 0.0, 0.0)[0] if form == 2.0 else fy0

    # Aligning moment, pure slip (4.E31-4.E49).
    sht = t.QHZ1 + t.QHZ2 * dfz + (t.QHZ3 + t.QHZ4 * dfz) * gz
    bt = ((t.QBZ1 + t.QBZ2 * dfz + t.QBZ3 * dfz * dfz)
          * (1.0 + t.QBZ4 * gz + t.QBZ5 * abs(gz) + t.QBZ6 * gz * gz) * t.LKY / t.LMUY)
    ct = t.QCZ1
    dt = (fz * (t.QDZ1 + t.QDZ2 * dfz) * (1.0 - t.PPZ1 * dpi)
          * (1.0 + t.QDZ3 * (abs(gz) if form == 0.0 else gz) + t.QDZ4 * gz * gz)
          * (r0 / fz0) * t.LTR)
    at = a + sht
    et = min(1.0, (t.QEZ1 + t.QEZ2 * dfz + t.QEZ3 * dfz * dfz)
             * (1.0 + (t.QEZ4 + t.QEZ5 * gz) * (2.0 / math.pi) * math.atan(bt * ct * at)))
    shf = shy + (svy / ky if ky != 0 else 0.0)
    ar = a + shf
    br = t.QBZ9 * t.LKY / t.LMUY + t.QBZ10 * by * cy
    cos_a = math.cos(alpha)  # cos'α = V_cx/V_c
    dr = (fz * r0 * ((t.QDZ6 + t.QDZ7 * dfz) * t.LRES
                     + ((t.QDZ8 + t.QDZ9 * dfz) * (1.0 + t.PPZ2 * dpi)
                        + (t.QDZ10 + t.QDZ11 * dfz) * abs(gz)) * gz * t.LKZC)
          * t.LMUY * cos_a)

    if combined:
        # Combined slip (4.E50-4.E67).
        bxa = (t.RBX1 + t.RBX3 * gs * gs) * math.cos(math.atan(t.RBX2 * kappa)) * t.LXAL
        exa = min(1.0, t.REX1 + t.REX2 * dfz)
        fx = _weight(bxa, t.RCX1, exa, a, t.RHX1) * fx0
        shyk = t.RHY1 + t.RHY2 * dfz
        byk = ((t.RBY1 + t.RBY4 * gs * gs) * math.cos(math.atan(t.RBY2 * (a - t.RBY3)))
               * t.LYKA)
        eyk = min(1.0, t.REY1 + t.REY2 * dfz)
        dvyk = (muy * fz * (t.RVY1 + t.RVY2 * dfz + t.RVY3 * gy)
                * math.cos(math.atan(t.RVY4 * a)))
        svyk = dvyk * math.sin(t.RVY5 * math.atan(t.RVY6 * kappa)) * t.LVYKA
        gyk = _weight(byk, t.RCY1, eyk, kappa, shyk)
        fy = gyk * fy0 + svyk
        ratio = (kx / ky) if ky != 0 else 0.0
        if form == 0.0:  # the book's 4.E77-4.E78
            at_eq = math.sqrt(at * at + (ratio * kappa) ** 2) * _sign(at)
            ar_eq = math.sqrt(ar * ar + (ratio * kappa) ** 2) * _sign(ar)
        else:  # the TNO solver's (Besselink et al. 2010, A54)
            at_eq = math.atan(math.sqrt(math.tan(at) ** 2 + (ratio * kappa) ** 2)) * _sign(at)
            ar_eq = math.atan(math.sqrt(math.tan(ar) ** 2 + (ratio * kappa) ** 2)) * _sign(ar)
        trail = _mf_cos(bt, ct, dt, et, at_eq) * cos_a
        mzr = dr * math.cos(math.atan(br * ar_eq))
        s = (t.SSZ1 + t.SSZ2 * (fy / t.FZ0_S) + (t.SSZ3 + t.SSZ4 * dfz) * gz) * r0 * t.LS
        mz = -trail * gyk * fy0_trail + mzr + s * fx
    else:
        fx, fy = fx0, fy0
        trail = _mf_cos(bt, ct, dt, et, at) * cos_a
        mz = -trail * fy0_trail + dr * math.cos(math.atan(br * ar))
    my = _rolling(t, fz, fx, gamma, vx)
    return TyreForces(fx, fy, mz, my, fx0, fy0, ky, kx, trail)


def linear_tyre(t: MagicFormulaTyre, fz, kappa, alpha, gamma, vx):
    """The same tyre linearised in the slips about zero slip, at this load and camber (the
    "linear tyre" of handling analyses): Fx = Fx(0) + Kx κ, Fy = Fy(0) + Ky α,
    Mz = Mz(0) - t0 Ky α, with Kx, Ky and the pneumatic trail t0 the Magic Formula's at zero
    slip (so it agrees with ``magic_formula`` to first order in κ and α) and My its rolling
    resistance at this Fx; no saturation, no combined-slip interaction. Fy(0), Mz(0) are the
    data's offsets (ply-steer, conicity, camber thrust)."""
    if t.CLIP != 0.0:
        fz = min(fz, t.FZMAX)
        gamma = _clip(gamma, t.CAMMIN, t.CAMMAX)
    f = magic_formula(t, fz, 0.0, 0.0, gamma, vx, combined=False)
    fx = f.fx + f.slip_stiffness * kappa
    fy = f.fy + f.cornering_stiffness * alpha
    my = _rolling(t, fz, fx, gamma, vx) if fz > 0.0 else 0.0
    mz = f.mz - f.pneumatic_trail * f.cornering_stiffness * alpha
    return TyreForces(fx, fy, mz, my, fx, fy, f.cornering_stiffness, f.slip_stiffness,
                      f.pneumatic_trail)


def relaxation_lengths_m(tyre, fz):
    """The file's own relaxation lengths (σκ, σα) in m at load ``fz``, zero slip and camber,
    or None when the file has none (``relaxation_source`` says which).

    PAC2002, from PTX*, PTY*: σκ = Fz (PTX1 + PTX2 dfz) exp(-PTX3 dfz) R0/Fz0 LSGKP,
    σα = PTY1 sin(2 atan(Fz / (PTY2 Fz0'))) R0 LFZO LSGAL (the forms of OpenTirePython's
    PAC2002, MIT; not checked against the MSC Adams manual).

    MF 6.1/6.2, which have no PTX*/PTY*, from the carcass stiffnesses: σκ = |Kxκ| / Cx,
    σα = |Kyα| / Cy with Cx = LONGITUDINAL_STIFFNESS (1 + PCFX1 dfz + PCFX2 dfz²)
    (1 + PCFX3 dpi), Cy = LATERAL_STIFFNESS (1 + PCFY1 dfz + PCFY2 dfz²)(1 + PCFY3 dpi) and
    Kxκ, Kyα this Magic Formula's slip and cornering stiffness at the same load and pressure
    (MF-Tyre 6.1's transient model; Pacejka and Besselink, 3rd ed. 2012, appendix 3, eqs.
    A3.9-A3.10 as TyreDyn's relaxation and stiffness modules cite them; not checked against
    the book's page). PCF* a file omits count as 0."""
    source = relaxation_source(tyre)
    if source is None:
        return None
    fz0 = tyre.FNOMIN * tyre.LFZO
    dfz = (fz - fz0) / fz0
    if source == "carcass":
        f = magic_formula(tyre, fz, 0.0, 0.0, 0.0, tyre.LONGVL, combined=False)
        def carcass(key, axis):
            p1, p2, p3 = (getattr(tyre, f"PCF{axis}{i}", 0.0) for i in (1, 2, 3))
            return getattr(tyre, key) * (1.0 + p1 * dfz + p2 * dfz * dfz) * (1.0 + p3 * tyre.DPI)
        c_x, c_y = carcass("LONGITUDINAL_STIFFNESS", "X"), carcass("LATERAL_STIFFNESS", "Y")
        return abs(f.slip_stiffness) / c_x, abs(f.cornering_stiffness) / c_y
    r0 = tyre.UNLOADED_RADIUS
    sigma_kappa = (fz * (tyre.PTX1 + tyre.PTX2 * dfz) * math.exp(-tyre.PTX3 * dfz)
                   * (r0 / tyre.FNOMIN) * tyre.LSGKP)
    sigma_alpha = (tyre.PTY1 * math.sin(2.0 * math.atan(fz / (tyre.PTY2 * fz0))) * r0
                   * tyre.LFZO * tyre.LSGAL)
    return sigma_kappa, sigma_alpha


def relaxation_source(tyre):
    """Where a tyre's relaxation lengths come from: "PTX/PTY" (PAC2002 with PTX1 or PTY1),
    "carcass" (MF 6.x giving LONGITUDINAL_STIFFNESS and LATERAL_STIFFNESS), or None."""
    if tyre.form == formats.PAC2002:
        return "PTX/PTY" if (tyre.PTX1 or tyre.PTY1) else None
    if tyre.form in (formats.MF61, formats.MF62):
        if hasattr(tyre, "LONGITUDINAL_STIFFNESS") and hasattr(tyre, "LATERAL_STIFFNESS"):
            return "carcass"  # given: their values are checked (``check_relaxation``)
    return None
