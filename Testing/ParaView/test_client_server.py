# SPDX-License-Identifier: BSD-3-Clause
"""ParaView.ClientServer: Sightline through a pvserver with remote rendering, against builtin.

A driver run by /usr/bin/python3 (ctest): it starts `pvserver` on a free localhost port (on 2 MPI
ranks through mpirun when mpirun exists, else 1 process) with PV_PLUGIN_PATH pointing at the
plugin, waits until the server accepts connections, runs client_server_scene.py in pvpython
connected to it (the server reads the data; each scene rendered remotely, RemoteRenderThreshold
0, and with local rendering asked for, where the geometry goes to the client), runs the same
scenes builtin (pvpython, no server), and compares each pair of images: at most 0.1 % of pixels
may differ by more than 24/255. The server's whole session is killed at the
end whatever happened, so no process outlives the test and no port stays taken.

Environment (from Testing/ParaView/CMakeLists.txt): SIGHTLINE_PVSERVER, SIGHTLINE_PVPYTHON,
SIGHTLINE_PLUGIN, SIGHTLINE_TEST_TEMP_DIR, PYTHONPATH, LD_LIBRARY_PATH, PV_PLUGIN_PATH, DISPLAY.
"""
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "client_server_scene.py")
SWC = os.path.join(HERE, "..", "Data", "SWC", "neuron_three_point_soma.swc")
PVSERVER = os.environ["SIGHTLINE_PVSERVER"]
PVPYTHON = os.environ["SIGHTLINE_PVPYTHON"]
PLUGIN = os.environ["SIGHTLINE_PLUGIN"]
OUTPUT = os.path.join(os.environ.get("SIGHTLINE_TEST_TEMP_DIR", "/tmp"), "ParaViewClientServer")
TOLERANCE = 0.001  # fraction of pixels allowed to differ by more than 24/255
CLIENT_TIMEOUT = 240
START_TIMEOUT = 60


def free_port():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def session_pids(sid):
    """Processes in session `sid` (the server's: mpirun and every pvserver rank it started)."""
    pids = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            # Fields after ')': state ppid pgrp session ...; a zombie has ended already (it
            # waits for a parent, which in a container may be a PID 1 that never reaps).
            if int(fields[3]) == sid and fields[0] != "Z":
                pids.append(int(entry))
    return pids


class Server:
    """pvserver in its own session, its output drained by a thread."""

    def __init__(self, ranks):
        self.port = free_port()
        command = [PVSERVER, f"--server-port={self.port}", "--force-offscreen-rendering"]
        if ranks > 1:
            command = [shutil.which("mpirun"), "--allow-run-as-root", "--oversubscribe",
                       "-np", str(ranks)] + [a for v in ("DISPLAY", "PV_PLUGIN_PATH",
                                                         "LD_LIBRARY_PATH", "PYTHONPATH")
                                             for a in ("-x", v)] + command
        print("server:", " ".join(command), flush=True)
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                        stdin=subprocess.DEVNULL, text=True,
                                        start_new_session=True)
        self.lines = []
        self.listening = threading.Event()
        self.reader = threading.Thread(target=self._drain, daemon=True)
        self.reader.start()

    def _drain(self):
        for line in self.process.stdout:
            self.lines.append(line.rstrip("\n"))
            if "Accepting connection" in line:
                self.listening.set()

    def wait_listening(self, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.listening.wait(0.2):
                return True
            if self.process.poll() is not None:
                return False
        return False

    def stop(self):
        """Waits 5 s for the server to end, then kills every process of its session: TERM, then
        KILL after 10 s."""
        sid = self.process.pid
        # After its client disconnects, pvserver exits by itself: give it a moment first.
        deadline = time.monotonic() + 5.0
        while time.monotonic() < deadline and (session_pids(sid) or self.process.poll() is None):
            time.sleep(0.1)
        for sig, grace in ((signal.SIGTERM, 10.0), (signal.SIGKILL, 10.0)):
            pids = session_pids(sid)
            if not pids and self.process.poll() is not None:
                break
            for pid in pids:
                try:
                    os.kill(pid, sig)
                except ProcessLookupError:
                    pass
            deadline = time.monotonic() + grace
            while time.monotonic() < deadline and (session_pids(sid) or self.process.poll() is None):
                time.sleep(0.1)
        self.process.wait(timeout=10)
        self.reader.join(timeout=5)
        left = session_pids(sid)
        if left:
            raise RuntimeError(f"server processes left running: {left}")
        return "\n".join(self.lines)


def run_scene(output, server=None, ranks=1):
    command = [PVPYTHON, "--force-offscreen-rendering", SCENE, "--plugin", PLUGIN,
               "--swc", SWC, "--output", output]
    if server:
        command += ["--server", server, "--ranks", str(ranks)]
    print("client:", " ".join(command), flush=True)
    started = time.monotonic()
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            timeout=CLIENT_TIMEOUT, stdin=subprocess.DEVNULL)
    print(result.stdout, flush=True)
    print(f"({time.monotonic() - started:.1f} s, exit {result.returncode})", flush=True)
    return result.returncode, errors(result.stdout)


