# SPDX-License-Identifier: BSD-3-Clause
"""ParaView.MPI.*: Sightline in `mpirun -np N pvbatch`, each rank tracing its own piece, IceT
compositing colour and depth, against the 1-rank image.

A driver run by /usr/bin/python3 (ctest). Modes:

  ranks   runs mpi_scene.py on 1, 2 and 4 ranks (same scene, same explicit camera) and checks
          - every rank's piece of the redistributed streamlines (points and cells) is smaller than
            the whole and not empty, and the pieces' union is the whole: the same multiset of
            points, the same cell count (streamlines kept whole), for spheres and tubes;
          - Spheres, Tubes and TubesSplit (streamlines cut between ranks) on 2 and 4 ranks differ
            from the 1-rank image in at most 0.1 % of pixels (by more than 24/255), printing the
            fraction;
          - ReaderPieces (the TrackVis reader's own pieces): every rank holds a run of whole
            streamlines, none empty, together the whole; the image matches too;
          - EmptyRanks (an SWC neuron, all on rank 0 as the SWC reader gives it; ranks 1-3 hold
            nothing) matches too: empty ranks draw nothing and the collective render does not hang;
          - translucent tubes (opacity 0.4 and 0.5), where the view blends the ranks in the
            visibility order of its kd-tree regions: the streamlines from three directions (one
            along the plane between two ranks' regions, found on 2 ranks and reused for 1 and 4),
            with opaque spheres among them, and an SWC tree (bifurcations, all of it read on rank
            0) from two directions, on 2 and 4 ranks differ from the 1-rank image in at most
            0.05 % of pixels by more than 8/255, printing the counts; rank 0's region is finite on
            several ranks and rank 0 draws fewer streamline points than one rank does;
          - no rank reports an error.
  bad     runs mpi_scene.py --bad-rank 1 on 2 ranks: rank 1's radius array is NaN. Rank 1 reports
          it (naming the radius), the run ends normally, and rank 0's spheres still render: the
          image covers part, and only part, of the pixels the good radii cover.

Every mpirun has a timeout (a hang fails the test). Environment (Testing/ParaView/CMakeLists.txt):
SIGHTLINE_PVBATCH, SIGHTLINE_MPIRUN, SIGHTLINE_PLUGIN, SIGHTLINE_TEST_TEMP_DIR, PYTHONPATH,
LD_LIBRARY_PATH, DISPLAY. SIGHTLINE_MPI_PICTURE=PATH also copies the 4-rank Ranks.png there.
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import time
import zipfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "mpi_scene.py")
BUNDLES = "/usr/lib/python3/dist-packages/dipy/data/files/minimal_bundles.zip"
SWC = os.path.join(HERE, "..", "Data", "SWC", "neuron_three_point_soma.swc")
PVBATCH = os.environ["SIGHTLINE_PVBATCH"]
MPIRUN = os.environ["SIGHTLINE_MPIRUN"]
PLUGIN = os.environ["SIGHTLINE_PLUGIN"]
TEMP = os.path.join(os.environ.get("SIGHTLINE_TEST_TEMP_DIR", "/tmp"), "ParaViewMPI")
TOLERANCE = 0.001  # fraction of pixels allowed to differ by more than 24/255 (opaque scenes)
# Translucent scenes: IceT blends the ranks' 8-bit premultiplied images, one rounding per rank.
TRANSLUCENT_TOLERANCE = 0.0005  # fraction of pixels allowed to differ by more than 8/255
TRANSLUCENT = ("Translucent", "TranslucentBorder", "TranslucentBelow", "TranslucentWithSpheres",
               "TranslucentTree", "TranslucentTreeSide",
               # A spherical volume cut into one box per rank; VolumeBorder looks along x = 0,
               # the plane between the 2- and 4-rank boxes.
               "Volume", "VolumeShaded", "VolumeBorder", "VolumeBelow",
               # The full sphere, its azimuth seam inside rank 0's box.
               "VolumeSphere", "VolumeSphereShaded",
               # Point data interpolated in the cells (one transfer table over the whole range).
               "VolumePoints")
RUN_TIMEOUT = 120
BACKGROUND = np.round(np.array([0.1, 0.1, 0.15]) * 255).astype(int)


def run(ranks, output, trk, *extra):
    command = [MPIRUN, "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)]
    for name in ("PYTHONPATH", "DISPLAY", "LD_LIBRARY_PATH"):
        command += ["-x", name]
    command += [PVBATCH, "--force-offscreen-rendering", SCENE, "--plugin", PLUGIN, "--trk", trk,
                "--swc", SWC, "--output", output, *extra]
    print(" ".join(command), flush=True)
    started = time.monotonic()
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            timeout=RUN_TIMEOUT, stdin=subprocess.DEVNULL)
    print(result.stdout, flush=True)
    print(f"({ranks} ranks: {time.monotonic() - started:.1f} s, exit {result.returncode})",
          flush=True)
    return result


def errors(output):
    return [line for line in output.splitlines() if "ERR|" in line or "ERROR:" in line]


def traced(output):
    """{scene: (distributed rendering, points rank 0's mapper traced)} from mpi_scene.py."""
    found = re.findall(r"^(\w+): distributed rendering (\d), rank 0 traced (\d+) points", output,
                       re.MULTILINE)
    return {name: (int(distributed), int(points)) for name, distributed, points in found}


def pieces(folder, name):
    files = sorted(glob.glob(os.path.join(folder, f"{name}-piece-*.npz")),
                   key=lambda f: int(f.rsplit("-", 1)[1].split(".")[0]))
    return [np.load(f) for f in files]


def covered(image):
    return np.abs(image - BACKGROUND).max(axis=2) > 8


def image(folder, name):
    return np.load(os.path.join(folder, f"{name}.npy")).astype(int)


def sorted_points(points):
    return points[np.lexsort(points.T[::-1])]


class Checks:
    def __init__(self):
        self.ok = True

    def expect(self, condition, message):
        if not condition:
            print("FAIL:", message, flush=True)
            self.ok = False
        return condition


def check_ranks(trk):
    checks = Checks()
    # 2 ranks first: that run finds the plane between its ranks' regions for the border camera.
    folders = {n: os.path.join(TEMP, f"np{n}") for n in (2, 1, 4)}
    border_camera = os.path.join(folders[2], "border_camera.json")
    rank0, regions, volume = {}, {}, {}
    for n, folder in folders.items():
        result = run(n, folder, trk, *(["--border-camera", border_camera] if n != 2 else []))
        if not checks.expect(result.returncode == 0, f"mpirun -np {n} pvbatch failed"):
            return 1
        checks.expect(not errors(result.stdout),
                      f"{n} ranks reported errors:\n" + "\n".join(errors(result.stdout)))
        rank0[n] = traced(result.stdout)
        regions[n] = re.findall(r"^Translucent: rank 0's region \((.*)\)", result.stdout, re.MULTILINE)
        volume[n] = {name: found for name, *found in re.findall(
            r"^(Volume|VolumeSphere): rank 0's piece (\d+) cells, drew (\d+) cells in the "
            r"region \((.*)\)", result.stdout, re.MULTILINE)}
        # Each rank traces its own piece: rank 0's mapper gets rank 0's piece, not the gathered
        # whole (the view did not move the geometry to one process).
        for name in ("Spheres", "TubesSplit", "ReaderPieces", "EmptyRanks"):
            recorded = len(pieces(folder, name)[0]["points"])
            distributed, points = rank0[n].get(name, (None, None))
            print(f"{name}, {n} ranks: distributed rendering {distributed}; rank 0 traced "
                  f"{points} points, its piece has {recorded}")
            checks.expect(points == recorded, f"{name}, {n} ranks: rank 0 did not trace its piece")
            checks.expect(n == 1 or distributed == 1, f"{name}, {n} ranks: not distributed")

    whole = pieces(folders[1], "Spheres")
    checks.expect(len(whole) == 1, "one piece on one rank")
    whole_points, whole_cells = whole[0]["points"], int(whole[0]["cells"])
    print(f"whole: {len(whole_points)} points, {whole_cells} streamlines")
    checks.expect(len(whole_points) > 0, "the 1-rank run read no points")
    for n in (2, 4):
        parts = pieces(folders[n], "Spheres")
        counts = [(len(p["points"]), int(p["cells"])) for p in parts]
        print(f"{n} ranks: (points, streamlines) per rank {counts}")
        checks.expect(len(parts) == n, f"{n} ranks: {len(parts)} pieces recorded")
        checks.expect(sorted(int(p["rank"]) for p in parts) == list(range(n)), "one piece per rank")
        for p in parts:
            checks.expect(0 < len(p["points"]) < len(whole_points),
                          f"{n} ranks: rank {int(p['rank'])} holds {len(p['points'])} of "
                          f"{len(whole_points)} points (neither none nor all)")
        union = np.concatenate([p["points"] for p in parts])
        checks.expect(union.shape == whole_points.shape and
                      np.array_equal(sorted_points(union), sorted_points(whole_points)),
                      f"{n} ranks: the pieces' points are not the whole's")
        checks.expect(sum(int(p["cells"]) for p in parts) == whole_cells,
                      f"{n} ranks: the streamlines are not each on one rank")
        cut = pieces(folders[n], "TubesSplit")
        print(f"{n} ranks, streamlines cut between ranks: points per rank "
              f"{[len(p['points']) for p in cut]} (1 rank: "
              f"{len(pieces(folders[1], 'TubesSplit')[0]['points'])})")
        checks.expect(all(len(p["points"]) > 0 for p in cut), "a rank got none of the cut tubes")
        own = sorted(pieces(folders[n], "ReaderPieces"), key=lambda p: int(p["rank"]))
        print(f"{n} ranks, the reader's own pieces: (points, streamlines) per rank "
              f"{[(len(p['points']), int(p['cells'])) for p in own]}")
        checks.expect(len(own) == n and all(len(p["points"]) > 0 for p in own),
                      f"{n} ranks: a rank got none of the reader's streamlines")
        checks.expect(sum(int(p["cells"]) for p in own) == whole_cells and
                      np.array_equal(np.concatenate([p["points"] for p in own]), whole_points),
                      f"{n} ranks: the reader's pieces in rank order are not the whole file")
        neuron = sorted(pieces(folders[n], "EmptyRanks"), key=lambda p: int(p["rank"]))
        whole_neuron = len(pieces(folders[1], "EmptyRanks")[0]["points"])
        checks.expect([len(p["points"]) for p in neuron] == [whole_neuron] + [0] * (n - 1),
                      f"{n} ranks: the SWC neuron is not all on rank 0")

    for name in ("Spheres", "Tubes", "TubesSplit", "ReaderPieces", "EmptyRanks"):
        reference = image(folders[1], name)
        share = float(np.mean(covered(reference)))
        checks.expect(share > 0.02, f"{name}: the 1-rank image is (almost) empty")
        for n in (2, 4):
            other = image(folders[n], name)
            difference = np.abs(other - reference).max(axis=2)
            fraction = float(np.mean(difference > 24))
            print(f"{name}: {n} ranks vs 1 rank: {fraction:.4%} of pixels differ by more than "
                  f"24/255 ({share:.1%} of pixels covered; {np.mean(difference > 0):.4%} differ "
                  f"at all, by {difference.max()}/255 at most)")
            checks.expect(fraction <= TOLERANCE, f"{name}: more than {TOLERANCE:.1%} differ")
    for n in (1, 2, 4):
        region = [float(v) for v in regions[n][0].split(",")] if regions[n] else []
        finite = [v for v in region if np.isfinite(v)]
        print(f"translucent tubes, {n} ranks: rank 0's region {region}; rank 0 drew "
              f"{rank0[n].get('Translucent', (0, 0))[1]} streamline points")
        checks.expect(len(region) == 6 and (bool(finite) == (n > 1)),
                      f"{n} ranks: rank 0's region is not {'finite' if n > 1 else 'all of space'}")
        if n > 1:
            checks.expect(0 < rank0[n]["Translucent"][1] < rank0[1]["Translucent"][1],
                          f"{n} ranks: rank 0 did not draw a part of the streamlines")
    # The spherical volume: rank 0 holds a piece of the grid (by extent) and draws the cells of
    # its box (received from the ranks that hold them), each less than the whole grid. For the
    # full sphere, whose seam lies in rank 0's box, that is the run of azimuths across the seam:
    # on 2 ranks half of them and a cell on each side for shading (26 of 48).
    for scene, most in (("Volume", {2: 1.0, 4: 1.0}), ("VolumeSphere", {2: 26 / 48, 4: 14 / 48})):
        grid_cells = int(volume[1][scene][0]) if scene in volume[1] else 0
        for n in (1, 2, 4):
            if not checks.expect(scene in volume[n], f"{scene}, {n} ranks: no spherical volume report"):
                continue
            piece, drawn = int(volume[n][scene][0]), int(volume[n][scene][1])
            region = [float(v) for v in volume[n][scene][2].split(",")]
            finite = [v for v in region if np.isfinite(v)]
            print(f"{scene}, {n} ranks: rank 0's piece {piece} of {grid_cells} cells, it "
                  f"drew {drawn} cells in its region {region}")
            if n == 1:
                checks.expect(piece == drawn > 0 and not finite, f"{scene}, 1 rank: not the whole grid")
            else:
                checks.expect(0 < piece < grid_cells and 0 < drawn < grid_cells and finite,
                              f"{scene}, {n} ranks: rank 0 held or drew the whole grid, or no region")
                checks.expect(drawn <= most[n] * grid_cells,
                              f"{scene}, {n} ranks: rank 0 drew more than {most[n]:.0%} of the grid")
    for name in TRANSLUCENT:
        reference = image(folders[1], name)
        share = float(np.mean(covered(reference)))
        checks.expect(share > 0.02, f"{name}: the 1-rank image is (almost) empty")
        for n in (2, 4):
            difference = np.abs(image(folders[n], name) - reference).max(axis=2)
            fraction = float(np.mean(difference > 8))
            print(f"{name}: {n} ranks vs 1 rank: {int(np.sum(difference > 8))} pixels "
                  f"({fraction:.4%}) differ by more than 8/255, {int(np.sum(difference > 2))} by "
                  f"more than 2/255, by {difference.max()}/255 at most ({share:.1%} covered)")
            checks.expect(fraction <= TRANSLUCENT_TOLERANCE,
                          f"{name}: more than {TRANSLUCENT_TOLERANCE:.2%} differ")
    ranks_image = image(folders[4], "Ranks")
    colours = {tuple(c) for c in ranks_image[covered(ranks_image)].reshape(-1, 3) // 32}
    checks.expect(len(colours) >= 4, "the 4-rank Ranks image shows fewer than 4 colours")
    picture = os.environ.get("SIGHTLINE_MPI_PICTURE")
    if picture:
        shutil.copyfile(os.path.join(folders[4], "Ranks.png"), picture)
        print("picture:", picture)
    return 0 if checks.ok else 1


def check_bad_rank(trk):
    checks = Checks()
    folder = os.path.join(TEMP, "bad")
    result = run(2, folder, trk, "--bad-rank", "1")
    if not checks.expect(result.returncode == 0, "mpirun -np 2 pvbatch failed"):
        return 1
    reports = [line for line in result.stdout.splitlines()
               if "pvbatch.1" in line and "radius nan" in line]
    print("rank 1's report:", reports)
    checks.expect(reports, "rank 1 did not report its NaN radii")
    checks.expect(not any("pvbatch.0" in line and "radius" in line
                          for line in result.stdout.splitlines()), "rank 0 reported radii")
    bad, good = covered(image(folder, "BadRadius")), covered(image(folder, "GoodRadius"))
    print(f"covered: {bad.mean():.2%} with rank 1's radii NaN, {good.mean():.2%} with good radii")
    parts = pieces(folder, "BadRadius")
    share = len(parts[0]["points"]) / sum(len(p["points"]) for p in parts)
    print(f"rank 0 holds {share:.0%} of the points")
    checks.expect(bad.mean() > 0.1 * good.mean(), "rank 0's spheres did not render")
    checks.expect(bad.mean() < 0.9 * good.mean(), "rank 1's NaN-radius spheres were drawn")
    checks.expect(float(np.mean(bad & ~good)) < 0.0005, "pixels covered outside the good image")
    return 0 if checks.ok else 1


def main():
    mode = sys.argv[1]
    shutil.rmtree(os.path.join(TEMP, mode), ignore_errors=True)
    os.makedirs(TEMP, exist_ok=True)
    with zipfile.ZipFile(BUNDLES) as archive:
        trk = archive.extract("sub_1/CST_R.trk", os.path.join(TEMP, "data"))
    if mode == "ranks":
        for n in (1, 2, 4):
            shutil.rmtree(os.path.join(TEMP, f"np{n}"), ignore_errors=True)
        return check_ranks(trk)
    return check_bad_rank(trk)


if __name__ == "__main__":
    sys.exit(main())
