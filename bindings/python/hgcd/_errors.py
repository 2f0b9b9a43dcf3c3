"""hgcd.Error, the one exception of the package, and the status codes."""
import enum

from ._hgcd import ffi, lib


class Status(enum.IntEnum):
    """The library's hgcd_status codes (values read from the compiled header)."""

    OK = lib.HGCD_OK
    NULL_ARGUMENT = lib.HGCD_ERROR_NULL_ARGUMENT
    INVALID_ARGUMENT = lib.HGCD_ERROR_INVALID_ARGUMENT
    BAD_DESCRIPTOR = lib.HGCD_ERROR_BAD_DESCRIPTOR
    STALE_ID = lib.HGCD_ERROR_STALE_ID
    INVALID_MESH = lib.HGCD_ERROR_INVALID_MESH
    MESH_IN_USE = lib.HGCD_ERROR_MESH_IN_USE
    OUT_OF_MEMORY = lib.HGCD_ERROR_OUT_OF_MEMORY
    CAPACITY = lib.HGCD_ERROR_CAPACITY
    NOT_SUPPORTED = lib.HGCD_ERROR_NOT_SUPPORTED
    INTERNAL = lib.HGCD_ERROR_INTERNAL


class Error(Exception):
    """Every failure of the package: a call the library refused, or an argument
    refused in Python before reaching the library (wrong dtype or shape, a
    closed world, a mesh of another world).

    status: the hgcd_status code (an int; Status(status) names it, unknown
        codes of a newer library stay plain ints);
    name: the code's name, e.g. "HGCD_ERROR_STALE_ID";
    message: what was wrong: the library's hgcd_world_last_error text, or
        the binding's own, both naming the call, e.g.
        "body_create: position[1] is not finite".
    """

    def __init__(self, status, message):
        self.status = int(status)
        self.name = ffi.string(lib.hgcd_status_string(self.status)).decode()
        self.message = message
        super().__init__(f"{message} ({self.name})")

    def __reduce__(self):  # pickled as its two arguments (multiprocessing passes errors back)
        return (Error, (self.status, self.message))


def argument_error(message):
    """An argument refused in Python, with the status the library would give."""
    return Error(Status.INVALID_ARGUMENT, message)
