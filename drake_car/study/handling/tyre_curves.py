"""A tyre's steady-state curves, the figures an engineer looks at first, and a summary, from
its Magic Formula (``law.tyre.magic_formula``) as the property file's format defines it;
``write`` puts them in a folder (the tyre command's, the handling study's ``tyre/``).

Signs ISO-W (the .tir's own axes: Fx > 0 driving, Fy < 0 for α > 0 with PKY1 < 0, Mz about the
upward z), the tyre as the file holds it (its TYRESIDE, unmirrored), speed LONGVL, inputs inside
the file's ranges (KPUMIN..KPUMAX, ALPMIN..ALPMAX, CAMMIN..CAMMAX; loads 0.5, 1, 1.5 and 2
FNOMIN limited to FZMIN..FZMAX).
"""

import math

import matplotlib
import numpy as np

from drake_car.law.tyre.magic_formula import (
    magic_formula,
    relaxation_lengths_m,
    relaxation_source,
)
from drake_car.results.files import write_csv, write_text

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLUMNS = ("fz_N", "kappa", "alpha_rad", "gamma_rad", "fx_N", "fy_N", "mz_Nm")
CAMBER_RAD = math.radians(3.0)


def loads_N(tyre):
    loads = [min(max(r * tyre.FNOMIN, tyre.FZMIN), tyre.FZMAX) for r in (0.5, 1.0, 1.5, 2.0)]
    return sorted(set(loads))


def _range(low, high, limit, n):
    return np.linspace(max(low, -limit), min(high, limit), n)


def _slips(tyre):
    """The sweeps' κ (±0.3) and α (±15°), inside the file's ranges."""
    return (_range(tyre.KPUMIN, tyre.KPUMAX, 0.3, 121),
            _range(tyre.ALPMIN, tyre.ALPMAX, math.radians(15.0), 121))


def peak_mu(tyre, fz):
    """(μx, μy) at load ``fz``: max |Fx|/Fz of the pure longitudinal sweep and max |Fy|/Fz of
    the pure lateral sweep, zero camber (the curves' sweeps)."""
    kappas, alphas = _slips(tyre)
    mux = max(abs(magic_formula(tyre, fz, k, 0.0, 0.0, tyre.LONGVL).fx) for k in kappas)
    muy = max(abs(magic_formula(tyre, fz, 0.0, a, 0.0, tyre.LONGVL).fy) for a in alphas)
    return mux / fz, muy / fz


def curves(tyre):
    """{"case": [...], COLUMNS...}: pure slip (``pure_long``, ``pure_lat``; ``lat_camber`` at
    γ = 3° or the file's CAMMAX) at every load, and ``combined`` (κ swept at α = 2, 5, 8°) at
    every load."""
    rows = []
    kappas, alphas = _slips(tyre)
    camber = min(CAMBER_RAD, tyre.CAMMAX)
    for fz in loads_N(tyre):
        sweeps = [("pure_long", k, 0.0, 0.0) for k in kappas]
        sweeps += [("pure_lat", 0.0, a, 0.0) for a in alphas]
        sweeps += [("lat_camber", 0.0, a, camber) for a in alphas]
        sweeps += [("combined", k, a, 0.0) for a in np.radians([2.0, 5.0, 8.0])
                   if tyre.ALPMIN <= a <= tyre.ALPMAX for k in kappas]
        for case, kappa, alpha, gamma in sweeps:
            f = magic_formula(tyre, fz, kappa, alpha, gamma, tyre.LONGVL)
            rows.append((case, fz, kappa, alpha, gamma, f.fx, f.fy, f.mz))
    table = {"case": [r[0] for r in rows]}
    for i, name in enumerate(COLUMNS, start=1):
        table[name] = np.array([r[i] for r in rows])
    return table


def stiffness_against_load(tyre, n=40):
    """(loads, Kx, Kyα) at zero slip and camber over the file's load range."""
    top = tyre.FZMAX if math.isfinite(tyre.FZMAX) else 2.0 * tyre.FNOMIN
    loads = np.linspace(max(tyre.FZMIN, 0.05 * tyre.FNOMIN), top, n)
    forces = [magic_formula(tyre, fz, 0.0, 0.0, 0.0, tyre.LONGVL) for fz in loads]
    return (loads, np.array([f.slip_stiffness for f in forces]),
            np.array([f.cornering_stiffness for f in forces]))


