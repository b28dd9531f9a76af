#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Exact higher-order tensor glyphs ray-traced by sightline.vtkSightlineTensorGlyphMapper.

Without --tensor: a copper polycrystal. Each grain is copper's published 4th-order stiffness
tensor (C11 = 168.4, C12 = 121.4, C44 = 75.4 GPa; Kittel, Introduction to Solid State
Physics) turned to a random crystal orientation; the glyph radius in direction w is the
longitudinal modulus C_ijkl w_i w_j w_k w_l, coloured black-red-yellow by that value (the
tensor glyph paper's Fig. 5 colour coding), stiffest along <111> (237.6 GPa), softest along
<100> (168.4 GPa). The tensors are handed to VTK as 3x3x3x3 arrays (81 components).

With --tensor FILE: one slice of a NIfTI image of tensors (4th axis = components; read with
vtkNIFTIImageReader, TimeAsVector on), e.g. the diffusion tensors or generalised-DTI tensors
that scripts/make_tensor_data.py fits to DIPY's small_64D. The layout is guessed from the
component count unless --layout says otherwise (6 components: VTK's XX, YY, ZZ, XY, YZ, XZ by
default; FSL-style xx, xy, xz, yy, yz, zz needs --layout unique).

Examples:
  render_tensor_glyphs.py --output out                               # copper polycrystal
  render_tensor_glyphs.py --tensor small_64D_gdti4.nii.gz --layout unique --output out
  render_tensor_glyphs.py --tensor small_64D_dti.nii.gz --layout unique --shape ellipsoid
  render_tensor_glyphs.py --tensor dt.mif.nii --layout unique --frame world   # MRtrix3 axes
  render_tensor_glyphs.py --method marching --step 0.2 --output out  # the paper's own method

Run with Debian's /usr/bin/python3 (VTK 9.1), PYTHONPATH pointing at the build tree's
lib/python3/dist-packages, and under xvfb-run -a for the window path (not with --gl-free).
"""
import argparse
import os
import sys
import time

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk

import sightline
from sightline import nifti

COPPER_GPA = (168.4, 121.4, 75.4)  # C11, C12, C44
VOIGT_PAIRS = {(0, 0): 0, (1, 1): 1, (2, 2): 2, (1, 2): 3, (2, 1): 3, (0, 2): 4, (2, 0): 4,
               (0, 1): 5, (1, 0): 5}
LAYOUTS = {"auto": "Automatic", "unique": "SymmetricUnique", "full": "Full",
           "vtk": "VTKSymmetric", "voigt": "Voigt"}
METHODS = ("exact", "marching", "interval", "affine")


def cubic_stiffness(c11, c12, c44):
    """The full 3x3x3x3 tensor of a cubic crystal's Voigt constants."""
    voigt = np.zeros((6, 6))
    voigt[:3, :3] = c12
    np.fill_diagonal(voigt[:3, :3], c11)
    voigt[3, 3] = voigt[4, 4] = voigt[5, 5] = c44
    full = np.empty((3, 3, 3, 3))
    for i, j, k, l in np.ndindex(3, 3, 3, 3):
        full[i, j, k, l] = voigt[VOIGT_PAIRS[i, j], VOIGT_PAIRS[k, l]]
    return full


def random_rotation(rng):
    q = rng.normal(size=4)
    a, b, c, d = q / np.linalg.norm(q)
    return np.array([
        [a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)],
        [2 * (b * c + a * d), a * a - b * b + c * c - d * d, 2 * (c * d - a * b)],
        [2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d]])


def copper_polycrystal(grains, seed=7):
    """Points on a grains x grains grid, each with a turned copper tensor (81 components,
    index i + 3j + 9k + 27l)."""
    rng = np.random.default_rng(seed)
    stiffness = cubic_stiffness(*COPPER_GPA)
    points = vtk.vtkPoints()
    tensors = []
    for gy in range(grains):
        for gx in range(grains):
            r = random_rotation(rng)
            turned = np.einsum("ai,bj,ck,dl,ijkl->abcd", r, r, r, r, stiffness)
            points.InsertNextPoint(2.2 * gx, 2.2 * gy, 0.0)
            tensors.append(turned.transpose(3, 2, 1, 0).reshape(81))
    poly = vtk.vtkPolyData()
    poly.SetPoints(points)
    array = numpy_to_vtk(np.array(tensors), deep=1)
    array.SetName("stiffness")
    poly.GetPointData().AddArray(array)
    return poly


