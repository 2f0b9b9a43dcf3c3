// load_meshes: loads a triangle mesh from a Wavefront OBJ file (through
// Debian's tinyobjloader, double-precision build), scatters copies of it like
// the bodies of scene `tetra` and reports the colliding pairs.
//
//   load_meshes FILE.obj [--n N] [--side L] [--seed S] [--threads K]
//   load_meshes --write-blob FILE.obj [--nu U --nv V]
//
// The first form: every shape of the file is merged into one hgcd mesh
// (polygons are triangulated by the loader; vertices are used as the loader
// parsed them), and N bodies are placed with the centres, orientations and
// radii r of hgcd_scene_tetra_generate (cube side L), each scaled so that the
// mesh's bounding sphere gets radius r. Prints what hgcd worked out about the
// mesh, then detects once and prints the pair count, the containment count,
// the time and the first pairs.
// The second form writes the blob of scene `meshes` (bench/SCENES-meshes.md)
// as an OBJ file, for a file to try the first form on.
//
// The core library knows no file formats: loading is all here.
#ifndef TINYOBJLOADER_USE_DOUBLE
#define TINYOBJLOADER_USE_DOUBLE
#endif
#include <tiny_obj_loader.h>

#include <hgcd/hgcd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "../bench/scene_meshes.h"

namespace {

int fail(hgcd_status s, hgcd_world *w, const char *what) {
    std::fprintf(stderr, "%s failed: %s (%s)\n", what, hgcd_status_string(s), w ? hgcd_world_last_error(w) : "");
    return 1;
}

int write_blob(const char *path, uint32_t nu, uint32_t nv) {
    std::vector<double> v(3 * size_t(hgcd_blob_vertex_count(nu, nv)));
    std::vector<uint32_t> t(3 * size_t(hgcd_blob_triangle_count(nu, nv)));
    hgcd_blob_mesh(nu, nv, v.data(), t.data());
    FILE *f = std::fopen(path, "w");
    if (!f) {
        std::perror(path);
        return 1;
    }
    std::fprintf(f, "# blob of scene meshes, nu = %u, nv = %u\n", nu, nv);
    for (size_t i = 0; i < v.size(); i += 3) std::fprintf(f, "v %.17g %.17g %.17g\n", v[i], v[i + 1], v[i + 2]);
    for (size_t i = 0; i < t.size(); i += 3) std::fprintf(f, "f %u %u %u\n", t[i] + 1, t[i + 1] + 1, t[i + 2] + 1);
    const bool ok = std::fclose(f) == 0;
    std::printf("wrote %s: %zu vertices, %zu triangles\n", path, v.size() / 3, t.size() / 3);
    return ok ? 0 : 1;
}

// Reads every shape of an OBJ file into one vertex and one index array.
bool load_obj(const char *path, std::vector<double> &verts, std::vector<uint32_t> &tris) {
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config)) {
        std::fprintf(stderr, "%s: %s\n", path, reader.Error().c_str());
        return false;
    }
    if (!reader.Warning().empty()) std::fprintf(stderr, "%s: %s", path, reader.Warning().c_str());
    const tinyobj::attrib_t &attrib = reader.GetAttrib();
    verts.assign(attrib.vertices.begin(), attrib.vertices.end());
    for (const tinyobj::shape_t &shape : reader.GetShapes()) {
        size_t offset = 0;
        for (const unsigned char fv : shape.mesh.num_face_vertices) {
            if (fv == 3) {
                for (int k = 0; k < 3; ++k)
                    tris.push_back(uint32_t(shape.mesh.indices[offset + k].vertex_index));
            }
            offset += fv;
        }
    }
    return true;
}

}  // namespace

