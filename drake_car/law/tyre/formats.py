"""Which Magic Formula a property file asks for, and the coefficients each form reads.

Forms (``FORMS``): the book's 2006 form (``PROPERTY_FILE_FORMAT = 'MF_2006_BOOK'``, the file
drake_car ships; H. B. Pacejka, *Tyre and Vehicle Dynamics*, 2nd ed. 2006, 4.E1-4.E71);
PAC2002 (MF 5.2 as MSC Adams/Tire names it: ``PROPERTY_FILE_FORMAT = 'PAC2002'``, or ``FITTYP``
6 or 21); MF 6.1 and MF 6.2 (``FITTYP`` 61, 62; the TNO MF-Tyre 6.x force and moment equations,
Pacejka and Besselink, *Tire and Vehicle Dynamics*, 3rd ed. 2012, 4.E1-4.E78, with the
inflation-pressure terms PPX*, PPY*, PPZ*, QSY7/QSY8). MF 6.1 and 6.2 share the steady-state
force and moment equations drake_car evaluates (6.2 differs in the loaded radius and vertical
stiffness model, which drake_car does not take from the file).

A coefficient a form reads and the file does not give takes the form's default (0, scaling
factors 1, PKY4 = 2 and QSY7 = 1, which reduce MF 6.x's lateral stiffness and rolling
resistance to PAC2002's), and is listed as defaulted. A coefficient the form does not read is
set to the value that removes its term (so one formula, ``magic_formula``, serves all forms).
"""

from drake_car.law.tyre.property_file import TirFileError

BOOK, PAC2002, MF61, MF62 = "MF_2006_BOOK", "PAC2002", "MF 6.1", "MF 6.2"
FORMS = (BOOK, PAC2002, MF61, MF62)
# The code of each form in the packed coefficients (``FORM``): the formula branches on it.
FORM_CODE = {BOOK: 0.0, PAC2002: 1.0, MF61: 2.0, MF62: 2.0}
SUPPORTED = ("PAC2002 (PROPERTY_FILE_FORMAT 'PAC2002' or FITTYP 6, 21), MF 6.1 (FITTYP 61), "
             "MF 6.2 (FITTYP 62), MF_2006_BOOK")


def _names(text):
    out = []
    for word in text.split():
        if "-" in word:  # PDX1-3 -> PDX1 PDX2 PDX3
            stem, last = word.split("-")
            first = int("".join(c for c in stem if c.isdigit()))
            base = stem.rstrip("0123456789")
            out += [f"{base}{i}" for i in range(first, int(last) + 1)]
        else:
            out.append(word)
    return tuple(out)


_COMMON = _names(
    "PCX1 PDX1-3 PEX1-4 PKX1-3 PHX1-2 PVX1-2 RBX1-2 RCX1 REX1-2 RHX1 "
    "PCY1 PDY1-3 PEY1-4 PKY1-3 PHY1-2 PVY1-4 RBY1-3 RCY1 REY1-2 RHY1-2 RVY1-6 "
    "QBZ1-3 QBZ5 QBZ9 QBZ10 QCZ1 QDZ1-4 QDZ6-9 QEZ1-5 QHZ1-4 SSZ1-4 QSY1-4")
_SCALING_COMMON = _names("LFZO LCX LMUX LEX LKX LHX LVX LCY LMUY LEY LKY LHY LVY LTR LRES "
                         "LXAL LYKA LVYKA LS LMY")
