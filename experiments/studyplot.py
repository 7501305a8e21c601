"""The studies' figure: one column per perturbation (sensor-noise seed or rear μy), the paper's
two panels per column (top: max slip or max |β| per GG; bottom: mean lap time of the completed
runs, ★ at the minimum, the aborted run marked with × on top and its reason at the bottom)."""

import math

import scwexp  # noqa: F401  (first: picks Debian's numpy/matplotlib, Agg backend)

import matplotlib.pyplot as plt  # noqa: E402


def _val(x):
    return math.nan if x is None else x


def plot_grid(panels, lines, top, top_label, path, title, hline=None):
    """panels: [(column title, {config: pack_series})]; lines: [(config, label, color, ls)];
    top: [(run field, linestyle or None for the line's own, legend suffix)]."""
    n = max(1, len(panels))
    fig, axes = plt.subplots(2, n, figsize=(4.6 * n + 0.6, 6.8), sharex=True, squeeze=False)
    for j, (col_title, series) in enumerate(panels):
        ax_t, ax_l = axes[0][j], axes[1][j]
        for k, (name, label, color, ls) in enumerate(lines):
            a = series.get(name)
            if not a or not a["runs"]:
                continue
            runs = a["runs"]
            gg = [r["gg_scale"] for r in runs]
            for field, fls, suffix in top:
                ax_t.plot(gg, [_val(r[field]) for r in runs], fls or ls, marker="o", ms=3,
                          color=color, label=f"{label}{suffix}")
                for r in runs:
                    if r["status"] != "completed":
                        ax_t.plot([r["gg_scale"]], [_val(r[field])], marker="x", ms=9,
                                  color=color, ls="none")
            done = [r for r in runs if r["status"] == "completed"]
            ax_l.plot([r["gg_scale"] for r in done], [r["mean_lap_time_s"] for r in done], ls,
                      marker="o", ms=3, color=color, label=label)
            if done:
                best = min(done, key=lambda r: r["mean_lap_time_s"])
                ax_l.plot([best["gg_scale"]], [best["mean_lap_time_s"]], marker="*", ms=12,
                          color=color, ls="none")
            for r in runs:
                if r["status"] != "completed":
                    ax_l.axvline(r["gg_scale"], color=color, ls=":", lw=1)
                    ax_l.annotate(r["status"], (r["gg_scale"], 0.97 - k * 0.9 / len(lines)),
                                  xycoords=("data", "axes fraction"), color=color, fontsize=7,
                                  ha="right", va="top", rotation=90)
        if hline is not None:
            ax_t.axhline(hline, color="k", ls=":", lw=1)
        ax_t.set_title(col_title, fontsize=10)
        ax_t.grid(True, alpha=0.3)
        ax_l.grid(True, alpha=0.3)
        ax_l.set_xlabel("acceleration scaling GG [-]")
        if j == 0:
            ax_t.set_ylabel(top_label)
            ax_l.set_ylabel("mean lap time [s]")
    axes[0][0].legend(fontsize=7)
    axes[1][0].legend(fontsize=7)
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
