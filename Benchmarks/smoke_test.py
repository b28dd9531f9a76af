#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Smoke test of sightline-benchmark (ctest: sightline-benchmark-smoke, labels benchmark;display,
sightline-benchmark-smoke-sh-glyphs, label benchmark, and sightline-benchmark-smoke-sh-glyph-window,
labels benchmark;display), and sightline-benchmark-smoke-tensor-glyphs, label benchmark.

--scene spheres (the default) runs the harness on a tiny sphere scene and checks what it wrote,
not the timings: every method has its row, the exact Sightline images (GL-free and in a window)
match the Embree reference, every tessellation is less accurate than the exact method, the images
exist, and plot_benchmarks.py makes its figure. Needs a display for the OpenGL methods
(xvfb-run).

--scene sh-glyphs runs a 12x12 slice of SH glyphs at 160x90 (no display needed) and checks that
every data set (k4, k8, dipy) has every method's row, the exact method matches its converged
reference, ray marching is less accurate than the exact method, coarser icosphere tessellations
are less accurate than finer ones, marching with near-exact boxes draws what marching with the
bounding sphere's boxes draws, the images and the intersection-cost CSV exist, and the plot script
makes its figure.

--scene sh-glyph-window runs a 12x12 tile of real SH glyphs at 192x108 in render windows (needs a
display; --data-dir keeps the generated data between runs, its first generation takes about 30 s)
and checks that k8 and k4 each have the Sightline row and both DIPY-sphere mesh rows with every
measurement (first image, still and interactive frames, memory, RSS, Sightline's ScaleFactor
update with no box recomputed), that the meshes line up with Sightline's exact glyphs (small
errors, so basis, size and colours agree) and that the coarser sphere is the less accurate.

--scene tensor-glyphs runs a 6x6 slice of tensor glyphs at 160x90 (no display needed) and checks
that every data set (cu4, hot8, hot12) has every method's row, the exact method and the fine
reduced affine subdivision match the converged reference, the paper's recommended marching
(step 0.2) is less accurate than the exact method and step 0.01 more accurate than step 0.2,
the intersection-cost CSV has positive costs, and the plot script makes its figure.

--scene tubes runs a neuron assembly of about 4,000 links at 200x150 (no display needed) and
checks that every method has its row, the four Sightline link layouts and the CSG path at
opacity 1 draw what Embree's round linear curves draw, the translucent frame differs from it,
and vtkTubeFilter with more sides is more accurate and uses more memory than with fewer.

--scene spherical runs spherical-step-aligned and spherical-r2 at N = 8 and 16 on 64x64 rays (no
display needed) and checks that the native projections are exact where they must be (the step on
a breakpoint; r^2 through the linear-in-r^2 sampler), that cell-constant r^2 beats Cartesian
resampling at equal N, that Cartesian resampling converges, and that the combined plot is made.
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


def csv_file(arguments, scene):
    return os.path.join(arguments.output, f"{scene}.csv")


def read_rows(arguments, scene, expected):
    """The scene's CSV rows, after checking that exactly the `expected` methods are there."""
    csv_path = csv_file(arguments, scene)
    if not os.path.isfile(csv_path):
        fail(f"no {csv_path}")
    with open(csv_path, newline="") as stream:
        rows = list(csv.DictReader(stream))
    methods = [row["method"] for row in rows]
    if sorted(methods) != sorted(expected):
        fail(f"methods in the CSV are {methods}, expected {expected}")
    return rows, {row["method"]: row for row in rows}


def check_size(row, count, width, height):
    size = (int(row["primitives"]), int(row["width"]), int(row["height"]))
    if size != (count, width, height):
        fail(f"{row['method']}: wrong primitives or image size in the CSV: {size}")


def check_spheres(arguments):
    if os.path.isdir(arguments.output):
        shutil.rmtree(arguments.output)
    command = [arguments.harness, "--scene", "spheres", "--spheres", str(COUNT),
               "--width", str(WIDTH), "--height", str(HEIGHT), "--runs", "1",
               "--tessellation", ",".join(map(str, TESSELLATIONS)),
               "--output", arguments.output, "--no-plot"]
    print(" ".join(command), flush=True)
    if subprocess.run(command, timeout=100).returncode != 0:
        fail("the harness failed")

    expected = [REFERENCE] + EXACT_METHODS + [f"vtk-tessellated-{r}" for r in TESSELLATIONS]
    rows, by_method = read_rows(arguments, "spheres", expected)

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
    plot = subprocess.run([sys.executable, arguments.plot_script, csv_file(arguments, "spheres")],
                          timeout=60)
    plot_path = os.path.join(arguments.output, "spheres.png")
    if plot.returncode != 0 or not os.path.isfile(plot_path) or os.path.getsize(plot_path) < 10000:
        fail("plot_benchmarks.py did not write the plot")

    print(f"OK: {len(rows)} methods; exact error {by_method['sightline']['rgb_mean_abs_diff']} "
          f"(RGB), {exact_coverage}% coverage; plot {plot_path}")
    return 0


