# SPDX-License-Identifier: BSD-3-Clause
"""The test ParaView.GUI: starts the real ParaView GUI (`paraview`) under the X server with
the plugin only on PV_PLUGIN_PATH, runs paraview_gui_script.py in it through `--script` and
quits through `--exit`, then checks the GUI's exit status and what the script found (JSON).

Usage (ctest): run_paraview_gui.py PARAVIEW_EXECUTABLE, with the paraview test environment
(PYTHONPATH with ParaView's Python, PV_PLUGIN_PATH, SIGHTLINE_SH_DATA_DIR,
SIGHTLINE_TEST_TEMP_DIR). Runs with /usr/bin/python3 and the standard library only.
"""
import json
import os
import subprocess
import sys
import tempfile
import zipfile

BUNDLES = "/usr/lib/python3/dist-packages/dipy/data/files/minimal_bundles.zip"
SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "paraview_gui_script.py")


def main():
    paraview = sys.argv[1]
    if not os.environ.get("PV_PLUGIN_PATH"):
        sys.exit("PV_PLUGIN_PATH is not set: the GUI would not find the plugin")
    if not os.environ.get("DISPLAY"):
        sys.exit("no DISPLAY: the ParaView GUI needs an X server (Xvfb)")
    temp = os.environ.get("SIGHTLINE_TEST_TEMP_DIR", tempfile.gettempdir())
    os.makedirs(temp, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=temp) as folder:
        with zipfile.ZipFile(BUNDLES) as archive:
            archive.extract("sub_1/CST_R.trk", folder)
        result_path = os.path.join(temp, "ParaViewGUI.json")
        if os.path.exists(result_path):
            os.remove(result_path)
        env = dict(os.environ,
                   SIGHTLINE_GUI_RESULT=result_path,
                   SIGHTLINE_GUI_TRK=os.path.join(folder, "sub_1", "CST_R.trk"),
                   XDG_RUNTIME_DIR=folder,
                   XDG_CONFIG_HOME=folder)  # even with --dr the GUI writes a settings file
        # --dr: no user settings; --exit: quit (closing all windows) once the script has run.
        command = [paraview, "--dr", f"--script={SCRIPT}", "--exit"]
        print(" ".join(command), flush=True)
        status = subprocess.run(command, env=env, timeout=240).returncode
    if status != 0:
        sys.exit(f"paraview exited with status {status}")
    if not os.path.exists(result_path):
        sys.exit("the GUI did not run the script (no result file)")
    with open(result_path) as f:
        found = json.load(f)
    print(json.dumps(found, indent=1))
    if "error" in found:
        sys.exit("the script failed in the GUI:\n" + found["error"])
    failures = []

    def check(condition, what):
        if not condition:
            failures.append(what)

    for name in ("SightlineTrackVisReader", "SightlineMRtrixImageReader", "SightlineSphericalField"):
        check(name in found["plugin_proxies"], f"plugin not autoloaded: no {name}")
    check(found["view"] == "RenderView", "the GUI's active view is not a render view")
    check(found["trk_reader"] == "SightlineTrackVisReader", ".trk not opened by Sightline's reader")
    check(found["mif_reader"] == "SightlineMIFReader", ".mif not opened by Sightline's reader")
    check(found["trk_points"] >= 1000, "CST_R.trk read (almost) no points")
    for name in ("Sightline Spheres", "Sightline Tubes"):
        check(name in found["polydata_representations"], f"no representation {name!r} for lines")
    for name in ("Sightline SH Glyphs", "Sightline Tensor Glyphs"):
        check(name in found["image_representations"], f"no representation {name!r} for images")
    check(found["tubes_representation"] == "Sightline Tubes", "Sightline Tubes not applied")
    check(found["glyphs_representation"] == "Sightline SH Glyphs", "Sightline SH Glyphs not applied")
    check(found["tubes_drawn"] > 0.02, "Sightline Tubes drew (almost) nothing")
    # Tubes 1 mm thick cover more pixels than ParaView's one-pixel lines of the same tracks.
    check(found["tubes_drawn"] > 1.5 * found["lines_drawn"], "tubes no wider than lines")
    check(found["glyphs_drawn"] > 0.01, "Sightline SH Glyphs drew (almost) nothing")
    if failures:
        sys.exit("ParaView.GUI: " + "; ".join(failures))
    print("ParaView.GUI: passed")


if __name__ == "__main__":
    main()
