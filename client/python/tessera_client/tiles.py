"""Tiles as numpy arrays, the whole image put together from them, and EXR files.

Every tile arrives as a complete 32-bit float EXR (see Tile.exr in render.proto). They are
decoded, and images written, through OpenImageIO (Debian's python3-openimageio), the library
the renderer writes its files with, so pixels keep every bit.
"""
import dataclasses
import os
import tempfile

import numpy


def _oiio():
    try:
        import OpenImageIO
    except ImportError as e:
        raise ImportError("tessera_client needs OpenImageIO's Python module for images "
                          "(Debian: apt-get install python3-openimageio)") from e
    return OpenImageIO


@dataclasses.dataclass(frozen=True)
class Tile:
    """One delivery of a job's stream: a finished tile, or a tile after one of its passes."""
    job_id: str
    index: int  # row-major position in the job's tile grid
    x: int
    y: int
    pass_index: int  # 1-based; the job's last pass is the final image
    sequence: int  # position in the job's stream, from 1
    channels: tuple  # channel names: R, G, B, A, then the AOVs' channels
    pixels: numpy.ndarray  # float32, height x width x len(channels)
    progress: object  # render_pb2.JobProgress including this delivery

    @property
    def width(self):
        return self.pixels.shape[1]

    @property
    def height(self):
        return self.pixels.shape[0]


def read_exr(path):
    """(pixels, channel names, (x, y) of the data window) of an image file, pixels as float32
    height x width x channels."""
    oiio = _oiio()
    image = oiio.ImageInput.open(os.fspath(path))
    if image is None:
        raise OSError(f"cannot read {os.fspath(path)}: {oiio.geterror()}")
    try:
        spec = image.spec()
        pixels = image.read_image(oiio.FLOAT)
        if pixels is None:
            raise OSError(f"cannot read {os.fspath(path)}: {image.geterror()}")
    finally:
        image.close()
    pixels = numpy.asarray(pixels, dtype=numpy.float32).reshape(spec.height, spec.width,
                                                                spec.nchannels)
    return pixels, tuple(spec.channelnames), (spec.x, spec.y)


def decode_tile(tile_message, scratch_dir):
    """A Tile from a render_pb2.Tile. OpenImageIO's Python module reads files only, so the
    EXR goes through a file in `scratch_dir`."""
    path = os.path.join(scratch_dir, "tile.exr")
    with open(path, "wb") as f:
        f.write(tile_message.exr)
    pixels, channels, origin = read_exr(path)
    rect = tile_message.rect
    if (origin != (rect.x, rect.y) or pixels.shape[1] != rect.width
            or pixels.shape[0] != rect.height):
        raise ValueError(f"tile {rect.index}: its EXR covers {pixels.shape[1]}x{pixels.shape[0]} "
                         f"at {origin}, the message says {rect.width}x{rect.height} at "
                         f"({rect.x}, {rect.y})")
    return Tile(job_id=tile_message.job_id, index=rect.index, x=rect.x, y=rect.y,
                pass_index=tile_message.pass_index or 1, sequence=tile_message.sequence,
                channels=channels, pixels=pixels, progress=tile_message.progress)


class ImageAssembler:
    """The whole image from a job's tiles, in any order: each tile's latest pass."""

    def __init__(self, width, height, passes=1):
        self.width, self.height = width, height
        self.passes = max(1, passes)
        self.image = None
        self.channels = None
        self._tile_passes = {}

    def add(self, tile):
        if tile.x + tile.width > self.width or tile.y + tile.height > self.height:
            raise ValueError(f"tile {tile.index} at ({tile.x}, {tile.y}) lies outside the "
                             f"{self.width}x{self.height} image")
        if self.image is None:
            self.channels = tile.channels
            self.image = numpy.zeros((self.height, self.width, len(tile.channels)),
                                     dtype=numpy.float32)
        elif tile.channels != self.channels:
            raise ValueError(f"tile {tile.index} has channels {tile.channels}, earlier tiles "
                             f"{self.channels}")
        previous = self._tile_passes.get(tile.index, 0)
        if tile.pass_index != previous + 1:
            raise ValueError(f"tile {tile.index}: pass {tile.pass_index} after pass {previous}")
        self._tile_passes[tile.index] = tile.pass_index
        self.image[tile.y:tile.y + tile.height, tile.x:tile.x + tile.width, :] = tile.pixels

    def tiles_complete(self):
        """Tiles that have reached the last pass."""
        return sum(1 for p in self._tile_passes.values() if p == self.passes)


def default_channels(count):
    names = {1: ("Y",), 3: ("R", "G", "B"), 4: ("R", "G", "B", "A")}
    if count not in names:
        raise ValueError(f"an image of {count} channels needs channels= names")
    return names[count]


def save_exr(image, path, channels=None):
    """Writes a height x width x channels array as a 32-bit float EXR (ZIP compressed).
    `channels`: their names; by default R, G, B, A for 4 channels, R, G, B for 3, Y for 1."""
    oiio = _oiio()
    pixels = numpy.ascontiguousarray(image, dtype=numpy.float32)
    if pixels.ndim == 2:
        pixels = pixels[:, :, numpy.newaxis]
    if pixels.ndim != 3:
        raise ValueError(f"image must be height x width x channels, got shape {image.shape}")
    names = tuple(channels) if channels is not None else default_channels(pixels.shape[2])
    if len(names) != pixels.shape[2]:
        raise ValueError(f"{len(names)} channel names for {pixels.shape[2]} channels")
    spec = oiio.ImageSpec(pixels.shape[1], pixels.shape[0], pixels.shape[2], oiio.FLOAT)
    spec.channelnames = names
    if "A" in names:
        spec.alpha_channel = names.index("A")
    spec.attribute("compression", "zip")
    path = os.fspath(path)
    parent = os.path.dirname(path)
    if parent:
        os.makedirs(parent, exist_ok=True)
    output = oiio.ImageOutput.create(path)
    if output is None:
        raise OSError(f"cannot write {path}: {oiio.geterror()}")
    try:
        if not output.open(path, spec) or not output.write_image(pixels):
            raise OSError(f"cannot write {path}: {output.geterror()}")
    finally:
        output.close()


def scratch_directory():
    return tempfile.TemporaryDirectory(prefix="tessera_client_")