SH_SIDE = 12
SH_WIDTH, SH_HEIGHT = 160, 90
SH_DATASETS = ["k4", "k8", "dipy"]
SH_LEVELS = [1, 2]  # icosphere levels, given to the harness as vertex counts 42, 162
SH_METHODS = (["reference", "sightline", "march-100-cyl", "march-100-aabb", "march-200-cyl",
               "march-200-aabb"] + [f"tess-L{level}" for level in SH_LEVELS]
              + ["boxes-only", "hard-shadows", "soft-shadows-16", "uncertainty",
                 "uncertainty-soft-shadows"])
# The default exact method against the converged reference (tolerance 1e-6 vs 1e-10, both in
# double): the same pixels up to an 8-bit rounding here and there.
MAX_SH_EXACT_RGB_DIFF = 0.05
MAX_SH_EXACT_COVERAGE_DIFF = 0.05


def check_sh_glyphs(arguments):
    if os.path.isdir(arguments.output):
        shutil.rmtree(arguments.output)
    count = SH_SIDE * SH_SIDE
    vertices = [10 * 4 ** level + 2 for level in SH_LEVELS]
    command = [arguments.harness, "--scene", "sh-glyphs", "--count", str(count),
               "--width", str(SH_WIDTH), "--height", str(SH_HEIGHT), "--runs", "1",
               "--tessellation", ",".join(map(str, vertices)),
               "--output", arguments.output, "--no-plot"]
    print(" ".join(command), flush=True)
    if subprocess.run(command, timeout=150).returncode != 0:
        fail("the harness failed")

    expected = [f"{d}:{m}" for d in SH_DATASETS for m in SH_METHODS]
    rows, by_method = read_rows(arguments, "sh-glyphs", expected)

    for row in rows:
        name = row["method"]
        if row["status"] != "ok":
            fail(f"{name}: status {row['status']} ({row['notes']})")
        check_size(row, count, SH_WIDTH, SH_HEIGHT)
        for column in ["frame_seconds_median", "bytes_per_primitive", "first_image_seconds"]:
            if value(row, column) <= 0:
                fail(f"{name}: {column} must be positive")
        if value(row, "build_seconds") < 0:
            fail(f"{name}: negative build time")
        if not 1.0 < value(row, "hit_percent") < 95.0:
            fail(f"{name}: {row['hit_percent']}% of the pixels hit; the camera framing is off")
        suffixes = ["", "-crop"] + ([] if name.endswith(":reference") else ["-diff"])
        for suffix in suffixes:
            image = os.path.join(arguments.output, "images", f"sh-glyphs-{count}-{name}{suffix}.png")
            if not os.path.isfile(image) or os.path.getsize(image) == 0:
                fail(f"no image {image}")

    def error(name, column="rgb_mean_abs_diff"):
        return value(by_method[name], column)

    for dataset in SH_DATASETS:
        reference = f"{dataset}:reference"
        for column in ["rgb_mean_abs_diff", "coverage_diff_percent"]:
            if error(reference, column) != 0.0:
                fail(f"{reference} differs from itself in {column}")
        exact = f"{dataset}:sightline"
        if error(exact) > MAX_SH_EXACT_RGB_DIFF or \
                error(exact, "coverage_diff_percent") > MAX_SH_EXACT_COVERAGE_DIFF:
            fail(f"{exact}: RGB error {error(exact)}, coverage error "
                 f"{error(exact, 'coverage_diff_percent')}: the exact method does not match its "
                 "converged reference")
        exact_total = error(exact) + error(exact, "coverage_diff_percent")
        for steps in (100, 200):
            cylinder, tight = f"{dataset}:march-{steps}-cyl", f"{dataset}:march-{steps}-aabb"
            # Same marching, other boxes: the near-exact boxes must not cut anything off.
            if abs(error(cylinder) - error(tight)) > 0.01:
                fail(f"{cylinder} and {tight} draw different images: the tight boxes lose hits")
        marching = f"{dataset}:march-100-cyl"
        if error(marching) + error(marching, "coverage_diff_percent") <= exact_total:
            fail(f"{marching} is as accurate as the exact method; the comparison is broken")
        coarse, fine = (f"{dataset}:tess-L{level}" for level in SH_LEVELS)
        if not error(coarse) > error(fine) > error(exact):
            fail(f"{dataset}: tessellation errors {error(coarse)} (L{SH_LEVELS[0]}), {error(fine)} "
                 f"(L{SH_LEVELS[1]}) do not decrease towards the exact method's {error(exact)}")
        for level, row in zip(SH_LEVELS, (by_method[coarse], by_method[fine])):
            if int(row["triangles"]) != count * 20 * 4 ** level:
                fail(f"{row['method']}: unexpected triangle count {row['triangles']}")
        if value(by_method[f"{dataset}:boxes-only"], "hit_percent") <= \
                value(by_method[reference], "hit_percent"):
            fail(f"{dataset}: the glyphs' boxes cover no more pixels than the glyphs")

    micro_path = os.path.join(arguments.output, "sh-glyphs-intersection.csv")
    if not os.path.isfile(micro_path):
        fail(f"no {micro_path}")
    with open(micro_path, newline="") as stream:
        micro = list(csv.DictReader(stream))
    if sorted(row["order"] for row in micro) != ["4", "8"]:
        fail(f"{micro_path}: expected rows for k = 4 and 8")
    for row in micro:
        for column in ["aabb_us_per_glyph_1thread", "exact_hit_ns", "exact_miss_ns",
                       "march200_cylinder_hit_ns", "march200_cylinder_miss_ns"]:
            if not float(row[column]) > 0:
                fail(f"{micro_path}: {column} = {row[column]} for k = {row['order']}")

    plot = subprocess.run([sys.executable, arguments.plot_script, csv_file(arguments, "sh-glyphs")],
                          timeout=60)
    plot_path = os.path.join(arguments.output, "sh-glyphs.png")
    if plot.returncode != 0 or not os.path.isfile(plot_path) or os.path.getsize(plot_path) < 10000:
        fail("plot_benchmarks.py did not write the plot")

    print(f"OK: {len(rows)} rows; exact RGB errors "
          + ", ".join(f"{d} {error(d + ':sightline')}" for d in SH_DATASETS)
          + "; marching-100 " + ", ".join(f"{d} {error(d + ':march-100-cyl')}" for d in SH_DATASETS)
          + f"; plot {plot_path}")
    return 0


