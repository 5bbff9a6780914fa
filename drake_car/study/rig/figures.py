"""The strut rig's figures: hysteresis loops, friction against side load."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def plot_loops(loops, path, title):
    """``loops``: list of (label, history) for one μs each panel: {mu_s: [(F_side, h)]}."""
    panels = sorted(loops)
    fig, axes = plt.subplots(1, len(panels), figsize=(6 * len(panels), 4.5), squeeze=False)
    for ax, mu_s in zip(axes[0], panels):
        for side, h in loops[mu_s]:
            ax.plot(1e3 * h["stroke_m"], h["load_cell_N"], lw=0.8, label=f"side {side:g} N")
        ax.set_xlabel("stroke q [mm] (rod extension)")
        ax.set_ylabel("axial force at the load cell [N]")
        ax.set_title(f"μs = {mu_s:g}")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_side_load(rows, path):
    """``rows``: dicts with mu_s, side_force_N, breakaway_N, sliding_N, mu_d, normal_N."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for mu_s in sorted({r["mu_s"] for r in rows}):
        sel = sorted((r for r in rows if r["mu_s"] == mu_s), key=lambda r: r["side_force_N"])
        side = [r["side_force_N"] for r in sel]
        line, = ax.plot(side, [r["breakaway_N"] for r in sel], "o-",
                        label=f"μs {mu_s:g}: break-away (rig)")
        ax.plot(side, [r["sliding_N"] for r in sel], "s--", color=line.get_color(),
                label=f"μd {sel[0]['mu_d']:g}: sliding (rig)")
        ax.plot(side, [mu_s * r["normal_N"] for r in sel], ":", color="k", lw=0.8)
        ax.plot(side, [r["mu_d"] * r["normal_N"] for r in sel], ":", color="k", lw=0.8)
    ax.set_xlabel("side force on the knuckle [N]")
    ax.set_ylabel("axial friction force [N]")
    ax.set_title("Friction against side load (dotted: μ·N, N = |M/d + F| of eq. 4)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
