"""What engines need around the pairs: body types, enabling, filters, pair
exclusions, begin/end events and contact margins, each over whole arrays of
bodies or pairs."""
import numpy as np

from . import _arrays as A
from ._arrays import BODY_ID
from ._errors import Error, Status, argument_error
from ._hgcd import ffi, lib
from ._types import FILTER, PAIR_EVENT


def make_filter(category_bits=1, mask_bits=2**64 - 1, group_index=0):
    """One filter (a FILTER scalar, Box2D v3's semantics): two bodies with the
    same non-zero group_index collide when it is positive and never when it
    is negative; otherwise when each one's mask_bits meet the other's
    category_bits. The defaults collide with every default body."""
    for name, value, lo, hi in (("category_bits", category_bits, 0, 2**64 - 1), ("mask_bits", mask_bits, 0, 2**64 - 1),
                                ("group_index", group_index, -2**31, 2**31 - 1)):
        if not isinstance(value, (int, np.integer)) or not lo <= value <= hi:
            raise argument_error(f"make_filter: {name} must be an int in [{lo}, {hi}], not {value!r}")
    return np.array((category_bits, mask_bits, group_index, 0), dtype=FILTER)


def per_body(value, n, dtype, what, call):
    """A packed (n,) array of dtype from one value for all or n values."""
    arr = A._as_array(value, dtype, what, call)
    if arr.ndim == 0:
        return np.full(n, arr, dtype=dtype)
    A._check_shape(arr, None, n, what, call)
    return A.packed(arr)


def type_values(types, n, call):
    """BodyType values as a packed (n,) int32 array; anything else is refused here."""
    given = np.asarray(types)
    if given.dtype.kind not in "iu" or given.ndim > 1 or np.any((given < 0) | (given > 2)):
        raise argument_error(f"{call}: types must be BodyType values, not {types!r}")
    return per_body(given.astype(np.int32), n, np.int32, "types", call)


