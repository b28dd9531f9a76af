#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Exact spherical-harmonics glyphs (fibre ODFs) of a real diffusion MRI slice, ray-traced by
sightline.vtkSightlineSHGlyphMapper, over an anatomical slice (FA or b0) drawn by an ordinary
vtkImageSlice in the same window and with the same affine.

Every voxel's glyph is the exact surface r(w) = |F(w)| of its SH series (no tessellation);
colour shows the lobe direction (red: left-right, green: anterior-posterior, blue:
inferior-superior), soft shadows come from an oblique scene light.

Data: without --sh, DIPY's small_64D DWI fitted with CSD (lmax 8) is generated into the
output folder by scripts/make_sh_data.py (about a minute, once) and its FA is the underlay.

Examples:
  render_sh_glyphs.py --output out                         # the showcase picture
  render_sh_glyphs.py --sh fod.nii.gz --basis mrtrix3 --slice coronal --index 40
  render_sh_glyphs.py --sh fod.nii.gz --uncertainty unc.nii.gz --shadows hard --gl-free

Run with Debian's /usr/bin/python3 (VTK 9.1), PYTHONPATH pointing at the build tree's
lib/python3/dist-packages, and under xvfb-run -a for the window path (not needed with --gl-free).
"""
import argparse
import os
import subprocess
import sys
import time

import numpy as np
import vtk

import sightline
from sightline import nifti
from sightline.view import BASES, add_legacy_options  # name: (mapper basis, legacy default)
from vtkmodules.util.numpy_support import vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))
MAKE_SH_DATA = os.path.join(HERE, os.pardir, os.pardir, "scripts", "make_sh_data.py")
DEFAULT_SH = "small_64D_sh_descoteaux07.nii.gz"
DEFAULT_ANATOMY = "small_64D_fa.nii.gz"

SLICES = ("axial", "coronal", "sagittal")
SHADOWS = ("off", "hard", "soft")
NEGATIVE_LOBES = ("show", "color", "hide")


def parse_arguments(argv=None, description=__doc__, interactive=False):
    """Options of this example; interactive_sh_glyphs.py adds --test and drops --gl-free."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sh", metavar="FILE",
                        help="NIfTI of SH coefficients (4th axis: coefficients). Default: DIPY's "
                             "small_64D CSD fit, generated into the output folder")
    parser.add_argument("--basis", choices=sorted(BASES), default="dipy",
                        help="SH basis: dipy (= descoteaux07, legacy) or mrtrix3 (= tournier07, "
                             "not legacy). Default dipy")
    add_legacy_options(parser)
    parser.add_argument("--sh-frame", choices=("auto", "world", "voxel"), default="auto",
                        help="axes of the SH directions: world (scanner axes, as MRtrix3 writes "
                             "FODs) or voxel (the file's axes: DIPY fits with FSL-style bvecs; "
                             "the glyphs then turn with the affine, through the mapper's "
                             "DirectionToWorldMatrix). auto: voxel for the generated DIPY data, "
                             "else world")
    parser.add_argument("--slice", choices=SLICES, default="axial",
                        help="slice orientation (voxel axis closest to world z, y or x)")
    parser.add_argument("--index", type=int, default=-1,
                        help="slice index along that voxel axis (default: middle)")
    parser.add_argument("--shadows", choices=SHADOWS, default="soft")
    parser.add_argument("--negative-lobes", choices=NEGATIVE_LOBES, default="show")
    parser.add_argument("--scale", type=float, default=1.0,
                        help="glyph scale: 1 fills the voxel (default 1)")
    parser.add_argument("--max-order", type=int, default=-1,
                        help="highest SH band drawn (default: all)")
    parser.add_argument("--uncertainty", metavar="FILE",
                        help="NIfTI of uncertainty glyphs (same grid and basis), drawn as a "
                             "grey volume enclosing each glyph")
    parser.add_argument("--anatomy", metavar="FILE",
                        help="scalar NIfTI (FA, b0, T1) drawn as a slice under the glyphs "
                             "(default with generated data: its FA); 'none' for no underlay")
    parser.add_argument("--size", type=int, nargs=2, default=(1600, 1000), metavar=("W", "H"))
    parser.add_argument("--output", default="output", help="output folder (default: output)")
    if interactive:
        parser.add_argument("--test", action="store_true",
                            help="run a fixed key sequence through the key handlers, render "
                                 "after each, write the last frame as a PNG and exit")
        parser.set_defaults(gl_free=False)
    else:
        parser.add_argument("--gl-free", action="store_true",
                            help="render with vtkSightlineImageRenderer (no window, no "
                                 "OpenGL; the anatomical vtkImageSlice is not drawn there)")
    parser.add_argument("--elevation", type=float, default=45.0,
                        help="camera elevation above the slice plane in degrees (default 45)")
    return parser.parse_args(argv)


