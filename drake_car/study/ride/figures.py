"""The ride study's figures: comfort, wheel load and sticking against μs per road class and
speed (error bars: the numerical error, each run against its half-step twin); the seat's
vertical acceleration PSD with and without friction."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from drake_car.law.comfort.iso2631 import wk_response  # noqa: E402

PANELS = (("aw_seat_mps2", "Wk-weighted RMS vertical acc. at the seat [m/s²]"),
          ("dlc_front", "dynamic wheel-load coefficient, front"),
          ("dlc_rear", "dynamic wheel-load coefficient, rear"),
          ("stick", "share of time the rods stick (mean L/R)"))


def plot_against_mu(rows, path, title):
    """``rows``: dicts with road_class, speed_kph, mu_s, the outcomes and their ``err_*``."""
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    cells = sorted({(r["road_class"], r["speed_kph"]) for r in rows})
    for ax, (key, label) in zip(axes.flat, PANELS):
        for road_class, speed in cells:
            sel = sorted((r for r in rows if (r["road_class"], r["speed_kph"])
                          == (road_class, speed)), key=lambda r: r["mu_s"])
            mu = [r["mu_s"] for r in sel]
            if key == "stick":
                y = [0.5 * (r["stick_left"] + r["stick_right"]) for r in sel]
                e = [0.5 * (r["err_stick_left"] + r["err_stick_right"]) for r in sel]
            else:
                y = [r[key] for r in sel]
                e = [r[f"err_{key}"] for r in sel]
            ax.errorbar(mu, y, yerr=e, marker="o", ms=4, capsize=3,
                        ls="-" if speed < 80 else "--", label=f"class {road_class}, {speed:g} km/h")
        ax.set_xlabel("μs (μd = 0.75 μs; 0: lubricated, the car's damper)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes.flat[0].legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_psd(curves, path, title):
    """``curves``: list of (label, f (Hz), PSD ((m/s²)²/Hz)); Wk² drawn on a second axis."""
    fig, ax = plt.subplots(figsize=(8, 5))
    for label, f, p in curves:
        keep = (f >= 0.3) & (f <= 100)
        ax.loglog(f[keep], p[keep], lw=1.0, label=label)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("PSD of the seat's vertical acceleration [(m/s²)²/Hz]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="lower left")
    twin = ax.twinx()
    f = np.logspace(np.log10(0.3), 2, 200)
    twin.semilogx(f, np.abs(wk_response(f)), "k:", lw=0.8)
    twin.set_ylabel("|Wk| (dotted)")
    twin.set_ylim(0, 1.2)
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
