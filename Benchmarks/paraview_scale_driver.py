# SPDX-License-Identifier: BSD-3-Clause
"""The ParaView scale benchmark: writes synthetic tractograms (.tck), runs
`mpirun -np N pvbatch --symmetric Benchmarks/paraview_scale.py` for each rank count, and writes
scale.csv (one row per rank and run) and scale.md (one line per run, the fit, the images
compared) into --output. Run it with /usr/bin/python3 under an X server (DISPLAY):

    /usr/bin/python3 Benchmarks/paraview_scale_driver.py --output scale-results

Two cases, each for every rank count N:
  strong  one fixed tractogram (--strong-streamlines x --points) and a fixed spherical grid
          (--strong-grid): each rank holds 1/N of it; the N-rank image is compared with the
          1-rank image (pixels differing by more than 24/255, and at all);
  weak    a tractogram of N x --weak-streamlines streamlines in the same box (denser) and a grid
          of N x --weak-grid's azimuthal cells: each rank holds the same amount.
The streamlines are smooth random walks (1 mm steps, direction kept with some noise) starting in
a cube of half-width --extent mm, written as MRtrix .tck (Float32LE, NaN triplet after each
streamline, Inf triplet at the end); a file is written once per size and reused.

Definitions (scale.md says them again): trace = the slowest rank's vtkSightlineMapper
GetLastFrameSeconds in a steady frame (median over the frames); frame = rank 0's Render() wall
time (returns after IceT compositing); compositing = frame - trace (everything in a frame that
is not the slowest rank's tracing: IceT's image exchange and blending, ParaView's frame
overhead, waiting). Memory: geometry + BVH bytes from the mapper, the piece's VTK data
(GetActualMemorySize), and peak RSS per rank process (the 'loaded' value, before any data, is
the constant ParaView itself costs). Timings are only meaningful while N does not exceed the
cores; the driver prints the cores it sees. Open MPI 4.1 binds each rank to one core when
N <= 2 (its default) and leaves more ranks unbound: the 1- and 2-rank runs trace on one core a
rank.

Environment (optional): SIGHTLINE_PVBATCH, SIGHTLINE_MPIRUN, SIGHTLINE_PLUGIN, PYTHONPATH,
LD_LIBRARY_PATH; the defaults are those of build-paraview/ (scripts/build.sh --paraview).
"""
import argparse
import csv
import glob
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
BUILD = os.path.join(ROOT, "build-paraview")
PREFIX = os.path.join(BUILD, "paraview-prefix", "usr")


def build_path(pattern):
    """The one path of the ParaView build matching pattern (its Python and ParaView versions
    are the platform's: lib/python3.11, lib/paraview-5.11 on Debian 12)."""
    found = glob.glob(os.path.join(BUILD, pattern))
    return found[0] if len(found) == 1 else os.path.join(BUILD, pattern)
SCRIPT = os.path.join(HERE, "paraview_scale.py")
MIB = 1024.0 * 1024.0


def write_tck(path, streamlines, points, extent, seed=7):
    """Smooth random streamlines; streamline i is the same in every file with the same seed."""
    rng = np.random.default_rng(seed)
    start = rng.uniform(-extent, extent, size=(streamlines, 3))
    direction = rng.normal(size=(streamlines, 3))
    noise = rng.normal(scale=0.25, size=(points, streamlines, 3))
    xyz = np.empty((streamlines, points + 1, 3), dtype=np.float32)
    position = start.copy()
    for k in range(points):
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
        xyz[:, k] = position
        # Turn back towards the box when leaving it, so the data stays in the camera's view.
        outside = np.abs(position) > extent
        direction = direction + noise[k] - 0.5 * outside * np.sign(position)
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
        position = position + direction
    xyz[:, points] = np.nan
    header = "mrtrix tracks\ndatatype: Float32LE\ncount: %d\nfile: . %%d\nEND\n" % streamlines
    offset = len(header % 0) + 8
    text = (header % offset).encode()
    text += b"\0" * (offset - len(text))
    with open(path, "wb") as stream:
        stream.write(text)
        stream.write(xyz.reshape(-1, 3).astype("<f4").tobytes())
        stream.write(np.full(3, np.inf, dtype="<f4").tobytes())


