#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Whole-brain tractograms: 10^6, 10^7 (and more) tube links, from a .trx file to an image.

A synthetic tractogram that looks like a brain's (smooth streamlines of 20-200 mm at 1 mm steps
inside an ellipsoid of semi-axes 70 x 85 x 60 mm, RAS mm; three crossing bundles following
smooth direction fields: left-right commissural arches, anterior-posterior association arcs and
inferior-superior projections fanning out, plus a little curvature noise) is generated in numpy,
all streamlines of a batch stepped together, and written straight to a stored TRX zip
(positions.3.float16, offsets.uint64, dps/bundle.uint8, dpv/height.float16) in streamed chunks,
and to an MRtrix .tck (float32, the same float16-rounded points) for nibabel.

Each measurement runs in a child process of its own, so that VmHWM (/proc/self/status) is that
run's peak: vtkSightlineTRXReader's Update (time, RSS after), then vtkSightlineTubeMapper (radius
0.3 mm) drawn by vtkSightlineImageRenderer (no OpenGL) at 1920x1080 from the left: the first
image (geometry + BVH + frame) and a second still frame, opaque or at opacity 0.4, with the
automatic link layout and with LINKS_COMBINED_ON_THE_FLY (up to 3e7 links; translucent up to
3e7 links), and streamed: the mapper pulling the file in pieces of 5e6 links into chunked
tubes (StreamedPieces; the read is then part of the first image, opaque only); the mapper's
GetGeometryMemoryBytes/GetBVHMemoryBytes; peak RSS. nibabel's nib.streamlines.load of the .tck
in a child of its own (while the .tck is under a third of the RAM). Timings are the machine's.

Usage: /usr/bin/python3 whole_brain.py [--links 1e6 1e7 ...] [--data DIR] [--output DIR]
         [--image PATH]
