"""cffi build script of the hgcd Python package: the extension module hgcd._hgcd.

API mode: the declarations below are compiled against the real public headers
(hgcd/hgcd.h, hgcd/hgcd_scene.h), so a declaration that no longer matches the
library (a changed signature, a renamed field, a removed constant) fails the
build instead of corrupting memory at run time. Structs are declared with
`...;`: the compiler supplies their layout, so fields appended to the header
(allowed by its ABI rules) need no change here.

The C library is linked statically (libhgcd.a and libhgcd_scene.a, with their
OpenMP and C++ runtimes), found as the first of:
  1. HGCD_LIB_DIR (a directory holding both archives) and HGCD_INCLUDE_DIR
     (the directories, separated by ':', holding hgcd/hgcd.h and
     hgcd/hgcd_scene.h; default: the include directory beside HGCD_LIB_DIR);
  2. the repository this file sits in: `make lib scene` is run at its root
     (incremental) and build-make/ is used;
  3. pkg-config --static hgcd (an installed hgcd, with `make install-scene`).
"""
import os
import re
import shlex
import subprocess

from cffi import FFI

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.normpath(os.path.join(HERE, "..", ".."))

CDEF = r"""
typedef int32_t hgcd_status;
enum hgcd_status_code {
    HGCD_OK, HGCD_ERROR_NULL_ARGUMENT, HGCD_ERROR_INVALID_ARGUMENT,
    HGCD_ERROR_BAD_DESCRIPTOR, HGCD_ERROR_STALE_ID, HGCD_ERROR_INVALID_MESH,
    HGCD_ERROR_MESH_IN_USE, HGCD_ERROR_OUT_OF_MEMORY, HGCD_ERROR_CAPACITY,
    HGCD_ERROR_NOT_SUPPORTED, HGCD_ERROR_INTERNAL, ...
};
enum hgcd_narrow_phase {
    HGCD_NARROW_WORLD, HGCD_NARROW_EXACT, HGCD_NARROW_GJK, HGCD_NARROW_MPR, ...
};
enum hgcd_thread_policy { HGCD_THREADS_ADAPTIVE, HGCD_THREADS_FIXED, ... };
enum hgcd_contact_kind {
    HGCD_CONTACT_SURFACE, HGCD_CONTACT_A_CONTAINS_B, HGCD_CONTACT_B_CONTAINS_A,
    HGCD_CONTACT_PENETRATION, ...
};

const char *hgcd_status_string(hgcd_status status);
uint32_t hgcd_version(void);
const char *hgcd_version_string(void);
int32_t hgcd_feature_libccd(void);

typedef struct hgcd_world hgcd_world;
typedef struct hgcd_mesh { uint32_t index; uint32_t generation; } hgcd_mesh;
typedef struct hgcd_body { uint32_t index; uint32_t generation; } hgcd_body;
typedef struct hgcd_pair { hgcd_body a; hgcd_body b; } hgcd_pair;

typedef struct hgcd_world_desc {
    uint32_t thread_count;
    uint32_t reflect_at_bounds;
    double time_step;
    double bounds_min[3];
    double bounds_max[3];
    double min_cell_size;
    double max_cell_size;
    int32_t narrow_phase;
    uint32_t contacts;
    int32_t thread_policy;
    uint32_t kinematic_pairs;
    double contact_margin;
    ...;
} hgcd_world_desc;
hgcd_world_desc hgcd_world_desc_default(void);
hgcd_status hgcd_world_create(const hgcd_world_desc *desc, hgcd_world **out_world);
void hgcd_world_destroy(hgcd_world *world);
const char *hgcd_world_last_error(const hgcd_world *world);
uint32_t hgcd_world_body_count(const hgcd_world *world);
uint32_t hgcd_world_mesh_count(const hgcd_world *world);
hgcd_status hgcd_world_set_thread_count(hgcd_world *world, uint32_t thread_count);
hgcd_status hgcd_world_set_narrow_phase(hgcd_world *world, int32_t narrow_phase);
hgcd_status hgcd_world_set_contacts(hgcd_world *world, uint32_t enable);
hgcd_status hgcd_world_set_thread_policy(hgcd_world *world, int32_t thread_policy);
hgcd_status hgcd_world_set_contact_margin(hgcd_world *world, double contact_margin);
hgcd_status hgcd_world_get_contact_margin(const hgcd_world *world, double *out_margin);
hgcd_status hgcd_world_step(hgcd_world *world);
hgcd_status hgcd_world_detect(hgcd_world *world);
hgcd_status hgcd_world_pairs(const hgcd_world *world, const hgcd_pair **out_pairs,
                             size_t *out_count);

typedef struct hgcd_contact {
    hgcd_pair pair;
    int32_t kind;
    uint32_t triangle_a;
    uint32_t triangle_b;
    double depth;
    double normal[3];
    double point[3];
    ...;
} hgcd_contact;
hgcd_status hgcd_world_contacts(const hgcd_world *world, const hgcd_contact **out_contacts,
                                size_t *out_count);

typedef struct hgcd_stats {
    uint32_t struct_size;
    uint32_t level_count;
    uint32_t oversize_count;
    uint32_t thread_count;
    uint64_t moved_bodies;
    uint64_t candidate_pairs;
    uint64_t narrow_tests;
    uint64_t triangle_tests;
    uint64_t colliding_pairs;
    uint64_t containment_pairs;
    double motion_seconds;
    double update_seconds;
    double broad_seconds;
    double narrow_seconds;
    double total_seconds;
    uint64_t libccd_tests;
    uint64_t libccd_fallback_tests;
    uint64_t unmoved_pairs;
    uint64_t searched_bodies;
    uint64_t filtered_pairs;
    double events_seconds;
    ...;
} hgcd_stats;
hgcd_status hgcd_world_stats(const hgcd_world *world, hgcd_stats *out_stats);

typedef struct hgcd_pair_event {
    hgcd_pair pair;
    uint64_t user_data_a;
    uint64_t user_data_b;
    ...;
} hgcd_pair_event;
hgcd_status hgcd_world_events(const hgcd_world *world, const hgcd_pair_event **out_began,
                              size_t *out_began_count, const hgcd_pair_event **out_ended,
                              size_t *out_ended_count);

enum hgcd_body_type { HGCD_BODY_DYNAMIC, HGCD_BODY_KINEMATIC, HGCD_BODY_STATIC, ... };
typedef struct hgcd_filter {
    uint64_t category_bits;
    uint64_t mask_bits;
    int32_t group_index;
    uint32_t reserved;
    ...;
} hgcd_filter;
hgcd_filter hgcd_filter_default(void);
hgcd_status hgcd_world_pair_excluded(const hgcd_world *world, hgcd_body a, hgcd_body b,
                                     uint32_t *out_excluded);

typedef struct hgcd_mesh_desc {
    const double *vertices;
    const uint32_t *triangles;
    uint32_t vertex_count;
    uint32_t triangle_count;
    ...;
} hgcd_mesh_desc;
hgcd_mesh_desc hgcd_mesh_desc_default(void);
hgcd_status hgcd_mesh_create(hgcd_world *world, const hgcd_mesh_desc *desc, hgcd_mesh *out_mesh);
hgcd_status hgcd_mesh_destroy(hgcd_world *world, hgcd_mesh mesh);

typedef struct hgcd_mesh_info {
    uint32_t struct_size;
    uint32_t vertex_count;
    uint32_t triangle_count;
    uint32_t closed;
    uint32_t convex;
    uint32_t component_count;
    uint32_t degenerate_triangle_count;
    uint32_t body_count;
    double center[3];
    double radius;
    int32_t narrow_phase_setting;
    int32_t narrow_phase;
    double reach;
    ...;
} hgcd_mesh_info;
hgcd_status hgcd_mesh_get_info(const hgcd_world *world, hgcd_mesh mesh, hgcd_mesh_info *out_info);
hgcd_status hgcd_mesh_set_narrow_phase(hgcd_world *world, hgcd_mesh mesh, int32_t narrow_phase);
hgcd_status hgcd_mesh_validate(const hgcd_world *world, hgcd_mesh mesh);

hgcd_status hgcd_body_validate(const hgcd_world *world, hgcd_body body);
hgcd_status hgcd_world_set_poses(hgcd_world *world, const hgcd_body *bodies, size_t count,
                                 const double *positions, size_t position_stride,
                                 const double *orientations, size_t orientation_stride);
hgcd_status hgcd_world_set_velocities(hgcd_world *world, const hgcd_body *bodies, size_t count,
                                      const double *velocities, size_t velocity_stride);
hgcd_status hgcd_world_get_poses(const hgcd_world *world, const hgcd_body *bodies, size_t count,
                                 double *positions, size_t position_stride,
                                 double *orientations, size_t orientation_stride);

typedef struct hgcd_ray {
    double origin[3];
    double direction[3];
    double max_distance;
} hgcd_ray;
typedef struct hgcd_ray_hit {
    hgcd_body body;
    uint32_t triangle;
    uint32_t inside;
    double distance;
} hgcd_ray_hit;
enum hgcd_ray_mode { HGCD_RAY_CLOSEST, HGCD_RAY_ANY, ... };
typedef struct hgcd_query_results {
    const size_t *offsets;
    const hgcd_body *bodies;
    size_t query_count;
    size_t body_count;
} hgcd_query_results;
typedef struct hgcd_mesh_pose {
    double position[3];
    double orientation[4];
    double scale;
} hgcd_mesh_pose;
hgcd_status hgcd_world_cast_rays(hgcd_world *world, const hgcd_ray *rays, size_t count,
                                 size_t ray_stride, int32_t mode, const hgcd_filter *filter,
                                 hgcd_ray_hit *out_hits);
hgcd_status hgcd_world_query_box(hgcd_world *world, const double *boxes, size_t count,
                                 size_t box_stride, const hgcd_filter *filter,
                                 hgcd_query_results *out);
hgcd_status hgcd_world_query_point(hgcd_world *world, const double *points, size_t count,
                                   size_t point_stride, const hgcd_filter *filter,
                                   hgcd_query_results *out);
hgcd_status hgcd_world_query_mesh(hgcd_world *world, hgcd_mesh mesh, const hgcd_mesh_pose *poses,
                                  size_t count, size_t pose_stride, const hgcd_filter *filter,
                                  hgcd_query_results *out);

typedef struct hgcd_scene_tetra_desc {
    uint64_t n;
    uint64_t seed;
    double side;
    double rmin;
    double rmax;
    double vmax;
    ...;
} hgcd_scene_tetra_desc;
hgcd_scene_tetra_desc hgcd_scene_tetra_desc_default(void);
int32_t hgcd_scene_tetra_generate(const hgcd_scene_tetra_desc *desc, double *centers,
                                  double *radii, double *scales, double *orientations,
                                  double *velocities);
int32_t hgcd_scene_tetra_populate(hgcd_world *world, const hgcd_scene_tetra_desc *desc,
                                  hgcd_mesh *mesh_out);
void hgcd_scene_tetra_unit_mesh(double *vertices, uint32_t *triangles);
void hgcd_scene_tetra_move(uint64_t n, double side, double *centers, double *velocities);

/* The binding's own loops (hgcd_py.h): one C call for many bodies. */
typedef struct hgcd_py_body_columns {
    const double *positions;
    const double *orientations;
    const double *velocities;
    const double *scales;
    const uint64_t *user_data;
    const int32_t *types;
    const uint8_t *enabled;
    const hgcd_filter *filters;
    const double *margins;
} hgcd_py_body_columns;
hgcd_status hgcd_py_create_bodies(hgcd_world *world, const hgcd_mesh *meshes, size_t mesh_count,
                                  size_t count, const hgcd_py_body_columns *columns,
                                  hgcd_body *out_bodies, size_t *out_failed);
hgcd_status hgcd_py_set_flags(hgcd_world *world, const hgcd_body *bodies, size_t count,
                              const int32_t *types, const uint8_t *enabled,
                              const hgcd_filter *filters, size_t *out_failed);
hgcd_status hgcd_py_get_flags(const hgcd_world *world, const hgcd_body *bodies, size_t count,
                              int32_t *types, uint8_t *enabled, hgcd_filter *filters,
                              size_t *out_failed);
hgcd_status hgcd_py_set_excluded(hgcd_world *world, const hgcd_pair *pairs, size_t count,
                                 uint32_t exclude, uint8_t *scratch, size_t *out_failed);
hgcd_status hgcd_py_pairs_excluded(const hgcd_world *world, const hgcd_pair *pairs, size_t count,
                                   uint8_t *out_excluded, size_t *out_failed);
hgcd_status hgcd_py_destroy_bodies(hgcd_world *world, const hgcd_body *bodies, size_t count,
                                   size_t *out_failed);
hgcd_status hgcd_py_get_bodies(const hgcd_world *world, const hgcd_body *bodies, size_t count,
                               double *velocities, hgcd_mesh *meshes, uint64_t *user_data,
                               size_t *out_failed);
size_t hgcd_py_validate_bodies(const hgcd_world *world, const hgcd_body *bodies, size_t count,
                               uint8_t *out_live);
hgcd_status hgcd_py_set_margins(hgcd_world *world, const hgcd_body *bodies, size_t count,
                                const double *margins, double *scratch, size_t *out_failed);
hgcd_status hgcd_py_get_margins(const hgcd_world *world, const hgcd_body *bodies, size_t count,
                                double *margins, size_t *out_failed);
int hgcd_py_gil_held(void);
"""


