"""Client: a connection to one tesserad."""
import os
import time
import uuid

import grpc

from . import scene as scene_module
from . import tiles as tiles_module
from ._proto import render_pb2, render_pb2_grpc
from .errors import JobCancelled, JobFailed, TesseraError

# Trailing metadata of a StreamTiles that ended UNAVAILABLE because the daemon is stopping
# with the job kept: the stream can be re-attached once it is back.
_JOB_RESUMES_KEY = "tessera-job-resumes"
# As the C++ client: tiles up to 64 MiB; requests (scenes with inline meshes) unbounded.
_CHANNEL_OPTIONS = [("grpc.max_receive_message_length", 64 * 1024 * 1024),
                    ("grpc.max_send_message_length", -1)]
# As the C++ client: a SubmitJob that carries a request id is retried with the same id when
# it timed out or could not reach the daemon, since the daemon then returns the job the
# first attempt created instead of making a second one. 4 attempts, 0.5 s apart, doubling.
_SUBMIT_ATTEMPTS = 4
_SUBMIT_RETRY_PAUSE = 0.5
_SUBMIT_RETRIED = (grpc.StatusCode.DEADLINE_EXCEEDED, grpc.StatusCode.UNAVAILABLE)


def _read_pem(ca):
    if isinstance(ca, bytes):
        return ca
    try:
        with open(ca, "rb") as f:
            return f.read()
    except OSError as e:
        raise TesseraError(f"ca: cannot read {os.fspath(ca)}: {e.strerror}") from e


def _is_token(token):
    return bool(token) and all(33 <= ord(c) <= 126 for c in token)


