"""The figures of a `scw tune` run folder (embedded into the scw binary; see tune_plots.h).

    python3 tune_plots.py RUN_DIR          (scw runs it as `python3 - RUN_DIR`, script on stdin)
    python3 tune_plots.py --front DIR      front.png from DIR/front.csv (scw tune --front)

Reads RUN_DIR/evaluations.csv (the evaluation log: eval, phase, cost, status, best_cost, ...) and
RUN_DIR/comparison.csv (ComparisonCsv: group, scenario, set, status, progress, mean_lap_time_s,
max_abs_sideslip_deg, ..., esc_count, cs_count, abs_count, tc_count, ..., cost, total_cost) and
writes

  convergence.png  the cost of every evaluation (log scale; colour = optimiser phase, marker = how
                   the training runs ended) with the best cost so far, phase boundaries marked;
                   below it the best cost so far on a linear scale
  comparison.png   per scenario (training, then held-out) and parameter set: how the run ended,
                   mean lap time, max |sideslip| and the interventions of ESC, CS, ABS and TC

Each PNG is written to a temporary name in RUN_DIR and renamed into place, so a failed or
interrupted run leaves either the previous figure or the new one. Deterministic: the Agg backend,
no software or date metadata, fixed sizes and resolutions, so the same inputs give the same bytes.

Exit codes: 0 written; 2 an input is missing or malformed; 3 matplotlib is not installed; 1 any
other failure. The reason is the last line on stderr, prefixed "tune_plots: ".
"""

import csv
import math
import os
import sys

PREFIX = "tune_plots: "


class InputError(Exception):
    pass


def fail(code, message):
    sys.stderr.write(PREFIX + message + "\n")
    sys.exit(code)


try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
except ImportError as e:  # the caller tries another interpreter on exit code 3
    fail(3, "matplotlib is not installed for %s (%s); Debian: apt-get install python3-matplotlib"
         % (sys.executable or "python3", e))

GLOBAL_ALGORITHMS = {"crs2", "isres", "esch", "direct_l", "lhs"}
PHASE_COLOURS = ["tab:blue", "tab:orange", "tab:purple", "tab:brown", "tab:pink", "tab:olive"]
SET_COLOURS = ["#6b6b6b", "tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown"]
SUBSYSTEMS = [("esc_count", "ESC", "tab:red"), ("cs_count", "CS", "tab:blue"),
              ("abs_count", "ABS", "tab:orange"), ("tc_count", "TC", "tab:green")]
DPI = 110


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def read_csv(path, required):
    """Rows of a CSV file as dicts; InputError when it is missing, empty or lacks a column."""
    name = os.path.basename(path)
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.reader(f)
            header = next(reader, None)
            rows = [r for r in reader if r]
    except OSError as e:
        raise InputError("cannot read %s: %s" % (path, e.strerror or e))
    except (UnicodeDecodeError, csv.Error) as e:
        raise InputError("%s is not a CSV file (%s)" % (path, e))
    if not header:
        raise InputError("%s is empty" % path)
    missing = [c for c in required if c not in header]
    if missing:
        raise InputError("%s lacks the column(s) %s" % (name, ", ".join(missing)))
    out = []
    for k, r in enumerate(rows, start=2):
        if len(r) != len(header):
            raise InputError("%s line %d has %d fields, the header %d"
                             % (name, k, len(r), len(header)))
        out.append(dict(zip(header, r)))
    return out


def save_atomic(fig, path):
    """savefig to a temporary file in the same folder, then rename it into place."""
    tmp = os.path.join(os.path.dirname(path),
                       ".%s.tmp-%d" % (os.path.basename(path), os.getpid()))
    try:
        with open(tmp, "wb") as f:
            fig.savefig(f, format="png", dpi=DPI, metadata={"Software": None})
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    finally:
        plt.close(fig)


