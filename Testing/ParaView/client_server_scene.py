# SPDX-License-Identifier: BSD-3-Clause
"""Renders two Sightline scenes with pvpython, either connected to a pvserver (--server
HOST:PORT) or builtin (no --server), and saves each as PNG plus a raw .npy of its pixels for
test_client_server.py to compare. Connected, each scene is saved twice: rendered remotely
(RemoteRenderThreshold 0: the server draws and delivers the image) and locally (the geometry is
delivered and the client draws it); builtin, the two are the same render.

Scenes: 'Spheres' (an SWC file read on the server, Sightline Spheres with its Radius array) and
'PREM' (the Sightline Spherical Field source, PREM Density, as a Sightline Spherical Volume).
The camera is set explicitly from the data bounds after the first Render (paraview.simple resets
the camera there), so both modes draw the same view.
"""
import argparse
import math
import os
import sys

from paraview import servermanager
from paraview.simple import (ColorBy, Connect, Delete, LoadPlugin, OpenDataFile, Render,
                             SaveScreenshot, Show)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paraview_test_support as support  # noqa: E402

SIZE = (400, 300)


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def server_plugins():
    """Names of the plugins loaded on the server side of the active session."""
    plugins = servermanager.vtkPVPluginsInformation()
    servermanager.ActiveConnection.Session.GatherInformation(
        servermanager.vtkSMSession.DATA_SERVER_ROOT, plugins, 0)
    return [plugins.GetPluginName(i) for i in range(plugins.GetNumberOfPlugins())
            if plugins.GetPluginLoaded(i)]


def make_view():
    return support.make_view(SIZE)


def set_camera(view, centre, distance, direction, up):
    """Camera looking at `centre` along `direction`, from `distance` away."""
    norm = math.sqrt(sum(d * d for d in direction))
    view.CameraFocalPoint = centre
    view.CameraPosition = [c + distance * d / norm for c, d in zip(centre, direction)]
    view.CameraViewUp = up
    view.CameraViewAngle = 30
    view.CameraParallelProjection = 0


def save_both_ways(view, output, name, remote, local_is_remote=False):
    """Saves the view rendered on the server (RemoteRenderThreshold 0: the image is delivered)
    as `name`, then with local rendering asked for (a threshold no data reaches: the geometry
    is delivered and the client draws it) as `name`Local. On a server, checks where the view
    really rendered; `local_is_remote` for representations that insist on the server."""
    for suffix, threshold, expected in (("", 0.0, True), ("Local", 1e9, local_is_remote)):
        view.RemoteRenderThreshold = threshold
        Render(view)
        if remote:
            distributed = view.GetClientSideObject().GetUseDistributedRenderingForRender()
            print(f"{name}{suffix}: rendered on the {'server' if distributed else 'client'}")
            if bool(distributed) != expected:
                fail(f"{name}{suffix}: expected rendering on the {'server' if expected else 'client'}")
        save(view, output, name + suffix)


def save(view, output, name):
    path = os.path.join(output, f"{name}.png")
    SaveScreenshot(path, view, ImageResolution=list(SIZE), TransparentBackground=0)
    pixels = support.read_png(path)
    import numpy as np
    np.save(os.path.join(output, f"{name}.npy"), pixels)
    print(f"{name}: {path} ({pixels.shape[1]}x{pixels.shape[0]})")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--server", help="HOST:PORT of a pvserver; builtin when absent")
    parser.add_argument("--ranks", type=int, default=1, help="the server's expected MPI ranks")
    parser.add_argument("--plugin", required=True, help="the client's Sightline.so")
    parser.add_argument("--swc", required=True)
    parser.add_argument("--output", required=True)
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)

    if args.server:
        host, port = args.server.rsplit(":", 1)
        Connect(host, int(port))
        if not servermanager.ActiveConnection.IsRemote():
            fail("not connected to a server")
        ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
        print(f"connected to {args.server}: {ranks} server rank(s)")
        if ranks != args.ranks:
            fail(f"the server has {ranks} ranks, expected {args.ranks}")
        # The server found the plugin itself (PV_PLUGIN_PATH in its environment).
        on_server = server_plugins()
        print("plugins on the server:", ", ".join(on_server))
        if "Sightline" not in on_server:
            fail("the server did not load the Sightline plugin from PV_PLUGIN_PATH")
    # The client needs the plugin's proxy definitions (and its client-side classes).
    LoadPlugin(args.plugin, remote=False, ns=globals())

    # Spheres from an SWC file, read on the server, with the file's Radius array.
    reader = OpenDataFile(args.swc)
    if reader is None or reader.GetXMLName() != "SightlineSWCReader":
        fail(f"{args.swc} did not open with the Sightline SWC reader")
    view = make_view()
    rep = Show(reader, view)
    rep.Representation = "Sightline Spheres"
    ColorBy(rep, None)
    rep.SphereRadiusArray = ["POINTS", "Radius"]
    Render(view)
    b = reader.GetDataInformation().GetBounds()
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    radius = 0.5 * math.sqrt((b[1] - b[0]) ** 2 + (b[3] - b[2]) ** 2 + (b[5] - b[4]) ** 2)
    set_camera(view, centre, 2.2 * radius, [1.0, -0.6, 0.8], [0, 0, 1])
    save_both_ways(view, args.output, "Spheres", bool(args.server))
    Delete(view)

    # PREM through the spherical field source, traced as a spherical volume.
    view = make_view()
    source, rep = support.show_prem(view, SightlineSphericalField)  # noqa: F821  (LoadPlugin)
    Render(view)
    # The grid's coordinates are (r, theta, phi): its bounds are not Cartesian; the sphere is
    # centred at the origin with the largest r as its radius.
    outer = source.GetDataInformation().GetBounds()[1]
    set_camera(view, [0.0, 0.0, 0.0], 4.5 * outer, [3.0, -2.0, 2.0], [0, 0, 1])
    # The spherical volume is traced where its grid is: it keeps the server rendering.
    save_both_ways(view, args.output, "PREM", bool(args.server), local_is_remote=True)
    Delete(view)
    print("done")


if __name__ == "__main__":
    main()
