"""The exceptions the client raises."""


class TesseraError(Exception):
    """A call that failed: `code` is the gRPC status code (a grpc.StatusCode) when the server
    or the transport answered, else None; `details` the message without the code."""

    def __init__(self, message, code=None, details=None):
        super().__init__(message)
        self.code = code
        self.details = details if details is not None else message


class SceneError(TesseraError):
    """The scene was refused before anything was sent: the message is the loader's
    `file:line: field: reason` (`<stdin>` for a dict or YAML text)."""


class JobCancelled(TesseraError):
    """The job was cancelled while its tiles were streamed."""


class JobFailed(TesseraError):
    """The job failed on the server; the message is the server's reason."""


class SceneWarning(UserWarning):
    """A scene key the loader ignored (with lenient=True) or a feature it approximated."""