def environment():
    env = dict(os.environ)
    paths = [os.path.join(PREFIX, "lib", "python3", "dist-packages"),
             build_path("lib/python3.*/site-packages")]
    if "paraview-prefix" not in env.get("PYTHONPATH", ""):
        env["PYTHONPATH"] = ":".join(paths + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    env.setdefault("LD_LIBRARY_PATH", os.path.join(BUILD, "lib"))
    return env


def run(args, ranks, tck, grid, folder):
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    command = [args.mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)]
    for name in ("PYTHONPATH", "DISPLAY", "LD_LIBRARY_PATH"):
        command += ["-x", name]
    command += [args.pvbatch, "--symmetric", "--force-offscreen-rendering", SCRIPT,
                "--plugin", args.plugin, "--tck", tck, "--output", folder,
                "--size", *map(str, args.size), "--frames", str(args.frames),
                "--extent", str(args.extent), "--radius", str(args.radius),
                "--grid", *map(str, grid)]
    print(" ".join(command), flush=True)
    started = time.monotonic()
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            timeout=args.timeout, stdin=subprocess.DEVNULL, env=environment())
    wall = time.monotonic() - started
    print(result.stdout[-4000:], flush=True)
    print(f"({ranks} ranks: {wall:.1f} s, exit {result.returncode})", flush=True)
    bad = [line for line in result.stdout.splitlines() if "ERR|" in line or "ERROR:" in line]
    if result.returncode != 0 or bad:
        raise SystemExit(f"mpirun -np {ranks} pvbatch failed:\n" + "\n".join(bad))
    records = []
    for rank in range(ranks):
        with open(os.path.join(folder, f"{rank}.json")) as stream:
            records.append(json.load(stream))
    return records