with PYTHONPATH at the build tree's lib/python3/dist-packages. Writes
OUTPUT/results-whole-brain-DATE.csv and OUTPUT/whole-brain-DATE.png, and the first opaque image
of 10^7 links (or the nearest size) to --image.
"""
import argparse
import csv
import datetime
import json
import os
import subprocess
import sys
import time
import zipfile

import numpy as np

MIB = 1024.0 * 1024.0
SEMI_AXES = np.array([70.0, 85.0, 60.0], dtype=np.float32)
BATCH = 100000         # streamlines stepped together
MAX_STEPS = 200        # 200 mm at 1 mm steps
COMBINED_MAX_LINKS = 3e7
TRANSLUCENT_MAX_LINKS = 3e7  # 10^7 chunked translucent frames take ~100 s already
WHOLE_READ_BYTES_PER_LINK = 100  # peak of a whole read (2026-11-28: 97 B/link at 10^8)
STREAM_PIECE_LINKS = 5e6
RADIUS = 0.3
SIZE = (1920, 1080)


def memory():
    """(VmRSS, VmHWM) in MiB."""
    values = {}
    with open("/proc/self/status") as status:
        for line in status:
            key, _, rest = line.partition(":")
            if key in ("VmRSS", "VmHWM"):
                values[key] = int(rest.split()[0]) / 1024.0
    return values["VmRSS"], values["VmHWM"]


def field(p, bounds):
    """The bundles' smooth direction fields at points p (n, 3), unnormalised; the streamlines
    of bundle b are the rows bounds[b]:bounds[b + 1]."""
    u = p / SEMI_AXES
    d = np.ones_like(p)
    lr, ap, is_ = (slice(bounds[b], bounds[b + 1]) for b in range(3))
    # Commissural: left-right, arching up over the midline, a little front-back wave.
    d[lr, 1] = 0.15 * np.sin(3.0 * u[lr, 1])
    d[lr, 2] = -1.2 * u[lr, 0] + 0.2 * u[lr, 2]
    # Association: front-back arcs that bend down at both ends and bow outwards.
    d[ap, 0] = 0.4 * u[ap, 0] * u[ap, 1]
    d[ap, 2] = -1.0 * u[ap, 1] * (0.6 + 0.4 * u[ap, 2])
    # Projection: bottom-up, fanning out towards the cortex.
    d[is_, 0] = 1.1 * u[is_, 0]
    d[is_, 1] = 0.8 * u[is_, 1]
    return d


def trace(rng, count):
    """One batch: points (steps + 1, count, 3) and point counts (count,), bundles (count,)."""
    bundle = np.sort(rng.integers(0, 3, size=count)).astype(np.uint8)  # bundles contiguous
    bounds = np.searchsorted(bundle, [0, 1, 2, 3])
    seed = rng.uniform(-1, 1, size=(count * 4, 3)).astype(np.float32)
    seed = seed[(seed ** 2).sum(1) < 0.8][:count] * SEMI_AXES  # inside 0.9 of the ellipsoid
    target = rng.integers(20, MAX_STEPS + 1, size=count)

    def walk(start, sign, steps, record):
        p, w = start.copy(), np.zeros_like(start)
        alive = np.ones(count, bool)
        taken = np.zeros(count, np.int64)
        previous = sign[:, None] * field(p, bounds)
        out = np.empty((steps + 1, count, 3), np.float32) if record else None
        if record:
            out[0] = p
        for step in range(1, steps + 1):
            w += -0.05 * w + 0.04 * rng.standard_normal(w.shape, dtype=np.float32)  # curvature noise
            d = field(p, bounds)
            d *= np.where((d * previous).sum(1) < 0, -1.0, 1.0).astype(np.float32)[:, None]  # keep heading
            d /= np.linalg.norm(d, axis=1)[:, None]
            d += w
            d /= np.linalg.norm(d, axis=1)[:, None]
            q = p + d
            alive &= (step <= target) & (((q / SEMI_AXES) ** 2).sum(1) < 1.0)
            p = np.where(alive[:, None], q, p)
            previous = np.where(alive[:, None], d, previous)
            taken += alive
            if record:
                out[step] = p
            if not alive.any():
                return p, taken, out[:step + 1] if record else None
        return p, taken, out

    sign = np.where(rng.random(count) < 0.5, -1.0, 1.0).astype(np.float32)
    start, _, _ = walk(seed, -sign, MAX_STEPS, False)     # back to one end ...
    _, taken, points = walk(start, sign, MAX_STEPS, True)  # ... and along the whole length
    return points, taken + 1, bundle


def tractogram(links, seed=7):
    """Batches (positions float16 (n, 3), points per streamline, bundles) of `links` links."""
    rng = np.random.default_rng(seed)
    left = int(links)
    while left > 0:
        points, counts, bundle = trace(rng, BATCH)
        keep = rng.permutation(np.flatnonzero(counts >= 21))  # 20 mm at least, bundles mixed
        points, counts, bundle = points[:, keep], counts[keep], bundle[keep]
        total = np.cumsum(counts - 1)
        n = min(int(np.searchsorted(total, left)) + 1, len(total))  # streamlines up to the target
        points, counts, bundle = points[:, :n], counts[:n], bundle[:n]
        if total[n - 1] > left:  # shorten the last one to hit the count exactly
            counts[-1] -= total[n - 1] - left
        mask = np.arange(points.shape[0])[None, :] < counts[:, None]
        positions = points.transpose(1, 0, 2)[mask].astype(np.float16)
        left -= int((counts - 1).sum())
        yield positions, counts, bundle


def write(links, trx_path, tck_path):
    """Streams the tractogram to a stored .trx (and a .tck unless tck_path is None)."""
    counts_all, bundles_all, vertices = [], [], 0
    dpv_path = trx_path + ".height.tmp"
    tck = open(tck_path + ".tmp", "wb") if tck_path else None
    if tck:
        header = b"mrtrix tracks\ndatatype: Float32LE\ncount: %010d\nfile: . 128\nEND\n"
        tck.write((header % 0).ljust(128, b"\0"))
    with zipfile.ZipFile(trx_path, "w", zipfile.ZIP_STORED, allowZip64=True) as archive, \
            open(dpv_path, "wb") as dpv:
        with archive.open("positions.3.float16", "w", force_zip64=True) as member:
            for positions, counts, bundle in tractogram(links):
                member.write(positions.tobytes())
                dpv.write(positions[:, 2].tobytes())  # height: z in mm
                counts_all.append(counts)
                bundles_all.append(bundle)
                vertices += len(positions)
                if tck:
                    ends = np.cumsum(counts)
                    rows = np.insert(positions.astype(np.float32), ends, np.nan, axis=0)
                    tck.write(rows.tobytes())
                print(f"  {vertices:,} points written", end="\r", flush=True)
        counts = np.concatenate(counts_all)
        offsets = np.concatenate([[0], np.cumsum(counts)]).astype(np.uint64)
        archive.writestr("offsets.uint64", offsets.tobytes())
        archive.writestr("dps/bundle.uint8", np.concatenate(bundles_all).tobytes())
        dpv.close()
        with archive.open("dpv/height.float16", "w", force_zip64=True) as member, \
                open(dpv_path, "rb") as source:
            while block := source.read(64 << 20):
                member.write(block)
        archive.writestr("header.json", json.dumps({
            "NB_VERTICES": int(vertices), "NB_STREAMLINES": int(len(counts)),
            "DIMENSIONS": [140, 170, 120],
            "VOXEL_TO_RASMM": [[1, 0, 0, -70], [0, 1, 0, -85], [0, 0, 1, -60], [0, 0, 0, 1]]}))
    os.remove(dpv_path)
    if tck:
        tck.write(np.full(3, np.inf, np.float32).tobytes())
        tck.seek(0)
        tck.write((header % len(counts)).ljust(128, b"\0"))
        tck.close()
        os.replace(tck_path + ".tmp", tck_path)
    print()
    return len(counts)


def child_render(trx, layout, opacity, image, pieces=1):
    """One run; with pieces > 1 the mapper streams the file (no whole read: its time is part of
    the first image's, and the poly data is never whole)."""
    import vtk
    import sightline
    base = memory()
    reader = sightline.vtkSightlineTRXReader()
    reader.SetFileName(trx)
    result = {"base": base}
    if pieces == 1:
        started = time.perf_counter()
        reader.Update()
        result.update(read_s=time.perf_counter() - started, read=memory())
        poly = reader.GetOutput()
        result["points"], result["streamlines"] = poly.GetNumberOfPoints(), poly.GetNumberOfLines()
        result["links"] = result["points"] - result["streamlines"]
        result["polydata_bytes"] = poly.GetActualMemorySize() * 1024.0
    else:
        with zipfile.ZipFile(trx) as archive:
            header = json.loads(archive.read("header.json"))
        result["points"], result["streamlines"] = header["NB_VERTICES"], header["NB_STREAMLINES"]
        result["links"] = result["points"] - result["streamlines"]
    mapper = sightline.vtkSightlineTubeMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.SetRadius(RADIUS)
    mapper.SetLinkLayout(layout)
    mapper.SetStreamedPieces(pieces)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.95, 0.85, 0.7)
    actor.GetProperty().SetOpacity(opacity)
    camera = vtk.vtkCamera()  # lateral view from the left, the brain filling the frame's height
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(-300, 0, 0)
    camera.SetViewUp(0, 0, 1)
    camera.SetViewAngle(30)
    camera.SetClippingRange(200, 400)
    renderer = sightline.vtkSightlineImageRenderer()
    renderer.AddActor(actor)
    renderer.SetActiveCamera(camera)
    renderer.SetSize(*SIZE)
    started = time.perf_counter()
    renderer.Update()
    result["first_s"] = time.perf_counter() - started
    result["first"] = memory()
    renderer.Modified()
    started = time.perf_counter()
    renderer.Update()
    result["still_s"] = time.perf_counter() - started
    result["second"] = memory()
    result["geometry"], result["bvh"] = mapper.GetGeometryMemoryBytes(), mapper.GetBVHMemoryBytes()
    result["layout"] = mapper.GetBuiltLinkLayout()
    result["hidden"], result["outer"] = mapper.GetHiddenLinks(), mapper.GetLastFrameOuter()
    # Where the first image's time went: reading and building (culling included), then the BVH.
    result["build_s"], result["bvh_s"] = mapper.GetLastGeometrySeconds(), mapper.GetLastBuildSeconds()
    result["culling_s"] = mapper.GetLastCullingSeconds()
    result["culling_mark_s"], result["culling_test_s"] = (mapper.GetLastCullingMarkSeconds(),
                                                          mapper.GetLastCullingTestSeconds())
    if image:
        writer = vtk.vtkPNGWriter()
        writer.SetInputConnection(renderer.GetOutputPort())
        writer.SetFileName(image)
        writer.Write()
    return result


