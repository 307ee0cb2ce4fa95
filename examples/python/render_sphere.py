#!/usr/bin/python3
"""Render a scene written in Python through tesserad and save it as an EXR.

Uses the tessera_client package (client/python), built with the rest of Tessera:

    PYTHONPATH=build/client/python /usr/bin/python3 examples/python/render_sphere.py \\
        --server 127.0.0.1:50051 --out out/python/sphere.exr
"""
import argparse
import sys

import tessera_client

# The same structure as a scene file (README, "Scenes").
SCENE = {
    "camera": {"position": [0, 1, 4], "look_at": [0, 0.5, 0], "fov": 40},
    "settings": {"background_color": [0.6, 0.7, 0.9], "background_intensity": 1},
    "materials": [
        {"name": "clay", "type": "lambertian", "albedo": [0.8, 0.5, 0.3]},
        {"name": "floor", "type": "lambertian"},
    ],
    "geometry": [
        {"type": "sphere", "material": "clay", "center": [0, 0.5, 0], "radius": 0.5},
        {"type": "rectangle", "material": "floor", "corner": [-5, 0, -5], "u": [0, 0, 10],
         "v": [10, 0, 0]},
    ],
    "render": {"width": 96, "height": 64, "spp": 8, "tile_size": 32},
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", default="127.0.0.1:50051")
    parser.add_argument("--token", help="bearer token, for a daemon started with --tokens")
    parser.add_argument("--ca", help="CA certificate (PEM) of a daemon serving TLS")
    parser.add_argument("--out", default="out/python/sphere.exr")
    args = parser.parse_args()

    def show(tile):
        p = tile.progress
        print(f"tile {tile.index} at ({tile.x}, {tile.y}): {p.tiles_done}/{p.tiles_total}, "
              f"{p.rays_per_second / 1e6:.2f} Mrays/s")

    with tessera_client.Client(args.server, token=args.token, ca=args.ca) as client:
        try:
            image = client.render(SCENE, name="python-example", on_tile=show)
        except tessera_client.TesseraError as e:
            sys.exit(f"render_sphere: {e}")
    tessera_client.save_exr(image, args.out)
    print(f"wrote {args.out}: {image.shape[1]}x{image.shape[0]}, mean {image[..., :3].mean():.4f}")


if __name__ == "__main__":
    main()