def _run(cmd, **kw):
    return subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True, **kw).stdout


def _repo_build():
    """The repository's build-make/, brought up to date, or None outside a repository."""
    if not (os.path.isfile(os.path.join(REPO, "Makefile"))
            and os.path.isfile(os.path.join(REPO, "include", "hgcd", "hgcd.h"))):
        return None
    subprocess.run(["make", "-s", "-C", REPO, "lib", "scene"], check=True)
    build = os.path.join(REPO, "build-make")
    return build, [os.path.join(REPO, "include"), os.path.join(REPO, "scene")]


def _static_link(lib_dir):
    """Archives and runtime libraries for a static link against lib_dir."""
    lib_dir = os.path.abspath(lib_dir)
    objects = [os.path.join(lib_dir, "libhgcd_scene.a"), os.path.join(lib_dir, "libhgcd.a")]
    for path in objects:
        if not os.path.isfile(path):
            raise SystemExit(f"hgcd: {path} is missing (run `make lib scene` at the repository root, "
                             "or `make install install-scene`, or set HGCD_LIB_DIR)")
    libraries = ["gomp", "stdc++", "m"]
    deps = os.path.join(lib_dir, "libhgcd-static-deps.txt")
    if os.path.isfile(deps):
        libraries = open(deps).read().split() + libraries
    elif os.path.exists("/usr/include/ccd/ccd.h"):
        libraries = ["ccd"] + libraries
    return objects, libraries, []


