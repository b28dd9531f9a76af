#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Interactive viewer for exact SH glyphs (sightline.vtkSightlineSHGlyphMapper) over an
anatomical slice, in a VTK window with the trackball camera.

Keys:
  Up / Down, Page Up / Page Down   move the slice by one voxel
  a / c / s                        axial / coronal / sagittal slice
  h                                shadows: off -> hard -> soft
  n                                negative lobes: show -> color -> hide
  u                                uncertainty volume on/off (with --uncertainty)
  r                                reset the camera to the slice view
  q / e                            quit (VTK's default)
While the camera moves the mapper traces every second pixel and refines when you stop.

It takes the same data options as render_sh_glyphs.py (--sh, --basis, --slice, --index,
--shadows, --uncertainty, --anatomy, --size, --output ...). --test runs a fixed key sequence
through the same handlers, renders after each step, saves the last frame as a PNG into --output
and exits (for CI under xvfb-run; no user needed).
"""
import os
import sys
import time

import vtk

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import render_sh_glyphs as common  # noqa: E402

BOUND_KEYS = ("Up", "Down", "Prior", "Next", "a", "c", "s", "h", "n", "u", "r")
TEST_KEYS = ("Up", "Up", "Down", "Next", "Prior", "h", "h", "h", "n", "n", "n", "u", "u",
             "c", "Up", "s", "Down", "a", "r")


class Viewer:
    def __init__(self, args):
        self.args = args
        self.scene = common.SHGlyphScene(args)
        self.renderer = vtk.vtkRenderer()
        self.renderer.SetBackground(0.06, 0.065, 0.08)
        self.renderer.AddActor(self.scene.actor)
        if self.scene.anatomy is not None:
            self.renderer.AddViewProp(self.scene.anatomy)
        self.light = self.scene.make_light()
        self.renderer.AddLight(self.light)
        self.window = vtk.vtkRenderWindow()
        self.window.AddRenderer(self.renderer)
        self.window.SetSize(*args.size)
        self.window.SetWindowName("Sightline SH glyphs")
        if args.test:
            self.window.SetOffScreenRendering(1)
        self.reset_view()

    # -- handlers: each changes the scene and returns a status line -------------------------
    def reset_view(self):
        self.scene.place_camera(self.renderer, self.args.elevation)
        self.update_light()
        return "camera reset"

    def update_light(self):
        fresh = self.scene.make_light()
        self.light.SetPosition(fresh.GetPosition())
        self.light.SetFocalPoint(fresh.GetFocalPoint())

    def move_slice(self, step):
        self.scene.move_slice(step)
        self.renderer.ResetCameraClippingRange()
        return self.scene.status()

    def set_orientation(self, orientation):
        self.scene.set_slice(orientation, -1)
        self.reset_view()
        return self.scene.status()

    def cycle_shadows(self):
        modes = common.SHADOWS
        self.scene.set_shadows(modes[(modes.index(self.scene.shadows) + 1) % len(modes)])
        return self.scene.status()

    def cycle_negative_lobes(self):
        modes = common.NEGATIVE_LOBES
        self.scene.set_negative_lobes(
            modes[(modes.index(self.scene.negative_lobes) + 1) % len(modes)])
        return self.scene.status()

    def toggle_uncertainty(self):
        if not self.scene.has_uncertainty:
            return "no uncertainty file given (--uncertainty FILE)"
        self.scene.set_uncertainty(not self.scene.uncertainty_on)
        return self.scene.status()

    def handle_key(self, key):
        """Run the handler bound to `key` (a vtkRenderWindowInteractor key symbol); None if the
        key is not bound."""
        actions = {
            "Up": lambda: self.move_slice(1), "Down": lambda: self.move_slice(-1),
            "Prior": lambda: self.move_slice(1), "Next": lambda: self.move_slice(-1),
            "a": lambda: self.set_orientation("axial"),
            "c": lambda: self.set_orientation("coronal"),
            "s": lambda: self.set_orientation("sagittal"),
            "h": self.cycle_shadows, "n": self.cycle_negative_lobes, "u": self.toggle_uncertainty,
            "r": self.reset_view,
        }
        action = actions.get(key)
        return action() if action else None

    def render(self):
        start = time.perf_counter()
        self.window.Render()
        return time.perf_counter() - start

    # -- modes ------------------------------------------------------------------------------
    def on_key(self, interactor, _event):
        key = interactor.GetKeySym()
        message = self.handle_key(key)
        if message is not None:
            seconds = self.render()
            mapper = self.scene.mapper
            print(f"[{key}] {message}: {mapper.GetNumberOfPrimitives()} glyphs, "
                  f"{seconds * 1e3:.0f} ms")

    def run(self):
        print(__doc__.split("It takes")[0].rstrip())
        print(self.scene.describe())
        print(self.scene.status())
        interactor = vtk.vtkRenderWindowInteractor()
        style = vtk.vtkInteractorStyleTrackballCamera()
        # Observing KeyPressEvent / CharEvent on the style replaces its own OnKeyPress/OnChar:
        # bound keys are ours ('s' would switch the actors to surface, 'r' reset the camera
        # to the bounds); every other key keeps VTK's meaning ('q'/'e' quit, 'f' fly to, ...).
        def on_key_press(caller, event):
            if caller.GetInteractor().GetKeySym() in BOUND_KEYS:
                self.on_key(caller.GetInteractor(), event)

        def on_char(caller, _event):
            if caller.GetInteractor().GetKeySym() not in BOUND_KEYS:
                caller.OnChar()

        style.AddObserver("KeyPressEvent", on_key_press)
        style.AddObserver("CharEvent", on_char)
        interactor.SetInteractorStyle(style)
        interactor.SetRenderWindow(self.window)
        interactor.Initialize()
        self.window.Render()
        interactor.Start()

    def run_test(self):
        print(self.scene.describe())
        seconds = self.render()
        print(f"start: {self.scene.status()}: {self.scene.mapper.GetNumberOfPrimitives()} "
              f"glyphs, {seconds * 1e3:.0f} ms")
        for key in TEST_KEYS:
            message = self.handle_key(key)
            seconds = self.render()
            print(f"[{key}] {message}: {self.scene.mapper.GetNumberOfPrimitives()} glyphs, "
                  f"{seconds * 1e3:.0f} ms")
        os.makedirs(self.args.output, exist_ok=True)
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(self.window)
        grab.ReadFrontBufferOff()
        writer = vtk.vtkPNGWriter()
        writer.SetInputConnection(grab.GetOutputPort())
        path = os.path.join(self.args.output, "interactive_sh_glyphs_test.png")
        writer.SetFileName(path)
        writer.Write()
        print(f"wrote {path}")
        return path


def main(argv=None):
    args = common.parse_arguments(argv, description=__doc__, interactive=True)
    viewer = Viewer(args)
    if args.test:
        viewer.run_test()
    else:
        viewer.run()


if __name__ == "__main__":
    main()