TENSOR_SIDE = 6
TENSOR_WIDTH, TENSOR_HEIGHT = 160, 90
TENSOR_DATASETS = ["cu4", "hot8", "hot12"]
TENSOR_METHODS = ["reference", "sightline", "march-0.2-lin", "march-0.2-lin-nocentre",
                  "march-0.2-bisect3", "march-0.1-lin", "march-0.05-lin", "march-0.02-lin",
                  "march-0.01-lin", "ia-1e-3", "raa-1e-3", "raa-1e-4"]


def check_tensor_glyphs(arguments):
    if os.path.isdir(arguments.output):
        shutil.rmtree(arguments.output)
    count = TENSOR_SIDE * TENSOR_SIDE
    command = [arguments.harness, "--scene", "tensor-glyphs", "--count", str(count),
               "--width", str(TENSOR_WIDTH), "--height", str(TENSOR_HEIGHT), "--runs", "1",
               "--output", arguments.output, "--no-plot"]
    print(" ".join(command), flush=True)
    if subprocess.run(command, timeout=150).returncode != 0:
        fail("the harness failed")
    expected = [f"{d}:{m}" for d in TENSOR_DATASETS for m in TENSOR_METHODS]
    rows, by_method = read_rows(arguments, "tensor-glyphs", expected)
    for row in rows:
        if row["status"] != "ok":
            fail(f"{row['method']}: status {row['status']} ({row['notes']})")
        check_size(row, count, TENSOR_WIDTH, TENSOR_HEIGHT)
        if value(row, "frame_seconds_median") <= 0:
            fail(f"{row['method']}: no frame time")

    def error(name):
        return value(by_method[name], "rgb_mean_abs_diff") + \
            value(by_method[name], "coverage_diff_percent")

    for dataset in TENSOR_DATASETS:
        if error(f"{dataset}:reference") != 0.0:
            fail(f"{dataset}:reference differs from itself")
        exact = error(f"{dataset}:sightline")
        if exact > 0.05 or error(f"{dataset}:raa-1e-4") > 0.05:
            fail(f"{dataset}: the exact method ({exact}) or the fine affine subdivision "
                 f"({error(dataset + ':raa-1e-4')}) does not match the converged reference")
        coarse, fine = error(f"{dataset}:march-0.2-lin"), error(f"{dataset}:march-0.01-lin")
        if not coarse > exact or not coarse > fine:
            fail(f"{dataset}: marching errors {coarse} (step 0.2), {fine} (step 0.01) against the "
                 f"exact method's {exact}: the comparison is broken")

    micro_path = os.path.join(arguments.output, "tensor-glyphs-intersection.csv")
    if not os.path.isfile(micro_path):
        fail(f"no {micro_path}")
    with open(micro_path, newline="") as stream:
        micro = list(csv.DictReader(stream))
    if len(micro) != len(TENSOR_DATASETS) * 5:
        fail(f"{micro_path}: {len(micro)} rows")
    for row in micro:
        if not float(row["hit_ns"]) > 0 or not float(row["miss_ns"]) > 0:
            fail(f"{micro_path}: no cost for {row['dataset']} {row['method']}")

    plot = subprocess.run([sys.executable, arguments.plot_script,
                           csv_file(arguments, "tensor-glyphs")], timeout=60)
    plot_path = os.path.join(arguments.output, "tensor-glyphs.png")
    if plot.returncode != 0 or not os.path.isfile(plot_path) or os.path.getsize(plot_path) < 10000:
        fail("plot_benchmarks.py did not write the plot")
    print(f"OK: {len(rows)} rows; exact errors "
          + ", ".join(f"{d} {error(d + ':sightline'):.3g}" for d in TENSOR_DATASETS)
          + "; marching 0.2 " + ", ".join(f"{d} {error(d + ':march-0.2-lin'):.3g}"
                                          for d in TENSOR_DATASETS) + f"; plot {plot_path}")
    return 0