def locate():
    """(include_dirs, extra_objects, libraries, library_dirs) of the C library."""
    lib_dir = os.environ.get("HGCD_LIB_DIR")
    if lib_dir:
        inc = os.environ.get("HGCD_INCLUDE_DIR", os.path.join(lib_dir, "..", "include"))
        objects, libraries, dirs = _static_link(lib_dir)
        return [os.path.abspath(d) for d in inc.split(os.pathsep)], objects, libraries, dirs
    repo = _repo_build()
    if repo:
        objects, libraries, dirs = _static_link(repo[0])
        return repo[1], objects, libraries, dirs
    try:
        cflags = shlex.split(_run(["pkg-config", "--cflags", "hgcd"]))
        libs = shlex.split(_run(["pkg-config", "--static", "--libs", "hgcd"]))
        libdir = _run(["pkg-config", "--variable=libdir", "hgcd"]).strip()
    except (OSError, subprocess.CalledProcessError):
        raise SystemExit("hgcd: no C library found: set HGCD_LIB_DIR, build the repository "
                         "(`make lib scene`), or install hgcd with pkg-config support")
    inc = [f[2:] for f in cflags if f.startswith("-I")]
    dirs = [f[2:] for f in libs if f.startswith("-L")] + [libdir]
    libraries = [f[2:] for f in libs if f.startswith("-l") and f != "-lhgcd"]
    objects = [os.path.join(libdir, "libhgcd_scene.a"), os.path.join(libdir, "libhgcd.a")]
    return inc, objects, libraries, dirs


