"""The car checked on its own, in figures: settling (wheel loads and strut overlaps against
time), the front suspension's kinematics (chassis fixed) and the steering's."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def plot_settle(run, path):
    h = run.history
    fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for w in ("fl", "fr", "rl", "rr"):
        axes[0].plot(h["t"], h[f"Fz_{w}_N"], label=w)
    axes[0].set_ylabel("wheel load Fz [N]")
    axes[0].legend(ncol=4)
    for s in ("left", "right"):
        axes[1].plot(h["t"], 1e3 * h[f"d_{s}_m"], label=f"overlap d {s}")
    axes[1].set_ylabel("strut overlap d [mm]")
    axes[1].set_xlabel("t [s]")
    axes[1].legend()
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.suptitle(f"Settling: {run.scene.name}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_kinematics(table, path):
    fields = [("camber_deg", "camber [deg]"), ("toe_deg", "toe-in [deg]"),
              ("caster_deg", "caster [deg]"), ("kingpin_deg", "kingpin incl. [deg]"),
              ("strut_length_m", "strut length [m]"), ("overlap_m", "overlap d [m]")]
    fig, axes = plt.subplots(2, 3, figsize=(12, 6.5))
    side = np.array(table["side"])
    travel = 1e3 * np.array(table["wheel_travel_m"])
    for ax, (name, label) in zip(axes.flat, fields):
        for s, style in (("left", "-"), ("right", "--")):
            mask = side == s
            ax.plot(np.array(table[name])[mask], travel[mask], style, label=s)
        ax.set_xlabel(label)
        ax.set_ylabel("wheel travel [mm] (bump +)")
        ax.grid(alpha=0.3)
    axes[0, 0].legend()
    fig.suptitle("Front suspension kinematics (chassis fixed)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_steering(table, path):
    fig, ax = plt.subplots(figsize=(6, 4.5))
    rack = 1e3 * np.array(table["rack_m"])
    ax.plot(rack, table["steer_left_deg"], label="left wheel")
    ax.plot(rack, table["steer_right_deg"], "--", label="right wheel")
    ax.set_xlabel("rack displacement [mm] (to the left +)")
    ax.set_ylabel("wheel steer angle [deg] (left +)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
