# SPDX-License-Identifier: BSD-3-Clause
"""ParaView.ReaderErrors: bad files opened in pvbatch report the reader's own message.

A driver run by /usr/bin/python3 (ctest). It writes broken files into a temporary folder (a
TrackVis file cut inside its header and one cut inside its streamlines, MRtrix .mif files with a
malformed header line and without END, SWC files with a negative radius and a non-number), and
for each one runs `pvbatch reader_open.py FILE READER` (OpenDataFile + UpdatePipeline). It
asserts that pvbatch ran to the end (no crash), that ParaView picked the Sightline reader, and
that pvbatch's stderr carries the reader's vtkErrorMacro (or, for the cut streamlines,
vtkWarningMacro) text naming the file and the problem.

Environment (from Testing/ParaView/CMakeLists.txt): SIGHTLINE_PVBATCH, SIGHTLINE_PLUGIN,
SIGHTLINE_TEST_TEMP_DIR, PYTHONPATH, LD_LIBRARY_PATH, PV_PLUGIN_PATH, DISPLAY.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SWC_DIR = os.path.join(HERE, "..", "Data", "SWC")
TRK = "/usr/lib/python3/dist-packages/nibabel/tests/data/standard.trk"
PVBATCH = os.environ["SIGHTLINE_PVBATCH"]
PLUGIN = os.environ["SIGHTLINE_PLUGIN"]

MIF_HEADER = "mrtrix image\ndim: 2,2,2\n{broken}\nlayout: +0,+1,+2\ndatatype: Float32LE\n"


def cases(folder):
    """(file, reader, level, regular expression its message must match) for each bad file."""
    with open(TRK, "rb") as f:
        trk = f.read()

    def write(name, data):
        path = os.path.join(folder, name)
        with open(path, "wb" if isinstance(data, bytes) else "w") as f:
            f.write(data)
        return path

    yield (write("cut_header.trk", trk[:600]), "SightlineTrackVisReader", "ERR",
           r"vtkSightlineTrackVisReader.*cut_header\.trk' is not a TrackVis file: it does not "
           r"start with a 1000-byte header whose id is TRACK\.")
    yield (write("cut_streamline.trk", trk[:-10]), "SightlineTrackVisReader", "WARN",
           r"vtkSightlineTrackVisReader.*cut_streamline\.trk' ends inside streamline \d+ "
           r"\(cut short\?\); the \d+ complete streamlines are kept\.")
    yield (write("no_colon.mif", MIF_HEADER.format(broken="vox 1,1,1") + "file: . 200\nEND\n"),
           "SightlineMIFReader", "ERR",
           r"vtkSightlineMIFReader.*no_colon\.mif': malformed header line \"vox 1,1,1\" "
           r"\(no ':'\)")
    yield (write("no_end.mif", MIF_HEADER.format(broken="vox: 1,1,1")), "SightlineMIFReader",
           "ERR", r"vtkSightlineMIFReader.*no_end\.mif': the header has no END line "
           r"\(truncated file\?\)")
    negative = shutil.copy(os.path.join(SWC_DIR, "bad_negative_radius.swc"), folder)
    yield (negative, "SightlineSWCReader", "ERR",
           r"vtkSightlineSWCReader.*bad_negative_radius\.swc' line 2: sample 2 has the "
           r"negative radius -0\.5\.")
    not_a_number = shutil.copy(os.path.join(SWC_DIR, "bad_not_a_number.swc"), folder)
    yield (not_a_number, "SightlineSWCReader", "ERR",
           r"vtkSightlineSWCReader.*bad_not_a_number\.swc' line 2: the y field \"zero\" is not "
           r"a number")


def main():
    failures = 0
    with tempfile.TemporaryDirectory(dir=os.environ.get("SIGHTLINE_TEST_TEMP_DIR")) as folder:
        for path, reader, level, pattern in cases(folder):
            name = os.path.basename(path)
            result = subprocess.run(
                [PVBATCH, "--force-offscreen-rendering", os.path.join(HERE, "reader_open.py"),
                 path, reader, PLUGIN],
                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=120,
                stdin=subprocess.DEVNULL)
            # The reader's message as ParaView prints it: "... ERR| vtkSightlineSWCReader (0x..):
            # text" (or WARN|); colour codes stripped.
            stderr = re.sub(r"\x1b\[[0-9;]*m", "", result.stderr)
            lines = [line for line in stderr.splitlines() if f"{level}|" in line]
            found = [line for line in lines if re.search(pattern, line)]
            problems = []
            if result.returncode != 0:
                problems.append(f"pvbatch exited with {result.returncode}")
            if f"reader: {reader}" not in result.stdout:
                problems.append(f"ParaView did not open it with {reader}")
            if "survived" not in result.stdout:
                problems.append("the script did not get past UpdatePipeline")
            if not found:
                problems.append(f"no {level}| line on stderr matches {pattern!r}")
            status = "FAIL" if problems else "ok"
            print(f"{status}: {name}: " + ("; ".join(problems) if problems else found[0].split(
                f"{level}|", 1)[1].strip()))
            if problems:
                failures += 1
                print("--- stdout ---\n" + result.stdout + "--- stderr ---\n" + stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