WINDOW_SIDE = 12
WINDOW_WIDTH, WINDOW_HEIGHT = 192, 108
WINDOW_ORDERS = ["k8", "k4"]
WINDOW_SPHERES = [724, 100]
# The meshes sample the same |F| on DIPY's spheres: at 8 px per glyph they differ from the
# exact glyphs on silhouettes only. A wrong basis, size or colour gives errors of 10 and more.
MAX_WINDOW_MESH_RGB_DIFF = 6.0


def check_sh_glyph_window(arguments):
    if os.path.isdir(arguments.output):
        shutil.rmtree(arguments.output)
    count = WINDOW_SIDE * WINDOW_SIDE
    command = [arguments.harness, "--scene", "sh-glyph-window", "--count", str(count),
               "--width", str(WINDOW_WIDTH), "--height", str(WINDOW_HEIGHT), "--runs", "3",
               "--tessellation", ",".join(map(str, WINDOW_SPHERES)),
               "--output", arguments.output, "--no-plot"]
    if arguments.data_dir:
        command += ["--data-dir", arguments.data_dir]
    print(" ".join(command), flush=True)
    if subprocess.run(command, timeout=110).returncode != 0:
        fail("the harness failed")

    meshes = [f"dipy-repulsion{vertices}" for vertices in WINDOW_SPHERES]
    expected = [f"{k}:{m}" for k in WINDOW_ORDERS for m in ["sightline"] + meshes]
    rows, by_method = read_rows(arguments, "sh-glyph-window", expected)

    for row in rows:
        name = row["method"]
        if row["status"] != "ok":
            fail(f"{name}: status {row['status']} ({row['notes']})")
        check_size(row, count, WINDOW_WIDTH, WINDOW_HEIGHT)
        for column in ["first_image_seconds", "frame_seconds_median",
                       "interactive_frame_seconds_median", "memory_bytes", "bytes_per_primitive"]:
            if value(row, column) <= 0:
                fail(f"{name}: {column} must be positive")
        value(row, "rss_increase_bytes")  # measured (its sign depends on the allocator)
        if not 1.0 < value(row, "hit_percent") < 95.0:
            fail(f"{name}: {row['hit_percent']}% of the pixels hit; the camera framing is off")
        suffixes = ["", "-crop"] + ([] if name.endswith(":sightline") else ["-diff"])
        for suffix in suffixes:
            image = os.path.join(arguments.output, "images",
                                 f"sh-glyph-window-{count}-{name}{suffix}.png")
            if not os.path.isfile(image) or os.path.getsize(image) == 0:
                fail(f"no image {image}")

    for k in WINDOW_ORDERS:
        exact = by_method[f"{k}:sightline"]
        if value(exact, "rgb_mean_abs_diff") != 0.0:
            fail(f"{k}:sightline differs from itself")
        if value(exact, "update_seconds") <= 0:
            fail(f"{k}:sightline: the ScaleFactor update was not timed")
        if "boxes computed on update: 0," not in exact["notes"]:
            fail(f"{k}:sightline: the ScaleFactor update recomputed boxes: {exact['notes']}")
        errors = []
        for mesh in meshes:
            row = by_method[f"{k}:{mesh}"]
            error = value(row, "rgb_mean_abs_diff")
            if not 0.0 < error < MAX_WINDOW_MESH_RGB_DIFF:
                fail(f"{k}:{mesh}: RGB error {error} against the exact glyphs; the mesh does not "
                     "line up with Sightline's glyphs (basis, size or colours)")
            if int(row["triangles"]) <= 0:
                fail(f"{k}:{mesh}: no triangle count")
            errors.append(error)
        if not errors[0] < errors[-1]:
            fail(f"{k}: the {WINDOW_SPHERES[0]}-vertex mesh ({errors[0]}) is not more accurate "
                 f"than the {WINDOW_SPHERES[-1]}-vertex one ({errors[-1]})")

    plot = subprocess.run([sys.executable, arguments.plot_script, csv_file(arguments, "sh-glyph-window")],
                          timeout=60)
    plot_path = os.path.join(arguments.output, "sh-glyph-window.png")
    if plot.returncode != 0 or not os.path.isfile(plot_path) or os.path.getsize(plot_path) < 10000:
        fail("plot_benchmarks.py did not write the plot")

    print(f"OK: {len(rows)} rows; mesh RGB errors "
          + ", ".join(f"{k}:{m} {by_method[k + ':' + m]['rgb_mean_abs_diff']}"
                      for k in WINDOW_ORDERS for m in meshes)
          + f"; plot {plot_path}")
    return 0