def phase_label(name):
    if name == "start":
        return "evaluation 0: the base set"
    kind = "global search" if name in GLOBAL_ALGORITHMS else "local polish"
    return "%s (%s)" % (name, kind)


def status_kind(status):
    if status == "ok":
        return "ok"
    if "abort(s)" in status:
        return "abort"
    if status == "over budget":
        return "over"
    return "failed"


def fmt_cost(x):
    return "%.3f" % x if abs(x) < 1e5 else "%.3g" % x


def convergence(run_dir):
    rows = read_csv(os.path.join(run_dir, "evaluations.csv"),
                    ["eval", "phase", "cost", "status", "best_cost"])
    if not rows:
        raise InputError("evaluations.csv has no evaluations")
    ev = [int(number(r["eval"])) if not math.isnan(number(r["eval"])) else i
          for i, r in enumerate(rows)]
    cost = [number(r["cost"]) for r in rows]
    best = [number(r["best_cost"]) for r in rows]
    phase = [r["phase"] for r in rows]
    kind = [status_kind(r["status"]) for r in rows]

    phases = []  # (name, first eval, last eval) in log order
    for e, p in zip(ev, phase):
        if phases and phases[-1][0] == p:
            phases[-1][2] = e
        else:
            phases.append([p, e, e])
    colour = {}
    for p, _, _ in phases:
        if p not in colour:
            colour[p] = "black" if p == "start" else \
                PHASE_COLOURS[(len(colour) - ("start" in colour)) % len(PHASE_COLOURS)]

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9.0, 7.0), sharex=True,
                                      gridspec_kw={"height_ratios": [3, 2]})
    markers = {"ok": ("o", "training runs all completed"),
               "abort": ("x", "a training run aborted"),
               "over": ("s", "over the clean-lap budget (ranked behind the base)"),
               "failed": ("v", "set rejected / evaluation failed")}
    # The scale fits the evaluations that ran; a rejected set's penalty (far above any run) is
    # drawn at the top edge instead of squeezing the rest.
    ran = [c for c, k in zip(cost, kind) if k not in ("failed", "over") and math.isfinite(c)]
    ran = ran or [c for c in cost if math.isfinite(c)] or [0.0]
    lo, hi = min(ran), max(ran)
    pad = 0.05 * (hi - lo) if hi > lo else max(0.05, 0.01 * abs(hi))
    y_top = hi + pad
    off_scale = False
    for p in colour:
        for k, (m, _) in markers.items():
            pts = [(e, c) for e, c, pp, kk in zip(ev, cost, phase, kind) if pp == p and kk == k]
            if not pts:
                continue
            clipped = [(e, min(c, y_top) if math.isfinite(c) else y_top) for e, c in pts]
            off_scale = off_scale or any(not (c <= y_top) for _, c in pts)
            top.scatter([e for e, _ in clipped], [c for _, c in clipped],
                        s=40 if p == "start" else 14, marker=m, color=colour[p], linewidths=1.0,
                        alpha=0.9, zorder=3, clip_on=False)
    top.set_ylim(lo - pad, y_top)
    for ax in (top, bottom):
        ax.step(ev, best, where="post", color="black", lw=1.4, zorder=4)
        ax.grid(True, alpha=0.3)
        for p, first, last in phases:
            if first > ev[0]:
                ax.axvline(first - 0.5, color="0.35", ls="--", lw=0.9, zorder=1)
    for p, first, last in phases:
        if p == "start":
            continue
        top.text((first + last) / 2.0 if last > first else first, 1.01, p,
                 transform=top.get_xaxis_transform(), ha="center", va="bottom", fontsize=9,
                 color=colour[p])
    i_best = min(range(len(best)), key=lambda i: (best[i], i)) if best else 0
    b_eval = next((e for e, c in zip(ev, cost) if c == best[-1]), ev[i_best])
    bottom.plot([b_eval], [best[-1]], marker="*", ms=12, color="gold", mec="black", zorder=5)
    start, final = cost[0], best[-1]
    change = final - start
    rel = " (%+.2f %%)" % (100.0 * change / abs(start)) if start else ""
    bottom.set_title("best cost so far: evaluation 0 %s, best %s at evaluation %d, change %+.3f%s"
                     % (fmt_cost(start), fmt_cost(final), b_eval, change, rel), fontsize=9)
    finite_best = [b for b in best if math.isfinite(b)]
    if finite_best:
        lo, hi = min(finite_best), max(finite_best)
        pad = 0.08 * (hi - lo) if hi > lo else max(0.05, 0.001 * abs(hi))
        bottom.set_ylim(lo - pad, hi + pad)
    top.set_ylabel("training cost of the evaluation")
    bottom.set_ylabel("best cost so far")
    bottom.set_xlabel("evaluation")
    fig.suptitle("scw tune: convergence (%d evaluations)" % len(rows), fontsize=11)
    handles = [Line2D([], [], color=colour[p], marker="s", ls="none", label=phase_label(p))
               for p in colour]
    handles += [Line2D([], [], color="0.3", marker=m, ls="none", label=text)
                for k, (m, text) in markers.items() if k in kind]
    if off_scale:
        handles.append(Line2D([], [], color="none", label="(costs above the scale: at the top)"))
    handles.append(Line2D([], [], color="black", lw=1.4, label="best cost so far"))
    handles.append(Line2D([], [], color="0.35", ls="--", lw=0.9, label="phase boundary"))
    top.legend(handles=handles, fontsize=8, loc="upper right", framealpha=0.9)
    fig.tight_layout()
    save_atomic(fig, os.path.join(run_dir, "convergence.png"))


