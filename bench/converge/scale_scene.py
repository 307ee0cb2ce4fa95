#!/usr/bin/env python3
"""Writes a copy of a scene with every position multiplied by SCALE and moved by OFFSET.

The image of a scene must not depend on its units or on where it sits; this makes the
copies that check it (README, "Scenes in any units, anywhere"). It handles the camera,
rectangles, triangles, spheres, disks, planes, cylinders, cones and tori; other shape kinds
are left as they are, with a warning. Run with /usr/bin/python3 (PyYAML).

  scale_scene.py IN.yaml OUT.yaml SCALE OFFSET [--width W --height H --max-depth D]
"""
import argparse
import sys

import yaml

POINTS = ('corner', 'center', 'v0', 'v1', 'v2', 'base', 'point')
VECTORS = ('u', 'v')
LENGTHS = ('radius', 'height', 'major_radius', 'minor_radius', 'base_radius', 'top_radius',
           'inner_radius')
KINDS = {'rectangle', 'quad', 'triangle', 'sphere', 'disk', 'plane', 'cylinder', 'cone', 'torus'}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('scene')
    parser.add_argument('out')
    parser.add_argument('scale', type=float)
    parser.add_argument('offset', type=float)
    parser.add_argument('--width', type=int)
    parser.add_argument('--height', type=int)
    parser.add_argument('--max-depth', type=int)
    args = parser.parse_args()

    with open(args.scene) as f:
        scene = yaml.safe_load(f)
    point = lambda p: [c * args.scale + args.offset for c in p]
    vector = lambda v: [c * args.scale for c in v]
    camera = scene['camera']
    camera['position'] = point(camera['position'])
    camera['look_at'] = point(camera.get('look_at', [0.0, 0.0, 0.0]))
    for shape in scene.get('geometry', scene.get('geometries', [])):
        if shape.get('type') not in KINDS or 'transform' in shape:
            print(f"scale_scene: left as it is: {shape.get('type')}", file=sys.stderr)
            continue
        for key in POINTS:
            if key in shape:
                shape[key] = point(shape[key])
        for key in VECTORS:
            if key in shape:
                shape[key] = vector(shape[key])
        for key in LENGTHS:
            if key in shape:
                shape[key] = shape[key] * args.scale
    render = scene.setdefault('render', {})
    for key, value in (('width', args.width), ('height', args.height),
                       ('max_depth', args.max_depth)):
        if value is not None:
            render[key] = value
    with open(args.out, 'w') as f:
        yaml.safe_dump(scene, f, default_flow_style=None)


if __name__ == '__main__':
    main()