int main(int argc, char **argv) {
    const char *path = nullptr, *blob_path = nullptr;
    uint64_t n = 1000, seed = 1;
    double side = 30;
    uint32_t threads = 0, nu = HGCD_BLOB_NU, nv = HGCD_BLOB_NV;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool has = i + 1 < argc;
        if (a == "--n" && has) n = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "--side" && has) side = std::atof(argv[++i]);
        else if (a == "--seed" && has) seed = std::strtoull(argv[++i], nullptr, 10);
        else if (a == "--threads" && has) threads = uint32_t(std::atoi(argv[++i]));
        else if (a == "--write-blob" && has) blob_path = argv[++i];
        else if (a == "--nu" && has) nu = uint32_t(std::atoi(argv[++i]));
        else if (a == "--nv" && has) nv = uint32_t(std::atoi(argv[++i]));
        else if (a[0] != '-' && !path) path = argv[i];
        else path = nullptr, i = argc;
    }
    if (blob_path) return nu >= 3 && nv >= 2 ? write_blob(blob_path, nu, nv) : 2;
    if (!path) {
        std::fprintf(stderr,
                     "usage: %s FILE.obj [--n N] [--side L] [--seed S] [--threads K]\n"
                     "       %s --write-blob FILE.obj [--nu U --nv V]\n",
                     argv[0], argv[0]);
        return 2;
    }
    std::vector<double> verts;
    std::vector<uint32_t> tris;
    if (!load_obj(path, verts, tris)) return 1;

    hgcd_world_desc wd = hgcd_world_desc_default();
    wd.thread_count = threads;
    hgcd_world *w;
    hgcd_status s = hgcd_world_create(&wd, &w);
    if (s != HGCD_OK) return fail(s, nullptr, "world_create");
    hgcd_mesh_desc md = hgcd_mesh_desc_default();
    md.vertices = verts.data();
    md.vertex_count = uint32_t(verts.size() / 3);
    md.triangles = tris.data();
    md.triangle_count = uint32_t(tris.size() / 3);
    hgcd_mesh mesh;
    if ((s = hgcd_mesh_create(w, &md, &mesh)) != HGCD_OK) return fail(s, w, "mesh_create");
    hgcd_mesh_info info;
    info.struct_size = sizeof info;
    hgcd_mesh_get_info(w, mesh, &info);
    std::printf("%s: %u vertices, %u triangles, closed %u, convex %u, %u component(s), "
                "%u zero-area, bounding radius %.6g\n",
                path, info.vertex_count, info.triangle_count, info.closed, info.convex, info.component_count,
                info.degenerate_triangle_count, info.radius);

    hgcd_scene_tetra_desc sd = hgcd_scene_tetra_desc_default();
    sd.n = n;
    sd.seed = seed;
    sd.side = side;
    std::vector<double> centers(3 * n), radii(n), quats(4 * n);
    if (hgcd_scene_tetra_generate(&sd, centers.data(), radii.data(), nullptr, quats.data(), nullptr) != 0) {
        std::fprintf(stderr, "bad scene parameters\n");
        return 2;
    }
    for (uint64_t i = 0; i < n; ++i) {
        hgcd_body_desc bd = hgcd_body_desc_default();
        bd.mesh = mesh;
        std::memcpy(bd.position, &centers[3 * i], sizeof bd.position);
        std::memcpy(bd.orientation, &quats[4 * i], sizeof bd.orientation);
        bd.scale = radii[i] / info.radius;
        hgcd_body b;
        if ((s = hgcd_body_create(w, &bd, &b)) != HGCD_OK) return fail(s, w, "body_create");
    }
    const auto t0 = std::chrono::steady_clock::now();
    if ((s = hgcd_world_detect(w)) != HGCD_OK) return fail(s, w, "world_detect");
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    hgcd_stats st;
    st.struct_size = sizeof st;
    hgcd_world_stats(w, &st);
    const hgcd_pair *pairs;
    size_t count;
    hgcd_world_pairs(w, &pairs, &count);
    std::printf("%llu bodies in a cube of side %g: %zu colliding pairs (%llu by containment) of %llu candidates, "
                "%.2f ms on %u thread(s)\n",
                (unsigned long long)n, side, count, (unsigned long long)st.containment_pairs,
                (unsigned long long)st.candidate_pairs, ms, st.thread_count);
    for (size_t k = 0; k < count && k < 5; ++k) std::printf("  bodies %u and %u\n", pairs[k].a.index, pairs[k].b.index);
    hgcd_world_destroy(w);
    return 0;
}
