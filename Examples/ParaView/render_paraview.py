# SPDX-License-Identifier: BSD-3-Clause
"""Sightline in ParaView, from pvbatch or pvpython: DIPY's corticospinal-tract bundle (.trk,
opened through File > Open's reader factory) as exact tubes coloured through a ParaView colour
map, PREM's density as a spherical volume beside it, ParaView's own outline and axes grid
around them, and a scalar bar.

  PYTHONPATH=<ParaView's Python>:<build>/lib/python3.X/site-packages \\
    pvbatch --force-offscreen-rendering render_paraview.py --plugin <Sightline.so> --output DIR
"""
import argparse
import os
import tempfile
import zipfile

from paraview.simple import (Calculator, ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             GetScalarBar, LoadPlugin, OpenDataFile, Outline, Render,
                             SaveScreenshot, Show, Transform)

BUNDLES = "/usr/lib/python3/dist-packages/dipy/data/files/minimal_bundles.zip"

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--plugin", required=True, help="path to the Sightline plugin (Sightline.so)")
parser.add_argument("--output", default="output", help="folder for paraview_sightline.png")
parser.add_argument("--size", type=int, nargs=2, default=(1600, 1000))
args = parser.parse_args()
os.makedirs(args.output, exist_ok=True)
LoadPlugin(args.plugin, ns=globals())

folder = tempfile.mkdtemp()
with zipfile.ZipFile(BUNDLES) as archive:
    archive.extract("sub_1/CST_R.trk", folder)
tracks = OpenDataFile(os.path.join(folder, "sub_1", "CST_R.trk"))  # Sightline's TrackVis reader
height = Calculator(Input=tracks, ResultArrayName="height (mm)", Function="coordsZ")

view = GetActiveViewOrCreate("RenderView")
view.ViewSize = list(args.size)
view.OrientationAxesVisibility = 0
tubes = Show(height, view)
tubes.Representation = "Sightline Tubes"
tubes.TubeRadius = 0.5
ColorBy(tubes, ("POINTS", "height (mm)"))
lut = GetColorTransferFunction("height (mm)")
lut.ApplyPreset("Viridis (matplotlib)", True)
tubes.RescaleTransferFunctionToDataRange(True)
tubes.SetScalarBarVisibility(view, True)
GetScalarBar(lut, view).Title = "height (mm)"
tubes.Shadows = "Hard"
Show(Outline(Input=height), view)  # ParaView's own geometry, composited by depth with the tubes

# PREM, scaled to 40 mm and placed beside the bundle, as a spherical volume with a wedge cut out.
earth = SightlineSphericalField(Field="PREM Density", RadialResolution=32,  # noqa: F821
                                PolarResolution=32, AzimuthalResolution=64,
                                AzimuthRange=[0.0, 4.71238898038469])
volume = Show(earth, view)
volume.Representation = "Sightline Spherical Volume"
volume.Scale = [40, 40, 40]
# ParaView 5.13 calls the display's offset Translation; 5.11 called it Position.
if "Translation" in volume.ListProperties():
    volume.Translation = [60, 0, 0]
else:
    volume.Position = [60, 0, 0]
ColorBy(volume, ("CELLS", "density"))
density = GetColorTransferFunction("density")
density.ApplyPreset("Inferno (matplotlib)", True)
volume.RescaleTransferFunctionToDataRange(True)
volume.ScalarOpacityUnitDistance = 0.3

view.ResetCamera()
view.CameraPosition = [260, -260, 120]
view.CameraFocalPoint = [30, -20, 10]
view.CameraViewUp = [0, 0, 1]
view.ResetCamera()
view.AxesGrid.Visibility = 1
Render(view)
path = os.path.join(args.output, "paraview_sightline.png")
SaveScreenshot(path, view, ImageResolution=list(args.size))
print(path)
