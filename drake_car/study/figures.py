"""Figures of the paper's study (Figs. 13-16 and the wheel loads), from run histories."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from drake_car.study.paper import places, run_of  # noqa: E402

CURVE_STYLE = {1: dict(color="tab:blue"), 2: dict(color="tab:orange"),
               3: dict(color="tab:green")}


def _phases(ax, timeline):
    t2, t3, t4, end = timeline.boundaries()
    for x in (t2, t3, t4):
        ax.axvline(x, color="k", lw=0.6, ls=":")
    top = ax.get_ylim()[1]
    for name, (a, b) in zip(("I", "II", "III", "IV"), ((0, t2), (t2, t3), (t3, t4), (t4, end))):
        ax.text(0.5 * (a + b), top, name, ha="center", va="bottom", fontsize=9)


def fig13(study, timeline, path):
    fig, ax = plt.subplots(figsize=(8, 3.8))
    for case, style in (("a", "-"), ("b", "--")):
        h = run_of(study, case, 1).columns
        ax.plot(h["t"], 1e3 * h["rack_m"], style, label=f"case {case}")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("rack displacement [mm] (left +)")
    ax.grid(alpha=0.3)
    ax.legend()
    _phases(ax, timeline)
    ax.set_title("Fig. 13: steering rack (Akima spline)", pad=16)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def fig_dd(study, timeline, case, side, path, title):
    fig, ax = plt.subplots(figsize=(9, 4.2))
    for number in (1, 2, 3):
        run = run_of(study, case, number)
        h = run.columns
        ax.plot(h["t"], 1e3 * h[f"dd_{side}_m"], label=run.friction.label,
                **CURVE_STYLE[number])
        ia, ib = places(h, timeline)
        for index, label in ((ia, "a"), (ib, "b")):
            ax.plot(h["t"][index], 1e3 * h[f"dd_{side}_m"][index], "o",
                    color=CURVE_STYLE[number]["color"], ms=4)
            if number == 3:
                ax.annotate(label, (h["t"][index], 1e3 * h[f"dd_{side}_m"][index]),
                            textcoords="offset points", xytext=(4, 6))
    ax.set_xlabel("t [s]")
    ax.set_ylabel("Δd from static equilibrium [mm] (rod in +)")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    _phases(ax, timeline)
    ax.set_title(title, pad=16)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def fig16(study, timeline, path, side="left"):
    run = run_of(study, "a", 2)
    h = run.columns
    fig, axes = plt.subplots(2, 1, figsize=(9, 5), sharex=True)
    axes[0].plot(h["t"], h[f"beta_{side}"])
    axes[0].set_ylabel("β")
    axes[1].plot(h["t"], h[f"mu1_{side}"])
    axes[1].axhline(run.friction.mu_s, color="k", lw=0.6, ls=":")
    axes[1].set_ylabel("μ1")
    axes[1].set_xlabel("t [s]")
    for ax in axes:
        ax.grid(alpha=0.3)
    _phases(axes[0], timeline)
    axes[0].set_title(f"Fig. 16: β and μ1, case a, set {run.friction.label}, {side} strut",
                      pad=16)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def wheel_loads(study, timeline, path):
    runs = {name: r.columns for name, r in study.items()}
    names = sorted(runs)
    wheels = ("fl", "fr", "rl", "rr")
    fig, ax = plt.subplots(figsize=(10, 4))
    width = 0.1
    x = np.arange(len(names))
    for k, w in enumerate(wheels):
        for j, (where, hatch) in enumerate((("a", ""), ("b", "//"))):
            values = []
            for name in names:
                h = runs[name]
                index = places(h, timeline)[j]
                values.append(h[f"Fz_{w}_N"][index])
            ax.bar(x + (2 * k + j - 3.5) * width, values, width, hatch=hatch,
                   color=f"C{k}", label=f"{w} at {where}")
    ax.set_xticks(x, names)
    ax.set_ylabel("wheel load Fz [N]")
    ax.set_title("Wheel loads before (place a) and after (place b, hatched) the manoeuvre")
    ax.legend(ncol=4, fontsize=7)
    ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def all_figures(study, timeline, out):
    runs = study
    fig13(runs, timeline, out / "fig13.png")
    fig_dd(runs, timeline, "a", "left", out / "fig14_a.png",
           "Fig. 14a: lane change starting left, left strut")
    fig_dd(runs, timeline, "a", "right", out / "fig14_b.png",
           "Fig. 14b: lane change starting left, right strut")
    fig_dd(runs, timeline, "b", "left", out / "fig15_a.png",
           "Fig. 15a: lane change starting right, left strut")
    fig_dd(runs, timeline, "b", "right", out / "fig15_b.png",
           "Fig. 15b: lane change starting right, right strut")
    fig16(runs, timeline, out / "fig16.png")
    wheel_loads(runs, timeline, out / "wheel_loads.png")
    return ["fig13.png", "fig14_a.png", "fig14_b.png", "fig15_a.png", "fig15_b.png",
            "fig16.png", "wheel_loads.png"]