class Client:
    """A connection to the tesserad at `address` ("HOST:PORT").

    token: sent as `authorization: Bearer TOKEN` metadata on every call (daemons configured
      with --tokens require it).
    ca: a PEM file (path, or its bytes) of the CA that signed the daemon's certificate;
      given, the connection uses TLS, else plaintext.
    cli: the `tessera` command that converts scenes (default: see scene.find_cli).
    timeout: seconds a unary call may take; submit_timeout the same for SubmitJob.
    reconnect_window: seconds a tile stream keeps re-attaching to a daemon that went away
      (restarting) since the last tile it received; 0: not at all.
    Every failed call raises TesseraError with the gRPC code.
    """

    def __init__(self, address="127.0.0.1:50051", token=None, ca=None, *, cli=None,
                 timeout=10.0, submit_timeout=120.0, reconnect_window=60.0):
        if not isinstance(address, str) or not address:
            raise ValueError(f"address: must be a non-empty \"HOST:PORT\" string, got {address!r}")
        if token is not None and (not isinstance(token, str) or not _is_token(token)):
            raise ValueError("token: must be a non-empty string of printable ASCII without "
                             "spaces (it travels in an HTTP/2 header)")
        for name, value in (("timeout", timeout), ("submit_timeout", submit_timeout)):
            if not value > 0:
                raise ValueError(f"{name}: must be > 0 seconds, got {value!r}")
        if not reconnect_window >= 0:
            raise ValueError(f"reconnect_window: must be >= 0 seconds, got {reconnect_window!r}")
        self.address = address
        self._metadata = (("authorization", f"Bearer {token}"),) if token else ()
        self._cli = cli
        self._timeout = timeout
        self._submit_timeout = submit_timeout
        self._reconnect_window = reconnect_window
        if ca is not None:
            credentials = grpc.ssl_channel_credentials(root_certificates=_read_pem(ca))
            self._channel = grpc.secure_channel(address, credentials, options=_CHANNEL_OPTIONS)
        else:
            self._channel = grpc.insecure_channel(address, options=_CHANNEL_OPTIONS)
        self._stub = render_pb2_grpc.RenderServiceStub(self._channel)

    def close(self):
        self._channel.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _call(self, method, request, timeout, doing):
        try:
            return method(request, timeout=timeout, metadata=self._metadata)
        except grpc.RpcError as e:
            raise _error(e, self.address, doing) from None

    # ---- jobs ----------------------------------------------------------------------------

    def submit_job(self, scene, **options):
        """Submits `scene` and returns the Job message (render_pb2.Job). `scene` and
        `options` as submit()."""
        request_id = options.pop("request_id", None)
        if isinstance(scene, render_pb2.SubmitJobRequest):
            if options:
                raise TypeError("options are for scenes; set them on the SubmitJobRequest")
            request = render_pb2.SubmitJobRequest()
            request.CopyFrom(scene)
        else:
            request = scene_module.submit_request(scene, cli=self._cli, **options)
        if request_id is not None:
            request.request_id = request_id
        if not request.request_id:
            request.request_id = uuid.uuid4().hex
        pause = _SUBMIT_RETRY_PAUSE
        for attempt in range(_SUBMIT_ATTEMPTS):
            try:
                response = self._stub.SubmitJob(request, timeout=self._submit_timeout,
                                                 metadata=self._metadata)
                return response.job
            except grpc.RpcError as e:
                if e.code() not in _SUBMIT_RETRIED or attempt + 1 == _SUBMIT_ATTEMPTS:
                    raise _error(e, self.address, "server rejected the scene") from None
            time.sleep(pause)
            pause *= 2

    def submit(self, scene, **options):
        """Queues `scene` and returns the job id.

        scene: a dict with a scene file's structure, YAML text, the path of a scene file, or a
          render_pb2.SubmitJobRequest (sent as it is). Converted by `tessera convert`: the
          same loader, checks and conversion as `tessera submit`.
        options: name, priority, labels (a dict), submitter, lenient, the render overrides
          width, height, spp, max_depth, tile_size, seed and passes, and request_id (default:
          a random one). With it a submit that timed out or found the daemon unreachable is
          retried (4 attempts, 0.5 s apart, doubling) without ever making two jobs.
        Raises SceneError for a bad scene (nothing is sent), TesseraError if the server
        refuses it.
        """
        return self.submit_job(scene, **options).id

    def job(self, job_id):
        """The job's render_pb2.Job (state, settings, progress)."""
        return self._call(self._stub.GetJob, render_pb2.GetJobRequest(job_id=job_id),
                          self._timeout, f"cannot get job {job_id}")

    def jobs(self, **filters):
        """Every job, newest first; filters as ListJobsRequest (state, submitter, label,
        name)."""
        found, token = [], ""
        while True:
            page = self._call(self._stub.ListJobs,
                              render_pb2.ListJobsRequest(page_token=token, **filters),
                              self._timeout, "listing jobs failed")
            found.extend(page.jobs)
            token = page.next_page_token
            if not token:
                return found

    def cancel(self, job_id):
        return self._call(self._stub.CancelJob, render_pb2.CancelJobRequest(job_id=job_id),
                          self._timeout, f"cannot cancel job {job_id}").job

    def delete(self, job_id):
        self._call(self._stub.DeleteJob, render_pb2.DeleteJobRequest(job_id=job_id),
                   self._timeout, f"cannot delete job {job_id}")

    # ---- tiles ---------------------------------------------------------------------------

    def stream_messages(self, job_id, after_sequence=0):
        """The job's deliveries as render_pb2.Tile messages (EXR bytes): every one the job
        has made after `after_sequence`, then each as it is made, until the job completes.
        Raises JobCancelled or JobFailed when the job ends otherwise. When the daemon goes
        away (a restart), re-attaches after the last delivery received for up to
        `reconnect_window` seconds, as the C++ client does, so every tile arrives once."""
        received, by_sequence = after_sequence, True
        give_up_at = time.monotonic() + self._reconnect_window
        pause = 0.2
        daemon_stopping = False  # a daemon said it stops, and none has streamed since
        while True:
            request = render_pb2.StreamTilesRequest(job_id=job_id)
            if by_sequence:
                request.after_sequence = received
            else:
                request.after_tiles = received
            call = self._stub.StreamTiles(request, metadata=self._metadata)
            try:
                for tile in call:
                    yield tile
                    # A daemon from before sequences sends 0; its tiles_done is the same place.
                    by_sequence = tile.sequence != 0
                    received = tile.sequence if by_sequence else tile.progress.tiles_done
                    daemon_stopping = False
                    give_up_at = time.monotonic() + self._reconnect_window
                    pause = 0.2
                return
            except grpc.RpcError as e:
                code = e.code()
                job_kept = any(key == _JOB_RESUMES_KEY for key, _ in e.trailing_metadata() or ())
                retry = time.monotonic() < give_up_at and (
                    (code == grpc.StatusCode.UNAVAILABLE
                     and (job_kept or received > 0 or daemon_stopping))
                    or (code == grpc.StatusCode.CANCELLED and daemon_stopping))
                if not retry:
                    raise _stream_error(e, self.address, job_id) from None
                # As the C++ client: a CANCELLED while the daemon stops is retried once, so
                # a job really cancelled meanwhile is reported by the next stream.
                if job_kept:
                    daemon_stopping = True
                    pause = max(pause, 1.0)
                elif code == grpc.StatusCode.CANCELLED:
                    daemon_stopping = False
            finally:
                call.cancel()  # no-op once finished; ends the call if the caller stopped early
            time.sleep(pause)
            pause = min(pause * 2, 2.0)

    def stream(self, job_id, after_sequence=0):
        """The job's tiles as Tile objects (pixels as float32 numpy arrays), as
        stream_messages() delivers them."""
        with tiles_module.scratch_directory() as scratch:
            for message in self.stream_messages(job_id, after_sequence):
                yield tiles_module.decode_tile(message, scratch)

    def wait_image(self, job_id, with_channels=False, on_tile=None):
        """The job's finished image as a float32 array, height x width x channels (R, G, B,
        A, then the AOVs' channels), from its stream; with_channels: (image, names).
        on_tile: called with each Tile as it arrives (progress display)."""
        job = self.job(job_id)
        settings = job.settings
        assembler = tiles_module.ImageAssembler(settings.width, settings.height,
                                                settings.passes)
        for tile in self.stream(job_id):
            assembler.add(tile)
            if on_tile:
                on_tile(tile)
        tiles_total = job.progress.tiles_total // assembler.passes
        if assembler.image is None or assembler.tiles_complete() != tiles_total:
            raise TesseraError(f"job {job_id}: the stream ended with "
                               f"{assembler.tiles_complete()} of {tiles_total} tiles")
        return (assembler.image, assembler.channels) if with_channels else assembler.image

    def render(self, scene, with_channels=False, on_tile=None, **options):
        """Submits `scene` (as submit()), streams its tiles and returns the image as a
        float32 array, height x width x channels; with_channels: (image, channel names).
        on_tile as wait_image()."""
        return self.wait_image(self.submit(scene, **options), with_channels=with_channels,
                               on_tile=on_tile)


def _stream_error(rpc_error, address, job_id):
    code, details = rpc_error.code(), rpc_error.details()
    if code == grpc.StatusCode.CANCELLED:
        return JobCancelled(f"job {job_id} was cancelled", code, details)
    if code == grpc.StatusCode.ABORTED:
        return JobFailed(f"job {job_id} failed: {details}", code, details)
    return _error(rpc_error, address, f"streaming job {job_id} failed")


def _error(rpc_error, address, doing):
    code, details = rpc_error.code(), rpc_error.details()
    if code == grpc.StatusCode.UNAVAILABLE:
        text = f"cannot reach the server at {address} (is tesserad running?): {details}"
    elif code == grpc.StatusCode.DEADLINE_EXCEEDED:
        text = f"the server at {address} did not answer in time: {details}"
    else:
        text = f"{doing}: {code.name}: {details}"
    return TesseraError(text, code, details)
