"""Scenes to SubmitJobRequest messages through `tessera convert`.

The YAML loader, its validation and the conversion to the API's messages are the C++ ones
that `tessera submit` uses, run by the `tessera` command, so a scene means the same from
Python as from the CLI (mesh and texture files included) and there is no second copy of the
format to keep in step.
"""
import os
import shutil
import subprocess
import warnings

from .errors import SceneError, SceneWarning, TesseraError
from ._proto import render_pb2

# Keyword arguments of submit() that override the scene's `render` section, and the
# `tessera convert` flag of each.
RENDER_OVERRIDES = {
    "width": "--width",
    "height": "--height",
    "spp": "--spp",
    "max_depth": "--max-depth",
    "tile_size": "--tile-size",
    "seed": "--seed",
    "passes": "--passes",
    "accel_builder": "--accel-builder",
}


def find_cli(cli=None):
    """The `tessera` command: `cli`, else $TESSERA_CLI, else the one this package was built
    or installed with, else `tessera` on PATH."""
    explicit = cli or os.environ.get("TESSERA_CLI")
    if explicit:
        found = shutil.which(str(explicit))
        if not found:
            raise TesseraError(f"the tessera command {str(explicit)!r} is not an executable file")
        return found
    try:
        from ._config import TESSERA_CLI
    except ImportError:
        TESSERA_CLI = None
    if TESSERA_CLI and os.access(TESSERA_CLI, os.X_OK):
        return TESSERA_CLI
    found = shutil.which("tessera")
    if not found:
        raise TesseraError("cannot find the tessera command; pass cli= or set TESSERA_CLI")
    return found


def _plain(value):
    """`value` with tuples, numpy arrays and numbers, and paths turned into the lists, floats,
    ints and strings yaml.safe_dump writes. Floats are written as repr() does, which reads
    back as the same double, so a number means exactly what it meant in Python."""
    if isinstance(value, dict):
        return {str(key): _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):  # numpy
        return _plain(value.tolist())
    return value


def _scene_source(scene):
    """(argument for tessera convert, bytes for its stdin or None)."""
    if isinstance(scene, dict):
        import yaml  # python3-yaml

        try:
            text = yaml.safe_dump(_plain(scene), sort_keys=False)
        except yaml.YAMLError as e:
            raise SceneError(f"the scene dict cannot be written as YAML: {e}") from e
        return "-", text.encode()
    if isinstance(scene, bytes):
        return "-", scene
    if isinstance(scene, os.PathLike):
        return os.fspath(scene), None
    if isinstance(scene, str):
        if "\n" in scene or scene.lstrip().startswith("{"):
            return "-", scene.encode()
        return scene, None
    raise TypeError(
        "scene must be a dict, YAML text (str or bytes), a path or a SubmitJobRequest, "
        f"not {type(scene).__name__}")


def _arguments(name, priority, labels, submitter, lenient, overrides):
    args = []
    for key, value in overrides.items():
        if key not in RENDER_OVERRIDES:
            raise TypeError(f"unknown render override {key!r}; expected one of "
                            + ", ".join(sorted(RENDER_OVERRIDES)))
        if value is not None:
            # Choices (accel_builder) go as they are; the CLI checks them.
            args += [RENDER_OVERRIDES[key], value if isinstance(value, str) else str(int(value))]
    if name is not None:
        args += ["--name", str(name)]
    if priority:
        args += ["--priority", str(int(priority))]
    for key, value in (labels or {}).items():
        args += ["--label", f"{key}={value}"]
    if submitter is not None:
        args += ["--submitter", str(submitter)]
    if lenient:
        args.append("--lenient")
    return args


def submit_request(scene, *, name=None, priority=0, labels=None, submitter=None, lenient=False,
                   cli=None, **overrides):
    """The SubmitJobRequest `tessera submit` would send for `scene`.

    `scene`: a dict with the YAML file's structure, YAML text (a str holding a newline or
    starting with '{', or bytes), or the path of a scene file (a str or os.PathLike). Relative
    mesh and texture paths resolve against the scene file's folder, or for a dict or text
    against the current directory. `overrides` (width, height, spp, max_depth, tile_size,
    seed, passes) replace the scene's `render` values, as the CLI's flags do.
    Raises SceneError with the loader's `file:line: field: reason` for a bad scene.
    """
    source, stdin = _scene_source(scene)
    command = [find_cli(cli), "convert", source, "-o", "-"]
    command += _arguments(name, priority, labels, submitter, lenient, overrides)
    result = subprocess.run(command, input=stdin, capture_output=True, check=False)
    message = result.stderr.decode(errors="replace").strip()
    if result.returncode == 2:
        lines = [line for line in message.splitlines() if not line.startswith("tessera: warning:")]
        text = lines[-1] if lines else message
        raise SceneError(text[len("tessera: "):] if text.startswith("tessera: ") else text)
    if result.returncode != 0:
        raise TesseraError(f"tessera convert failed (exit {result.returncode}): {message}")
    for line in message.splitlines():  # --lenient: the keys it ignored
        if line.startswith("tessera: warning: "):
            warnings.warn(line[len("tessera: warning: "):], SceneWarning, stacklevel=3)
    request = render_pb2.SubmitJobRequest()
    request.ParseFromString(result.stdout)
    return request
