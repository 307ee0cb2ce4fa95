#!/usr/bin/python3
"""The Python client (client/python, tessera_client), run by CTest with Debian's python3.

    test_client.py Daemon    against a tesserad started here on a free loopback port
    test_client.py Offline   scene conversion, EXR files, token and TLS against a stand-in server

Environment (set by tests/python/CMakeLists.txt): PYTHONPATH holds the built package,
TESSERA_CLI and TESSERAD the two programs, TESSERA_SOURCE_DIR the repository. Exits 77
(CTest: skipped) when a Python module the client needs is missing.
"""
import concurrent.futures
import importlib
import os
import pathlib
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

SKIP = 77
missing = []
for module in ("grpc", "google.protobuf", "numpy", "OpenImageIO", "yaml"):
    try:
        importlib.import_module(module)
    except ImportError:
        missing.append(module)
if missing:
    print(f"skipped: Python modules missing: {', '.join(missing)} "
          "(scripts/install-deps.sh installs them)")
    sys.exit(SKIP)

import grpc  # noqa: E402
import numpy  # noqa: E402
import yaml  # noqa: E402

import tessera_client  # noqa: E402
from tessera_client import render_pb2, render_pb2_grpc  # noqa: E402

SOURCE_DIR = pathlib.Path(os.environ.get("TESSERA_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))
CORNELL = SOURCE_DIR / "examples" / "scenes" / "cornell.yaml"
TESSERA = os.environ.get("TESSERA_CLI", "tessera")
TESSERAD = os.environ.get("TESSERAD", "tesserad")
# Small enough for a loaded 2-core machine; two tiles across, two down.
SMALL = dict(width=64, height=48, spp=8, tile_size=32)


def bits(image):
    """The array's bits, so a comparison tells -0 from 0 and sees NaNs."""
    return numpy.ascontiguousarray(image, dtype=numpy.float32).view(numpy.uint32)


class TesseradProcess:
    """tesserad on a free loopback port with its data in `folder`, stopped by stop()."""

    def __init__(self, folder, listen="127.0.0.1:0"):
        self.log_path = folder / "tesserad.log"
        with open(self.log_path, "ab") as log:
            self.process = subprocess.Popen(
                [TESSERAD, "--listen", listen, "--data", str(folder / "data"), "--threads", "2"],
                stdout=subprocess.PIPE, stderr=log)
        self.address = f"127.0.0.1:{self._read_port()}"

    def _read_port(self):
        text = b""
        give_up = time.monotonic() + 60
        while time.monotonic() < give_up:
            ready, _, _ = select.select([self.process.stdout], [], [], 0.1)
            if not ready:
                if self.process.poll() is not None:
                    break
                continue
            chunk = os.read(self.process.stdout.fileno(), 256)
            if not chunk:
                break
            text += chunk
            at = text.find(b"(port ")
            if at >= 0 and b")" in text[at:]:
                return int(text[at + 6:text.index(b")", at)])
        self.stop()
        raise RuntimeError(f"tesserad did not report its port; stdout: {text!r}; log: "
                           f"{self.log_path.read_text(errors='replace')}")

    def stop(self):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(30)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.process.stdout.close()


class Daemon(unittest.TestCase):
    """The client against a real tesserad: images, tiles, errors."""

    @classmethod
    def setUpClass(cls):
        cls.folder = pathlib.Path(tempfile.mkdtemp(prefix="tessera-python-client-"))
        cls.daemon = TesseradProcess(cls.folder)
        cls.client = tessera_client.Client(cls.daemon.address)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.daemon.stop()
        shutil.rmtree(cls.folder, ignore_errors=True)

    def local_render(self, name, **settings):
        """`tessera render --local` of the Cornell box: (pixels, channel names)."""
        output = self.folder / f"{name}.exr"
        flags = []
        for key, value in settings.items():
            flags += ["--" + key.replace("_", "-"), str(value)]
        subprocess.run([TESSERA, "render", str(CORNELL), "--local", "-o", str(output), *flags],
                       check=True, capture_output=True)
        pixels, channels, _ = tessera_client.read_exr(output)
        return pixels, channels

    def test_cornell_through_the_daemon_matches_a_local_render_bit_for_bit(self):
        image, channels = self.client.render(str(CORNELL), with_channels=True, **SMALL)
        expected, expected_channels = self.local_render("cornell-local", **SMALL)
        self.assertEqual(channels, ("R", "G", "B", "A"))
        self.assertEqual(channels, expected_channels)
        self.assertEqual(image.dtype, numpy.float32)
        self.assertEqual(image.shape, (48, 64, 4))
        self.assertGreater(float(image[..., :3].mean()), 0.01)  # lit, not an empty buffer
        numpy.testing.assert_array_equal(bits(image), bits(expected))

        # What save_exr writes reads back bit for bit.
        path = self.folder / "saved" / "cornell.exr"
        tessera_client.save_exr(image, path)
        saved, saved_channels, _ = tessera_client.read_exr(path)
        self.assertEqual(saved_channels, channels)
        numpy.testing.assert_array_equal(bits(saved), bits(image))

    def test_a_scene_dict_renders_like_its_file(self):
        scene = yaml.safe_load(CORNELL.read_text())
        from_dict = self.client.render(scene, **SMALL)
        from_file = self.client.render(CORNELL, **SMALL)  # a pathlib.Path
        numpy.testing.assert_array_equal(bits(from_dict), bits(from_file))

    def test_stream_yields_every_pass_of_every_tile_in_order(self):
        job_id = self.client.submit(str(CORNELL), passes=2, name="python-passes", **SMALL)
        tiles = list(self.client.stream(job_id))
        self.assertEqual(len(tiles), 4 * 2)
        self.assertEqual([t.sequence for t in tiles], list(range(1, 9)))
        seen = {}
        for tile in tiles:
            self.assertEqual(tile.job_id, job_id)
            self.assertEqual(tile.pass_index, seen.get(tile.index, 0) + 1)
            seen[tile.index] = tile.pass_index
            self.assertEqual((tile.x, tile.y), (tile.index % 2 * 32, tile.index // 2 * 32))
            self.assertEqual(tile.pixels.shape, (32 if tile.y == 0 else 16, 32, 4))  # 48 rows
        self.assertEqual(seen, {0: 2, 1: 2, 2: 2, 3: 2})
        self.assertEqual(tiles[-1].progress.tiles_done, 8)
        self.assertEqual(self.client.job(job_id).state, render_pb2.JOB_STATE_COMPLETED)
        # The last pass is the one-pass image, also when assembled in Python.
        two_passes = self.client.wait_image(job_id)
        one_pass = self.client.render(str(CORNELL), **SMALL)
        numpy.testing.assert_array_equal(bits(two_passes), bits(one_pass))

    def test_a_stream_re_attaches_when_the_daemon_restarts(self):
        folder = self.folder / "restart"
        folder.mkdir()
        settings = dict(width=128, height=64, spp=256, tile_size=16)  # 32 tiles
        first = TesseradProcess(folder)
        second = None
        try:
            with tessera_client.Client(first.address) as client:
                job_id = client.submit(str(CORNELL), **settings)
                stream = client.stream(job_id)
                tiles = [next(stream)]
                # SIGTERM: tiles in flight finish, the rest wait for the next start, and the
                # stream ends UNAVAILABLE saying the job is kept.
                self.assertEqual(first.process.send_signal(signal.SIGTERM), None)
                first.process.wait(30)
                second = TesseradProcess(folder, listen=first.address)
                tiles += list(stream)
                image = client.wait_image(job_id)
        finally:
            first.stop()
            if second:
                second.stop()
        self.assertIn("resuming 1 unfinished jobs", first.log_path.read_text())
        self.assertEqual(sorted(t.index for t in tiles), list(range(32)))
        self.assertEqual([t.sequence for t in tiles], list(range(1, 33)))
        expected, _ = self.local_render("restart-local", **settings)
        numpy.testing.assert_array_equal(bits(image), bits(expected))

    def test_the_example_script_renders(self):
        output = self.folder / "example" / "sphere.exr"
        subprocess.run([sys.executable, str(SOURCE_DIR / "examples" / "python" / "render_sphere.py"),
                        "--server", self.daemon.address, "--out", str(output)],
                       check=True, capture_output=True)
        pixels, channels, _ = tessera_client.read_exr(output)
        self.assertEqual((pixels.shape, channels), ((64, 96, 4), ("R", "G", "B", "A")))

    def test_submit_options_reach_the_job(self):
        job = self.client.submit_job(str(CORNELL), name="shot-010", priority=5,
                                     labels={"show": "demo"}, submitter="ana", **SMALL)
        self.assertEqual(job.name, "shot-010")
        self.assertEqual(job.priority, 5)
        self.assertEqual(dict(job.labels), {"show": "demo"})
        self.assertEqual(job.submitter, "ana")
        self.assertEqual((job.settings.width, job.settings.height), (64, 48))
        self.assertIn(job.id, [j.id for j in self.client.jobs(submitter="ana")])

    def test_a_bad_scene_raises_scene_error_and_sends_nothing(self):
        before = len(self.client.jobs())
        scene = yaml.safe_load(CORNELL.read_text())
        scene["geometry"][6]["radius"] = -2  # the mirror sphere
        with self.assertRaises(tessera_client.SceneError) as caught:
            self.client.submit(scene)
        self.assertRegex(str(caught.exception),
                         r"^<stdin>:\d+: geometry\[6\]\.radius: must be > 0, got -2$")
        self.assertEqual(len(self.client.jobs()), before)

    def test_a_refused_request_raises_with_the_grpc_code(self):
        request = tessera_client.submit_request(str(CORNELL), **SMALL)
        request.settings.tile_size = 4  # below the server's minimum; the CLI would refuse it
        with self.assertRaises(tessera_client.TesseraError) as caught:
            self.client.submit(request)
        self.assertEqual(caught.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
        self.assertIn("settings.tile_size", str(caught.exception))

    def test_a_cancelled_job_ends_its_stream_with_job_cancelled(self):
        job_id = self.client.submit(str(CORNELL), width=320, height=240, spp=65536)
        self.client.cancel(job_id)
        with self.assertRaises(tessera_client.JobCancelled):
            for _ in self.client.stream(job_id):
                pass
        self.assertEqual(self.client.job(job_id).state, render_pb2.JOB_STATE_CANCELLED)

    def test_an_unknown_job_raises_not_found(self):
        with self.assertRaises(tessera_client.TesseraError) as caught:
            self.client.job("no-such-job")
        self.assertEqual(caught.exception.code, grpc.StatusCode.NOT_FOUND)


class RecordingService(render_pb2_grpc.RenderServiceServicer):
    """A stand-in RenderService that records the metadata of each GetJob."""

    def __init__(self):
        self.metadata = []
        self.request_ids = []
        self.lock = threading.Lock()

    def GetJob(self, request, context):
        with self.lock:
            self.metadata.append(dict(context.invocation_metadata()))
        return render_pb2.Job(id=request.job_id)

    def SubmitJob(self, request, context):
        # The first attempt fails as a dropped connection would; the retry succeeds.
        with self.lock:
            self.request_ids.append(request.request_id)
            first = len(self.request_ids) == 1
        if first:
            context.abort(grpc.StatusCode.UNAVAILABLE, "connection dropped")
        return render_pb2.SubmitJobResponse(job=render_pb2.Job(id="job-1"))


def start_stand_in(credentials=None):
    service = RecordingService()
    server = grpc.server(concurrent.futures.ThreadPoolExecutor(2))
    render_pb2_grpc.add_RenderServiceServicer_to_server(service, server)
    if credentials is None:
        port = server.add_insecure_port("127.0.0.1:0")
    else:
        port = server.add_secure_port("127.0.0.1:0", credentials)
    server.start()
    return server, service, port


class Offline(unittest.TestCase):
    """What needs no renderer: scene conversion, EXR files, token metadata and TLS."""

    def setUp(self):
        self.folder = pathlib.Path(tempfile.mkdtemp(prefix="tessera-python-offline-"))

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_a_dict_yaml_text_and_a_path_convert_to_the_same_scene(self):
        text = CORNELL.read_text()
        from_path = tessera_client.submit_request(str(CORNELL))
        from_text = tessera_client.submit_request(text)
        from_dict = tessera_client.submit_request(yaml.safe_load(text))
        self.assertEqual(from_path.name, "cornell")  # the CLI's default: the file's stem
        self.assertEqual(from_text.name, "")
        for other in (from_text, from_dict):
            self.assertEqual(other.scene.SerializeToString(deterministic=True),
                             from_path.scene.SerializeToString(deterministic=True))
            self.assertEqual(other.settings, from_path.settings)
        # The same bytes `tessera convert` writes, so the CLI and Python send one request.
        cli = subprocess.run([TESSERA, "convert", str(CORNELL), "-o", "-"], check=True,
                             capture_output=True).stdout
        self.assertEqual(from_path.SerializeToString(), cli)

    def test_tuples_and_numpy_values_in_a_dict_mean_what_lists_and_floats_do(self):
        scene = yaml.safe_load(CORNELL.read_text())
        expected = tessera_client.submit_request(scene)
        camera = scene["camera"]
        camera["position"] = tuple(camera["position"])
        camera["look_at"] = numpy.array(camera["look_at"], dtype=numpy.float64)
        camera["fov"] = numpy.float64(camera["fov"])
        self.assertEqual(tessera_client.submit_request(scene).scene, expected.scene)

    def test_relative_mesh_paths_of_a_dict_resolve_against_the_current_directory(self):
        mesh = self.folder / "tri.obj"
        mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        scene = {"materials": [{"name": "m", "type": "lambertian"}],
                 "geometry": [{"type": "mesh", "material": "m", "file": "tri.obj"}]}
        here = os.getcwd()
        os.chdir(self.folder)
        try:
            request = tessera_client.submit_request(scene)
        finally:
            os.chdir(here)
        self.assertEqual(len(request.scene.geometry), 1)
        self.assertEqual(len(request.scene.geometry[0].mesh.indices), 3)
        with self.assertRaises(tessera_client.SceneError) as caught:
            tessera_client.submit_request(scene)  # not found from this directory
        self.assertIn("tri.obj", str(caught.exception))

    def test_overrides_and_bad_arguments(self):
        request = tessera_client.submit_request(str(CORNELL), width=40, seed=9, passes=2)
        self.assertEqual((request.settings.width, request.settings.seed), (40, 9))
        self.assertEqual(request.settings.passes, 2)
        request = tessera_client.submit_request(str(CORNELL), accel_builder="binned")
        self.assertEqual(request.settings.accel_builder, "binned")
        with self.assertRaises(tessera_client.SceneError):
            tessera_client.submit_request(str(CORNELL), accel_builder="sbvh")
        with self.assertRaises(TypeError):
            tessera_client.submit_request(str(CORNELL), widht=40)
        with self.assertRaises(TypeError):
            tessera_client.submit_request(42)
        with self.assertRaises(tessera_client.SceneError) as caught:
            tessera_client.submit_request(str(self.folder / "missing.yaml"))
        self.assertIn("missing.yaml: scene file not found", str(caught.exception))

    def test_unknown_keys_are_errors_unless_lenient_and_then_warnings(self):
        scene = yaml.safe_load(CORNELL.read_text())
        scene["camera"]["fvo"] = 30
        with self.assertRaises(tessera_client.SceneError) as caught:
            tessera_client.submit_request(scene)
        self.assertIn("camera.fvo", str(caught.exception))
        with self.assertWarns(tessera_client.SceneWarning):
            tessera_client.submit_request(scene, lenient=True)

    def test_save_exr_keeps_every_bit_and_the_channel_names(self):
        rng = numpy.random.default_rng(7)
        image = rng.standard_normal((5, 7, 6)).astype(numpy.float32)
        image[0, 0, 0] = -0.0
        image[1, 1, 1] = numpy.float32(1e-42)  # a denormal
        names = ("R", "G", "B", "A", "depth.Z", "albedo.R")
        path = self.folder / "aovs.exr"
        tessera_client.save_exr(image, path, channels=names)
        pixels, channels, origin = tessera_client.read_exr(path)
        self.assertEqual(origin, (0, 0))
        self.assertEqual(sorted(channels), sorted(names))
        reordered = pixels[..., [channels.index(n) for n in names]]
        numpy.testing.assert_array_equal(bits(reordered), bits(image))
        with self.assertRaises(ValueError):
            tessera_client.save_exr(image, path)  # six channels need names

    def test_a_token_travels_as_bearer_metadata(self):
        server, service, port = start_stand_in()
        try:
            with tessera_client.Client(f"127.0.0.1:{port}", token="s3cret") as client:
                self.assertEqual(client.job("j1").id, "j1")
            with tessera_client.Client(f"127.0.0.1:{port}") as client:
                client.job("j2")
        finally:
            server.stop(None)
        self.assertEqual(service.metadata[0].get("authorization"), "Bearer s3cret")
        self.assertNotIn("authorization", service.metadata[1])

    def test_submit_retries_with_the_same_request_id(self):
        server, service, port = start_stand_in()
        request = render_pb2.SubmitJobRequest()
        request.scene.SetInParent()
        try:
            with tessera_client.Client(f"127.0.0.1:{port}") as client:
                self.assertEqual(client.submit(request), "job-1")
        finally:
            server.stop(None)
        # A random 32-hex-digit id, the same on the retry; the caller's request is not changed.
        self.assertEqual(len(service.request_ids), 2)
        self.assertEqual(service.request_ids[0], service.request_ids[1])
        self.assertRegex(service.request_ids[0], "^[0-9a-f]{32}$")
        self.assertEqual(request.request_id, "")

    def test_bad_arguments_name_the_field(self):
        for kwargs, field in ((dict(token="two words"), "token"), (dict(token=""), "token"),
                              (dict(token="caf\u00e9"), "token"), (dict(timeout=0), "timeout"),
                              (dict(reconnect_window=-1), "reconnect_window")):
            with self.assertRaisesRegex(ValueError, "^" + field + ": ", msg=str(kwargs)):
                tessera_client.Client("127.0.0.1:1", **kwargs)
        with self.assertRaisesRegex(ValueError, "^address: "):
            tessera_client.Client("")

    def test_ca_makes_the_connection_tls(self):
        if not shutil.which("openssl"):
            self.skipTest("openssl not installed")
        key, cert = self.folder / "key.pem", self.folder / "cert.pem"
        subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1",
                        "-subj", "/CN=localhost", "-addext", "subjectAltName=DNS:localhost",
                        "-keyout", str(key), "-out", str(cert)], check=True, capture_output=True)
        credentials = grpc.ssl_server_credentials([(key.read_bytes(), cert.read_bytes())])
        server, service, port = start_stand_in(credentials)
        try:
            with tessera_client.Client(f"localhost:{port}", token="t", ca=cert) as client:
                self.assertEqual(client.job("tls").id, "tls")
            with tessera_client.Client(f"localhost:{port}", timeout=5) as plaintext:
                with self.assertRaises(tessera_client.TesseraError) as caught:
                    plaintext.job("plain")
            self.assertEqual(caught.exception.code, grpc.StatusCode.UNAVAILABLE)
        finally:
            server.stop(None)
        self.assertEqual(service.metadata, [service.metadata[0]])  # only the TLS call arrived
        self.assertEqual(service.metadata[0].get("authorization"), "Bearer t")
        with self.assertRaises(tessera_client.TesseraError):
            tessera_client.Client("localhost:1", ca=self.folder / "no-such-ca.pem")


if __name__ == "__main__":
    unittest.main(verbosity=2)
