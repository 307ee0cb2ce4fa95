#!/usr/bin/env python3
"""Writes studio.exr for heldout_hdr_studio.yaml: a 512 x 256 equirectangular environment,
rows from the zenith down, of a dim blue-grey sky over a dark ground, a warm softbox (40-60
degrees up, 30 degrees wide) and a small hot sun (2.5 degrees in radius, 30 degrees up).
Needs numpy and OpenImageIO's Python module: run it with /usr/bin/python3."""
import sys

import numpy as np
import OpenImageIO as oiio


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "studio.exr"
    width, height = 512, 256
    polar = (np.arange(height) + 0.5) / height * np.pi  # from +y
    azimuth = (np.arange(width) + 0.5) / width * 2.0 * np.pi
    polar, azimuth = np.meshgrid(polar, azimuth, indexing="ij")
    elevation = np.degrees(np.pi / 2 - polar)
    image = np.zeros((height, width, 3), np.float32)
    sky = np.clip(np.sin(np.radians(elevation)), 0.0, 1.0)[..., None]
    image += (0.08 + 0.25 * sky) * np.array([0.55, 0.65, 0.9], np.float32)
    image[elevation < 0] = (0.05, 0.045, 0.04)
    softbox = (elevation > 40) & (elevation < 60) & (np.abs(np.degrees(azimuth) - 250) < 15)
    image[softbox] = (6.0, 5.0, 4.0)
    sun_elevation, sun_azimuth = np.radians(30.0), np.radians(80.0)
    sun = np.array([np.cos(sun_elevation) * np.cos(sun_azimuth), np.sin(sun_elevation),
                    np.cos(sun_elevation) * np.sin(sun_azimuth)])
    directions = np.stack([np.sin(polar) * np.cos(azimuth), np.cos(polar),
                           np.sin(polar) * np.sin(azimuth)], -1)
    image[directions @ sun > np.cos(np.radians(2.5))] = (400.0, 360.0, 300.0)
    output = oiio.ImageOutput.create(out)
    if output is None or not output.open(out, oiio.ImageSpec(width, height, 3, "float")):
        sys.exit(f"make_studio_environment.py: cannot write {out}: {oiio.geterror()}")
    output.write_image(image)
    output.close()


if __name__ == "__main__":
    main()