def summary(tyre):
    """The summary's text: format read, peak μ, stiffnesses at FNOMIN, defaults, warnings."""
    lines = [f"tyre property file: {tyre.name}",
             f"format: {tyre.form} ({tyre.format_note}); TYRESIDE {tyre.side} (curves as the "
             "file holds them, unmirrored)",
             f"FNOMIN {tyre.FNOMIN:g} N, UNLOADED_RADIUS {tyre.UNLOADED_RADIUS:g} m, LONGVL "
             f"{tyre.LONGVL:g} m/s; ranges Fz {tyre.FZMIN:g}..{tyre.FZMAX:g} N, kappa "
             f"{tyre.KPUMIN:g}..{tyre.KPUMAX:g}, alpha {tyre.ALPMIN:g}..{tyre.ALPMAX:g} rad, "
             f"gamma {tyre.CAMMIN:g}..{tyre.CAMMAX:g} rad"]
    if tyre.form in ("MF 6.1", "MF 6.2"):
        lines.append(f"inflation pressure: {tyre.P_RATIO:g} x NOMPRES (dpi = {tyre.DPI:g})")
    lines.append("peak friction (max |F|/Fz in the pure sweeps):")
    for fz in loads_N(tyre):
        mux, muy = peak_mu(tyre, fz)
        lines.append(f"  Fz = {fz:7.0f} N: mu_x {mux:.3f}, mu_y {muy:.3f}")
    f = magic_formula(tyre, tyre.FNOMIN, 0.0, 0.0, 0.0, tyre.LONGVL)
    lines.append(f"at FNOMIN: slip stiffness Kx {f.slip_stiffness:.4g} N "
                 f"({f.slip_stiffness / tyre.FNOMIN:.2f} Fz), cornering stiffness Kya "
                 f"{f.cornering_stiffness:.4g} N/rad ({f.cornering_stiffness / tyre.FNOMIN:.2f}"
                 f" Fz), pneumatic trail {f.pneumatic_trail * 1e3:.1f} mm")
    sigma = relaxation_lengths_m(tyre, tyre.FNOMIN)
    if sigma:
        source = {"PTX/PTY": "PTX*/PTY*", "carcass": "the carcass stiffnesses (Kx/Cx, "
                  "|Kya|/Cy: LONGITUDINAL_STIFFNESS, LATERAL_STIFFNESS, PCFX*, PCFY*)"}
        lines.append(f"relaxation lengths at FNOMIN from {source[relaxation_source(tyre)]}: "
                     f"sigma_kappa {sigma[0]:.3f} m, sigma_alpha {sigma[1]:.3f} m (the car uses "
                     "them with tyres.slip.relaxation_lengths_from_file, at its wheel load at "
                     "rest)")
    else:
        lines.append("relaxation lengths: none in the file (the car uses tyres.slip's)")
    lines.append("coefficients defaulted (absent from the file; 0, scaling factors 1, PKY4 2, "
                 f"QSY7 1): {', '.join(tyre.defaulted) if tyre.defaulted else 'none'}")
    if tyre.RBX1 == 0.0 or tyre.RBY1 == 0.0:
        lines.append("note: RBX1 or RBY1 is 0 (the file has no combined-slip fit): Fx and Fy "
                     "do not weaken each other in combined slip")
    for warning in tyre.warnings:
        lines.append(f"warning: {warning}")
    return "\n".join(lines) + "\n"


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def figures(tyre, table, out):
    """Fy-α, Mz-α, Fx-κ at the loads, the friction ellipse at FNOMIN, the stiffnesses against
    load: PNG files in ``out``; returns their names."""
    case = np.array(table["case"])
    loads = loads_N(tyre)
    plots = (("fy_alpha.png", "pure_lat", "alpha_rad", "fy_N", "slip angle α (deg)", "Fy (N)"),
             ("mz_alpha.png", "pure_lat", "alpha_rad", "mz_Nm", "slip angle α (deg)",
              "Mz (N m)"),
             ("fx_kappa.png", "pure_long", "kappa", "fx_N", "longitudinal slip κ", "Fx (N)"))
    for name, kind, x, y, xlabel, ylabel in plots:
        fig, ax = plt.subplots(figsize=(6, 4))
        for i, fz in enumerate(loads):
            color = f"C{i}"
            for sweep, style in ((kind, "-"), ("lat_camber", "--")):
                if sweep == "lat_camber" and kind != "pure_lat":
                    continue
                sel = (case == sweep) & (table["fz_N"] == fz)
                xs = np.degrees(table[x][sel]) if x == "alpha_rad" else table[x][sel]
                label = f"Fz {fz:.0f} N" + (f", γ {math.degrees(table['gamma_rad'][sel][0]):.0f}°"
                                            if sweep == "lat_camber" else "")
                ax.plot(xs, table[y][sel], style, color=color, label=label)
        ax.set(xlabel=xlabel, ylabel=ylabel, title=f"{tyre.form}: {name[:-4]} (ISO-W)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
        _save(fig, out / name)
    fig, ax = plt.subplots(figsize=(5, 5))
    nominal = min(loads, key=lambda fz: abs(fz - tyre.FNOMIN))
    for i, alpha in enumerate(sorted(set(table["alpha_rad"][case == "combined"]))):
        sel = (case == "combined") & (table["fz_N"] == nominal) & (table["alpha_rad"] == alpha)
        ax.plot(table["fy_N"][sel] / 1e3, table["fx_N"][sel] / 1e3, color=f"C{i}",
                label=f"α {math.degrees(alpha):.0f}°, κ swept")
    ax.set(xlabel="Fy (kN)", ylabel="Fx (kN)", title=f"combined slip at Fz {nominal:.0f} N")
    ax.axis("equal")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    _save(fig, out / "friction_ellipse.png")
    loads_, kx, ky = stiffness_against_load(tyre)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(loads_, kx / 1e3, label="slip stiffness Kx (kN)")
    ax.plot(loads_, -ky / 1e3, label="cornering stiffness -Kyα (kN/rad)")
    ax.axvline(tyre.FNOMIN, color="0.5", ls=":", label="FNOMIN")
    ax.set(xlabel="Fz (N)", ylabel="stiffness", title="stiffness against load (zero slip)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    _save(fig, out / "stiffness_load.png")
    return ["fy_alpha.png", "mz_alpha.png", "fx_kappa.png", "friction_ellipse.png",
            "stiffness_load.png"]


def write(tyre, out):
    """``curves.csv``, ``summary.txt`` and the figures of ``tyre`` into the folder ``out`` (the
    tyre command's files; the handling study's ``tyre/``). Returns (summary text, figure
    names)."""
    table = curves(tyre)
    text = summary(tyre)
    write_csv(out / "curves.csv", table)
    write_text(out / "summary.txt", text)
    return text, figures(tyre, table, out)
