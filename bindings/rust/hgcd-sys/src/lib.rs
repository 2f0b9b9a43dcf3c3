//! Raw FFI bindings to the hgcd C API (`include/hgcd/hgcd.h`).
//!
//! `bindings.rs` is the unedited output of the bindgen CLI, produced by
//! `generate.sh` beside this crate's `Cargo.toml` (the options are pinned
//! there; `generate.sh --check` verifies that a fresh generation is
//! byte-identical). bindgen's layout tests are part of it and run with
//! `cargo test`.
//!
//! Everything here is `unsafe` to use and follows the C contract documented
//! in the header; the `hgcd` crate is the safe wrapper. `build.rs` decides
//! which `libhgcd` is linked (see the crate README for the search order).
#![allow(non_upper_case_globals, non_camel_case_types, non_snake_case)]
#![allow(clippy::all)]
#![allow(rustdoc::broken_intra_doc_links, rustdoc::bare_urls)]

include!("bindings.rs");
