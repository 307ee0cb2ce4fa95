#!/usr/bin/env python3
"""Submit a scene to tesserad from Python and save the finished tiles.

Shows the gRPC API from a language other than C++. Needs Debian's python3-grpcio and
python3-protobuf; the stubs are generated from proto/ on the fly with the system protoc and
grpc_python_plugin (package protobuf-compiler-grpc), which understand proto3 `optional`.

    python3 examples/python/render_sphere.py --server 127.0.0.1:50051 --out out/python
"""
import argparse
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

import grpc

REPO = pathlib.Path(__file__).resolve().parents[2]


def load_stubs():
    out = tempfile.mkdtemp(prefix="tessera_py_")
    proto_dir = REPO / "proto"
    plugin = shutil.which("grpc_python_plugin")
    if not shutil.which("protoc") or not plugin:
        sys.exit("needs protoc and grpc_python_plugin (apt-get install protobuf-compiler-grpc)")
    protos = [str(proto_dir / "tessera" / "v1" / name) for name in ("scene.proto", "render.proto")]
    subprocess.run(["protoc", f"-I{proto_dir}", f"--python_out={out}", f"--grpc_python_out={out}",
                    f"--plugin=protoc-gen-grpc_python={plugin}", *protos], check=True)
    sys.path.insert(0, out)
    from tessera.v1 import render_pb2, render_pb2_grpc, scene_pb2  # noqa: E402
    return render_pb2, render_pb2_grpc, scene_pb2


def build_scene(scene_pb2):
    scene = scene_pb2.Scene()
    scene.camera.position.CopyFrom(scene_pb2.Vec3(x=0, y=1, z=4))
    scene.camera.look_at.CopyFrom(scene_pb2.Vec3(x=0, y=0.5, z=0))
    scene.camera.fov_degrees = 40
    scene.background.color.CopyFrom(scene_pb2.Vec3(x=0.6, y=0.7, z=0.9))
    scene.materials.add(name="clay", type=scene_pb2.MATERIAL_TYPE_LAMBERTIAN, albedo=scene_pb2.Vec3(x=0.8, y=0.5, z=0.3))
    scene.materials.add(name="floor", type=scene_pb2.MATERIAL_TYPE_LAMBERTIAN)
    ball = scene.geometry.add(material="clay")
    ball.sphere.center.CopyFrom(scene_pb2.Vec3(x=0, y=0.5, z=0))
    ball.sphere.radius = 0.5
    ground = scene.geometry.add(material="floor")
    ground.rectangle.corner.CopyFrom(scene_pb2.Vec3(x=-5, y=0, z=-5))
    ground.rectangle.u.CopyFrom(scene_pb2.Vec3(x=0, y=0, z=10))
    ground.rectangle.v.CopyFrom(scene_pb2.Vec3(x=10, y=0, z=0))
    return scene


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", default="127.0.0.1:50051")
    parser.add_argument("--out", default="out/python", help="folder for the tile EXRs")
    args = parser.parse_args()

    render_pb2, render_pb2_grpc, scene_pb2 = load_stubs()
    stub = render_pb2_grpc.RenderServiceStub(grpc.insecure_channel(args.server))
    settings = render_pb2.RenderSettings(width=96, height=64, samples_per_pixel=8, tile_size=32)
    try:
        job = stub.SubmitJob(render_pb2.SubmitJobRequest(scene=build_scene(scene_pb2), settings=settings,
                                                         name="python-example")).job
    except grpc.RpcError as e:
        sys.exit(f"submit failed: {e.code().name}: {e.details()}")
    print(f"submitted {job.id}: {job.settings.width}x{job.settings.height}, {job.progress.tiles_total} tiles")

    os.makedirs(args.out, exist_ok=True)
    for tile in stub.StreamTiles(render_pb2.StreamTilesRequest(job_id=job.id)):
        path = os.path.join(args.out, f"tile_{tile.rect.index:04d}.exr")
        with open(path, "wb") as f:
            f.write(tile.exr)
        p = tile.progress
        print(f"tile {tile.rect.index} at ({tile.rect.x}, {tile.rect.y}): {p.tiles_done}/{p.tiles_total}, "
              f"{p.rays_per_second / 1e6:.2f} Mrays/s")
    final = stub.GetJob(render_pb2.GetJobRequest(job_id=job.id))
    print(f"job {final.id}: {render_pb2.JobState.Name(final.state)}")


if __name__ == "__main__":
    main()