TUBE_LINKS = 4000
TUBE_WIDTH, TUBE_HEIGHT = 200, 150
TUBE_EXACT = ["sightline:combined-on-the-fly", "sightline:combined-precomputed",
              "sightline:separate-on-the-fly", "sightline:separate-precomputed",
              "sightline:chunked-4", "sightline:chunked-8", "sightline:chunked-16",
              "sightline:chunked-32", "sightline-csg"]
TUBE_FILTER_SIDES = [6, 12, 24]


def check_tubes(arguments):
    if os.path.isdir(arguments.output):
        shutil.rmtree(arguments.output)
    command = [arguments.harness, "--scene", "tubes", "--count", str(TUBE_LINKS),
               "--width", str(TUBE_WIDTH), "--height", str(TUBE_HEIGHT), "--runs", "1",
               "--output", arguments.output, "--no-plot"]
    print(" ".join(command), flush=True)
    if subprocess.run(command, timeout=150).returncode != 0:
        fail("the harness failed")
    methods = ["embree-round-curves"] + TUBE_EXACT + ["sightline-translucent-0.4"] + \
        [f"vtk-tube-filter-{n}" for n in TUBE_FILTER_SIDES]
    rows, by_method = read_rows(arguments, "tubes", [f"neurons:{m}" for m in methods])
    for row in rows:
        if row["status"] == "skipped":
            fail(f"{row['method']}: {row['notes']}")
        if value(row, "frame_seconds_median") <= 0 or value(row, "bytes_per_primitive") <= 0:
            fail(f"{row['method']}: no frame time or memory")

    def error(name):
        row = by_method["neurons:" + name]
        return value(row, "rgb_mean_abs_diff") + value(row, "coverage_diff_percent")

    for name in TUBE_EXACT:
        if error(name) > 0.05:
            fail(f"{name} does not draw what Embree's round linear curves draw: error {error(name)}")
    if not error("sightline-translucent-0.4") > 0.5:
        fail("the translucent frame looks like the opaque reference")
    filters = [error(f"vtk-tube-filter-{n}") for n in TUBE_FILTER_SIDES]
    memory = [value(by_method[f"neurons:vtk-tube-filter-{n}"], "bytes_per_primitive") for n in TUBE_FILTER_SIDES]
    if not (filters[0] > filters[-1] > error(TUBE_EXACT[0])) or not memory[0] < memory[-1]:
        fail(f"vtkTubeFilter errors {filters} / bytes {memory}: the comparison is broken")
    print(f"OK: {len(rows)} rows; exact layouts within {max(error(n) for n in TUBE_EXACT):.3g}; "
          f"vtkTubeFilter errors {', '.join(f'{e:.3g}' for e in filters)}")
    return 0


