# SPDX-License-Identifier: BSD-3-Clause
"""What the ParaView test scripts share (test_paraview.py, client_server_scene.py,
mpi_scene.py): a plain render view, a PNG read back as pixels, and the PREM scene."""
from paraview.simple import ColorBy, CreateView, GetColorTransferFunction, SetActiveView, Show
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

BACKGROUND = [0.1, 0.1, 0.15]


def make_view(size):
    """A render view without orientation axes or FXAA (which smooths thin glyph lobes), on a
    fixed background, made the active view."""
    view = CreateView("RenderView")
    view.ViewSize = list(size)
    view.OrientationAxesVisibility = 0
    view.Background = list(BACKGROUND)
    view.UseColorPaletteForBackground = 0
    view.UseFXAA = 0
    SetActiveView(view)
    return view


def read_png(path):
    """The PNG at `path` as an (h, w, 3) uint8 array, rows as VTK stores them (bottom first)."""
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].copy()


def show_prem(view, source_factory):
    """PREM density from the Sightline Spherical Field source (a quarter wedge cut out, to see
    inside) as a Sightline Spherical Volume coloured through Inferno; returns (source, rep).
    `source_factory` is SightlineSphericalField, which LoadPlugin adds to the caller's names."""
    source = source_factory()
    source.Field = "PREM Density"
    source.RadialResolution = 24
    source.PolarResolution = 24
    source.AzimuthalResolution = 48
    source.AzimuthRange = [0.0, 4.71238898038469]
    rep = Show(source, view)
    rep.Representation = "Sightline Spherical Volume"
    ColorBy(rep, ("CELLS", "density"))
    GetColorTransferFunction("density").ApplyPreset("Inferno (matplotlib)", True)
    rep.RescaleTransferFunctionToDataRange(True)
    rep.ScalarOpacityUnitDistance = 0.05
    return source, rep
