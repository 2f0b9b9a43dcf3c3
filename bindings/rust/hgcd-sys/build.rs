//! Finds the hgcd C library and tells cargo how to link it. No crates: the
//! pkg-config binary is run directly.
//!
//! Search order (the first that yields a library wins):
//!   1. `HGCD_LIB_DIR`: a directory holding `libhgcd.a` (or `libhgcd.so`).
//!      Setting it to a directory without the library is an error.
//!   2. `pkg-config --static --libs hgcd` (the `PKG_CONFIG` variable names
//!      another binary), using its `-L` directories and `libdir` variable.
//!   3. The repository's own build: `../../../build-make/` relative to this
//!      crate, which is what a plain `make` at the repository root produces.
//!
//! If none has it, a warning is printed and `-lhgcd` is left to the linker's
//! default search path (building this crate's rlib does not need the library;
//! linking an executable or a test does).
//!
//! Link kind: `HGCD_LINK=static` or `HGCD_LINK=dylib`. Unset: static if a
//! `libhgcd.a` is there, else the shared library. A static libhgcd needs its
//! C++ and OpenMP runtimes: `stdc++`, `gomp` and `m` are linked as dylibs
//! (override the list with `HGCD_RUNTIME_LIBS`, e.g. "c++ omp" for a
//! clang/libomp build; an empty value links none). A static libhgcd built
//! with libccd also needs `ccd`: the Makefile lists such libraries in
//! `libhgcd-static-deps.txt` beside `libhgcd.a`, and they are linked as dylibs
//! too. A shared libhgcd is found
//! at run time by the dynamic loader (set `LD_LIBRARY_PATH` or install it).

use std::env;
use std::path::{Path, PathBuf};
use std::process::Command;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kind {
    Static,
    Dylib,
}

struct Found {
    kind: Kind,
    /// Directory to add to the native search path, with the library file.
    dir: PathBuf,
    file: PathBuf,
    source: &'static str,
    /// Extra libraries named by pkg-config (besides hgcd).
    extra_libs: Vec<String>,
    extra_dirs: Vec<PathBuf>,
}

fn lib_name(kind: Kind) -> &'static str {
    let macos = env::var("CARGO_CFG_TARGET_OS")
        .map(|o| o == "macos")
        .unwrap_or(false);
    match (kind, macos) {
        (Kind::Static, _) => "libhgcd.a",
        (Kind::Dylib, false) => "libhgcd.so",
        (Kind::Dylib, true) => "libhgcd.dylib",
    }
}

/// The library in `dir`: of the requested kind, or (no kind requested) the
/// static one if present, else the shared one.
fn find_in(dir: &Path, want: Option<Kind>) -> Option<(Kind, PathBuf)> {
    let kinds: &[Kind] = match want {
        Some(Kind::Static) => &[Kind::Static],
        Some(Kind::Dylib) => &[Kind::Dylib],
        None => &[Kind::Static, Kind::Dylib],
    };
    kinds.iter().find_map(|&k| {
        let f = dir.join(lib_name(k));
        if f.is_file() {
            Some((k, f))
        } else {
            None
        }
    })
}

fn from_env(want: Option<Kind>) -> Option<Found> {
    let dir = PathBuf::from(env::var_os("HGCD_LIB_DIR").filter(|v| !v.is_empty())?);
    match find_in(&dir, want) {
        Some((kind, file)) => Some(Found {
            kind,
            dir,
            file,
            source: "HGCD_LIB_DIR",
            extra_libs: Vec::new(),
            extra_dirs: Vec::new(),
        }),
        None => panic!(
            "HGCD_LIB_DIR={} holds no {} (build the C library with `make lib` at the \
             repository root, or point HGCD_LIB_DIR at its build directory)",
            dir.display(),
            match want {
                Some(k) => lib_name(k).to_string(),
                None => format!("{} or {}", lib_name(Kind::Static), lib_name(Kind::Dylib)),
            }
        ),
    }
}

fn run(cmd: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(cmd).args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    String::from_utf8(out.stdout).ok()
}

fn from_pkg_config(want: Option<Kind>) -> Option<Found> {
    let pc = env::var("PKG_CONFIG").unwrap_or_else(|_| "pkg-config".to_string());
    run(&pc, &["--exists", "hgcd"])?;
    let libs = if want == Some(Kind::Dylib) {
        run(&pc, &["--libs", "hgcd"])?
    } else {
        run(&pc, &["--static", "--libs", "hgcd"])?
    };
    let mut dirs = Vec::new();
    let mut extra_libs = Vec::new();
    let mut tokens = libs.split_whitespace();
    while let Some(t) = tokens.next() {
        if t == "-L" {
            if let Some(d) = tokens.next() {
                dirs.push(PathBuf::from(d));
            }
        } else if let Some(d) = t.strip_prefix("-L") {
            dirs.push(PathBuf::from(d));
        } else if let Some(l) = t.strip_prefix("-l") {
            if l != "hgcd" {
                extra_libs.push(l.to_string());
            }
        } else if t == "-fopenmp" {
            extra_libs.push("gomp".to_string());
        } else if t == "-pthread" {
            extra_libs.push("pthread".to_string());
        }
    }
    if let Some(libdir) = run(&pc, &["--variable=libdir", "hgcd"]) {
        let libdir = libdir.trim();
        if !libdir.is_empty() {
            dirs.push(PathBuf::from(libdir));
        }
    }
    for dir in &dirs {
        if let Some((kind, file)) = find_in(dir, want) {
            return Some(Found {
                kind,
                dir: dir.clone(),
                file,
                source: "pkg-config",
                extra_libs,
                extra_dirs: dirs.clone(),
            });
        }
    }
    println!(
        "cargo:warning=pkg-config knows hgcd but no {} was found in {:?}; trying the repository build",
        lib_name(want.unwrap_or(Kind::Static)),
        dirs
    );
    None
}