def check_spherical(arguments):
    """spherical-step-aligned and spherical-r2 at N = 8 and 16, 64x64 rays."""
    if os.path.isdir(arguments.output):
        shutil.rmtree(arguments.output)
    results = {}
    for scene in ("spherical-step-aligned", "spherical-r2"):
        command = [arguments.harness, "--scene", scene, "--count", "8,16", "--width", "64",
                   "--height", "64", "--runs", "1", "--output", arguments.output, "--no-plot"]
        print(" ".join(command), flush=True)
        if subprocess.run(command, timeout=120).returncode != 0:
            fail("the harness failed")
        with open(csv_file(arguments, scene), newline="") as stream:
            rows = list(csv.DictReader(stream))
        results[scene] = {(row["method"], int(row["primitives"])): row for row in rows}

    def rms(scene, method, n):
        return value(results[scene][(method, n)], "integral_rms_error")

    for n in (8, 16):
        # The grid's cells hold the step exactly: the native traversal is exact, Cartesian is not.
        if not rms("spherical-step-aligned", "sightline-spherical", n) < 1e-12:
            fail(f"aligned step, N = {n}: the native projection is not exact")
        if not rms("spherical-step-aligned", "cartesian-resampled", n) > 1e-3:
            fail(f"aligned step, N = {n}: Cartesian resampling looks exact, the comparison is broken")
        # r^2: linear in r^2 is exact; cell-constant values beat Cartesian at equal N.
        if not rms("spherical-r2", "sightline-spherical-linear-r2", n) < 1e-12:
            fail(f"r^2, N = {n}: the linear-in-r^2 sampler is not exact")
        if not rms("spherical-r2", "sightline-spherical", n) < rms("spherical-r2", "cartesian-resampled", n):
            fail(f"r^2, N = {n}: the native projection is less accurate than Cartesian resampling")
    if not rms("spherical-r2", "cartesian-resampled", 16) < rms("spherical-r2", "cartesian-resampled", 8):
        fail("r^2: Cartesian resampling does not converge")
    plot = os.path.join(arguments.output, "spherical.png")
    if subprocess.run([sys.executable, arguments.plot_script, csv_file(arguments, "spherical-step-aligned"),
                       csv_file(arguments, "spherical-r2"), "--output", plot], timeout=120).returncode != 0 \
            or not os.path.isfile(plot):
        fail("plot_benchmarks.py made no figure")
    print("OK: native projections exact where the grid holds the field, Cartesian errors "
          f"{rms('spherical-step-aligned', 'cartesian-resampled', 16):.3g} (step) and "
          f"{rms('spherical-r2', 'cartesian-resampled', 16):.3g} (r^2) at N = 16")
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--harness", required=True)
    parser.add_argument("--plot-script", required=True)
    parser.add_argument("--output", required=True)
    parser.add_argument("--scene", choices=["spheres", "sh-glyphs", "sh-glyph-window",
                                            "tensor-glyphs", "tubes", "spherical"],
                        default="spheres")
    parser.add_argument("--data-dir", help="sh-glyph-window: where its data is kept")
    arguments = parser.parse_args()
    if arguments.scene == "sh-glyphs":
        return check_sh_glyphs(arguments)
    if arguments.scene == "sh-glyph-window":
        return check_sh_glyph_window(arguments)
    if arguments.scene == "tensor-glyphs":
        return check_tensor_glyphs(arguments)
    if arguments.scene == "tubes":
        return check_tubes(arguments)
    if arguments.scene == "spherical":
        return check_spherical(arguments)
    return check_spheres(arguments)


if __name__ == "__main__":
    sys.exit(main())
