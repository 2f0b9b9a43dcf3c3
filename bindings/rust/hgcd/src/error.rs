//! `hgcd::Error`: the library's status code plus its message.

use std::ffi::CStr;
use std::fmt;

use hgcd_sys as sys;

/// The error codes of `hgcd_status` (every negative code of the header), plus
/// `Unknown` for a code this crate does not know (a newer library).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ErrorKind {
    /// `HGCD_ERROR_NULL_ARGUMENT`: a required pointer was NULL. The safe API
    /// never passes NULL, so seeing it means a bug in this crate.
    NullArgument,
    /// `HGCD_ERROR_INVALID_ARGUMENT`: NaN, infinite, out of range, a
    /// quaternion that is not of unit length, ...
    InvalidArgument,
    /// `HGCD_ERROR_BAD_DESCRIPTOR`: a descriptor not made by its
    /// `*_desc_default()` (the safe API always starts from those).
    BadDescriptor,
    /// `HGCD_ERROR_STALE_ID`: a null, destroyed, forged or foreign id.
    StaleId,
    /// `HGCD_ERROR_INVALID_MESH`: no triangles, index out of range,
    /// non-finite vertex, too large.
    InvalidMesh,
    /// `HGCD_ERROR_MESH_IN_USE`: destroying a mesh that live bodies use.
    MeshInUse,
    /// `HGCD_ERROR_OUT_OF_MEMORY`: an allocation failed; nothing changed.
    OutOfMemory,
    /// `HGCD_ERROR_CAPACITY`: a count limit was reached.
    Capacity,
    /// `HGCD_ERROR_NOT_SUPPORTED`: not compiled into this build of hgcd.
    NotSupported,
    /// `HGCD_ERROR_INTERNAL`: a bug in hgcd.
    Internal,
    /// A negative code this crate does not know.
    Unknown(i32),
}

impl ErrorKind {
    /// The kind of a non-zero `hgcd_status` (0 is not an error: it maps to
    /// `Unknown(0)`, which the crate never produces).
    pub fn from_code(code: sys::hgcd_status) -> ErrorKind {
        match code {
            sys::HGCD_ERROR_NULL_ARGUMENT => ErrorKind::NullArgument,
            sys::HGCD_ERROR_INVALID_ARGUMENT => ErrorKind::InvalidArgument,
            sys::HGCD_ERROR_BAD_DESCRIPTOR => ErrorKind::BadDescriptor,
            sys::HGCD_ERROR_STALE_ID => ErrorKind::StaleId,
            sys::HGCD_ERROR_INVALID_MESH => ErrorKind::InvalidMesh,
            sys::HGCD_ERROR_MESH_IN_USE => ErrorKind::MeshInUse,
            sys::HGCD_ERROR_OUT_OF_MEMORY => ErrorKind::OutOfMemory,
            sys::HGCD_ERROR_CAPACITY => ErrorKind::Capacity,
            sys::HGCD_ERROR_NOT_SUPPORTED => ErrorKind::NotSupported,
            sys::HGCD_ERROR_INTERNAL => ErrorKind::Internal,
            other => ErrorKind::Unknown(other),
        }
    }

    /// The C status code.
    pub fn code(self) -> sys::hgcd_status {
        match self {
            ErrorKind::NullArgument => sys::HGCD_ERROR_NULL_ARGUMENT,
            ErrorKind::InvalidArgument => sys::HGCD_ERROR_INVALID_ARGUMENT,
            ErrorKind::BadDescriptor => sys::HGCD_ERROR_BAD_DESCRIPTOR,
            ErrorKind::StaleId => sys::HGCD_ERROR_STALE_ID,
            ErrorKind::InvalidMesh => sys::HGCD_ERROR_INVALID_MESH,
            ErrorKind::MeshInUse => sys::HGCD_ERROR_MESH_IN_USE,
            ErrorKind::OutOfMemory => sys::HGCD_ERROR_OUT_OF_MEMORY,
            ErrorKind::Capacity => sys::HGCD_ERROR_CAPACITY,
            ErrorKind::NotSupported => sys::HGCD_ERROR_NOT_SUPPORTED,
            ErrorKind::Internal => sys::HGCD_ERROR_INTERNAL,
            ErrorKind::Unknown(code) => code,
        }
    }

    /// The library's name of the code (`hgcd_status_string`), e.g.
    /// `"HGCD_ERROR_STALE_ID"`.
    pub fn name(self) -> &'static str {
        // SAFETY: hgcd_status_string accepts any code and returns a static,
        // NUL-terminated string, never NULL (header contract); checked anyway.
        unsafe {
            let p = sys::hgcd_status_string(self.code());
            if p.is_null() {
                return "HGCD_ERROR_UNKNOWN";
            }
            CStr::from_ptr(p).to_str().unwrap_or("HGCD_ERROR_UNKNOWN")
        }
    }
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ErrorKind::Unknown(code) => write!(f, "{} ({code})", self.name()),
            _ => f.write_str(self.name()),
        }
    }
}

/// An error of an hgcd call: its status and the detail message.
///
/// For calls that change the world the message is the library's own
/// (`hgcd_world_last_error`, e.g. `"body_create: position[1] is not
/// finite"`). Read-only calls record no message in C (so that they may
/// overlap), and checks done on the Rust side before calling C have none
/// either: for those the message names the call (`"body_get_pose"`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    kind: ErrorKind,
    message: String,
}

impl Error {
    /// An error with the given kind and message.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error {
            kind,
            message: message.into(),
        }
    }

    pub(crate) fn from_status(code: sys::hgcd_status, message: impl Into<String>) -> Error {
        Error::new(ErrorKind::from_code(code), message)
    }

    /// What went wrong, as the library's status.
    pub fn kind(&self) -> ErrorKind {
        self.kind
    }

    /// The C status code (negative).
    pub fn code(&self) -> i32 {
        self.kind.code()
    }

    /// The detail message.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.message.is_empty() {
            write!(f, "{}", self.kind)
        } else {
            write!(f, "{}: {}", self.kind, self.message)
        }
    }
}

impl std::error::Error for Error {}

/// `Result` with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