def child_nibabel(tck):
    import nibabel as nib
    base = memory()
    started = time.perf_counter()
    loaded = nib.streamlines.load(tck)
    seconds = time.perf_counter() - started
    return {"load_s": seconds, "base": base, "loaded": memory(),
            "points": int(len(loaded.streamlines.get_data())), "type": type(loaded.streamlines).__name__}


def run_child(*arguments):
    command = [sys.executable, os.path.abspath(__file__), "--child", json.dumps(arguments)]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        print(f"  child {arguments} failed ({done.returncode}):\n{done.stderr[-3000:]}")
        return None
    return json.loads(done.stdout.strip().splitlines()[-1])


def load():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--links", type=float, nargs="+", default=[1e6, 1e7])
    parser.add_argument("--data", default="/tmp/sightline-whole-brain")
    parser.add_argument("--output", default=os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--image", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                        "..", "Documentation", "images", "whole-brain-1e7.png"))
    parser.add_argument("--append", action="store_true",
                        help="add this run's rows to today's CSV (and plot all of them) instead of replacing it")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        kind, *rest = json.loads(args.child)
        print(json.dumps(child_render(*rest) if kind == "render" else child_nibabel(*rest)))
        return

    import sightline
    automatic = sightline.vtkSightlineTubeMapper.LINKS_AUTOMATIC
    chunked = sightline.vtkSightlineTubeMapper.LINKS_CHUNKED
    combined = sightline.vtkSightlineTubeMapper.LINKS_COMBINED_ON_THE_FLY
    os.makedirs(args.data, exist_ok=True)
    os.makedirs(os.path.dirname(os.path.abspath(args.image)), exist_ok=True)
    ram = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    image_links = min(args.links, key=lambda n: abs(np.log10(n) - 7))
    today = datetime.date.today().isoformat()
    rows = []
    for links in args.links:
        links = int(links)
        name = os.path.join(args.data, f"brain-{links}")
        tck_bytes = 16.5 * links  # 12 B a point and one NaN row per ~100 points
        want_tck = tck_bytes < ram / 3
        if not os.path.exists(name + ".trx") or (want_tck and not os.path.exists(name + ".tck")):
            print(f"{links:.0e} links: generating and writing {name}.trx" + (" and .tck" if want_tck else ""))
            started = time.perf_counter()
            write(links, name + ".trx", name + ".tck" if want_tck else None)
            print(f"  written in {time.perf_counter() - started:.1f} s")
        # Streamed: one piece per STREAM_PIECE_LINKS links (opaque only: its frames are the
        # chunked layout's, which the automatic rows time).
        pieces = max(2, int(np.ceil(links / STREAM_PIECE_LINKS)))
        # Read whole only where its peak fits in most of the RAM (not 10^9 links on 24 GB).
        whole = WHOLE_READ_BYTES_PER_LINK * links < 0.8 * ram
        layouts = ([("automatic", automatic, 1)] if whole else []) + [("streamed", chunked, pieces)] + \
            ([("combined", combined, 1)] if links <= COMBINED_MAX_LINKS else [])
        for layout_name, layout, layout_pieces in layouts:
            for opacity in (1.0, 0.4):
                if opacity < 1.0 and (layout_pieces > 1 or links > TRANSLUCENT_MAX_LINKS):
                    continue
                image = os.path.abspath(args.image) if (links == int(image_links) and layout == automatic
                                                        and opacity == 1.0) else ""
                print(f"  {links:.0e} links, {layout_name}, opacity {opacity}: ...", end="", flush=True)
                load_before = load()
                r = run_child("render", name + ".trx", layout, opacity, image, layout_pieces)
                if r is None:
                    continue
                n = r["links"]
                row = {"links": n, "streamlines": r["streamlines"], "points": r["points"],
                       "file_mb": os.path.getsize(name + ".trx") / 1e6, "layout": layout_name,
                       "built_layout": r["layout"], "opacity": opacity, "pieces": layout_pieces,
                       "hidden_links": r["hidden"], "outer_frames": int(r["outer"]),
                       "read_s": r.get("read_s", float("nan")),
                       "rss_after_read_mb": r.get("read", [float("nan")])[0],
                       "rss_base_mb": r["base"][0],
                       "polydata_b_per_link": r.get("polydata_bytes", float("nan")) / n,
                       "first_image_s": r["first_s"], "still_frame_s": r["still_s"],
                       "read_build_s": r["build_s"] - r["culling_s"], "culling_s": r["culling_s"],
                       "culling_mark_s": r["culling_mark_s"], "culling_test_s": r["culling_test_s"],
                       "bvh_build_s": r["bvh_s"],
                       "geometry_b_per_link": r["geometry"] / n, "bvh_b_per_link": r["bvh"] / n,
                       "rss_after_frames_mb": r["second"][0],
                       "peak_rss_gb": r["second"][1] * MIB / 1e9,
                       "peak_b_per_link": r["second"][1] * MIB / n,
                       "load_before": load_before, "load_after": load()}
                rows.append(row)
                print(f" read {row['read_s']:.2f} s, first {r['first_s']:.2f} s, still {r['still_s']:.2f} s,"
                      f" peak {row['peak_rss_gb']:.2f} GB (load {load_before:.1f}-{row['load_after']:.1f})")
        if want_tck:
            print(f"  {links:.0e} links, nibabel .tck load: ...", end="", flush=True)
            load_before = load()
            r = run_child("nibabel", name + ".tck")
            if r is not None:
                rows.append({"links": links, "layout": "nibabel-tck", "file_mb": os.path.getsize(name + ".tck") / 1e6,
                             "read_s": r["load_s"], "rss_base_mb": r["base"][0],
                             "rss_after_read_mb": r["loaded"][0], "peak_rss_gb": r["loaded"][1] * MIB / 1e9,
                             "peak_b_per_link": r["loaded"][1] * MIB / links,
                             "load_before": load_before, "load_after": load()})
                print(f" {r['load_s']:.2f} s, peak {rows[-1]['peak_rss_gb']:.2f} GB")

    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")), "")
    machine = f"{cpu}, {os.cpu_count()} cores, {ram / 2**30:.1f} GiB, loadavg {open('/proc/loadavg').read().split()[:3]}"
    for row in rows:
        row["machine"] = machine
    path = os.path.join(args.output, f"results-whole-brain-{today}.csv")
    if args.append and os.path.exists(path):
        with open(path, newline="") as f:
            earlier = [{k: number(v) for k, v in row.items() if v != ""} for row in csv.DictReader(f)]
        rows = earlier + rows
    keys = list(dict.fromkeys(k for row in rows for k in row if k != "machine"))
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, keys + ["machine"])
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in row.items()})
    print(f"\n{path}\n")
    print("| links | layout | opacity | file MB | read s | first image s | still s | geometry B/link"
          " | BVH B/link | peak GB | peak B/link |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['links']:.0e} | {r['layout']} | {r.get('opacity', '')} | {r['file_mb']:.0f} | {r['read_s']:.2f}"
              f" | {r.get('first_image_s', float('nan')):.2f} | {r.get('still_frame_s', float('nan')):.2f}"
              f" | {r.get('geometry_b_per_link', float('nan')):.1f} | {r.get('bvh_b_per_link', float('nan')):.1f}"
              f" | {r['peak_rss_gb']:.2f} | {r['peak_b_per_link']:.0f} |")
    plot(rows, os.path.join(args.output, f"whole-brain-{today}.png"))


