"""tessera_client: submit scenes to tesserad from Python and get the image back as numpy.

    from tessera_client import Client, save_exr
    with Client("127.0.0.1:50051") as client:
        image = client.render("examples/scenes/cornell.yaml", width=160, height=120)
    save_exr(image, "out/cornell.exr")

Needs Debian's python3-grpcio, python3-protobuf, python3-numpy, python3-yaml and, for
tiles and images, python3-openimageio; scenes are converted by the `tessera` command.
"""
from ._proto import render_pb2, render_pb2_grpc, scene_pb2
from .client import Client
from .errors import JobCancelled, JobFailed, SceneError, SceneWarning, TesseraError
from .scene import submit_request
from .tiles import Tile, read_exr, save_exr

__all__ = [
    "Client", "JobCancelled", "JobFailed", "SceneError", "SceneWarning", "TesseraError", "Tile",
    "read_exr", "render_pb2", "render_pb2_grpc", "save_exr", "scene_pb2", "submit_request",
]
