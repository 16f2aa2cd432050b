// Nothing a file holds is dropped silently: for each format, an element, property or primitive
// kind the reader does not turn into triangles is read, refused with one line naming it, or (data
// that is no surface: edges, points, lines, curves, per-vertex extras) skipped with one warning
// line naming it. Also PLY header lines that are no keyword (Blender's "Created by ...").
#include "engine/error.h"
#include "engine/mesh_loader.h"

#include <doctest/doctest.h>

#include <string>

using namespace arbor;

namespace {

struct Loaded {
    std::size_t triangles = 0;
    std::string error;     ///< the InputError's message, or empty
    std::string warnings;  ///< all warning lines, each ended by '\n'
};

Loaded load(const std::string& bytes, const std::string& name) {
    Loaded out;
    engine::Warnings w;
    try {
        out.triangles = engine::load_mesh_bytes(bytes, name, "", w, false).triangle_count();
    } catch (const engine::InputError& e) {
        out.error = e.what();
    }
    for (const std::string& line : w.lines) out.warnings += line + "\n";
    return out;
}

const std::string ply_head =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n";
const std::string ply_verts = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
const std::string ply_face = "element face 1\nproperty list uchar int vertex_indices\n";

}  // namespace

TEST_CASE("loader unread: PLY edges, materials and extra properties are read past with one warning naming them") {
    const Loaded l = load(ply_head + "property float confidence\n" + ply_face + "property uchar flags\n" +
                              "element edge 2\nproperty int vertex1\nproperty int vertex2\n"
                              "element material 1\nproperty uchar ambient_red\nend_header\n"
                              "0 0 0 0.5\n1 0 0 0.5\n1 1 0 0.5\n0 1 0 0.5\n4 0 1 2 3 7\n0 1\n1 2\n9\n",
                          "extra.ply");
    CHECK(l.error.empty());
    CHECK(l.triangles == 2);
    const std::string want =
        "extra.ply: PLY data not read (no surfaces): vertex properties confidence; face properties flags; "
        "element 'edge' (2 records); element 'material' (1 record)\n";
    CHECK(l.warnings == want);
}

TEST_CASE("loader unread: PLY face-like data arbor does not read is refused, naming the element") {
    const Loaded grid =
        load(ply_head + ply_face + "element range_grid 1\nproperty list uchar int vertex_indices\nend_header\n" +
                 ply_verts + "3 0 1 2\n1 3\n",
             "grid.ply");
    CHECK(grid.error ==
          "grid.ply: element 'range_grid' holds vertex_indices lists that arbor does not read as surfaces (it reads "
          "'face' and 'tristrips')");
    const Loaded nolist =
        load(ply_head + "element face 1\nproperty list uchar int vertex_ids\nend_header\n" + ply_verts + "3 0 1 2\n",
             "nolist.ply");
    CHECK(nolist.error ==
          "nolist.ply: element 'face' has no list property vertex_indices (nothing to read its surfaces from)");
    const Loaded noz = load(
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n", "noz.ply");
    CHECK(noz.error == "noz.ply: element 'vertex' has no property z");
}

TEST_CASE("loader unread: a PLY header line that is no keyword (Blender 2.4x) is a warning naming the line") {
    const std::string blender =
        "ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: 'x.blend'\n" +
        ply_head.substr(std::string("ply\nformat ascii 1.0\n").size()) + ply_face + "end_header\n" + ply_verts +
        "4 0 1 2 3\n";
    const Loaded l = load(blender, "blender.ply");
    CHECK(l.error.empty());
    CHECK(l.triangles == 2);
    CHECK(l.warnings ==
          "blender.ply:3: not a PLY header keyword, line skipped: Created by Blender3D 247 - www.blender.org, "
          "source file: 'x.blend'\n");
    // Malformed keyword lines are still errors.
    CHECK(load("ply\nformat ascii 1.0\nelement vertex\nend_header\n", "e.ply").error ==
          "e.ply:3: PLY element line must be 'element <name> <count>'");
}

TEST_CASE("loader unread: OBJ points, lines and curves are warned about by name, free-form surfaces refused") {
    const std::string quad = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    const Loaded l = load(quad + "l 1 2 3\np 4\nl 2 3\ncurv 0 1 1 2\n", "mixed.obj");
    CHECK(l.error.empty());
    CHECK(l.triangles == 2);
    CHECK(l.warnings ==
          "mixed.obj: not read (no surfaces): 1 point (p, first on line 7), 2 lines (l, first on line 6), "
          "1 curve (curv, first on line 9)\n");
    const Loaded s = load(quad + "cstype bspline\ndeg 1 1\nsurf 0 1 0 1 1 2 3 4\n", "surf.obj");
    CHECK(s.error == "surf.obj:8: free-form surface (surf) not read: arbor reads polygon faces (f) only");
}

TEST_CASE("loader unread: STL, every solid of an ASCII file is read") {
    auto solid = [](const std::string& name, float z) {
        const std::string zs = std::to_string(z);
        return "solid " + name + "\nfacet normal 0 0 1\nouter loop\nvertex 0 0 " + zs + "\nvertex 1 0 " + zs +
               "\nvertex 0 1 " + zs + "\nendloop\nendfacet\nendsolid " + name + "\n";
    };
    const Loaded l = load(solid("a", 0) + solid("b", 1) + solid("c", 2), "three.stl");
    CHECK(l.error.empty());
    CHECK(l.triangles == 3);
}

TEST_CASE("loader unread: an OFF file is refused by name, not read as OBJ text") {
    const Loaded l = load("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "tri.off");
    CHECK(l.error == "tri.off:1: an OFF file ('OFF'), a format arbor does not read (OBJ, PLY, STL, glTF)");
}
