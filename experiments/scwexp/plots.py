"""The studies' figures (matplotlib, Agg backend): the per-study grid (one column per
perturbation, the paper's two panels per column: top max slip or max |β| per GG, bottom mean
lap time of the completed runs, ★ at the minimum, the aborted run marked with × on top and its
reason at the bottom), and the abort marks of a series."""

import math

import debpython  # noqa: F401  (Debian numpy/matplotlib; before importing them)
import matplotlib  # noqa: E402

matplotlib.use("Agg")
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


def mark_aborts(ax, rows, key, field, color, linestyle="-"):
    """An 'x' at the aborted run of a series (the last reported one)."""
    for r in rows:
        if r["status"] != "completed" and not math.isnan(r[field]):
            ax.plot([r[key]], [r[field]], marker="x", color=color, markersize=9, linestyle="none")


def claims_map_heat_map(variants, path, set_label, columns, steers, margin_names):
    """The claims map's brake x steering dead-time grid: per claim, pass (green) / fail (red)
    with the margin in each cell (variants with a "grid" key: (brake column, steering))."""
    claims = ("a", "b", "c", "d")
    fig, axes = plt.subplots(1, 4, figsize=(16, 4.2))
    for ax, k in zip(axes, claims):
        grid = [[None] * len(columns) for _ in steers]
        for v in variants:
            key = v.get("grid")
            if key is None:
                continue
            i, j = steers.index(key[1]), columns.index(key[0])
            grid[i][j] = v["claims"][k]
        for i in range(len(steers)):
            for j in range(len(columns)):
                c = grid[i][j]
                color = "#bbbbbb" if c is None else ("#7fc97f" if c["ok"] else "#f0a0a0")
                ax.add_patch(plt.Rectangle((j - 0.5, i - 0.5), 1, 1, color=color))
                if c is not None:
                    unit = " s" if k == "d" else ""
                    ax.text(j, i, f"{'holds' if c['ok'] else 'fails'}\n{c['margin']:+.3f}{unit}",
                            ha="center", va="center", fontsize=9)
        ax.set_xlim(-0.5, len(columns) - 0.5)
        ax.set_ylim(-0.5, len(steers) - 0.5)
        ax.set_xticks(range(len(columns)))
        ax.set_xticklabels([f"{b * 1000:.0f}" if b != "nodyn" else "none" for b in columns])
        ax.set_yticks(range(len(steers)))
        ax.set_yticklabels([f"{s * 1000:.0f}" for s in steers])
        ax.set_xlabel("brake dead time [ms]")
        if k == "a":
            ax.set_ylabel("steering dead time [ms]")
        ax.set_title(f"claim ({k}): margin = {margin_names[k]}", fontsize=9)
    fig.suptitle(f"Claims map, {set_label} set: pass (green) / fail (red) with the margin; brake "
                 "dead time within the fixed 150 ms response, 'none': no brake dynamics; real "
                 "car's actuators otherwise (study 1 seed 1, study 2 rear μy 0.80)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def claims_map_bars(variants, path, set_label, margin_names, thresh):
    """The claims map one change at a time: per claim, each variant's margin (green: holds)
    against the criterion's threshold (dotted)."""
    claims = ("a", "b", "c", "d")
    fig, axes = plt.subplots(1, 4, figsize=(17, 0.45 * len(variants) + 1.8), sharey=True)
    labels = [v["label"] for v in variants]
    for ax, k in zip(axes, claims):
        vals = [v["claims"][k]["margin"] for v in variants]
        cols = ["tab:green" if v["claims"][k]["ok"] else "tab:red" for v in variants]
        ax.barh(range(len(variants)), vals, color=cols)
        ax.axvline(thresh[k], color="k", ls=":", lw=1)
        ax.set_title(f"({k}) {margin_names[k]}", fontsize=9)
        ax.grid(True, axis="x", alpha=0.3)
    axes[0].set_yticks(range(len(variants)))
    axes[0].set_yticklabels(labels, fontsize=8)
    axes[0].invert_yaxis()
    fig.suptitle(f"Claims map, {set_label} set, one at a time: margin per claim (green: claim "
                 "holds; dotted: the criterion's threshold)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
