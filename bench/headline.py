#!/usr/bin/env python3
"""Draws the README's picture, docs/headline.png, from bench/headline.json: each headline
ratio as a bar from its lowest to its highest measured value, on a log scale, against 1x.

    python bench/headline.py            # needs matplotlib (the test venv has it)
"""

import json
import pathlib

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent


def main():
    rows = json.loads((ROOT / "bench/headline.json").read_text())["rows"]
    fig, ax = plt.subplots(figsize=(10, 0.55 * len(rows) + 1.0), dpi=100)
    for i, row in enumerate(reversed(rows)):
        low, high = row["low"], row["high"]
        ax.barh(i, high - low if high > low else 0.02 * low, left=low, height=0.5, color="#4c72b0")
        label = f"{low:.2f}x" if high == low else f"{low:.2f}-{high:.2f}x"
        ax.text(high * 1.04, i, label, va="center", fontsize=9)
    ax.set_yticks(range(len(rows)), [r["what"] for r in reversed(rows)], fontsize=9)
    ax.set_xscale("log")
    ax.set_xlim(0.3, 8)
    ticks = [0.5, 1, 2, 4]
    ax.xaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.set_xticklabels([f"{t:g}x" for t in ticks])
    ax.axvline(1.0, color="black", linewidth=0.8)
    ax.set_xlabel("gymfleet / peer (higher is better; 1x = parity)")
    ax.set_title("gymfleet's headline ratios (BENCHMARKS.md)", fontsize=10)
    fig.tight_layout()
    out = ROOT / "docs/headline.png"
    fig.savefig(out)
    print(f"wrote {out.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
