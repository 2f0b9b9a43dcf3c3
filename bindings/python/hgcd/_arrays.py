"""Checking numpy arguments before they reach C, and handing them over.

Inputs that are numpy arrays must already have the exact dtype (no silent
conversion of float32 positions or int64 triangles: the error says which
.astype to write); lists and tuples are converted. Shapes are checked exactly.
A row-strided array (rows of 8-byte elements, rows a multiple of 8 bytes apart,
e.g. one field of an array of the caller's records) is passed to the batch
calls with its stride, without a copy; any other layout is copied first.
"""
import numpy as np

from ._errors import argument_error
from ._hgcd import ffi

#: dtype of an id (hgcd_body / hgcd_mesh): the C struct's layout, so an array
#: of ids is passed to C as it is.
BODY_ID = np.dtype([("index", "<u4"), ("generation", "<u4")])
MESH_ID = BODY_ID

assert BODY_ID.itemsize == ffi.sizeof("hgcd_body") == ffi.sizeof("hgcd_mesh")


def _as_array(value, dtype, what, call):
    if isinstance(value, np.ndarray):
        if value.dtype != dtype:
            raise argument_error(
                f"{call}: {what} must have dtype {np.dtype(dtype).name}, not {value.dtype} "
                f"(convert with .astype(np.{np.dtype(dtype).name}))")
        return value
    try:
        return np.asarray(value, dtype=dtype)
    except (TypeError, ValueError) as e:
        raise argument_error(f"{call}: {what} is not convertible to {np.dtype(dtype).name}: {e}")


def _check_shape(arr, width, count, what, call):
    """arr must be (count, width) (count None: any) or, for width None, (count,)."""
    want = (count,) if width is None else (count, width)
    ok = arr.ndim == len(want) and all(w is None or s == w for s, w in zip(arr.shape, want))
    if not ok:
        shown = "(" + ", ".join("N" if w is None else str(w) for w in want) + ("," if len(want) == 1 else "") + ")"
        raise argument_error(f"{call}: {what} must have shape {shown}, not {arr.shape}")


def rows(value, width, count, what, call, dtype=np.float64):
    """A (count, width) array of dtype, checked; count None takes any number."""
    arr = _as_array(value, dtype, what, call)
    _check_shape(arr, width, count, what, call)
    return arr


def column(value, count, what, call, dtype):
    """A (count,) array of dtype, checked."""
    arr = _as_array(value, dtype, what, call)
    _check_shape(arr, None, count, what, call)
    return arr


def strided(arr):
    """(array, stride) for a batch call: arr itself with its row stride in bytes
    when C can read it in place (each row's elements packed, rows a positive
    multiple of the element size apart, at least a row wide, aligned);
    otherwise a packed copy with stride 0."""
    n, width = arr.shape
    item = arr.itemsize
    s_row, s_col = arr.strides
    if n <= 1:
        s_row = width * item  # only row 0 is read: its stride does not matter
    if (s_col == item or width == 1) and arr.ctypes.data % item == 0 and (
            n <= 1 or (s_row >= width * item and s_row % item == 0)):
        return arr, (0 if s_row == width * item else s_row)
    return np.ascontiguousarray(arr), 0


def packed(arr):
    """arr, packed in C order (copied only when it is not)."""
    return np.ascontiguousarray(arr)


def ptr(ctype, arr):
    """A C pointer to arr's first element (arr must stay referenced during the call)."""
    return ffi.cast(ctype, arr.ctypes.data)


def ids(value, count, what, call):
    """A packed (count,) array of ids (BODY_ID); count None takes any number."""
    arr = _as_array(value, BODY_ID, what, call)
    _check_shape(arr, None, count, what, call)
    return packed(arr)
