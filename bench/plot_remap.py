"""Bar chart of bench_remap's table (read from stdin): panoproj against cv::remap (the faster of
its two map forms, given its maps for free) per conversion and kernel, with the memcpy floor.

    build-bench/bench/bench_remap --runs 11 | python bench/plot_remap.py docs/bench_remap.png
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(lines):
    """The table's rows as dicts (conversion, kernel, ours, cv, memcpy)."""
    for line in lines:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 8 or not cells[2].replace(".", "", 1).isdigit():
            continue
        left, _, right = cells[0].partition("->")
        yield dict(conversion=f"{left.split()[0]} -> {right.split()[0]}", kernel=cells[1].split(" ")[0], ours=float(cells[2]),
                   cv=min(float(cells[3]), float(cells[4])), memcpy=float(cells[5]))


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: bench_remap ... | python bench/plot_remap.py OUT.png")
    lines = sys.stdin.read().splitlines()
    data = list(rows(lines))
    if not data:
        sys.exit("plot_remap: no bench_remap table on stdin")
    labels = [f"{d['conversion']}\n{d['kernel']}" for d in data]
    x = range(len(data))
    fig, ax = plt.subplots(figsize=(11, 4.2), dpi=100)
    ax.bar([i - 0.2 for i in x], [d["cv"] for d in data], 0.4, label="cv::remap (maps given free)", color="#b0b0b0")
    ax.bar([i + 0.2 for i in x], [d["ours"] for d in data], 0.4, label="panoproj (geometry included)", color="#2a7ab0")
    ax.scatter(list(x), [d["memcpy"] for d in data], marker="_", s=400, color="black", label="memcpy of the output",
               zorder=3)
    for i, d in enumerate(data):
        ax.annotate(f"{d['ours'] / d['cv']:.2f}x", (i + 0.2, d["ours"]), ha="center", va="bottom", fontsize=8)
    ax.set_xticks(list(x))
    ax.set_xticklabels(labels, fontsize=8)
    ax.set_ylabel("ms (median, 2 threads)")
    ax.set_yscale("log")
    header = next((l for l in lines if l.startswith("panoproj")), "")
    ax.set_title(header, fontsize=9)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(sys.argv[1])


if __name__ == "__main__":
    main()
