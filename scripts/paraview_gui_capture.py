# SPDX-License-Identifier: BSD-3-Clause
"""Grabs the top-left WIDTH x HEIGHT of the X screen on $DISPLAY into a PNG (Pillow's ImageGrab,
through XCB). Used by scripts/paraview-gui-picture.sh.

Usage: paraview_gui_capture.py OUTPUT.png WIDTH HEIGHT
"""
import os
import sys

from PIL import ImageGrab


def main():
    output, width, height = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    screen = ImageGrab.grab(xdisplay=os.environ["DISPLAY"])
    image = screen.crop((0, 0, width, height)).convert("RGB")
    os.makedirs(os.path.dirname(os.path.abspath(output)), exist_ok=True)
    image.save(output, optimize=True)
    print(f"{output}: {width}x{height}, {os.path.getsize(output) // 1024} KiB")


if __name__ == "__main__":
    main()
