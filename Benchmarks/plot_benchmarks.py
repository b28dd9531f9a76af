#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Plots the CSV files written by sightline-benchmark.

For each <scene>.csv, writes <scene>.png next to it (or to --output): the median frame time
(log scale) of every method against its image error (mean RGB difference and coverage
difference against the reference method), and a bar chart of the bytes each method holds per
primitive. Methods named GROUP:NAME (a scene that renders several data sets, each with its own
reference, e.g. sh-glyphs' k4:sightline) get one row of panels per GROUP, and a method keeps
its colour across groups. When the CSV has interactive frame times (sh-glyph-window), a fourth
panel per row shows what a window user waits for: time to the first image, still and interactive
frames and the scene's update (e.g. a ScaleFactor change), per method. Needs matplotlib (Debian: python3-matplotlib); run with
/usr/bin/python3.

    /usr/bin/python3 plot_benchmarks.py RESULTS/spheres.csv [MORE.csv ...] [--output FILE.png]
"""

import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)


def number(text):
    """A CSV number, or None for an empty (not measured) field."""
    try:
        value = float(text)
    except (TypeError, ValueError):
        return None
    return value if math.isfinite(value) else None


def read_rows(path):
    with open(path, newline="") as stream:
        return [row for row in csv.DictReader(stream)]


def split_method(method):
    """(group, name) of a method: "k4:sightline" -> ("k4", "sightline"); no group -> ""."""
    group, separator, name = method.partition(":")
    return (group, name) if separator else ("", method)


def method_colors(methods):
    """One colour per method name (without its group), so a method looks alike in every group."""
    names = list(dict.fromkeys(split_method(method)[1] for method in methods))
    palette = plt.get_cmap("tab10" if len(names) <= 10 else "tab20")
    size = 10 if len(names) <= 10 else 20
    by_name = {name: palette(i % size) for i, name in enumerate(names)}
    return {method: by_name[split_method(method)[1]] for method in methods}


def short_count(count):
    count = int(count)
    if count >= 1000000 and count % 1000000 == 0:
        return f"{count // 1000000}M"
    if count >= 1000 and count % 1000 == 0:
        return f"{count // 1000}k"
    return str(count)


def plot_time_against_error(axis, rows, colors, markers, error_column, error_label):
    largest_error = 0.0
    labels_near = {}  # methods often coincide (sightline and sightline-window): stack labels
    for row in rows:
        time = number(row["frame_seconds_median"])
        error = number(row[error_column])
        if time is None or error is None:
            continue
        largest_error = max(largest_error, error)
        axis.scatter(error, time, color=colors[row["method"]], marker=markers[row["primitives"]],
                     s=60, edgecolors="black", linewidths=0.5, zorder=3)
        near = (round(math.log10(time) * 12), round(math.asinh(error / 0.01) * 2))
        stacked = labels_near.get(near, 0)
        labels_near[near] = stacked + 1
        axis.annotate(f"{split_method(row['method'])[1]} ({short_count(row['primitives'])})",
                      (error, time),
                      textcoords="offset points", xytext=(6, 4 - 9 * stacked), fontsize=7)
    axis.set_yscale("log")
    # The reference has zero error by definition: a symmetric-log axis shows it next to the rest.
    # Margins keep the markers at zero and at the largest error inside the axes.
    axis.set_xscale("symlog", linthresh=0.01)
    axis.set_xlim(left=-0.003, right=max(0.1, largest_error * 4.0))
    axis.set_xlabel(error_label)
    axis.set_ylabel("median frame time [s] (log)")
    axis.grid(True, which="both", alpha=0.3)


def plot_bytes(axis, rows, colors, counts):
    methods = list(dict.fromkeys(row["method"] for row in rows))
    width = 0.8 / max(1, len(counts))
    for c, count in enumerate(counts):
        by_method = {row["method"]: number(row["bytes_per_primitive"])
                     for row in rows if row["primitives"] == count}
        for m, method in enumerate(methods):
            value = by_method.get(method)
            if value is None:
                continue
            bar = axis.bar(m + (c - (len(counts) - 1) / 2) * width, value, width,
                           color=colors[method], edgecolor="black", linewidth=0.5,
                           hatch=None if c == 0 else "//")
            axis.bar_label(bar, fmt="%.0f", fontsize=6, padding=1)
    axis.set_xticks(range(len(methods)))
    axis.set_xticklabels([split_method(method)[1] for method in methods], rotation=30, ha="right",
                         fontsize=8)
    axis.set_yscale("log")
    axis.set_ylabel("bytes per primitive (log)")
    axis.set_title("memory: " + ", ".join(f"{short_count(c)}" + ("" if i == 0 else " (hatched)")
                                          for i, c in enumerate(counts)), fontsize=9)
    axis.grid(True, axis="y", which="both", alpha=0.3)


TIME_COLUMNS = [("first_image_seconds", "first image"), ("frame_seconds_median", "still frame"),
                ("interactive_frame_seconds_median", "interactive frame"),
                ("update_seconds", "update + frame")]


def has_interactive_times(rows):
    return any(number(row.get("interactive_frame_seconds_median")) is not None for row in rows)


def plot_times(axis, rows):
    """Grouped bars: for each method, the times a window user waits for (log scale)."""
    methods = list(dict.fromkeys(row["method"] for row in rows))
    by_method = {row["method"]: row for row in rows}
    width = 0.8 / len(TIME_COLUMNS)
    palette = plt.get_cmap("Set2")
    for c, (column, label) in enumerate(TIME_COLUMNS):
        for m, method in enumerate(methods):
            value = number(by_method[method].get(column))
            if value is None:
                continue
            bar = axis.bar(m + (c - (len(TIME_COLUMNS) - 1) / 2) * width, value, width,
                           color=palette(c), edgecolor="black", linewidth=0.5,
                           label=label if m == next(i for i, name in enumerate(methods)
                                                    if number(by_method[name].get(column))
                                                    is not None) else None)
            axis.bar_label(bar, fmt="%.2g", fontsize=6, padding=1)
    axis.set_xticks(range(len(methods)))
    axis.set_xticklabels([split_method(method)[1] for method in methods], rotation=30, ha="right",
                         fontsize=8)
    axis.set_yscale("log")
    axis.set_ylabel("seconds (log)")
    axis.legend(fontsize=7, loc="upper left")
    axis.grid(True, axis="y", which="both", alpha=0.3)


def has_integral_errors(rows):
    return any(number(row.get("integral_rms_error")) is not None and row["status"] == "ok"
               for row in rows)


def plot_integral_scenes(row_sets, output):
    """Spherical scenes (thesis Figures 6.11-6.14): for each scene the RMS error of the ray
    integrals against the frame time, one point per grid resolution N; then frame time against
    N (first scene)."""
    panels = len(row_sets) + 1
    columns = min(panels, 2)
    rows_of_panels = (panels + columns - 1) // columns
    figure, grid = plt.subplots(rows_of_panels, columns, figsize=(6.5 * columns, 5.2 * rows_of_panels),
                                squeeze=False)
    axes = [axis for row in grid for axis in row][:panels]
    methods = list(dict.fromkeys(r["method"] for rows in row_sets for r in rows if r["status"] == "ok"))
    colors = method_colors(methods)
    for axis, rows in zip(axes, row_sets):
        measured = [row for row in rows if row["status"] == "ok"]
        for method in dict.fromkeys(r["method"] for r in measured):
            points = [(number(r["frame_seconds_median"]), number(r["integral_rms_error"]), r["primitives"])
                      for r in measured if r["method"] == method]
            # Machine-precision errors are drawn at 1e-16 so that the log axis keeps them.
            points = [(t, max(e, 1e-16), n) for t, e, n in points if t and e is not None]
            if not points:
                continue
            axis.plot([p[0] for p in points], [p[1] for p in points], "o-", color=colors[method],
                      label=method)
            for t, e, n in points:
                axis.annotate(n, (t, e), fontsize=7, xytext=(3, 3), textcoords="offset points")
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("frame time [s] (median)")
        axis.set_ylabel("RMS error of the ray integrals (labels: N)")
        axis.set_title(f"{rows[0]['scene']}: error against run time (cartesian-resampled and "
                       "-exact-samples overlap where they agree)", fontsize=8)
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize=7)
    timing = axes[-1]
    first_rows = [row for row in row_sets[0] if row["status"] == "ok"]
    for method in dict.fromkeys(r["method"] for r in first_rows):
        timed = [(int(r["primitives"]), number(r["frame_seconds_median"])) for r in first_rows
                 if r["method"] == method]
        timing.plot([p[0] for p in timed], [p[1] for p in timed], "o-", color=colors[method],
                    label=method)
    timing.set_xscale("log", base=2)
    timing.set_yscale("log")
    timing.set_xlabel("grid resolution N per axis")
    timing.set_ylabel("frame time [s] (median)")
    timing.set_title(f"{row_sets[0][0]['scene']}: run time against resolution", fontsize=9)
    timing.grid(True, which="both", alpha=0.3)
    timing.legend(fontsize=7)
    first = row_sets[0][0]
    figure.suptitle(f"sightline-benchmark spherical scenes, {first['width']}x{first['height']} rays "
                    f"parallel to x; {first['cpu_model']}, {first['logical_cores']} cores, "
                    f"load {first['load_average']}", fontsize=9)
    figure.tight_layout()
    figure.savefig(output, dpi=100)
    plt.close(figure)
    print(f"plot: {output}")


def plot_csv(path, output):
    rows = read_rows(path)
    if not rows:
        raise SystemExit(f"{path}: no rows")
    if has_integral_errors(rows):
        plot_integral_scenes([rows], output)
        return
    measured = [row for row in rows if row["status"] != "skipped"]
    scene = rows[0]["scene"]
    methods = list(dict.fromkeys(row["method"] for row in rows))
    counts = list(dict.fromkeys(row["primitives"] for row in rows))
    colors = method_colors(methods)
    marker_cycle = ["o", "s", "^", "D", "v", "P"]
    markers = {count: marker_cycle[i % len(marker_cycle)] for i, count in enumerate(counts)}

    groups = list(dict.fromkeys(split_method(row["method"])[0] for row in rows))
    columns = 4 if has_interactive_times(measured) else 3
    figure, axes = plt.subplots(len(groups), columns, figsize=(6 * columns, 6 * len(groups)),
                                squeeze=False)
    for g, group in enumerate(groups):
        in_group = [row for row in measured if split_method(row["method"])[0] == group]
        title = f"{group}: " if group else ""
        plot_time_against_error(axes[g][0], in_group, colors, markers, "rgb_mean_abs_diff",
                                "mean |RGB difference| to the reference (0-255)")
        plot_time_against_error(axes[g][1], in_group, colors, markers, "coverage_diff_percent",
                                "pixels whose coverage differs from the reference [%]")
        plot_bytes(axes[g][2], in_group, colors, counts)
        axes[g][0].set_title(title + "frame time against colour error", fontsize=9)
        axes[g][1].set_title(title + "frame time against silhouette (coverage) error", fontsize=9)
        if title:
            axes[g][2].set_title(title + axes[g][2].get_title(), fontsize=9)
        if columns == 4:
            plot_times(axes[g][3], in_group)
            axes[g][3].set_title(title + "what a window user waits for", fontsize=9)

    first = rows[0]
    skipped = [f"{row['method']} ({short_count(row['primitives'])})"
               for row in rows if row["status"] == "skipped"]
    figure.suptitle(
        f"sightline-benchmark '{scene}', {first['width']}x{first['height']}, "
        f"counts {', '.join(short_count(c) for c in counts)} (markers "
        + ", ".join(f"{markers[c]} {short_count(c)}" for c in counts) + ")\n"
        f"{first['cpu_model']}, {first['logical_cores']} cores, {first['tbb_threads']} TBB threads;"
        f" OpenGL: {first['gl_renderer']}"
        + (f"\nskipped: {', '.join(skipped)}" if skipped else ""),
        fontsize=9)
    # Keep the suptitle (up to three lines) clear of the top row of panels.
    figure.tight_layout(rect=(0, 0, 1, 1 - 0.7 / figure.get_figheight()))
    figure.savefig(output, dpi=110)
    plt.close(figure)
    print(f"plot: {output}")


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", nargs="+", help="CSV files written by sightline-benchmark")
    parser.add_argument("--output", help="output PNG (only with a single CSV, or several "
                        "spherical-* CSVs drawn side by side); "
                        "default <csv directory>/<scene>.png")
    arguments = parser.parse_args()
    if arguments.output and len(arguments.csv) != 1:
        # Several spherical scenes side by side in one figure.
        row_sets = [read_rows(path) for path in arguments.csv]
        if all(rows and has_integral_errors(rows) for rows in row_sets):
            plot_integral_scenes(row_sets, arguments.output)
            return 0
        parser.error("--output needs exactly one CSV (or several spherical-* CSVs)")
    for path in arguments.csv:
        if arguments.output:
            output = arguments.output
        else:
            rows = read_rows(path)
            scene = rows[0]["scene"] if rows else os.path.splitext(os.path.basename(path))[0]
            output = os.path.join(os.path.dirname(os.path.abspath(path)), scene + ".png")
        plot_csv(path, output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