def number(text):
    """A CSV field as written above: an int, a float (nan included) or the text itself."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, (left, right) = plt.subplots(1, 2, figsize=(12, 9))
    series = {}
    for r in rows:
        series.setdefault((r["layout"], r.get("opacity")), []).append(r)
    for (layout, opacity), group in series.items():
        x = [r["links"] for r in group]
        label = layout if opacity is None else f"{layout}, opacity {opacity}"
        left.plot(x, [r["peak_b_per_link"] for r in group], "o-", label=f"peak RSS, {label}")
        if opacity == 1.0:
            left.plot(x, [r["geometry_b_per_link"] + r["bvh_b_per_link"] for r in group], "s--",
                      label=f"geometry + BVH, {layout}")
            right.plot(x, [r["read_s"] for r in group], "^:", label=f"TRX read, {layout}")
        if opacity is not None:
            right.plot(x, [r["first_image_s"] for r in group], "o-", label=f"first image, {label}")
            right.plot(x, [r["still_frame_s"] for r in group], "s--", label=f"still frame, {label}")
        else:
            right.plot(x, [r["read_s"] for r in group], "d-", label="nibabel .tck load")
    for axis, title in ((left, "bytes per link"), (right, "seconds")):
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("links")
        axis.set_title(title)
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)  # under the axes: the points stay visible
    figure.suptitle("Whole-brain tractograms: vtkSightlineTRXReader + vtkSightlineTubeMapper, 1920x1080")
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    print(path)


if __name__ == "__main__":
    main()
