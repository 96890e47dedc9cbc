#!/usr/bin/env python3
"""Draws the report's throughput plots from the results the benchmarks write:

- docs/suite_vs_envpool.png from bench/results/suite.json (``suite_bench.py --json``):
  each v5 id's ``make_vec`` against EnvPool's same task, per batch size, medians of the
  rounds with the range of the rounds' own ratios;
- docs/scaling.png from bench/results/scaling.json (``scaling.py --json``): env-steps/s
  against the envs of a batch, per thread count, gymfleet and EnvPool.

    python bench/plots.py            # needs matplotlib (the test venv has it)

Each plot names the commit, date and machine its file records.
"""

import json
import pathlib
import statistics

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent


def caption(result: dict) -> str:
    return f"{result['commit']}, {result['date']}, {result['machine']}"


def suite(result: dict, out: pathlib.Path) -> None:
    rows = result["rows"]
    names = list(dict.fromkeys(r["name"] for r in rows))
    sizes = sorted({r["envs"] for r in rows})
    fig, ax = plt.subplots(figsize=(9, 0.5 * len(names) * len(sizes) ** 0.5 + 1.6), dpi=100)
    height = 0.8 / len(sizes)
    colors = ["#4c72b0", "#dd8452", "#55a868", "#c44e52"]
    for k, n in enumerate(sizes):
        for i, name in enumerate(reversed(names)):
            row = next((r for r in rows if r["name"] == name and r["envs"] == n), None)
            if row is None:
                continue
            ratio = statistics.median(row["gymfleet"]) / statistics.median(row["envpool"])
            each = [g / e for g, e in zip(row["gymfleet"], row["envpool"])]
            y = i + ((len(sizes) - 1) / 2 - k) * height
            ax.barh(y, ratio, height=height * 0.9, color=colors[k % len(colors)],
                    label=f"{n} envs" if i == 0 else None)
            ax.plot([min(each), max(each)], [y, y], color="black", linewidth=0.8)
            ax.text(max(ratio, max(each)) + 0.04, y, f"{ratio:.2f}x", va="center", fontsize=8)
    ax.set_yticks(range(len(names)), [f"{n}-v5" for n in reversed(names)], fontsize=9)
    ax.axvline(1.0, color="black", linewidth=0.8)
    ax.axvline(1.5, color="gray", linewidth=0.8, linestyle="--")
    ax.set_xlabel("gymfleet make_vec / EnvPool env-steps/s (higher is better; "
                  "line: the rounds' range; dashed: 1.5x)")
    ax.set_title(f"Gymnasium's v5 tasks against EnvPool ({result['envpool_threads']} threads "
                 f"each)\n{caption(result)}", fontsize=9)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def scaling(result: dict, out: pathlib.Path) -> None:
    rows = result["rows"]
    names = list(dict.fromkeys(r["name"] for r in rows))
    fig, axes = plt.subplots(1, len(names), figsize=(6 * len(names), 4.5), dpi=100, squeeze=False)
    for ax, name in zip(axes[0], names):
        mine = [r for r in rows if r["name"] == name]
        for t, style in zip(sorted({r["threads"] for r in mine}), ["-", "--", ":", "-."]):
            line = sorted((r for r in mine if r["threads"] == t), key=lambda r: r["envs"])
            envs = [r["envs"] for r in line]
            for side, label, color in (("gymfleet", "gymfleet", "#4c72b0"),
                                       ("envpool", "EnvPool", "#dd8452")):
                rates = [statistics.median(r[side]) for r in line]
                ax.plot(envs, rates, style, marker="o", color=color,
                        label=f"{label}, {t} thread{'s' * (t > 1)}")
        ax.set_xscale("log", base=2)
        sizes = sorted({r["envs"] for r in mine})
        ax.set_xticks(sizes, [str(n) for n in sizes])
        ax.set_yscale("log")
        ax.set_xlabel("envs in the batch")
        ax.set_ylabel("env-steps/s (median of the rounds)")
        ax.set_title(f"{name}-v5", fontsize=10)
        ax.grid(True, which="both", linewidth=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"make_vec in process by batch size and threads: {caption(result)}", fontsize=9)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def main() -> None:
    results = ROOT / "bench/results"
    for name, draw, out in (("suite.json", suite, "suite_vs_envpool.png"),
                            ("scaling.json", scaling, "scaling.png")):
        path = results / name
        if path.exists():
            draw(json.loads(path.read_text()), ROOT / "docs" / out)
            print(f"docs/{out} from bench/results/{name}")
        else:
            print(f"bench/results/{name} is missing: docs/{out} not drawn")


if __name__ == "__main__":
    main()