# What each form reads beyond the common set (coefficients, then scaling factors).
_EXTRA = {
    BOOK: (_names("PHY3 PKY4-7 PEY5 RBX3 RBY4 QBZ6 QDZ10 QDZ11"), _names("LKYC LKZC")),
    PAC2002: (_names("PHY3 QBZ4 PTX1-3 PTY1-2"), _names("LGAX LGAY LGAZ LSGKP LSGAL")),
    MF61: (_names("PKY4-7 PEY5 RBX3 RBY4 QBZ4 QDZ10 QDZ11 PPX1-4 PPY1-5 PPZ1-2 QSY5-8"),
           _names("LKYC LKZC")),
}
_EXTRA[MF62] = _EXTRA[MF61]
# Every coefficient the formula reads, in any form.
ALL = tuple(dict.fromkeys(_COMMON + sum((c for c, _ in _EXTRA.values()), ())))
ALL_SCALING = tuple(dict.fromkeys(_SCALING_COMMON + sum((s for _, s in _EXTRA.values()), ())))
_DEFAULT = {"PKY4": 2.0, "QSY7": 1.0}
# Given by every file (no default).
BASIC = ("UNLOADED_RADIUS", "FNOMIN", "LONGVL")
# The book form requires its Table A3.1 coefficients (drake_car's own file gives them all).
BOOK_REQUIRED = BASIC + tuple(k for k in _COMMON + ("PHY3",) if k not in ("PKY4",))
# The validity ranges of a file ([..._RANGE] sections) and the inflation pressure.
RANGES = ("FZMIN", "FZMAX", "KPUMIN", "KPUMAX", "ALPMIN", "ALPMAX", "CAMMIN", "CAMMAX")
# MF 6.x's carcass stiffnesses (N/m) and their load and pressure terms: its relaxation lengths
# (``magic_formula.relaxation_lengths_m``); kept when the file gives them.
CARCASS = ("LONGITUDINAL_STIFFNESS", "LATERAL_STIFFNESS") + _names("PCFX1-3 PCFY1-3")
# The vertical spring and damper (MF 6.x: the stiffness's pressure term PFZ1), kept when given
# (``contact.vertical_from_file``).
VERTICAL = ("VERTICAL_STIFFNESS", "VERTICAL_DAMPING", "PFZ1")
# Named formats drake_car does not evaluate, refused by name.
_FORMAT_NAMES = {"PAC2002": PAC2002, "MF_2006_BOOK": BOOK, "MF_61": MF61, "MF61": MF61,
                 "MF6.1": MF61, "MF_62": MF62, "MF62": MF62, "MF6.2": MF62}
_FITTYP = {6: PAC2002, 21: PAC2002, 61: MF61, 62: MF62}


def detect(tir):
    """The form a ``PropertyFile`` asks for, and a note saying how it was chosen."""
    written = tir.header("PROPERTY_FILE_FORMAT")
    fittyp = tir.coefficients().get("FITTYP")
    name = written.strip().upper() if isinstance(written, str) else None
    if name in _FORMAT_NAMES:
        note = f"PROPERTY_FILE_FORMAT '{written}'"
        if fittyp is not None:
            note += f" (FITTYP {fittyp:g} not used: the format is named)"
        return _FORMAT_NAMES[name], note
    if name not in (None, "USER", ""):
        raise TirFileError(f"{tir.name}: PROPERTY_FILE_FORMAT '{written}' is a tyre model "
                           f"drake_car does not implement; it reads {SUPPORTED}")
    if fittyp is None:
        raise TirFileError(f"{tir.name}: neither PROPERTY_FILE_FORMAT nor FITTYP says which "
                           f"Magic Formula the file holds; drake_car reads {SUPPORTED}")
    form = _FITTYP.get(int(fittyp)) if fittyp == int(fittyp) else None
    if form is None:
        raise TirFileError(f"{tir.where('FITTYP')}: FITTYP = {fittyp:g} is a Magic Formula "
                           f"version drake_car does not implement; it reads {SUPPORTED}")
    return form, f"FITTYP {fittyp:g}" + (f" (PROPERTY_FILE_FORMAT '{written}')" if written else "")


def effective(values, form, name, where):
    """(coefficients {KEY: float} for the formula in ``form``, the keys that took defaults).
    ``values``: the file's {KEY: value}; ``where(key)``: "file:line" for messages."""
    required = BOOK_REQUIRED if form == BOOK else BASIC
    missing = [k for k in required if k not in values]
    if missing:
        raise TirFileError(f"{name}: missing Magic Formula coefficients {missing}")
    reads, scalings = _EXTRA[form]
    reads, scalings = set(_COMMON + reads), set(_SCALING_COMMON + scalings)
    out, defaulted = {}, []
    for key in ALL + ALL_SCALING:
        neutral = 1.0 if key in ALL_SCALING else _DEFAULT.get(key, 0.0)
        if key in reads or key in scalings:
            if key not in values:
                if not (form == BOOK and key in scalings):
                    defaulted.append(key)
                out[key] = neutral
            else:
                out[key] = values[key]
        else:
            out[key] = 2.0 if key == "PKY4" else (1.0 if key in ALL_SCALING else
                                                 (1.0 if key == "QSY7" else 0.0))
    for key in BASIC + RANGES + CARCASS + VERTICAL + ("INFLPRES", "NOMPRES", "PRESMIN",
                                                       "PRESMAX", "LMUV"):
        if key in values:
            out[key] = values[key]
    for key, value in out.items():
        if isinstance(value, str):
            raise TirFileError(f"{where(key)}: {key} = {value!r} must be a number")
        out[key] = float(value)
    if out.get("LMUV", 0.0) != 0.0:
        raise TirFileError(f"{where('LMUV')}: LMUV = {out['LMUV']:g} (friction decaying with slip "
                           "speed) is not implemented; drake_car reads LMUV = 0 only")
    return out, tuple(defaulted)
