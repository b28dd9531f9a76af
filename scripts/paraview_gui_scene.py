# SPDX-License-Identifier: BSD-3-Clause
"""The scene of Data/Images/paraview-gui.png, run inside the ParaView GUI by
scripts/paraview-gui-picture.sh (`paraview --dr --script=paraview_gui_scene.py`), with the
plugin autoloaded from PV_PLUGIN_PATH. Left view: DIPY's corticospinal tract (CST_R.trk) as
Sightline Tubes coloured by height through Viridis; right view: the SHData fixture's .mif as
Sightline SH Glyphs. The tubes stay the active source, so the Properties panel shows their
Sightline Tubes group. Writes SIGHTLINE_GUI_READY when done (the driver then takes the picture).
Writes nothing to stderr: that would open ParaView's Output Messages window over the views.
"""
import os
import tempfile
import zipfile

import paraview.simple as pvs

BUNDLES = "/usr/lib/python3/dist-packages/dipy/data/files/minimal_bundles.zip"
folder = tempfile.mkdtemp()
with zipfile.ZipFile(BUNDLES) as archive:
    archive.extract("sub_1/CST_R.trk", folder)

layout = pvs.GetLayout()
left = pvs.GetActiveView()
left.OrientationAxesVisibility = 0

# Right: SH glyphs of one axial slice, by lobe direction.
image = pvs.OpenDataFile(os.environ["SIGHTLINE_GUI_MIF"])
layout.SplitHorizontal(0, 0.55)
right = pvs.CreateView("RenderView")
pvs.AssignViewToLayout(view=right, layout=layout, hint=2)
right.OrientationAxesVisibility = 0
glyphs = pvs.Show(image, right)
glyphs.Representation = "Sightline SH Glyphs"
pvs.ColorBy(glyphs, None)
glyphs.SHCoefficients = ["POINTS", "SHCoefficients"]
glyphs.SHBasis = "tournier07 (MRtrix3)"
glyphs.GlyphSliceOrientation = "Axial"
glyphs.GlyphSlice = -1
right.CameraPosition = [0, 0, 1]
right.CameraFocalPoint = [0, 0, 0]
right.CameraViewUp = [0, 1, 0]
right.ResetCamera()

# Left: the tract as tubes coloured by height.
pvs.SetActiveView(left)
tracks = pvs.OpenDataFile(os.path.join(folder, "sub_1", "CST_R.trk"))
height = pvs.Calculator(Input=tracks, ResultArrayName="height (mm)", Function="coordsZ")
tubes = pvs.Show(height, left)
pvs.Hide(tracks, left)
tubes.Representation = "Sightline Tubes"
tubes.TubeRadius = 0.5
tubes.Shadows = "Hard"
pvs.ColorBy(tubes, ("POINTS", "height (mm)"))
lut = pvs.GetColorTransferFunction("height (mm)")
lut.ApplyPreset("Viridis (matplotlib)", True)
tubes.RescaleTransferFunctionToDataRange(True)
tubes.SetScalarBarVisibility(left, True)
left.ResetCamera()
left.CameraPosition = [260, -260, 120]
left.CameraFocalPoint = [22, -18, -14]
left.CameraViewUp = [0, 0, 1]
left.ResetCamera()
pvs.SetActiveSource(height)
pvs.Render(left)
pvs.Render(right)
with open(os.environ["SIGHTLINE_GUI_READY"], "w") as f:
    f.write("ready\n")