/// The repository root: three levels above this crate (bindings/rust/hgcd-sys).
fn repo_root() -> PathBuf {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let root = manifest.join("..").join("..").join("..");
    root.canonicalize().unwrap_or(root)
}

fn repo_build_dir() -> PathBuf {
    repo_root().join("build-make")
}

fn from_repo(want: Option<Kind>) -> Option<Found> {
    let dir = repo_build_dir();
    let (kind, file) = find_in(&dir, want)?;
    Some(Found {
        kind,
        dir,
        file,
        source: "repository build-make/",
        extra_libs: Vec::new(),
        extra_dirs: Vec::new(),
    })
}

fn main() {
    for var in [
        "HGCD_LIB_DIR",
        "HGCD_LINK",
        "HGCD_RUNTIME_LIBS",
        "PKG_CONFIG",
        "PKG_CONFIG_PATH",
    ] {
        println!("cargo:rerun-if-env-changed={var}");
    }
    println!("cargo:rerun-if-changed=build.rs");

    let want = match env::var("HGCD_LINK").ok().as_deref() {
        None | Some("") => None,
        Some("static") => Some(Kind::Static),
        Some("dylib") | Some("dynamic") | Some("shared") => Some(Kind::Dylib),
        Some(other) => panic!("HGCD_LINK={other}: expected `static` or `dylib`"),
    };

    let runtime: Vec<String> = match env::var("HGCD_RUNTIME_LIBS") {
        Ok(list) => list.split_whitespace().map(str::to_string).collect(),
        Err(_) => ["stdc++", "gomp", "m"]
            .iter()
            .map(|s| s.to_string())
            .collect(),
    };

    let include = repo_root().join("include");
    if include.join("hgcd").join("hgcd.h").is_file() {
        println!("cargo:include={}", include.display());
    }

    let found = from_env(want)
        .or_else(|| from_pkg_config(want))
        .or_else(|| from_repo(want));
    let mut libs: Vec<String> = Vec::new();
    match found {
        Some(f) => {
            println!("cargo:rerun-if-changed={}", f.file.display());
            println!("cargo:rustc-link-search=native={}", f.dir.display());
            for d in &f.extra_dirs {
                if d != &f.dir {
                    println!("cargo:rustc-link-search=native={}", d.display());
                }
            }
            // The reference scenes' support library (the `hgcd::scene`
            // module), beside libhgcd or in the repository build; it calls
            // libhgcd, so it comes first.
            let scene_dir = [f.dir.clone(), repo_build_dir()]
                .into_iter()
                .find(|d| d.join("libhgcd_scene.a").is_file());
            match scene_dir {
                Some(d) => {
                    if d != f.dir {
                        println!("cargo:rustc-link-search=native={}", d.display());
                    }
                    println!("cargo:rerun-if-changed={}", d.join("libhgcd_scene.a").display());
                    println!("cargo:rustc-link-lib=static=hgcd_scene");
                }
                None => println!(
                    "cargo:warning=libhgcd_scene.a not found beside libhgcd nor in build-make/: \
                     the hgcd_scene_* functions will not link (run `make scene`)"
                ),
            }
            match f.kind {
                Kind::Static => println!("cargo:rustc-link-lib=static=hgcd"),
                Kind::Dylib => println!("cargo:rustc-link-lib=dylib=hgcd"),
            }
            if f.kind == Kind::Static {
                // Libraries the static archive needs (libccd), written by the Makefile.
                let deps = f.dir.join("libhgcd-static-deps.txt");
                println!("cargo:rerun-if-changed={}", deps.display());
                if let Ok(text) = std::fs::read_to_string(&deps) {
                    libs.extend(text.split_whitespace().map(str::to_string));
                }
            }
            println!("cargo:lib_dir={}", f.dir.display());
            println!("cargo:link_source={}", f.source);
            libs.extend(f.extra_libs);
        }
        None => {
            // Missing file: cargo reruns this script on every build until it
            // appears, so a later `make lib` is picked up.
            let repo_lib = repo_build_dir().join(lib_name(Kind::Static));
            println!("cargo:rerun-if-changed={}", repo_lib.display());
            println!(
                "cargo:warning=libhgcd not found (HGCD_LIB_DIR unset, pkg-config has no hgcd, no {}): \
                 linking `-lhgcd` from the default search path. Run `make lib` at the repository root \
                 or set HGCD_LIB_DIR.",
                repo_lib.display()
            );
            println!("cargo:rustc-link-lib=hgcd");
            println!("cargo:link_source=none");
        }
    }
    for l in runtime {
        if !libs.contains(&l) {
            libs.push(l);
        }
    }
    for l in libs {
        println!("cargo:rustc-link-lib=dylib={l}");
    }
}
