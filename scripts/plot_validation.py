#!/usr/bin/python3
"""Plots of `mgelastic bench validation --json` (docs/validation.md): error vs resolution, log-log.

    mgelastic bench validation --json > validation.json
    scripts/plot_validation.py validation.json docs/images

writes validation_lame_sphere.png, validation_cantilever.png and validation_disc.png into the
output folder and prints the summary table of docs/validation.md (Markdown) on stdout. Needs numpy
and matplotlib (Debian python3-matplotlib; /usr/bin/python3).
"""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def slope_guide(ax, xs, ys, order, label):
    """A dashed line of the given order through the first point of the finest series."""
    x = np.array([min(xs), max(xs)], dtype=float)
    y0 = max(ys)
    ax.loglog(x, y0 * (x / x[0]) ** (-order), "k--", lw=0.8, alpha=0.6, label=label)


def plot(series, title, path, guide_order=1.0):
    if not series:
        return
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    xs_all, ys_all = [], []
    for s in series:
        rows = [r for r in s["rows"] if r["relative_error"] > 0]
        if not rows:
            continue
        n = [r["resolution"] for r in rows]
        e = [r["relative_error"] for r in rows]
        xs_all += n
        ys_all += e
        order = s["fitted_order"]
        # The study tells the cantilever's two loads apart (same quantity).
        label = (f'{s["engine"]} {s["study"].removeprefix("cantilever_")} '
                 f'nu={s["poisson_ratio"]:g} {s["quantity"].split(",")[0]}')
        if order is not None:
            label += f" (fit {order:.2f})"
        style = "o-" if s["engine"] == "grid" else "s--"
        ax.loglog(n, e, style, label=label)
    if xs_all:
        slope_guide(ax, xs_all, ys_all, guide_order, f"order {guide_order:g}")
    ax.set_xlabel("cells across (resolution)")
    ax.set_ylabel("relative error" if "disc" not in path.name else "max error")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def markdown_table(report):
    """One row per series: errors at each resolution, orders, Richardson; then the patch test."""
    lines = ["| case | engine | nu | resolutions | relative error | order (last / fit) "
             "| Richardson vs reference |", "|---|---|---|---|---|---|---|"]
    for s in report["series"]:
        rows = s["rows"]
        ns = ", ".join(str(r["resolution"]) for r in rows)
        errors = ", ".join(f'{100 * r["relative_error"]:.2g} %' if r["reference"] != 0 else
                           f'{r["relative_error"]:.2e}' for r in rows)
        rich = "-"
        if s["richardson_value"] is not None and rows[-1]["reference"] != 0:
            rich = f'{100 * (s["richardson_value"] / rows[-1]["reference"] - 1):+.2f} % ' \
                   f'(p = {s["richardson_order"]:.2f})'
        case = f'{s["study"]}: {s["quantity"].split(",")[0]}'.replace("|", "\\|")
        lines.append(f'| {case} | {s["engine"]} | {s["poisson_ratio"]:g} | {ns} | {errors} | '
                     f'{fmt(s["observed_order"], ".2f")} / {fmt(s["fitted_order"], ".2f")} | '
                     f'{rich} |')
    for p in report["patch_test"]:
        lines.append(f'| patch_test: max error / max \\|G x\\| | {p["engine"]} | 0.3 | '
                     f'{p["resolution"]} | {p["max_relative_error"]:.1e} | - | - |')
    return "\n".join(lines)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    report = json.loads(Path(sys.argv[1]).read_text())
    out = Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    series = report["series"]

    def pick(*studies):
        return [s for s in series if s["study"] in studies]

    plot(pick("lame_sphere"), "Lamé hollow sphere: mean u_r at r = a and r = b",
         out / "validation_lame_sphere.png")
    plot(pick("cantilever_tip_force", "cantilever_gravity"),
         "Cantilever tip deflection vs Timoshenko", out / "validation_cantilever.png")
    plot(pick("disc"), "Paper's disc (Sec. 9.2, 2D): max error", out / "validation_disc.png", 1.0)
    print(markdown_table(report))


if __name__ == "__main__":
    main()
