# SPDX-License-Identifier: BSD-3-Clause
"""Run by test_reader_errors.py in pvbatch: opens one file through File > Open's reader factory
(OpenDataFile), checks which reader ParaView picked, updates it and reports what came out.
Arguments: FILE READER_XML_NAME. The reader's own errors go to stderr through VTK's output
window; this script must get to its end (no crash) whatever the file holds."""
import sys

from paraview import servermanager
from paraview.simple import LoadPlugin, OpenDataFile

path, expected = sys.argv[1:3]
plugins = servermanager.vtkPVPluginsInformation()
servermanager.ActiveConnection.Session.GatherInformation(
    servermanager.vtkSMSession.CLIENT_AND_SERVERS, plugins, 0)
if not any(plugins.GetPluginName(i) == "Sightline" and plugins.GetPluginLoaded(i)
           for i in range(plugins.GetNumberOfPlugins())):
    # Not loaded from PV_PLUGIN_PATH at startup (a second load of it would report an error).
    LoadPlugin(sys.argv[3], ns=globals())

reader = OpenDataFile(path)
if reader is None:
    print(f"no reader for {path}")
    sys.exit(2)
print(f"reader: {reader.GetXMLName()}")
if reader.GetXMLName() != expected:
    sys.exit(3)
reader.UpdatePipeline()
print(f"points after UpdatePipeline: {reader.GetDataInformation().GetNumberOfPoints()}")
print("survived")
