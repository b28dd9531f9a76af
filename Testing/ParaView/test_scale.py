# SPDX-License-Identifier: BSD-3-Clause
"""ParaView.MPI.Scale (label mpi): Benchmarks/paraview_scale_driver.py on a tiny configuration
(200 streamlines of 20 points, 320x240, an 8x8x16 grid, 1 and 2 ranks, strong scaling only) runs
and writes scale.csv and scale.md; the CSV has one row per rank for 1 and 2 ranks, and each rank
of the 2-rank run holds strictly fewer points, links, geometry + BVH bytes and grid cells than the
1-rank run, the pieces adding up to the whole; a rank draws fewer volume cells than the whole
grid. Timings are written, never checked.

Environment (Testing/ParaView/CMakeLists.txt): SIGHTLINE_PVBATCH, SIGHTLINE_MPIRUN,
SIGHTLINE_PLUGIN, SIGHTLINE_TEST_TEMP_DIR, PYTHONPATH, LD_LIBRARY_PATH, DISPLAY.
"""
import csv
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
DRIVER = os.path.join(HERE, "..", "..", "Benchmarks", "paraview_scale_driver.py")
OUTPUT = os.path.join(os.environ.get("SIGHTLINE_TEST_TEMP_DIR", "/tmp"), "ParaViewScale")


def main():
    shutil.rmtree(OUTPUT, ignore_errors=True)
    command = [sys.executable, DRIVER, "--output", OUTPUT, "--ranks", "1", "2", "--cases", "strong",
               "--strong-streamlines", "200", "--points", "20", "--size", "320", "240",
               "--frames", "1", "--strong-grid", "8", "8", "16", "--timeout", "120"]
    print(" ".join(command), flush=True)
    result = subprocess.run(command, timeout=300, stdin=subprocess.DEVNULL)
    if result.returncode != 0:
        print("FAIL: the driver failed")
        return 1
    with open(os.path.join(OUTPUT, "scale.csv")) as stream:
        rows = list(csv.DictReader(stream))
    ok = True

    def expect(condition, message):
        nonlocal ok
        if not condition:
            print("FAIL:", message)
            ok = False

    one = [r for r in rows if r["ranks"] == "1"]
    two = [r for r in rows if r["ranks"] == "2"]
    expect(len(one) == 1 and len(two) == 2, f"rows: {len(one)} for 1 rank, {len(two)} for 2")
    expect(sorted(r["rank"] for r in two) == ["0", "1"], "the 2-rank rows are not ranks 0 and 1")
    if not ok:
        return 1
    whole = one[0]
    expect(int(whole["points"]) == 200 * 20, f"1 rank read {whole['points']} of 4000 points")
    for key in ("points", "links", "grid_cells"):
        counts = [int(r[key]) for r in two]
        print(f"{key}: 1 rank {whole[key]}, 2 ranks {counts}")
        expect(all(0 < c < int(whole[key]) for c in counts),
               f"{key}: a 2-rank piece is empty or not smaller than the whole")
        expect(sum(counts) == int(whole[key]), f"{key}: the 2 pieces do not add up to the whole")
    # The volume: each rank draws the cells that may meet its box. On 2 ranks the full sphere is
    # cut at x = 0, and the half x > 0 holds the azimuth seam (phi = 0): a wrapping range of
    # azimuths, which that rank takes whole. The other rank draws fewer cells than the grid.
    drawn = [int(r["volume_cells"]) for r in two]
    print(f"volume cells drawn: 1 rank {whole['volume_cells']}, 2 ranks {drawn}")
    expect(int(whole["volume_cells"]) == int(whole["grid_cells"]), "1 rank did not draw the grid")
    expect(all(0 < c <= int(whole["grid_cells"]) for c in drawn) and
           min(drawn) < int(whole["grid_cells"]), "a rank drew no volume cells, or both all")
    for key in ("geometry_mib", "bvh_mib"):
        values = [float(r[key]) for r in two]
        print(f"{key}: 1 rank {whole[key]}, 2 ranks {values}")
        expect(all(0 < v < float(whole[key]) for v in values), f"{key} per rank did not fall")
    with open(os.path.join(OUTPUT, "scale.md")) as stream:
        table = stream.read()
    print(table)
    expect("| strong | 2 |" in table, "scale.md lacks the 2-rank line")
    print("ok" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
