#!/usr/bin/python3
"""benchmarks/plot_report.py — turns the CSV of lieservo_speed_error_report into the Markdown
table and the speed-against-error (Pareto) plot of docs/performance.md.

  plot_report.py REPORT.csv OUT.md OUT.png   (OUT.md: the table fragment make_report.sh splices in)
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def tolerance(r):
    """> 0: a row of the converged rule (its tolerance in standard deviations)."""
    return float(r.get("tolerance") or 0)


def label(r):
    name = "closed form" if r["policy"] == "closed" else f"series N={r['order']}"
    name += ", square-root form" if r.get("form") == "square_root" else ""
    return name + (f", converged rule {tolerance(r):g} σ" if tolerance(r) > 0 else "")


def iterations(r):
    """The fixed count, or the converged rule's cap and mean number of updates."""
    return f"≤ {r['iterations']} ({float(r['mean_updates']):.2f})" if tolerance(r) > 0 else r["iterations"]


def kind(r):
    return (r["policy"] + r["order"] + ("square_root" if r.get("form") == "square_root" else "")
            + ("converged" if tolerance(r) > 0 else ""))


def is_paper(r):
    """The paper's configuration: series N = 2, 5 iterations, the default (information) form."""
    return (r["policy"] == "series" and r["order"] == "2" and r["iterations"] == "5"
            and r.get("form", "information") == "information" and tolerance(r) == 0)


def pareto(rows, key):
    """Rows not dominated in (time, error): no other row is both faster and more accurate."""
    front = set()
    for i, a in enumerate(rows):
        dominated = any(
            (float(b["ns_median"]) <= float(a["ns_median"]) and float(b[key]) <= float(a[key])
             and (float(b["ns_median"]) < float(a["ns_median"]) or float(b[key]) < float(a[key])))
            for j, b in enumerate(rows) if j != i)
        if not dominated:
            front.add(i)
    return front


def main():
    src, out_md, out_png = sys.argv[1:4]
    with open(src) as f:
        rows = list(csv.DictReader(f))
    key = "real_rot_mean_rad"
    lines = []
    for scalar in ("double", "float"):
        rs = [r for r in rows if r["scalar"] == scalar]
        front = pareto(rs, key)
        lines.append(f"\n**SE(3) {scalar}** — fusion of two factors; time = median per fuse() call; errors against the "
                     "long-double converged reference (realistic set: mean; hard set: max). ★ = on the Pareto front "
                     "of (time, mean rotation error). Hard fails: fuse() returned a non-ok Status (near π + extreme σ + tiny angles).\n")
        lines.append("| Jacobian | it. | time (ns) | rot. err (rad) | trans. err (mm) | cov. rel. err | "
                     "hard: rot. (rad) | hard: trans. (mm) | hard: cov. | hard fails | Pareto |")
        lines.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|:---:|")
        for i, r in enumerate(rs):
            paper = " (paper)" if is_paper(r) else ""
            lines.append(
                f"| {label(r)}{paper} | {iterations(r)} | {float(r['ns_median']):.0f} | {float(r[key]):.2e} | "
                f"{float(r['real_trans_mean_mm']):.2e} | {float(r['real_cov_mean_rel']):.2e} | "
                f"{float(r['hard_rot_max_rad']):.1e} | {float(r['hard_trans_max_mm']):.1e} | "
                f"{float(r['hard_cov_max_rel']):.1e} | {r['hard_failures']}/{r['hard_cases']} "
                f"({r['hard_fail_near_pi']}+{r['hard_fail_extreme_sigma']}+{r['hard_fail_tiny_angle']}) | "
                f"{'★' if i in front else ''} |")
    with open(out_md, "w") as f:
        f.write("\n".join(lines) + "\n")

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), sharey=True)
    markers = {"series1": "v", "series2": "o", "series3": "s", "series4": "D", "closed-1": "*",
               "series2square_root": "P", "closed-1square_root": "X", "series2converged": "^",
               "closed-1converged": "h"}
    for ax, scalar in zip(axes, ("double", "float")):
        rs = [r for r in rows if r["scalar"] == scalar]
        front = pareto(rs, key)
        for pol in markers:
            sel = [r for r in rs if kind(r) == pol]
            if not sel:
                continue
            xs = [float(r["ns_median"]) for r in sel]
            ys = [max(float(r[key]), 1e-17) for r in sel]
            ax.plot(xs, ys, marker=markers[pol], linestyle="-", label=label(sel[0]), alpha=0.8)
            for r, x, y in zip(sel, xs, ys):
                ax.annotate(f"{float(r['mean_updates']):.2f}" if tolerance(r) > 0 else r["iterations"], (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7)
        fr = sorted((float(rs[i]["ns_median"]), max(float(rs[i][key]), 1e-17)) for i in front)
        ax.plot([p[0] for p in fr], [p[1] for p in fr], "k--", lw=0.8, label="Pareto front")
        paper = [r for r in rs if is_paper(r)]
        if paper:
            ax.plot(float(paper[0]["ns_median"]), float(paper[0][key]), "ro", mfc="none", ms=12,
                    label="paper (N=2, 5 it.)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("median time per fuse() call (ns)")
        ax.set_title(f"SE(3) {scalar}: two-factor fusion (labels: iterations)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("mean rotation error of fused mean (rad)")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)


if __name__ == "__main__":
    main()