class EngineFeatures:
    """Mixed into World: types, enabling, filters, exclusions, events and margins."""

    def _flags_call(self, bodies, call, types=None, enabled=None, filters=None):
        b = A.ids(bodies, None, "bodies", call)
        n = len(b)
        t = None if types is None else type_values(types, n, call)
        e = None if enabled is None else per_body(np.asarray(enabled, dtype=bool).astype(np.uint8), n,
                                                  np.uint8, "enabled", call)
        f = None if filters is None else per_body(filters, n, FILTER, "filters", call)
        ptrs = [ffi.NULL if arr is None else A.ptr(ctype, arr)
                for arr, ctype in ((t, "int32_t *"), (e, "uint8_t *"), (f, "hgcd_filter *"))]
        failed = ffi.new("size_t *")
        with self._lock:
            status = lib.hgcd_py_set_flags(self._live(), A.ptr("hgcd_body *", b), n, *ptrs, failed)
            if status == lib.HGCD_ERROR_INVALID_ARGUMENT:
                raise Error(status, f"{call}: entry {failed[0]}: a filter's reserved field must be 0")
            self._check_entry(status, call, failed[0])

    def set_types(self, bodies, types):
        """Sets the BodyType of the bodies of a BODY_ID array (one type for all,
        or one per body), from the next detect; all or nothing."""
        self._flags_call(bodies, "set_types", types=types)

    def set_enabled(self, bodies, enabled):
        """Enables (True) or disables (False) bodies (one flag, or one per body):
        a disabled body keeps its id and state but leaves every pair."""
        self._flags_call(bodies, "set_enabled", enabled=enabled)

    def set_filters(self, bodies, filters):
        """Sets the bodies' filters: one FILTER (hgcd.make_filter) for all, or a
        (N,) FILTER array; all or nothing."""
        self._flags_call(bodies, "set_filters", filters=filters)

    def get_body_flags(self, bodies):
        """(types (N,) int32 BodyType values, enabled (N,) bool, filters (N,) FILTER)
        of the bodies of a BODY_ID array."""
        b = A.ids(bodies, None, "bodies", "get_body_flags")
        types = np.empty(len(b), dtype=np.int32)
        enabled = np.empty(len(b), dtype=np.uint8)
        filters = np.zeros(len(b), dtype=FILTER)
        failed = ffi.new("size_t *")
        with self._lock:
            status = lib.hgcd_py_get_flags(self._live(), A.ptr("hgcd_body *", b), len(b),
                                           A.ptr("int32_t *", types), A.ptr("uint8_t *", enabled),
                                           A.ptr("hgcd_filter *", filters), failed)
            self._const_check(status, f"get_body_flags: entry {failed[0]}")
        return types, enabled.astype(bool), filters

    def _pairs_arg(self, pairs, call):
        arr = A._as_array(pairs, BODY_ID, "pairs", call)
        if arr.ndim != 2 or arr.shape[1] != 2:
            raise argument_error(f"{call}: pairs must have shape (N, 2), not {arr.shape}")
        return A.packed(arr)

    def _pairs_call(self, pairs, call, exclude):
        p = self._pairs_arg(pairs, call)
        scratch = np.empty(len(p), dtype=np.uint8)
        failed = ffi.new("size_t *")
        with self._lock:
            if exclude is None:
                status = lib.hgcd_py_pairs_excluded(self._live(), A.ptr("hgcd_pair *", p), len(p),
                                                    A.ptr("uint8_t *", scratch), failed)
            else:
                status = lib.hgcd_py_set_excluded(self._live(), A.ptr("hgcd_pair *", p), len(p),
                                                  1 if exclude else 0, A.ptr("uint8_t *", scratch), failed)
            if status == lib.HGCD_ERROR_STALE_ID:
                raise Error(status, f"{call}: pair {failed[0]} has a body that is not live in this world")
            if status == lib.HGCD_ERROR_INVALID_ARGUMENT:
                raise Error(status, f"{call}: pair {failed[0]} is one body twice")
            self._check(status, f"{call}: pair {failed[0]}: ")
        return scratch.astype(bool)

    def exclude_pairs(self, pairs):
        """Excludes the pairs of an (N, 2) BODY_ID array from detection (two bodies
        joined by a joint, say) until include_pairs or a body's destruction;
        all or nothing."""
        self._pairs_call(pairs, "exclude_pairs", True)

    def include_pairs(self, pairs):
        """Ends the exclusion of the pairs of an (N, 2) BODY_ID array (pairs not
        excluded are left as they are); all or nothing."""
        self._pairs_call(pairs, "include_pairs", False)

    def pairs_excluded(self, pairs):
        """A (N,) bool array: whether each pair of an (N, 2) BODY_ID array is excluded."""
        return self._pairs_call(pairs, "pairs_excluded", None)

    def events(self):
        """(began, ended): the pairs that began and ended colliding at the last
        step/detect, each a new sorted (N,) array of dtype PAIR_EVENT (a, b,
        user_data_a, user_data_b); ended includes pairs whose body was
        destroyed, disabled, made static or filtered out since."""
        began, began_n = ffi.new("hgcd_pair_event **"), ffi.new("size_t *")
        ended, ended_n = ffi.new("hgcd_pair_event **"), ffi.new("size_t *")
        with self._lock:
            status = lib.hgcd_world_events(self._live(), began, began_n, ended, ended_n)
            if status != lib.HGCD_OK:
                raise Error(Status(status), "events: refused")
            return tuple(np.frombuffer(ffi.buffer(p[0], n[0] * PAIR_EVENT.itemsize), dtype=PAIR_EVENT).copy()
                         if n[0] else np.empty(0, dtype=PAIR_EVENT) for p, n in ((began, began_n), (ended, ended_n)))

    @property
    def contact_margin(self):
        """The world's contact margin (hgcd_world_desc.contact_margin)."""
        out = ffi.new("double *")
        with self._lock:
            self._const_check(lib.hgcd_world_get_contact_margin(self._live(), out), "contact_margin")
        return out[0]

    def set_contact_margin(self, margin):
        """Sets the world's contact margin d from the next step/detect: two bodies
        a, b are reported when their closed solids come within d + margin_a +
        margin_b of each other (Euclidean distance, decided exactly), so resting
        contacts do not flicker under a solver's noise. Finite, >= 0 and
        <= 1e15; every pair is tested again at the next detect."""
        try:
            value = float(margin)
        except (TypeError, ValueError):
            raise argument_error(f"set_contact_margin: margin must be a float, not {margin!r}") from None
        with self._lock:
            self._check(lib.hgcd_world_set_contact_margin(self._live(), value), "set_contact_margin: ")

    def set_margins(self, bodies, margins):
        """Sets the bodies' own contact margins (one float for all, or (N,)),
        added to the world's, from the next step/detect; all or nothing. Each
        change makes the next detect rebuild the broad phase: give margins at
        create_bodies where possible."""
        call = "set_margins"
        b = A.ids(bodies, None, "bodies", call)
        m = per_body(margins, len(b), np.float64, "margins", call)
        scratch = np.empty(len(b), dtype=np.float64)
        failed = ffi.new("size_t *")
        with self._lock:
            status = lib.hgcd_py_set_margins(self._live(), A.ptr("hgcd_body *", b), len(b),
                                             A.ptr("double *", m), A.ptr("double *", scratch), failed)
            self._check_entry(status, call, failed[0])

    def get_margins(self, bodies):
        """The bodies' own contact margins, a (N,) float64 array."""
        b = A.ids(bodies, None, "bodies", "get_margins")
        out = np.empty(len(b), dtype=np.float64)
        failed = ffi.new("size_t *")
        with self._lock:
            status = lib.hgcd_py_get_margins(self._live(), A.ptr("hgcd_body *", b), len(b),
                                             A.ptr("double *", out), failed)
            self._const_check(status, f"get_margins: entry {failed[0]}")
        return out