def ensure_default_data(folder):
    """The small_64D files in `folder`, generated by scripts/make_sh_data.py when missing."""
    sh = os.path.join(folder, DEFAULT_SH)
    if not os.path.exists(sh):
        print(f"generating DIPY's small_64D SH data into {folder} (scripts/make_sh_data.py) ...",
              flush=True)
        start = time.perf_counter()
        result = subprocess.run([sys.executable, os.path.normpath(MAKE_SH_DATA), folder],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if result.returncode != 0 or not os.path.exists(sh):
            sys.stderr.write(result.stdout[-4000:])
            raise SystemExit(f"make_sh_data.py failed (exit {result.returncode})")
        print(f"  done in {time.perf_counter() - start:.1f} s", flush=True)
    return sh, os.path.join(folder, DEFAULT_ANATOMY)


def read_nifti(path, as_vector):
    """vtkNIFTIImageReader, updated; a missing or unreadable file exits with its name."""
    try:
        return nifti.read(path, as_vector)
    except nifti.NiftiError as error:
        raise SystemExit(f"error: {error}") from None


class SHGlyphScene:
    """Glyph actor (+ optional anatomical slice) for one SH volume; shared by the batch and
    the interactive example."""

    def __init__(self, args):
        self.args = args
        sh_path, anatomy_path = args.sh, args.anatomy
        if sh_path is None:
            default_sh, default_anatomy = ensure_default_data(os.path.join(args.output, "sh_data"))
            sh_path = default_sh
            if anatomy_path is None:
                anatomy_path = default_anatomy
        if anatomy_path is not None and anatomy_path.lower() == "none":
            anatomy_path = None
        self.sh_path, self.anatomy_path = sh_path, anatomy_path

        self.reader = read_nifti(sh_path, as_vector=True)
        image = self.reader.GetOutput()
        self.coefficients = image.GetPointData().GetScalars()
        basis, legacy = BASES[args.basis]
        legacy = legacy if args.legacy is None else args.legacy
        frame = args.sh_frame
        if frame == "auto":
            frame = "voxel" if args.sh is None else "world"
        self.frame = frame
        self.has_uncertainty = False
        if args.uncertainty:
            # A second coefficient array in the same image (a renamed shallow copy, the
            # reader calls every array "NIFTI").
            uncertainty_reader = read_nifti(args.uncertainty, as_vector=True)
            if uncertainty_reader.GetOutput().GetDimensions() != image.GetDimensions():
                raise SystemExit(f"{args.uncertainty}: grid differs from {sh_path}")
            source = uncertainty_reader.GetOutput().GetPointData().GetScalars()
            uncertainty = source.NewInstance()
            uncertainty.ShallowCopy(source)
            uncertainty.SetName("uncertainty")
            combined = vtk.vtkImageData()
            combined.ShallowCopy(image)
            combined.GetPointData().AddArray(uncertainty)
            image = combined
            self.has_uncertainty = True
        self.image = image

        mapper = sightline.vtkSightlineSHGlyphMapper()
        mapper.SetInputDataObject(image)
        # Voxel centres in world space from the file's best affine (sform, else qform, else
        # nibabel's base affine), for VTK's slice order.
        self.data_to_world = nifti.data_to_world(self.reader)
        mapper.SetDataToWorldMatrix(self.data_to_world)
        if frame == "voxel":
            # The glyphs turn with the image: their directions are in the file's voxel axes.
            mapper.SetDirectionToWorldMatrix(nifti.file_axes_to_world(self.reader))
        if not mapper.SetBasisByName(basis):
            raise SystemExit(f"unknown basis {basis}")
        mapper.SetLegacyBasis(legacy)
        mapper.SetMaximumOrder(args.max_order)
        mapper.SetScaleFactor(args.scale)
        mapper.SetInteractiveSubsampling(2)
        self.mapper = mapper
        self.actor = vtk.vtkActor()
        self.actor.SetMapper(mapper)
        prop = self.actor.GetProperty()
        prop.SetAmbient(0.15)
        prop.SetDiffuse(0.85)
        prop.SetSpecular(0.4)
        prop.SetSpecularPower(40)

        self.anatomy = None
        if anatomy_path:
            self.anatomy_reader = read_nifti(anatomy_path, as_vector=False)
            if self.anatomy_reader.GetOutput().GetDimensions() != image.GetDimensions():
                print(f"warning: {anatomy_path} has another grid than {sh_path}: the underlay "
                      "follows its own slice index", file=sys.stderr)
            self.anatomy_mapper = vtk.vtkImageSliceMapper()
            self.anatomy_mapper.SetInputConnection(self.anatomy_reader.GetOutputPort())
            self.anatomy_mapper.BorderOn()  # whole voxels, also at the edges
            self.anatomy = vtk.vtkImageSlice()
            self.anatomy.SetMapper(self.anatomy_mapper)
            # The same affine as the glyph centres (see vtkSightlineSHGlyphMapper's docs).
            # Moved along the slice normal to just below the glyphs (set_slice) so that they sit
            # on the slice instead of being cut by it.
            self.anatomy_matrix = vtk.vtkMatrix4x4()
            self.anatomy.SetUserMatrix(self.anatomy_matrix)
            low, high = self.anatomy_reader.GetOutput().GetScalarRange()
            if anatomy_path and "fa" in os.path.basename(anatomy_path).lower():
                low, high = 0.0, max(high, 1e-6) * 0.9
            property_ = self.anatomy.GetProperty()
            # Dimmed (the brightest voxel shows 70% grey) so the glyphs stand out.
            window = max(high - low, 1e-6) / 0.7
            property_.SetColorWindow(window)
            property_.SetColorLevel(low + 0.5 * window)
            property_.SetInterpolationTypeToNearest()

        self.set_slice(args.slice, args.index)
        self.set_shadows(args.shadows)
        self.set_negative_lobes(args.negative_lobes)
        if self.has_uncertainty:
            self.set_uncertainty(True)

    # -- state changes (also the interactive example's key handlers) -----------------------
    def set_slice(self, orientation, index=None):
        mapper = self.mapper
        getattr(mapper, "SetSliceOrientationTo" + orientation.capitalize())()
        axis = mapper.GetSliceAxis()
        extent = self.image.GetExtent()
        low, high = extent[2 * axis], extent[2 * axis + 1]
        if index is None or index < 0:
            index = (low + high) // 2
        index = min(max(index, low), high)
        mapper.SetSliceNumber(index)
        self.orientation, self.axis, self.index = orientation, axis, index
        if self.anatomy is not None:
            self.anatomy_mapper.SetOrientation(axis)
            self.anatomy_mapper.SetSliceNumber(index)
            _, normal, _ = self.slice_frame()
            radius = self.args.scale * 0.5 * min(self.image.GetSpacing())
            self.anatomy_matrix.DeepCopy(nifti.data_to_world(self.anatomy_reader))
            for row in range(3):
                self.anatomy_matrix.SetElement(row, 3, self.anatomy_matrix.GetElement(row, 3)
                                               - 0.6 * radius * normal[row])
        return index

    def move_slice(self, step):
        return self.set_slice(self.orientation, self.index + step)

    def set_shadows(self, mode):
        getattr(self.mapper, "SetShadowModeTo" + mode.capitalize())()
        self.shadows = mode

    def set_negative_lobes(self, mode):
        getattr(self.mapper, "SetNegativeLobesTo" + mode.capitalize())()
        self.negative_lobes = mode

    def set_uncertainty(self, on):
        self.mapper.SetUncertaintyArrayName("uncertainty" if on and self.has_uncertainty else None)
        self.uncertainty_on = bool(on and self.has_uncertainty)

    # -- view -------------------------------------------------------------------------------
    def slice_frame(self):
        """World centre of the drawn slice, its world normal (towards the viewer's side:
        superior, anterior or right... whichever world axis the slice is closest to) and a
        view-up direction in the slice plane."""
        matrix = self.data_to_world
        spacing = self.image.GetSpacing()
        origin = self.image.GetOrigin()
        extent = list(self.image.GetExtent())
        extent[2 * self.axis] = extent[2 * self.axis + 1] = self.index
        centre_data = [origin[i] + spacing[i] * 0.5 * (extent[2 * i] + extent[2 * i + 1])
                       for i in range(3)]
        centre = matrix.MultiplyPoint(centre_data + [1.0])[:3]
        normal = np.array([matrix.GetElement(r, self.axis) for r in range(3)])
        normal /= np.linalg.norm(normal)
        world_axis = {"axial": 2, "coronal": 1, "sagittal": 0}[self.orientation]
        if normal[world_axis] < 0:
            normal = -normal
        # Axial: anterior (+y) up on screen; coronal and sagittal: superior (+z) up.
        up = np.array([0.0, 1.0, 0.0]) if self.orientation == "axial" else np.array([0.0, 0.0, 1.0])
        up = up - normal * np.dot(up, normal)
        up /= np.linalg.norm(up)
        return np.array(centre), normal, up

    def place_camera(self, renderer, elevation):
        """Look at the slice from its normal side, tilted by `elevation` degrees from the
        slice plane's 'up' edge towards the viewer, then frame the glyphs."""
        centre, normal, up = self.slice_frame()
        tilt = np.radians(90.0 - elevation)  # 0: straight down the normal
        direction = np.cos(tilt) * normal - np.sin(tilt) * up
        camera = renderer.GetActiveCamera()
        camera.SetFocalPoint(*centre)
        camera.SetPosition(*(centre + 100.0 * direction))
        camera.SetViewUp(*(np.cos(tilt) * up + np.sin(tilt) * normal))
        camera.SetViewAngle(30)
        renderer.ResetCamera(self.mapper.GetBounds())
        camera.Zoom(1.45)
        # The slice's far edge is foreshortened: shift the picture up a little to centre it.
        camera.SetWindowCenter(0.0, -0.17 * np.sin(np.radians(90.0 - elevation)))
        renderer.ResetCameraClippingRange()
        return camera

    def make_light(self):
        """A white scene light from the upper left, oblique to the slice, so the glyphs cast
        visible shadows onto their neighbours."""
        centre, normal, up = self.slice_frame()
        side = np.cross(up, normal)
        direction = 0.35 * normal + 0.55 * up - 0.75 * side
        light = vtk.vtkLight()
        light.SetLightTypeToSceneLight()
        light.SetFocalPoint(*centre)
        light.SetPosition(*(centre + 100.0 * direction / np.linalg.norm(direction)))
        light.SetIntensity(1.0)
        return light

    def status(self):
        text = (f"{self.orientation} slice {self.index}, shadows {self.shadows}, negative lobes "
                f"{self.negative_lobes}")
        if self.has_uncertainty:
            text += f", uncertainty {'on' if self.uncertainty_on else 'off'}"
        return text

    def describe(self):
        image = self.image
        return (f"{os.path.basename(self.sh_path)}: {image.GetDimensions()} voxels, "
                f"{self.coefficients.GetNumberOfComponents()} coefficients, basis "
                f"{self.mapper.GetBasisAsString()} (legacy {bool(self.mapper.GetLegacyBasis())})")


def non_background_fraction(rgb, background):
    rgb = np.asarray(rgb)[..., :3].astype(int)
    bg = np.round(np.asarray(background) * 255).astype(int)
    return float((np.abs(rgb - bg).max(axis=-1) > 8).mean())


def print_timings(mapper, label, seconds):
    print(f"{label}: {seconds * 1e3:.1f} ms (ray tracing {mapper.GetLastFrameSeconds() * 1e3:.1f} ms)")


def main(argv=None):
    args = parse_arguments(argv)
    os.makedirs(args.output, exist_ok=True)
    width, height = args.size
    background = (0.06, 0.065, 0.08)

    scene = SHGlyphScene(args)
    print(scene.describe())
    mapper = scene.mapper

    renderer = vtk.vtkRenderer()
    renderer.SetBackground(*background)
    renderer.AddActor(scene.actor)
    if scene.anatomy is not None and not args.gl_free:
        renderer.AddViewProp(scene.anatomy)
    light = scene.make_light()
    renderer.AddLight(light)
    camera = scene.place_camera(renderer, args.elevation)

    suffix = f"{args.slice}_{scene.index}"
    if args.gl_free:
        if scene.anatomy is not None:
            print("note: --gl-free draws only Sightline actors; the anatomical vtkImageSlice "
                  "is not drawn (use the window path for the underlay)")
        batch = sightline.vtkSightlineImageRenderer()
        batch.AddActor(scene.actor)
        batch.AddLight(light)
        batch.SetActiveCamera(camera)
        batch.SetSize(width, height)
        batch.SetBackground(*background)
        start = time.perf_counter()
        batch.Update()
        seconds = time.perf_counter() - start
        output = batch.GetOutput()
        rgb = vtk_to_numpy(output.GetPointData().GetScalars())
        path = os.path.join(args.output, f"sh_glyphs_{suffix}_gl_free.png")
        writer = vtk.vtkPNGWriter()
        writer.SetInputConnection(batch.GetOutputPort())
        label = f"GL-free frame ({width}x{height}, incl. geometry and BVH)"
    else:
        window = vtk.vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.SetMultiSamples(0)
        window.AddRenderer(renderer)
        window.SetSize(width, height)
        start = time.perf_counter()
        window.Render()
        seconds = time.perf_counter() - start
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.ReadFrontBufferOff()
        grab.Update()
        rgb = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
        path = os.path.join(args.output, f"sh_glyphs_{suffix}.png")
        writer = vtk.vtkPNGWriter()
        writer.SetInputConnection(grab.GetOutputPort())
        label = f"window frame ({width}x{height}, first render incl. geometry, BVH, GL setup)"
    writer.SetFileName(path)
    writer.Write()

    print(f"glyphs: {mapper.GetNumberOfPrimitives()} ({scene.status()}; "
          f"{mapper.GetLastComputedBoxes()} glyph boxes computed)")
    print(f"geometry (glyph boxes): {mapper.GetLastGeometrySeconds() * 1e3:.1f} ms")
    print(f"BVH build: {mapper.GetLastBuildSeconds() * 1e3:.1f} ms")
    print_timings(mapper, label, seconds)
    covered = non_background_fraction(rgb, background)
    print(f"wrote {path} ({covered * 100:.1f}% of pixels not background)")
    if mapper.GetNumberOfPrimitives() == 0:
        print("warning: no glyphs in this slice (all masked or zero?)", file=sys.stderr)
    return path


if __name__ == "__main__":
    main()
