// load_meshes: loads a triangle mesh from a file, scatters copies of it like
// the bodies of scene `tetra` and reports the colliding pairs. Wavefront OBJ
// goes through Debian's tinyobjloader (double-precision build), STL, PLY and
// the other formats Assimp knows through Debian's libassimp; meson builds this
// example with whichever of the two it finds (HGCD_HAVE_TINYOBJ,
// HGCD_HAVE_ASSIMP; without tinyobjloader, OBJ goes through Assimp too).
//
//   load_meshes FILE [--n N] [--side L] [--seed S] [--threads K]
//   load_meshes --write-blob FILE.obj|FILE.stl [--nu U --nv V]
//
// The first form: every shape of the file is merged into one hgcd mesh
// (polygons are triangulated by the loader), vertices at exactly the same
// position are welded into one (STL stores each triangle's corners
// separately; without welding no edge would be shared and the mesh would be
// open), and N bodies are placed with the centres, orientations and radii r
// of hgcd_scene_tetra_generate (cube side L), each scaled so that the mesh's
// bounding sphere gets radius r. Prints what hgcd worked out about the mesh,
// then detects once and prints the pair count, the containment count, the
// time and the first pairs.
// The second form writes the blob of scene `meshes` (docs/scenes.md)
// as OBJ or ASCII STL (by the extension), for a file to try the first form
// on.
//
// The core library knows no file formats: loading is all here.
#ifdef HGCD_HAVE_TINYOBJ
#ifndef TINYOBJLOADER_USE_DOUBLE
#define TINYOBJLOADER_USE_DOUBLE
#endif
#include <tiny_obj_loader.h>
#endif
#ifdef HGCD_HAVE_ASSIMP
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#endif

#include <hgcd/hgcd.h>
#include <hgcd/hgcd_scene.h>

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "../scene/scene_meshes.h"

namespace {

int fail(hgcd_status s, hgcd_world *w, const char *what) {
    std::fprintf(stderr, "%s failed: %s (%s)\n", what, hgcd_status_string(s), w ? hgcd_world_last_error(w) : "");
    return 1;
}

bool ends_with(const std::string &s, const char *tail) {
    const size_t n = std::strlen(tail);
    if (s.size() < n) return false;
    for (size_t i = 0; i < n; ++i)
        if (std::tolower((unsigned char)s[s.size() - n + i]) != tail[i]) return false;
    return true;
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
    if (ends_with(path, ".stl")) {
        std::fprintf(f, "solid blob\n");
        for (size_t i = 0; i < t.size(); i += 3) {
            std::fprintf(f, "facet normal 0 0 0\nouter loop\n");
            for (int k = 0; k < 3; ++k) {
                const double *p = &v[3 * size_t(t[i + k])];
                std::fprintf(f, "vertex %.9g %.9g %.9g\n", p[0], p[1], p[2]);
            }
            std::fprintf(f, "endloop\nendfacet\n");
        }
        std::fprintf(f, "endsolid blob\n");
    } else {
        std::fprintf(f, "# blob of scene meshes, nu = %u, nv = %u\n", nu, nv);
        for (size_t i = 0; i < v.size(); i += 3) std::fprintf(f, "v %.17g %.17g %.17g\n", v[i], v[i + 1], v[i + 2]);
        for (size_t i = 0; i < t.size(); i += 3) std::fprintf(f, "f %u %u %u\n", t[i] + 1, t[i + 1] + 1, t[i + 2] + 1);
    }
    const bool ok = std::fclose(f) == 0;
    std::printf("wrote %s: %zu vertices, %zu triangles\n", path, v.size() / 3, t.size() / 3);
    return ok ? 0 : 1;
}

#ifdef HGCD_HAVE_TINYOBJ
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
#endif

#ifdef HGCD_HAVE_ASSIMP
// Reads every mesh of a file Assimp knows (STL, PLY, OBJ, ...), triangulated,
// into one vertex and one index array. Node transforms are not applied (STL
// and PLY have none).
bool load_assimp(const char *path, std::vector<double> &verts, std::vector<uint32_t> &tris) {
    Assimp::Importer importer;
    const aiScene *scene = importer.ReadFile(path, aiProcess_Triangulate);
    if (!scene) {
        std::fprintf(stderr, "%s: %s\n", path, importer.GetErrorString());
        return false;
    }
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh *mesh = scene->mMeshes[m];
        const uint32_t base = uint32_t(verts.size() / 3);
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            verts.push_back(mesh->mVertices[v].x);
            verts.push_back(mesh->mVertices[v].y);
            verts.push_back(mesh->mVertices[v].z);
        }
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            if (mesh->mFaces[f].mNumIndices != 3) continue;  // points and lines
            for (int k = 0; k < 3; ++k) tris.push_back(base + mesh->mFaces[f].mIndices[k]);
        }
    }
    return true;
}
#endif

// Merges vertices with exactly equal coordinates (only the triangles' ones
// are kept), so that triangles stored with their own corners share edges.
void weld(std::vector<double> &verts, std::vector<uint32_t> &tris) {
    std::map<std::tuple<double, double, double>, uint32_t> index;
    std::vector<double> out;
    std::vector<uint32_t> remap(verts.size() / 3, UINT32_MAX);
    for (uint32_t &t : tris) {
        if (remap[t] == UINT32_MAX) {
            const auto key = std::make_tuple(verts[3 * size_t(t)], verts[3 * size_t(t) + 1], verts[3 * size_t(t) + 2]);
            auto it = index.find(key);
            if (it == index.end()) {
                it = index.emplace(key, uint32_t(out.size() / 3)).first;
                out.insert(out.end(), &verts[3 * size_t(t)], &verts[3 * size_t(t)] + 3);
            }
            remap[t] = it->second;
        }
        t = remap[t];
    }
    verts.swap(out);
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
                     "usage: %s FILE [--n N] [--side L] [--seed S] [--threads K]\n"
                     "       %s --write-blob FILE.obj|FILE.stl [--nu U --nv V]\n",
                     argv[0], argv[0]);
        return 2;
    }
    std::vector<double> verts;
    std::vector<uint32_t> tris;
    bool loaded = false;
#ifdef HGCD_HAVE_TINYOBJ
    if (ends_with(path, ".obj")) {
        if (!load_obj(path, verts, tris)) return 1;
        loaded = true;
    }
#endif
#ifdef HGCD_HAVE_ASSIMP
    if (!loaded) {
        if (!load_assimp(path, verts, tris)) return 1;
        loaded = true;
    }
#endif
    if (!loaded) {
        std::fprintf(stderr, "%s: no loader for this format in this build\n", path);
        return 1;
    }
    const size_t file_vertices = verts.size() / 3;
    weld(verts, tris);
    std::printf("%s: %zu vertices in the file, %zu after welding equal positions\n", path, file_vertices,
                verts.size() / 3);

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
