//! Smoke tests of the raw bindings against the linked library, and the check
//! that `src/bindings.rs` is what `generate.sh` produces today.

use hgcd_sys::*;
use std::ffi::CStr;
use std::mem::size_of;
use std::process::Command;

#[test]
fn runtime_version_matches_header() {
    let v = unsafe { hgcd_version() };
    assert_eq!(
        v,
        (HGCD_VERSION_MAJOR << 16) | (HGCD_VERSION_MINOR << 8) | HGCD_VERSION_PATCH
    );
    let s = unsafe { CStr::from_ptr(hgcd_version_string()) }
        .to_str()
        .unwrap();
    assert_eq!(
        s,
        format!("{HGCD_VERSION_MAJOR}.{HGCD_VERSION_MINOR}.{HGCD_VERSION_PATCH}")
    );
}

#[test]
fn status_strings() {
    let name = |s: hgcd_status| {
        unsafe { CStr::from_ptr(hgcd_status_string(s)) }
            .to_str()
            .unwrap()
            .to_owned()
    };
    assert_eq!(name(HGCD_OK), "HGCD_OK");
    assert_eq!(name(HGCD_ERROR_STALE_ID), "HGCD_ERROR_STALE_ID");
    assert_eq!(name(HGCD_ERROR_INTERNAL), "HGCD_ERROR_INTERNAL");
    assert_eq!(name(-12345), "HGCD_ERROR_UNKNOWN");
}

#[test]
fn defaults_carry_their_size() {
    unsafe {
        assert_eq!(
            hgcd_world_desc_default().struct_size as usize,
            size_of::<hgcd_world_desc>()
        );
        assert_eq!(
            hgcd_mesh_desc_default().struct_size as usize,
            size_of::<hgcd_mesh_desc>()
        );
        assert_eq!(
            hgcd_body_desc_default().struct_size as usize,
            size_of::<hgcd_body_desc>()
        );
        assert_eq!(
            hgcd_scene_tetra_desc_default().struct_size as usize,
            size_of::<hgcd_scene_tetra_desc>()
        );
    }
}

#[test]
fn raw_world_roundtrip() {
    unsafe {
        let desc = hgcd_world_desc_default();
        let mut w: *mut hgcd_world = std::ptr::null_mut();
        assert_eq!(hgcd_world_create(&desc, &mut w), HGCD_OK);
        assert!(!w.is_null());
        assert_eq!(hgcd_world_body_count(w), 0);
        assert_eq!(hgcd_world_detect(w), HGCD_OK);
        let mut pairs: *const hgcd_pair = std::ptr::null();
        let mut count = usize::MAX;
        assert_eq!(hgcd_world_pairs(w, &mut pairs, &mut count), HGCD_OK);
        assert_eq!(count, 0);
        // A NULL out pointer is refused, not dereferenced.
        assert_eq!(
            hgcd_world_pairs(w, std::ptr::null_mut(), &mut count),
            HGCD_ERROR_NULL_ARGUMENT
        );
        hgcd_world_destroy(w);
        hgcd_world_destroy(std::ptr::null_mut());
    }
}

/// Fails when the committed src/bindings.rs differs from a fresh bindgen run;
/// skipped (with a message on stderr) when bindgen is not installed.
#[test]
fn bindings_are_regenerated_identically() {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/generate.sh");
    let out = Command::new("bash")
        .arg(script)
        .arg("--check")
        .output()
        .expect("run bash generate.sh --check");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if stdout.starts_with("SKIP") {
        eprintln!("{stdout}");
        return;
    }
    assert!(
        out.status.success(),
        "generate.sh --check failed:\n{stdout}\n{stderr}"
    );
}
