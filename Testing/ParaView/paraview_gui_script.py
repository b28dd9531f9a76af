# SPDX-License-Identifier: BSD-3-Clause
"""Runs inside the ParaView GUI (`paraview --script=paraview_gui_script.py --exit`), started by
run_paraview_gui.py for the test ParaView.GUI. It does not load the plugin: the GUI must have
loaded it from PV_PLUGIN_PATH at startup. It opens CST_R.trk and the SHData fixture's .mif in
the GUI's own render view, shows them as Sightline Tubes and Sightline SH Glyphs, renders,
saves the view and counts drawn pixels, and writes what it found as JSON to
SIGHTLINE_GUI_RESULT. Exceptions only print a traceback in the GUI (its exit status stays 0),
so the driver fails the test when that file is missing or says a check failed.
"""
import json
import os
import traceback

RESULT = os.environ["SIGHTLINE_GUI_RESULT"]
TRK = os.environ["SIGHTLINE_GUI_TRK"]
MIF = os.path.join(os.environ["SIGHTLINE_SH_DATA_DIR"], "small_64D_sh_tournier07.mif")
BACKGROUND = [0.0, 0.0, 0.0]


def drawn_fraction(view, path):
    """Saves the view as `path` and returns the fraction of pixels that are not background."""
    from paraview.simple import SaveScreenshot
    from vtkmodules.vtkIOImage import vtkPNGReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    SaveScreenshot(path, view, ImageResolution=[900, 600], TransparentBackground=0)
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    pixels = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())[:, :3]
    return float((pixels.max(axis=1) > 24).mean())


def representation(rep):
    """The representation type as the server manager holds it."""
    return rep.SMProxy.GetProperty("Representation").GetElement(0)


def run():
    import paraview.simple as pvs
    found = {}
    # Autoloaded from PV_PLUGIN_PATH: the readers and the representations exist before this
    # script loads anything (it never calls LoadPlugin).
    found["plugin_proxies"] = sorted(n for n in dir(pvs) if n.startswith("Sightline"))
    view = pvs.GetActiveView()
    found["view"] = view.GetXMLName() if view else None
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = BACKGROUND
    out = os.path.dirname(RESULT)

    tracks = pvs.OpenDataFile(TRK)                        # File > Open's reader factory
    found["trk_reader"] = tracks.GetXMLName()
    tracks.UpdatePipeline()
    found["trk_points"] = tracks.GetDataInformation().GetNumberOfPoints()
    tracks_rep = pvs.Show(tracks, view)
    found["polydata_representations"] = list(tracks_rep.Representation.Available)
    tracks_rep.Representation = "Wireframe"               # ParaView's own lines, for scale
    tracks_rep.AmbientColor = tracks_rep.DiffuseColor = [1.0, 1.0, 1.0]
    view.ResetCamera()
    pvs.Render(view)
    found["lines_drawn"] = drawn_fraction(view, os.path.join(out, "ParaViewGUILines.png"))
    tracks_rep.Representation = "Sightline Tubes"
    tracks_rep.TubeRadius = 1.0
    pvs.Render(view)
    found["tubes_representation"] = representation(tracks_rep)
    found["tubes_drawn"] = drawn_fraction(view, os.path.join(out, "ParaViewGUITubes.png"))
    pvs.Hide(tracks, view)

    image = pvs.OpenDataFile(MIF)
    found["mif_reader"] = image.GetXMLName()
    glyphs = pvs.Show(image, view)
    found["image_representations"] = list(glyphs.Representation.Available)
    glyphs.Representation = "Sightline SH Glyphs"
    pvs.ColorBy(glyphs, None)
    glyphs.SHCoefficients = ["POINTS", "SHCoefficients"]
    glyphs.SHBasis = "tournier07 (MRtrix3)"
    glyphs.GlyphSliceOrientation = "Axial"
    view.CameraPosition = [0, 0, 1]
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraViewUp = [0, 1, 0]
    view.ResetCamera()
    pvs.Render(view)
    found["glyphs_representation"] = representation(glyphs)
    found["glyphs_drawn"] = drawn_fraction(view, os.path.join(out, "ParaViewGUIGlyphs.png"))
    return found


try:
    result = run()
except Exception:  # reported to the driver, which fails the test
    result = {"error": traceback.format_exc()}
try:
    text = json.dumps(result, indent=1)
except TypeError:
    text = json.dumps({"error": traceback.format_exc()})
with open(RESULT, "w") as f:
    f.write(text)