def status_text(row):
    if row["status"] == "completed":
        return "completed"
    p = number(row["progress"])
    where = "" if math.isnan(p) else " at %.0f %%" % (100.0 * p)
    return "abort: %s%s" % (row["status"].replace("_", " "), where)


def comparison(run_dir):
    rows = read_csv(os.path.join(run_dir, "comparison.csv"),
                    ["group", "scenario", "set", "status", "progress", "mean_lap_time_s",
                     "max_abs_sideslip_deg"] + [c for c, _, _ in SUBSYSTEMS])
    if not rows:
        raise InputError("comparison.csv has no rows")
    sets, groups, data = [], [], {}
    for r in rows:
        if r["set"] not in sets:
            sets.append(r["set"])
        g = r["group"]
        if not any(gg == g for gg, _ in groups):
            groups.append((g, []))
        scen = next(s for gg, s in groups if gg == g)
        if r["scenario"] not in scen:
            scen.append(r["scenario"])
        data[(g, r["scenario"], r["set"])] = r
    group_title = {"training": "training scenarios",
                   "held_out": "held-out (not used for tuning)"}

    # One row per group header and per scenario, top to bottom (y grows downwards).
    layout = []  # (kind, group, text)
    for g, scen in groups:
        layout.append(("group", g, group_title.get(g, g)))
        layout += [("scenario", g, s) for s in scen]
    n_sets = len(sets)
    step = 0.8 / max(1, n_sets)

    def y_of(i, j):
        return i + (j - (n_sets - 1) / 2.0) * step

    height = 1.2 + 0.2 * sum(1.2 if k == "group" else max(2, n_sets) + 0.7 for k, _, _ in layout)
    fig, axes = plt.subplots(1, 4, figsize=(13.0, height), sharey=True,
                             gridspec_kw={"width_ratios": [1.25, 1, 1, 1.15]})
    ax_status, ax_lap, ax_beta, ax_int = axes
    colour = {s: SET_COLOURS[j % len(SET_COLOURS)] for j, s in enumerate(sets)}
    ax_status.set_xlim(0, 1)
    ax_status.set_xticks([])
    no_lap = []
    for i, (kind, g, text) in enumerate(layout):
        if kind == "group":
            for ax in axes:
                ax.axhline(i - 0.5, color="0.6", lw=0.8)
            ax_status.text(0.02, i + 0.1, text, fontsize=9, fontweight="bold", va="center")
            continue
        laps, betas = [], []
        for j, s in enumerate(sets):
            r = data.get((g, text, s))
            if r is None:
                continue
            y = y_of(i, j)
            done = r["status"] == "completed"
            ax_status.text(0.03, y, "%s: %s" % (s, status_text(r)), fontsize=8, va="center",
                           color="black" if done else "darkred",
                           bbox=dict(boxstyle="round,pad=0.2", lw=0,
                                     fc="#d9f0d3" if done else "#f8d0c8"))
            lap, beta = number(r["mean_lap_time_s"]), number(r["max_abs_sideslip_deg"])
            if math.isfinite(lap):
                ax_lap.plot([lap], [y], "o", color=colour[s], ms=6, zorder=3)
                laps.append((j, lap))
            else:
                no_lap.append(y)
            if math.isfinite(beta):
                ax_beta.plot([beta], [y], "o", color=colour[s], ms=6, zorder=3)
                betas.append((j, beta))
            left = 0.0
            for col, name, c in SUBSYSTEMS:
                n = number(r[col])
                if math.isfinite(n) and n > 0:
                    ax_int.barh(y, n, left=left, height=step * 0.85, color=c, lw=0)
                    left += n
            ax_int.text(left, y, " %d" % left, fontsize=7, va="center")
        for ax, values, unit, digits in ((ax_lap, laps, "s", 3), (ax_beta, betas, "°", 2)):
            if len(values) >= 2:
                ax.plot([v for _, v in values], [y_of(i, j) for j, _ in values], color="0.6",
                        lw=0.8, zorder=2)
                d = round(values[-1][1] - values[0][1], digits) + 0.0  # no "-0.00"
                ax.text(1.0, i, " Δ %+.*f %s" % (digits, d, unit), fontsize=7.5, va="center",
                        transform=ax.get_yaxis_transform())
    for y in no_lap:
        ax_lap.text(0.02, y, "no lap completed", fontsize=7, color="0.4", va="center",
                    transform=ax_lap.get_yaxis_transform())
    ax_status.set_ylim(len(layout) - 0.5, -0.5)
    ticks = [i for i, (k, _, _) in enumerate(layout) if k == "scenario"]
    ax_status.set_yticks(ticks)
    ax_status.set_yticklabels([layout[i][2] for i in ticks], fontsize=8.5)
    ax_status.set_title("how the run ended", fontsize=10)
    ax_lap.set_title("mean lap time [s]", fontsize=10)
    ax_beta.set_title("max |sideslip β| [deg]", fontsize=10)
    ax_int.set_title("interventions [count]", fontsize=10)
    for ax in (ax_lap, ax_beta, ax_int):
        ax.grid(True, axis="x", alpha=0.3)
        ax.tick_params(axis="x", labelsize=8)
    ax_int.set_xlim(left=0)
    lo, hi = ax_int.get_xlim()
    ax_int.set_xlim(0, hi * 1.12 if hi > 0 else 1)
    handles = [Line2D([], [], color=colour[s], marker="o", ls="none", label=s) for s in sets]
    handles += [Patch(color=c, label=name) for _, name, c in SUBSYSTEMS]
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=8,
               frameon=False, bbox_to_anchor=(0.5, 1.0))
    fig.suptitle("scw tune: %s per scenario (Δ: %s − %s; costs in comparison.md)"
                 % (" vs ".join(sets), sets[-1], sets[0]) if n_sets >= 2 else
                 "scw tune: %s per scenario" % sets[0], fontsize=11, y=1.0 - 0.3 / height)
    fig.tight_layout(rect=(0, 0, 1, 1.0 - 0.45 / height), w_pad=2.5)
    save_atomic(fig, os.path.join(run_dir, "comparison.png"))


