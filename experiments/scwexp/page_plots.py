"""The three figures of the report's first page (matplotlib, Agg backend), drawn from plain data
(scwexp.report.page_data prepares it): A, study 2 of one column as the paper drew it, with the
paper's stated points and a second axis in % of the plant's limits; B, `none`'s ESC margin
against GG per column; C, the gain of ESC and ESC + CS over `none` per claims-map variant. Each
draws what it is given and writes on the figure what is missing; none invents a number."""

import math
import textwrap

import debpython  # noqa: F401  (Debian numpy/matplotlib; before importing them)
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLORS = {"none": "tab:gray", "esc": "tab:red", "cs": "tab:blue", "esc+cs": "tab:purple"}


def _pct_axis(ax, fraction):
    """A second x axis on top: GG in % of the plant's combined limits."""
    top = ax.secondary_xaxis("top", functions=(lambda x: x * fraction * 100,
                                               lambda p: p / (fraction * 100)))
    top.set_xlabel("% of the plant's combined limits", fontsize=8)
    return top


def _note(ax, text):
    ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", fontsize=9,
            wrap=True, color="0.3")


def figure_a(data, paper, fraction, path, title):
    """data: page_data.figure_a_data; paper: PAPER_POINTS. Top: the sideslip metric per GG
    (× at the run that ended the series); bottom: mean lap time of the completed runs, the
    paper's Δ at GG 1.3 drawn from our `none` lap there (or stated, if `none` has none)."""
    fig, (ax_t, ax_l) = plt.subplots(2, 1, figsize=(7.2, 6.8), sharex=True)
    if data is None:
        _note(ax_t, "no study 2 in this results tree (experiments/study2_lateral.py)")
        data = {"series": {}, "key": "", "what": "sideslip", "labels": {}}
    ggs = [p[0] for pts in data["series"].values() for p in pts]
    for name, pts in data["series"].items():
        c = COLORS.get(name, "k")
        lab = data["labels"].get(name, name)
        ax_t.plot([p[0] for p in pts], [p[1] for p in pts], "-o", ms=3, color=c, label=lab)
        ax_t.plot([p[0] for p in pts if p[3]], [p[1] for p in pts if p[3]], "x", ms=10, color=c)
        done = [p for p in pts if p[2] is not None]
        ax_l.plot([p[0] for p in done], [p[2] for p in done], "-o", ms=3, color=c, label=lab)
    if data["key"] == "max_esc_beta_error_ratio":
        ax_t.axhline(1.0, color="k", ls=":", lw=1)
        ax_t.annotate("ESC's activation threshold", (0.01, 1.0), xycoords=("axes fraction",
                      "data"), fontsize=7, va="bottom")
    x_paper = paper["gg"]
    none_at = [p[2] for p in data["series"].get("none", []) if abs(p[0] - x_paper) < 1e-6
               and p[2] is not None]
    for k in ("esc", "esc+cs"):
        if none_at:
            ax_l.plot([x_paper], [none_at[0] + paper[k]], marker="*", ms=13, ls="none",
                      color=COLORS[k], markeredgecolor="k",
                      label=f"paper: {k.upper().replace('+', ' + ')} +{paper[k]:.2f} s")
    ax_l.axvline(x_paper, color="k", ls="--", lw=0.8)
    ax_l.text(0.3, 0.04, "paper, GG 1.3 (dashed): ESC +0.15 s, ESC + CS +0.05 s vs none"
              + ("" if none_at else "\n(not drawn: no `none` lap at GG 1.3 here)"),
              transform=ax_l.transAxes, fontsize=7, va="bottom",
              bbox=dict(fc="white", ec="0.7", alpha=0.9))
    for ax in (ax_t, ax_l):
        ax.axvspan(paper["none_lost_before"], paper["none_lost_before"] + 0.02, color="0.85")
        ax.grid(True, alpha=0.3)
    ax_t.text(paper["none_lost_before"] - 0.005, 0.5, "paper: none lost\nbefore GG 1.4",
              transform=ax_t.get_xaxis_transform(), fontsize=7, ha="right", va="center")
    lo = min(ggs + [x_paper]) - 0.03
    hi = max(ggs + [paper["none_lost_before"]]) + 0.05
    ax_l.set_xlim(lo, hi)
    _pct_axis(ax_t, fraction)
    ax_t.set_ylabel(data["what"], fontsize=8)
    ax_l.set_ylabel("mean lap time [s]")
    ax_l.set_xlabel("acceleration scaling GG [-]")
    ax_t.legend(fontsize=7, loc="upper left")
    ax_l.legend(fontsize=7, loc="upper right")
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def figure_b(series, titles, fraction, path, title):
    """series: {column: [(gg, max_esc_margin, lost)]}; titles: {column: its title}. One line per
    column, × at a lost run, the activation condition (margin 1) dotted."""
    fig, ax = plt.subplots(figsize=(7.2, 4.2))
    styles = ["-", "--", ":", "-."]
    ys = []
    for i, (col, pts) in enumerate(series.items()):
        if not pts:
            continue
        line, = ax.plot([p[0] for p in pts], [p[1] for p in pts], styles[i % 4], marker="o",
                        ms=3, label=titles.get(col, col))
        lost = [p for p in pts if p[2]]
        ax.plot([p[0] for p in lost], [p[1] for p in lost], "x", ms=10, mew=2,
                color=line.get_color())
        ys += [p[1] for p in pts]
    ax.axhline(1.0, color="k", ls=":", lw=1)
    ax.annotate("ESC's activation condition (margin 1)", (0.01, 1.0),
                xycoords=("axes fraction", "data"), fontsize=7, va="bottom")
    if ys and min(ys) > 0:
        ax.set_yscale("log")
    if not ys:
        _note(ax, "no study-2 run of `none` with max_esc_margin in this results tree")
    else:
        ax.plot([], [], "x", color="k", mew=2, label="lost (the run that ended the series)")
        ax.legend(fontsize=7)
    _pct_axis(ax, fraction)
    ax.set_xlabel("acceleration scaling GG [-]")
    ax.set_ylabel("`none`: max ESC margin [-]")
    ax.grid(True, alpha=0.3)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def figure_c(rows, missing, path, title, step=0.05):
    """rows: [(label, gain ESC, gain ESC + CS, limit-cycling, scored, ESC open, ESC + CS
    open)]: two horizontal bars per row (ESC, ESC + CS), limit-cycling rows grey, scored
    columns' labels bold, "≥" where the series never aborted (a lower bound); claim (b)'s one
    step dotted; `missing` written under the bars."""
    n = max(1, len(rows))
    dense = n > 40   # the full reference: over a hundred variants
    fig, ax = plt.subplots(figsize=(8.0, (0.13 if dense else 0.32) * n + 2.2))
    h = 0.38
    for i, (label, ge, gb, cyc, _, oe, ob) in enumerate(rows):
        for off, gv, c, lb in ((-h / 2, ge, "tab:red", oe), (h / 2, gb, "tab:purple", ob)):
            if gv is None or (isinstance(gv, float) and math.isnan(gv)):
                ax.text(0, i + off, " no run", fontsize=5 if dense else 6, va="center")
                continue
            ax.barh(i + off, gv, height=h, color="0.75" if cyc else c,
                    hatch="//" if cyc else None, edgecolor="0.5" if cyc else c)
            ax.plot([gv], [i + off], "|", ms=3 if dense else 7, color="0.5" if cyc else c)
            if not dense:
                ax.annotate(("≥ " if lb else "") + f"{gv:+.3f}", (gv, i + off), xytext=(3, 0),
                            textcoords="offset points", fontsize=6, va="center")
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels([r[0] + (" (limit-cycling)" if r[3] else "") for r in rows],
                       fontsize=5 if dense else 7)
    ax.set_ylim(n - 0.5, -0.5)
    for t, r in zip(ax.get_yticklabels(), rows):
        if r[4]:
            t.set_fontweight("bold")
        if r[3]:
            t.set_color("0.5")
    ax.axvline(0, color="k", lw=0.8)
    ax.axvline(step, color="k", ls=":", lw=1)
    from matplotlib.patches import Patch
    ax.legend(handles=[Patch(color="tab:red", label="ESC − none"),
                       Patch(color="tab:purple", label="ESC + CS − none"),
                       Patch(fc="0.75", hatch="//", ec="0.5", label="limit-cycling controller")],
              fontsize=7, loc="lower right")
    ax.set_xlabel("first-abort GG − none's [GG]; dotted: one step (claim (b))")
    ax.grid(True, axis="x", alpha=0.3)
    if not rows:
        _note(ax, "no study 2 and no claims map in this results tree")
    note = textwrap.fill("Missing: " + "; ".join(missing), 120) if missing else ""
    if note:
        fig.text(0.01, 0.005, note, fontsize=7, color="tab:red", va="bottom")
    fig.suptitle(title, fontsize=9)
    bottom = (note.count("\n") + 1) * 0.14 / fig.get_figheight() if note else 0
    fig.tight_layout(rect=(0, bottom, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