def fit_inverse(ranks, values):
    """Least squares values = constant + slope / ranks; returns (constant, slope, max residual)."""
    x = 1.0 / np.asarray(ranks, dtype=float)
    y = np.asarray(values, dtype=float)
    matrix = np.stack([np.ones_like(x), x], axis=1)
    (constant, slope), *_ = np.linalg.lstsq(matrix, y, rcond=None)
    residual = float(np.max(np.abs(matrix @ [constant, slope] - y))) if len(y) else 0.0
    return float(constant), float(slope), residual


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--output", required=True)
    parser.add_argument("--ranks", type=int, nargs="+", default=[1, 2, 4])
    parser.add_argument("--cases", nargs="+", default=["strong", "weak"])
    parser.add_argument("--strong-streamlines", type=int, default=20000)
    parser.add_argument("--weak-streamlines", type=int, default=5000, help="per rank")
    parser.add_argument("--points", type=int, default=50, help="per streamline")
    parser.add_argument("--strong-grid", type=int, nargs=3, default=[96, 96, 192])
    parser.add_argument("--weak-grid", type=int, nargs=3, default=[48, 48, 96],
                        help="per rank: the azimuthal cells are multiplied by the ranks")
    parser.add_argument("--size", type=int, nargs=2, default=[1920, 1080])
    parser.add_argument("--frames", type=int, default=3)
    parser.add_argument("--extent", type=float, default=60.0)
    parser.add_argument("--radius", type=float, default=0.3)
    parser.add_argument("--timeout", type=int, default=900, help="seconds per mpirun")
    parser.add_argument("--pvbatch", default=os.environ.get("SIGHTLINE_PVBATCH",
                                                            os.path.join(PREFIX, "bin", "pvbatch")))
    parser.add_argument("--mpirun", default=os.environ.get("SIGHTLINE_MPIRUN", "mpirun"))
    parser.add_argument("--plugin", default=os.environ.get(
        "SIGHTLINE_PLUGIN", build_path("lib/paraview-*/plugins/Sightline/Sightline.so")))
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)
    data = os.path.join(args.output, "data")
    os.makedirs(data, exist_ok=True)
    print(f"cores: {os.cpu_count()}", flush=True)

    rows, runs = [], []
    images, volume_images = {}, {}
    for case in args.cases:
        for ranks in args.ranks:
            streamlines = (args.strong_streamlines if case == "strong"
                           else args.weak_streamlines * ranks)
            grid = (list(args.strong_grid) if case == "strong"
                    else [args.weak_grid[0], args.weak_grid[1], args.weak_grid[2] * ranks])
            tck = os.path.join(data, f"tracks-{streamlines}x{args.points}.tck")
            if not os.path.exists(tck):
                write_tck(tck, streamlines, args.points, args.extent)
            folder = os.path.join(args.output, f"{case}-np{ranks}")
            records = run(args, ranks, tck, grid, folder)
            image = np.load(os.path.join(folder, "tubes.npy")).astype(int)
            images[case, ranks] = image
            volume_image = os.path.join(folder, "volume.npy")
            if os.path.exists(volume_image):
                volume_images[case, ranks] = np.load(volume_image).astype(int)
            trace_per_frame = np.max([r["trace_seconds"] for r in records], axis=0)
            frame_per_frame = np.asarray(records[0]["frame_seconds"])
            trace = float(np.median(trace_per_frame))
            frame = float(np.median(frame_per_frame))
            compositing = float(np.median(frame_per_frame - trace_per_frame))
            for r in records:
                rows.append({
                    "case": case, "ranks": ranks, "rank": r["rank"],
                    "width": r["width"], "height": r["height"],
                    "total_streamlines": streamlines, "total_points": streamlines * args.points,
                    "points": r["points"], "streamlines": r["streamlines"], "links": r["links"],
                    "piece_mib": r["piece_bytes"] / MIB,
                    "geometry_mib": r["geometry_bytes"] / MIB, "bvh_mib": r["bvh_bytes"] / MIB,
                    "bytes_per_link": ((r["geometry_bytes"] + r["bvh_bytes"]) / r["links"]
                                       if r["links"] else ""),
                    "geometry_s": r["geometry_seconds"], "bvh_s": r["bvh_seconds"],
                    "trace_s": float(np.median(r["trace_seconds"])),
                    "frame_s": frame if r["rank"] == 0 else "",
                    "compositing_s": compositing if r["rank"] == 0 else "",
                    "first_frame_s": r["first_frame_seconds"] if r["rank"] == 0 else "",
                    "rss_loaded_mib": r["rss_loaded"] / MIB, "rss_tubes_mib": r["rss_tubes"] / MIB,
                    "rss_end_mib": r["rss_end"] / MIB,
                    "grid_cells": r.get("grid_cells", ""), "grid_points": r.get("grid_points", ""),
                    "grid_mib": r["grid_bytes"] / MIB if "grid_bytes" in r else "",
                    "grid_s": r.get("grid_seconds", ""),
                    "volume_cells": r.get("volume_cells", ""),
                    "volume_mib": r["volume_bytes"] / MIB if "volume_bytes" in r else "",
                    "volume_trace_s": (float(np.median(r["volume_trace_seconds"]))
                                       if r.get("volume_trace_seconds") else ""),
                    "volume_frame_s": (float(np.median(r["volume_frame_seconds"]))
                                       if r["rank"] == 0 and r.get("volume_frame_seconds") else ""),
                    "volume_first_frame_s": (r.get("volume_first_seconds", "")
                                             if r["rank"] == 0 else ""),
                    "distributed": r["distributed"],
                })
            runs.append({"case": case, "ranks": ranks, "records": records, "trace": trace,
                         "frame": frame, "compositing": compositing,
                         "streamlines": streamlines, "grid": grid})

    with open(os.path.join(args.output, "scale.csv"), "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in row.items()})

    width, height = args.size
    lines = [f"Sightline Tubes (opaque, radius {args.radius}) from a .tck of {args.points}-point "
             f"streamlines, {width}x{height}, {args.frames} steady frames (medians); "
             f"PREM Density grid drawn as a Sightline Spherical Volume after the tubes (each rank "
             f"the cells of its box; ordered compositing). cores: {os.cpu_count()}.", "",
             "| case | ranks | links/rank (max) | geometry+BVH MiB/rank (max) | bytes/link | "
             "piece MiB/rank (max) | peak RSS MiB/rank (max; loaded) | geometry+BVH build s (max) "
             "| trace s (slowest) | compositing s | frame s | first frame s | grid cells/rank "
             "(max) | grid MiB/rank (max) | image vs 1 rank |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for run_ in runs:
        records = run_["records"]
        links = max(r["links"] for r in records)
        gb = [r["geometry_bytes"] + r["bvh_bytes"] for r in records]
        total_links = sum(r["links"] for r in records)
        comparison = ""
        if run_["case"] == "strong" and ("strong", 1) in images and run_["ranks"] != 1:
            diff = np.abs(images["strong", run_["ranks"]] - images["strong", 1]).max(axis=2)
            run_["differ24"] = float(np.mean(diff > 24))
            run_["differ0"] = float(np.mean(diff > 0))
            comparison = f"{run_['differ24']:.4%} (>24/255), {run_['differ0']:.4%} at all"
        grid_cells = max((r.get("grid_cells", 0) for r in records), default=0)
        grid_mib = max((r.get("grid_bytes", 0) for r in records), default=0) / MIB
        lines.append(
            f"| {run_['case']} | {run_['ranks']} | {links} | {max(gb) / MIB:.1f} | "
            f"{sum(gb) / total_links:.1f} | {max(r['piece_bytes'] for r in records) / MIB:.1f} | "
            f"{max(r['rss_tubes'] for r in records) / MIB:.0f} "
            f"({max(r['rss_loaded'] for r in records) / MIB:.0f}) | "
            f"{max(r['geometry_seconds'] + r['bvh_seconds'] for r in records):.3f} | "
            f"{run_['trace']:.3f} | {run_['compositing']:.3f} | {run_['frame']:.3f} | "
            f"{records[0]['first_frame_seconds']:.2f} | {grid_cells} | {grid_mib:.1f} | "
            f"{comparison} |")
    lines += ["", "| case | ranks | grid cells | volume cells drawn/rank (max) | volume MiB/rank "
              "(max) | volume trace s (slowest) | volume frame s | volume first frame s | "
              "volume image vs 1 rank |", "|---|---|---|---|---|---|---|---|---|"]
    for run_ in runs:
        records = run_["records"]
        if "volume_cells" not in records[0]:
            continue
        comparison = ""
        key = (run_["case"], run_["ranks"])
        if run_["case"] == "strong" and ("strong", 1) in volume_images and run_["ranks"] != 1:
            diff = np.abs(volume_images[key] - volume_images["strong", 1]).max(axis=2)
            comparison = (f"{np.mean(diff > 8):.4%} (>8/255), {np.mean(diff > 2):.4%} (>2/255), "
                          f"{diff.max()}/255 at most")
        trace = float(np.median(np.max([r["volume_trace_seconds"] for r in records], axis=0)))
        lines.append(
            f"| {run_['case']} | {run_['ranks']} | {sum(r['grid_cells'] for r in records)} | "
            f"{max(r['volume_cells'] for r in records)} | "
            f"{max(r['volume_bytes'] for r in records) / MIB:.1f} | {trace:.3f} | "
            f"{float(np.median(records[0]['volume_frame_seconds'])):.3f} | "
            f"{records[0]['volume_first_seconds']:.2f} | {comparison} |")
    strong = [r for r in runs if r["case"] == "strong"]
    if len(strong) >= 2:
        ns = [r["ranks"] for r in strong]
        lines += ["", "Strong scaling, per-rank memory fitted as constant + slope / ranks "
                  "(least squares over the ranks run; the slope is the whole data's share):", ""]
        for label, key in (("geometry + BVH", lambda r: r["geometry_bytes"] + r["bvh_bytes"]),
                           ("piece (VTK poly data)", lambda r: r["piece_bytes"]),
                           ("peak RSS after the tubes", lambda r: r["rss_tubes"]),
                           ("grid piece", lambda r: r.get("grid_bytes", 0)),
                           ("volume cells drawn", lambda r: r.get("volume_bytes", 0))):
            values = [max(key(rec) for rec in r["records"]) / MIB for r in strong]
            constant, slope, residual = fit_inverse(ns, values)
            measured = ", ".join(f"{v:.1f}" for v in values)
            lines.append(f"- {label}: {constant:.1f} MiB + {slope:.1f} MiB / ranks "
                         f"(measured {measured} MiB for {ns} ranks; largest residual "
                         f"{residual:.1f} MiB)")
    lines += ["", "Definitions: trace = the slowest rank's GetLastFrameSeconds (median over "
              "frames); frame = rank 0's Render() wall time; compositing = frame - trace, per "
              "frame, median. More ranks than cores: memory and images only, not speed."]
    with open(os.path.join(args.output, "scale.md"), "w") as stream:
        stream.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