def build_pipeline(args):
    mapper = sightline.vtkSightlineTensorGlyphMapper()
    if args.tensor:
        try:
            reader = nifti.read(args.tensor, as_vector=True)
        except nifti.NiftiError as error:
            raise SystemExit(f"error: {error}") from None
        mapper.SetInputConnection(reader.GetOutputPort())
        # The file's best affine (sform, else qform, else nibabel's base affine).
        mapper.SetDataToWorldMatrix(nifti.data_to_world(reader))
        if args.frame == "voxel":
            mapper.SetDirectionToWorldMatrix(nifti.file_axes_to_world(reader))
        mapper.SetSliceOrientationToAxial()
        mapper.SetScaleFactor(0.9)
        if args.index is not None:
            mapper.SetSliceNumber(args.index)
    else:
        producer = vtk.vtkTrivialProducer()
        producer.SetOutput(copper_polycrystal(args.grains))
        mapper.SetInputConnection(producer.GetOutputPort())
        mapper.SetTensorArrayName("stiffness")
        mapper.SetNormalizationToGlobal()  # sizes compare between grains
    getattr(mapper, "SetTensorLayoutTo" + LAYOUTS[args.layout])()
    mapper.SetShapeToEllipsoid() if args.shape == "ellipsoid" else mapper.SetShapeToTensorFunction()
    getattr(mapper, "SetIntersectionMethodTo" + args.method.capitalize())()
    mapper.SetMarchingStepSize(args.step)
    coloring = args.coloring or ("direction" if args.tensor else "radius")
    getattr(mapper, "SetColoringTo" + coloring.capitalize())()
    if coloring == "radius" and not args.tensor:
        mapper.SetRadiusRange(160.0, 240.0)
    if args.shadows == "soft":
        mapper.SetShadowModeToSoft()
    elif args.shadows == "hard":
        mapper.SetShadowModeToHard()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetAmbient(0.2)
    actor.GetProperty().SetSpecular(0.35)
    actor.GetProperty().SetSpecularPower(30)
    return mapper, actor


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tensor", help="NIfTI image of tensors (default: copper polycrystal)")
    parser.add_argument("--layout", choices=sorted(LAYOUTS), default="auto")
    parser.add_argument("--shape", choices=("function", "ellipsoid"), default="function")
    parser.add_argument("--method", choices=METHODS, default="exact")
    parser.add_argument("--step", type=float, default=0.2, help="marching step (bounding radii)")
    parser.add_argument("--coloring", choices=("direction", "radius", "solid"))
    parser.add_argument("--shadows", choices=("off", "hard", "soft"), default="soft")
    parser.add_argument("--index", type=int, help="axial slice index (default: middle)")
    parser.add_argument("--frame", choices=("voxel", "world"), default="voxel",
                        help="axes of the tensor's directions: the file's voxel axes (FSL, DIPY; "
                             "the default) or world axes (MRtrix3)")
    parser.add_argument("--grains", type=int, default=4, help="copper grains per side")
    parser.add_argument("--size", type=int, nargs=2, default=(1200, 900))
    parser.add_argument("--gl-free", action="store_true", help="render without OpenGL")
    parser.add_argument("--output", default="output")
    args = parser.parse_args(argv)

    if args.tensor and not os.path.exists(args.tensor):
        parser.error(f"{args.tensor} does not exist")
    os.makedirs(args.output, exist_ok=True)
    mapper, actor = build_pipeline(args)
    width, height = args.size

    camera = vtk.vtkCamera()
    light = vtk.vtkLight()
    light.SetLightTypeToSceneLight()
    start = time.perf_counter()
    if args.gl_free:
        renderer = sightline.vtkSightlineImageRenderer()
        renderer.AddActor(actor)
    else:
        renderer = vtk.vtkRenderer()
        renderer.AddActor(actor)
        renderer.SetBackground(0.08, 0.08, 0.1)
        window = vtk.vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.AddRenderer(renderer)
        window.SetSize(width, height)
    bounds = actor.GetBounds()
    centre = [0.5 * (bounds[2 * i] + bounds[2 * i + 1]) for i in range(3)]
    extent = max(bounds[1] - bounds[0], bounds[3] - bounds[2])
    # Fit the bounding sphere into the 30 degree view, looking down at 60 degrees.
    radius = 0.5 * np.linalg.norm([bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4]])
    distance = 0.8 * radius / np.sin(np.radians(15.0))
    direction = np.array([0.0, -0.5, 0.866])
    camera.SetFocalPoint(*centre)
    camera.SetPosition(*(np.array(centre) + distance * direction))
    camera.SetViewUp(0, 0, 1)
    camera.SetViewAngle(30)
    light.SetFocalPoint(*centre)
    light.SetPosition(centre[0] - extent, centre[1] - 0.5 * extent, centre[2] + 2 * extent)
    renderer.SetActiveCamera(camera)
    renderer.AddLight(light)

    if args.gl_free:
        renderer.SetSize(width, height)
        renderer.Update()
        image = renderer.GetOutput()
    else:
        renderer.ResetCameraClippingRange()
        window.Render()
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.Update()
        image = grab.GetOutput()
    seconds = time.perf_counter() - start
    name = os.path.splitext(os.path.splitext(os.path.basename(args.tensor or "copper_polycrystal"))[0])[0]
    path = os.path.join(args.output, f"tensor_glyphs_{name}_{args.method}.png")
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()
    print(f"{path}: order {mapper.GetTensorOrder()}, {width}x{height}, {seconds:.2f} s "
          f"(first image, {'GL-free' if args.gl_free else 'VTK window'})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
