# SPDX-License-Identifier: BSD-3-Clause
"""Run by TestParaViewInstall.cmake: pvbatch with PV_PLUGIN_PATH = the installed plugin's folder,
no LD_LIBRARY_PATH. Checks that pvbatch loaded the installed plugin from there, checks that every Sightline library mapped into
this process comes from the install prefix (the plugin finds its module libraries by RPATH),
and renders an SWC file as Sightline Spheres. Arguments: PREFIX SWC_FILE."""
import os
import sys

from paraview import servermanager
from paraview.simple import ColorBy, CreateView, OpenDataFile, Render, Show
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter
import numpy as np

prefix, swc = (os.path.realpath(a) for a in sys.argv[1:3])
assert "LD_LIBRARY_PATH" not in os.environ, "LD_LIBRARY_PATH is set"
(plugin_dir,) = os.environ["PV_PLUGIN_PATH"].split(os.pathsep)
assert os.path.realpath(plugin_dir).startswith(prefix + os.sep), plugin_dir

# pvbatch loads the plugins it finds in PV_PLUGIN_PATH at startup (a second LoadPlugin of the
# same file would report "Plugin load failed: No plugin loaded yet.").
plugins = servermanager.vtkPVPluginsInformation()
servermanager.ActiveConnection.Session.GatherInformation(
    servermanager.vtkSMSession.CLIENT_AND_SERVERS, plugins, 0)
loaded = {plugins.GetPluginName(i): plugins.GetPluginFileName(i)
          for i in range(plugins.GetNumberOfPlugins()) if plugins.GetPluginLoaded(i)}
print("loaded plugins:", loaded)
assert "Sightline" in loaded, "pvbatch did not load Sightline from PV_PLUGIN_PATH"
assert os.path.realpath(loaded["Sightline"]) == os.path.realpath(
    os.path.join(plugin_dir, "Sightline.so")), loaded["Sightline"]

with open("/proc/self/maps") as maps:
    mapped = sorted({line.split()[-1] for line in maps if "Sightline" in line.split()[-1]})
print("Sightline libraries in this process:\n  " + "\n  ".join(mapped))
names = {os.path.basename(path).split(".so")[0] for path in mapped}
for needed in ("Sightline", "libSightlineKernel", "libSightlineRendering", "libSightlineIO",
               "libSightlineSources", "libSightlineParaView"):
    assert needed in names, f"{needed} is not loaded"
outside = [path for path in mapped if not os.path.realpath(path).startswith(prefix + os.sep)]
assert not outside, f"Sightline libraries loaded from outside the prefix: {outside}"

reader = OpenDataFile(swc)
assert reader is not None and reader.GetXMLName() == "SightlineSWCReader", reader
view = CreateView("RenderView")
view.ViewSize = [300, 200]
view.OrientationAxesVisibility = 0
view.UseColorPaletteForBackground = 0
view.Background = [0, 0, 0]
rep = Show(reader, view)
rep.Representation = "Sightline Spheres"
ColorBy(rep, None)
rep.SphereRadiusArray = ["POINTS", "Radius"]
view.ResetCamera()
Render(view)
grab = vtkWindowToImageFilter()
grab.SetInput(view.GetRenderWindow())
grab.ReadFrontBufferOff()
grab.Update()
image = grab.GetOutput()
w, h, _ = image.GetDimensions()
pixels = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3]
covered = float(np.mean(pixels.max(axis=2) > 8))
print(f"installed plugin: Sightline Spheres cover {covered:.1%} of the view")
assert covered > 0.02, "the installed plugin drew (almost) nothing"
print("ok")