def signature_checks(cdef):
    """C that takes each declared function's address as a pointer of its
    declared type: with -Werror=incompatible-pointer-types, a return or
    parameter type that differs from the header's fails the compile (cffi's
    own call wrappers would convert a differing integer type silently)."""
    proto = re.compile(r"^(?!typedef)([A-Za-z_][\w \*]*?)\s*\b(hgcd_\w+)\(([^)]*)\);", re.M)
    checks = []
    for ret, name, params in proto.findall(cdef):
        params = " ".join(params.split())
        checks.append(f"static {ret} (*const hgcd_py_check_{name})({params}) = {name};")
    return "\n".join(checks) + "\n"


def make_ffi(link=True):
    """The FFI of hgcd._hgcd; link=False skips finding the C library (enough
    to emit the C source, as a test does)."""
    ffi = FFI()
    ffi.cdef(CDEF)
    include_dirs, objects, libraries, library_dirs = locate() if link else ([], [], [], [])
    with open(os.path.join(HERE, "hgcd_py.h")) as f:
        helpers = f.read()
    ffi.set_source(
        "hgcd._hgcd",
        "#include <hgcd/hgcd.h>\n#include <hgcd/hgcd_scene.h>\n" + helpers + signature_checks(CDEF),
        include_dirs=include_dirs,
        extra_objects=objects,
        libraries=libraries,
        library_dirs=library_dirs,
        # A declaration above that disagrees with the header is an error, not
        # a warning; the archives' symbols stay inside the extension.
        extra_compile_args=["-std=c99", "-Wno-unused-variable", "-Werror=incompatible-pointer-types",
                            "-Werror=int-conversion", "-Werror=implicit-function-declaration"],
        extra_link_args=["-fopenmp", "-Wl,--exclude-libs,ALL"],
        # Not the limited API: the GIL probe (hgcd_py.h) needs PyGILState_Check.
        define_macros=[("_CFFI_NO_LIMITED_API", None)],
        py_limited_api=False,
    )
    return ffi


if __name__ == "__main__":
    # `python3 hgcd_build.py [PACKAGE_DIR]` builds _hgcd*.so into PACKAGE_DIR
    # (default: hgcd/ beside this file, the build tree's package).
    import glob
    import shutil
    import sys

    dest = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "hgcd")
    built = make_ffi().compile(tmpdir=os.path.join(HERE, "build-cffi"))
    for old in glob.glob(os.path.join(dest, "_hgcd.*.so")):
        os.remove(old)
    shutil.copy2(built, dest)