def front(run_dir):
    """front.png: the clean-lap loss against the stability cost of every point of a front,
    training and held-out, and the base set (the car's shipped set unless --base) at loss 0.
    Points on the same spot (a looser budget that found nothing better) share one label."""
    rows = read_csv(os.path.join(run_dir, "front.csv"),
                    ["point", "label", "training_lap_loss_s", "training_stability",
                     "held_out_lap_loss_s", "held_out_stability", "training_aborts",
                     "held_out_aborts"])
    if not rows:
        raise InputError("front.csv has no points")
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.6))
    for ax, group, title in ((axes[0], "training", "training scenarios (tuned on)"),
                             (axes[1], "held_out", "held-out scenarios (not tuned on)")):
        xs = [number(r[group + "_lap_loss_s"]) for r in rows]
        ys = [number(r[group + "_stability"]) for r in rows]
        pts = [(x, y, r) for x, y, r in zip(xs, ys, rows) if math.isfinite(x) and math.isfinite(y)]
        if pts:
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "-", color="0.6", lw=1.0, zorder=2)
        spots = []  # [(x, y, [rows])] in point order
        for x, y, r in pts:
            if spots and spots[-1][0] == x and spots[-1][1] == y:
                spots[-1][2].append(r)
            else:
                spots.append((x, y, [r]))
        for x, y, same in spots:
            ax.plot([x], [y], "o", color="tab:blue", ms=7, zorder=3)
            first, last = same[0], same[-1]
            name = ("%s %s" % (first["point"], first["label"]) if len(same) == 1 else
                    "%s-%s %s to %s" % (first["point"], last["point"], first["label"],
                                        last["label"]))
            ax.annotate("%s\n%s aborts" % (name, first[group + "_aborts"]),
                        (x, y), textcoords="offset points", xytext=(6, 4), fontsize=8)
        base_y = number(rows[0].get("base_%s_stability" % group, ""))
        if math.isfinite(base_y):
            ax.plot([0.0], [base_y], "s", color="black", ms=7, zorder=3)
            aborts = rows[0].get("base_%s_aborts" % group, "")
            ax.annotate("base set" + ("\n%s aborts" % aborts if aborts else ""), (0.0, base_y),
                        textcoords="offset points", xytext=(-8, -4), ha="right", va="top",
                        fontsize=8)
        ax.axvline(0.0, color="0.35", ls="--", lw=0.9)
        ax.set_xlabel("largest clean-lap loss against the base set [s per lap]")
        ax.set_ylabel("stability cost of the critical scenarios")
        ax.set_title(title, fontsize=10)
        ax.grid(True, alpha=0.3)
    fig.suptitle("scw tune --front: what a set costs on clean laps against what it saves "
                 "(lower left is better; 0 s = the base set's laps)", fontsize=11)
    fig.tight_layout()
    save_atomic(fig, os.path.join(run_dir, "front.png"))


def main(argv):
    if len(argv) == 3 and argv[1] == "--front":
        if not os.path.isdir(argv[2]):
            fail(2, "no such front folder: %s" % argv[2])
        try:
            front(argv[2])
        except InputError as e:
            fail(2, str(e))
        except Exception as e:  # one line for the caller, not a traceback
            fail(1, "%s: %s" % (type(e).__name__, e))
        return 0
    if len(argv) != 2:
        fail(2, "usage: tune_plots.py RUN_DIR | tune_plots.py --front FRONT_DIR")
    run_dir = argv[1]
    if not os.path.isdir(run_dir):
        fail(2, "no such run folder: %s" % run_dir)
    try:
        convergence(run_dir)
        comparison(run_dir)
    except InputError as e:
        fail(2, str(e))
    except Exception as e:  # one line for the caller, not a traceback
        fail(1, "%s: %s" % (type(e).__name__, e))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