def errors(output):
    """VTK/ParaView error lines (vtkErrorMacro: 'ERR|' in ParaView's log format, or 'ERROR:')."""
    return [line for line in output.splitlines() if "ERR|" in line or "ERROR:" in line]


def main():
    ranks = 2 if shutil.which("mpirun") else 1
    shutil.rmtree(OUTPUT, ignore_errors=True)
    remote_dir, builtin_dir = os.path.join(OUTPUT, "remote"), os.path.join(OUTPUT, "builtin")

    # The client-server run. The port is free when picked; should another process take it before
    # pvserver binds, the server exits or never listens, and the next attempt picks another.
    client_rc, server_errors = None, []
    for attempt in range(3):
        started = time.monotonic()
        server = Server(ranks)
        try:
            listening = server.wait_listening(START_TIMEOUT)
            print(f"server listening after {time.monotonic() - started:.1f} s: {listening}")
            if not listening:
                print(f"server did not listen on port {server.port} (attempt {attempt + 1})")
                continue
            client_rc, client_errors = run_scene(remote_dir, f"localhost:{server.port}", ranks)
            break
        finally:
            stopping = time.monotonic()
            log = server.stop()
            print(f"server stopped in {time.monotonic() - stopping:.1f} s")
            server_errors = errors(log)
            print("--- server output ---\n" + log + "\n---------------------", flush=True)
    if client_rc is None:
        print("FAIL: no pvserver came up")
        return 1
    if client_rc != 0:
        print("FAIL: the client-server run failed")
        return 1

    # The same scene builtin (no server).
    builtin_rc, builtin_errors = run_scene(builtin_dir)
    if builtin_rc != 0:
        print("FAIL: the builtin run failed")
        return 1
    # Neither side may report errors (e.g. a mapper refusing the client's placeholder input).
    for side, lines in (("client", client_errors), ("server", server_errors),
                        ("builtin", builtin_errors)):
        if lines:
            print(f"FAIL: the {side} reported errors:\n" + "\n".join(lines))
            return 1

    ok = True
    for name in ("Spheres", "SpheresLocal", "PREM", "PREMLocal"):
        remote = np.load(os.path.join(remote_dir, f"{name}.npy")).astype(int)
        builtin = np.load(os.path.join(builtin_dir, f"{name}.npy")).astype(int)
        if remote.shape != builtin.shape:
            print(f"FAIL {name}: image sizes differ: {remote.shape} vs {builtin.shape}")
            ok = False
            continue
        background = np.round(np.array([0.1, 0.1, 0.15]) * 255).astype(int)
        covered = float(np.mean(np.abs(builtin - background).max(axis=2) > 8))
        fraction = float(np.mean(np.abs(remote - builtin).max(axis=2) > 24))
        mode = "local" if name.endswith("Local") else "remote"
        print(f"{name}: {covered:.1%} of pixels covered; client-server ({ranks} ranks, {mode} "
              f"rendering asked) vs builtin: {fraction:.4%} of pixels differ by more than 24/255")
        if covered < 0.02:
            print(f"FAIL {name}: the builtin image is (almost) empty")
            ok = False
        if fraction > TOLERANCE:
            print(f"FAIL {name}: more than {TOLERANCE:.1%} of pixels differ")
            ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
