#!/usr/bin/python3
"""Smoke test of sightline-benchmark (ctest: sightline-benchmark-smoke, labels benchmark;display).

Runs the harness on a tiny sphere scene and checks what it wrote, not the timings: every method
has its row, the exact Sightline images (GL-free and in a window) match the Embree reference,
every tessellation is less accurate than the exact method, the images exist, and
plot_benchmarks.py makes its figure. Needs a display for the OpenGL methods (xvfb-run).
"""

import argparse
import csv
import math
import os
import shutil
import subprocess
import sys

COUNT = 2000
WIDTH, HEIGHT = 320, 240
TESSELLATIONS = [8, 16, 32]
EXACT_METHODS = ["sightline", "sightline-window"]
REFERENCE = "embree-builtin"

# The exact methods and the reference intersect the same spheres in float precision: they may
# differ on a handful of silhouette pixels and by rounding, nothing more.
MAX_EXACT_RGB_DIFF = 0.5  # mean |RGB difference|, 0-255
MAX_EXACT_COVERAGE_DIFF = 0.2  # percent of pixels
MAX_EXACT_DEPTH_P99 = 1e-5  # window depth


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def value(row, column):
    text = row[column]
    try:
        number = float(text)
    except ValueError:
        fail(f"{row['method']}: column {column} is not a number: {text!r}")
    if not math.isfinite(number):
        fail(f"{row['method']}: column {column} is not finite")
    return number


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--harness", required=True)
    parser.add_argument("--plot-script", required=True)
    parser.add_argument("--output", required=True)
    arguments = parser.parse_args()

    if os.path.isdir(arguments.output):
        shutil.rmtree(arguments.output)
    command = [arguments.harness, "--scene", "spheres", "--spheres", str(COUNT),
               "--width", str(WIDTH), "--height", str(HEIGHT), "--runs", "1",
               "--tessellation", ",".join(map(str, TESSELLATIONS)),
               "--output", arguments.output, "--no-plot"]
    print(" ".join(command), flush=True)
    if subprocess.run(command, timeout=100).returncode != 0:
        fail("the harness failed")

    csv_path = os.path.join(arguments.output, "spheres.csv")
    if not os.path.isfile(csv_path):
        fail(f"no {csv_path}")
    with open(csv_path, newline="") as stream:
        rows = list(csv.DictReader(stream))
    expected = [REFERENCE] + EXACT_METHODS + [f"vtk-tessellated-{r}" for r in TESSELLATIONS]
    methods = [row["method"] for row in rows]
    if sorted(methods) != sorted(expected):
        fail(f"methods in the CSV are {methods}, expected {expected}")
    by_method = {row["method"]: row for row in rows}

    for row in rows:
        name = row["method"]
        if row["status"] == "skipped":
            fail(f"{name}: {row['notes']}")
        wanted_status = "reference" if name == REFERENCE else "ok"
        if row["status"] != wanted_status:
            fail(f"{name}: status {row['status']}, expected {wanted_status}")
        size = (int(row["primitives"]), int(row["width"]), int(row["height"]))
        if size != (COUNT, WIDTH, HEIGHT):
            fail(f"{name}: wrong primitives or image size in the CSV")
        for column in ["frame_seconds_median", "frame_seconds_min", "bytes_per_primitive"]:
            if value(row, column) <= 0:
                fail(f"{name}: {column} must be positive")
        if value(row, "build_seconds") < 0 or value(row, "first_image_seconds") <= 0:
            fail(f"{name}: bad build or first-image time")
        # Every method sees the same framing: a well covered image that is not saturated.
        if not 5.0 < value(row, "hit_percent") < 95.0:
            fail(f"{name}: {row['hit_percent']}% of the pixels hit; the camera framing is off")
        for suffix in ["", "-crop"] + ([] if name == REFERENCE else ["-diff"]):
            image = os.path.join(arguments.output, "images", f"spheres-{COUNT}-{name}{suffix}.png")
            if not os.path.isfile(image) or os.path.getsize(image) == 0:
                fail(f"no image {image}")

    reference = by_method[REFERENCE]
    for column in ["rgb_mean_abs_diff", "coverage_diff_percent", "depth_max_abs_diff"]:
        if value(reference, column) != 0.0:
            fail(f"the reference differs from itself in {column}")

    for name in EXACT_METHODS:
        row = by_method[name]
        checks = [("rgb_mean_abs_diff", MAX_EXACT_RGB_DIFF),
                  ("coverage_diff_percent", MAX_EXACT_COVERAGE_DIFF),
                  ("depth_p99_abs_diff", MAX_EXACT_DEPTH_P99)]
        for column, limit in checks:
            if value(row, column) > limit:
                fail(f"{name}: {column} = {row[column]} exceeds {limit}: the exact spheres no "
                     "longer match Embree's")

    # Tessellated spheres are inscribed polygons: their silhouettes must differ from the exact
    # ones, the more so the coarser they are.
    exact_coverage = value(by_method["sightline"], "coverage_diff_percent")
    tessellated_coverage = []
    for resolution in TESSELLATIONS:
        row = by_method[f"vtk-tessellated-{resolution}"]
        coverage = value(row, "coverage_diff_percent")
        if coverage <= exact_coverage:
            fail(f"{row['method']} is as accurate as the exact spheres; the comparison is broken")
        if int(row["triangles"]) != COUNT * 2 * resolution * (resolution - 2):
            fail(f"{row['method']}: unexpected triangle count {row['triangles']}")
        tessellated_coverage.append(coverage)
    if tessellated_coverage[0] <= tessellated_coverage[-1]:
        fail("the coarsest tessellation is not less accurate than the finest")

    # The plot script, run as the harness would (it was told --no-plot to test the script here).
    plot = subprocess.run([sys.executable, arguments.plot_script, csv_path], timeout=60)
    plot_path = os.path.join(arguments.output, "spheres.png")
    if plot.returncode != 0 or not os.path.isfile(plot_path) or os.path.getsize(plot_path) < 10000:
        fail("plot_benchmarks.py did not write the plot")

    print(f"OK: {len(rows)} methods; exact error {by_method['sightline']['rgb_mean_abs_diff']} "
          f"(RGB), {exact_coverage}% coverage; plot {plot_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
