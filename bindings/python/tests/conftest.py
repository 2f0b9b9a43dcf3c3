"""Fixtures of the hgcd Python tests: the C reference program (ref_pairs.c),
built against the same C library as the package (HGCD_LIB_DIR and
HGCD_INCLUDE_DIR, else the repository's build-make/ after `make lib scene`)."""
import os
import subprocess

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", "..", ".."))


def _library():
    lib_dir = os.environ.get("HGCD_LIB_DIR", os.path.join(REPO, "build-make"))
    if "HGCD_INCLUDE_DIR" in os.environ:
        includes = os.environ["HGCD_INCLUDE_DIR"].split(os.pathsep)
    elif "HGCD_LIB_DIR" in os.environ:
        includes = [os.path.join(lib_dir, "..", "include")]
    else:
        includes = [os.path.join(REPO, "include"), os.path.join(REPO, "scene")]
    archives = [os.path.join(lib_dir, "libhgcd_scene.a"), os.path.join(lib_dir, "libhgcd.a")]
    missing = [a for a in archives if not os.path.isfile(a)]
    if missing:
        pytest.fail(f"{missing[0]} is missing: run `make lib scene` at the repository root "
                    "or set HGCD_LIB_DIR")
    deps_file = os.path.join(lib_dir, "libhgcd-static-deps.txt")
    deps = open(deps_file).read().split() if os.path.isfile(deps_file) else []
    return includes, archives, ["-l" + d for d in deps]


def _build(tmp_path_factory, name):
    """The C program tests/<name>.c linked against the library: its path."""
    includes, archives, deps = _library()
    exe = str(tmp_path_factory.mktemp("ref") / name)
    cc = os.environ.get("CC", "cc")
    subprocess.run([cc, "-std=c99", "-O2", *("-I" + i for i in includes), os.path.join(HERE, name + ".c"),
                    "-o", exe, *archives, *deps, "-fopenmp", "-lstdc++", "-lm"], check=True)
    return exe


@pytest.fixture(scope="session")
def ref_queries(tmp_path_factory):
    """run(n, seed, side, threads, count) -> the path of ref_queries.c's output."""
    exe = _build(tmp_path_factory, "ref_queries")
    out_dir = tmp_path_factory.mktemp("ref_queries_out")

    def run(*args):
        out = str(out_dir / "queries.bin")
        subprocess.run([exe, *map(str, args), out], check=True)
        return out

    return run


@pytest.fixture(scope="session")
def ref_pairs(tmp_path_factory):
    """run(*args) -> list of (N, 2) uint32 pair arrays, one per detect."""
    exe = _build(tmp_path_factory, "ref_pairs")
    out_dir = tmp_path_factory.mktemp("ref_out")

    def run(*args):
        out = str(out_dir / "pairs.bin")
        subprocess.run([exe, *map(str, args), out], check=True)
        raw = np.fromfile(out, dtype=np.uint8)
        result, at = [], 0
        while at < len(raw):
            n = int(raw[at:at + 8].view(np.uint64)[0])
            at += 8
            result.append(raw[at:at + 8 * n].view(np.uint32).reshape(n, 2))
            at += 8 * n
        return result

    return run
