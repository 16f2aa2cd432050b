#include "engine/formats/assimp_import.h"

#include "engine/error.h"
#include "engine/polygon.h"
#include "engine/texture.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace arbor::engine::formats {

namespace {

/// Serves the file's bytes under one name and reads every other name from disk, unless
/// `disk` is false (the fuzzers: nothing outside the input may be read).
class BufferIOSystem final : public Assimp::IOSystem {
public:
    BufferIOSystem(std::string name, std::string_view bytes, bool disk) : name_(std::move(name)), bytes_(bytes), disk_(disk) {}
    bool Exists(const char* file) const override { return name_ == file || (disk_ && fs_.Exists(file)); }
    char getOsSeparator() const override { return '/'; }
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (name_ == file)
            return new Assimp::MemoryIOStream(reinterpret_cast<const std::uint8_t*>(bytes_.data()), bytes_.size(), false);
        return disk_ ? fs_.Open(file, mode) : nullptr;
    }
    void Close(Assimp::IOStream* s) override { delete s; }

private:
    std::string name_;
    std::string_view bytes_;
    bool disk_;
    Assimp::DefaultIOSystem fs_;
};

const char* extension(MeshFormat f) {
    switch (f) {
    case MeshFormat::ply: return "ply";
    case MeshFormat::stl_ascii:
    case MeshFormat::stl_binary: return "stl";
    case MeshFormat::gltf: return "gltf";
    case MeshFormat::glb: return "glb";
    case MeshFormat::obj: return "obj";
    }
    return "";
}

std::string one_line(std::string s) {
    for (char& c : s)
        if (c == '\n' || c == '\r') c = ' ';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

/// p transformed by m; untouched when m is the identity (a product with a NaN coordinate would
/// spread the NaN to the others, and the file's own values are what a message should show).
Vec3f transform_point(const aiMatrix4x4& m, const aiVector3D& p) {
    if (m.IsIdentity()) return {p.x, p.y, p.z};
    const aiVector3D q = m * p;
    return {q.x, q.y, q.z};
}

/// The material's diffuse colour and texture (glTF: base colour factor and texture).
Material convert_material(const aiScene& scene, const aiMaterial& am, const std::string& name, const std::string& base_dir,
                          Mesh& mesh, Warnings& warnings) {
    Material m;
    aiString label;
    if (am.Get(AI_MATKEY_NAME, label) == AI_SUCCESS && label.length > 0) m.name = label.C_Str();
    aiColor4D c;
    if (am.Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS || am.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) {
        m.diffuse = {c.r, c.g, c.b};
        for (int k = 0; k < 3; ++k) m.diffuse[k] = std::isfinite(m.diffuse[k]) ? std::clamp(m.diffuse[k], 0.0f, 1.0f) : 0.0f;
    }
    aiString path;
    if (am.GetTexture(aiTextureType_BASE_COLOR, 0, &path) != AI_SUCCESS && am.GetTexture(aiTextureType_DIFFUSE, 0, &path) != AI_SUCCESS)
        return m;
    try {
        const auto [embedded, index] = scene.GetEmbeddedTextureAndIndex(path.C_Str());
        if (embedded) {
            const std::string tname = name + " (embedded image " + std::to_string(index) + ")";
            if (embedded->mHeight != 0) throw InputError(tname, 0, "uncompressed embedded textures are not read");
            mesh.textures.push_back(decode_texture({reinterpret_cast<const unsigned char*>(embedded->pcData), embedded->mWidth}, tname));
        } else {
            mesh.textures.push_back(load_texture(base_dir + path.C_Str()));
        }
        m.diffuse_texture = int(mesh.textures.size() - 1);
    } catch (const InputError& e) {
        warnings.add(name + ": material '" + m.name + "': texture not used: " + e.what());
    }
    return m;
}

struct Converter {
    const std::string& name;
    const aiScene& scene;
    MeshFormat format;
    Mesh& mesh;
    std::vector<Vec3f> corners;
    std::vector<std::array<std::uint32_t, 3>> triangles;

    void add(const aiMesh& am, const aiMatrix4x4& m, std::uint32_t material) {
        const auto base = std::uint32_t(mesh.vertex_count());
        for (unsigned v = 0; v < am.mNumVertices; ++v) mesh.add_vertex(transform_point(m, am.mVertices[v]));
        // STL's normals are its facets' (flat) normals: nothing a flat shading does not already have.
        const bool normals = am.HasNormals() && format != MeshFormat::stl_ascii && format != MeshFormat::stl_binary;
        const auto normal_base = std::uint32_t(mesh.normals.size());
        if (normals) {
            aiMatrix3x3 nm(m);
            nm.Inverse().Transpose();
            for (unsigned v = 0; v < am.mNumVertices; ++v) {
                const aiVector3D n = nm * am.mNormals[v];
                const Vec3f f{n.x, n.y, n.z};
                const float len = simd::length(f);
                mesh.normals.push_back(len > 0.0f && std::isfinite(len) ? f / len : Vec3f{0.0f});
            }
        }
        const bool uvs = am.HasTextureCoords(0);
        const auto uv_base = std::uint32_t(mesh.uvs.size());
        if (uvs)
            for (unsigned v = 0; v < am.mNumVertices; ++v) mesh.uvs.push_back({am.mTextureCoords[0][v].x, am.mTextureCoords[0][v].y});
        if (am.HasVertexColors(0)) {
            mesh.colors.resize(base, Vec3f{1.0f});
            for (unsigned v = 0; v < am.mNumVertices; ++v) {
                Vec3f c{am.mColors[0][v].r, am.mColors[0][v].g, am.mColors[0][v].b};
                // glTF's colours are linear.
                for (int k = 0; k < 3; ++k) c[k] = std::isfinite(c[k]) ? std::clamp(c[k], 0.0f, 1.0f) : 1.0f;
                mesh.colors.push_back(c);
            }
        } else if (!mesh.colors.empty()) {
            mesh.colors.resize(mesh.vertex_count(), Vec3f{1.0f});
        }
        for (unsigned f = 0; f < am.mNumFaces; ++f) {
            const aiFace& face = am.mFaces[f];
            if (face.mNumIndices < 3) continue;
            corners.clear();
            for (unsigned k = 0; k < face.mNumIndices; ++k) {
                const unsigned i = face.mIndices[k];
                // Assimp's readers are not trusted to have checked indices.
                if (i >= am.mNumVertices)
                    throw InputError(name, 0, "face " + std::to_string(f + 1) + " refers to vertex " + std::to_string(i) +
                                                  ", past the " + std::to_string(am.mNumVertices) + " vertices of its mesh");
                corners.push_back(transform_point(m, am.mVertices[i]));
            }
            triangles.clear();
            triangulate_polygon(corners, triangles);
            for (const auto& t : triangles) {
                std::uint32_t idx[3];
                CornerAttributes attr;
                for (int c = 0; c < 3; ++c) {
                    const unsigned i = face.mIndices[t[std::size_t(c)]];
                    idx[c] = base + i;
                    if (normals) attr.normal[c] = normal_base + i;
                    if (uvs) attr.uv[c] = uv_base + i;
                }
                mesh.add_triangle(idx[0], idx[1], idx[2], material, attr);
            }
        }
    }

    /// Every (mesh, node transform) pair in node order, depth first (what walk() places).
    void placements(const aiNode& node, const aiMatrix4x4& parent, std::vector<std::pair<unsigned, aiMatrix4x4>>& out) {
        const aiMatrix4x4 m = parent * node.mTransformation;
        for (unsigned i = 0; i < node.mNumMeshes; ++i)
            if (node.mMeshes[i] < scene.mNumMeshes && scene.mMeshes[node.mMeshes[i]])
                out.push_back({node.mMeshes[i], m});
        for (unsigned c = 0; c < node.mNumChildren; ++c)
            if (node.mChildren[c]) placements(*node.mChildren[c], m, out);
    }

    void walk(const aiNode& node, const aiMatrix4x4& parent, const std::vector<std::uint32_t>& material_of) {
        const aiMatrix4x4 m = parent * node.mTransformation;
        for (unsigned i = 0; i < node.mNumMeshes; ++i) {
            const unsigned id = node.mMeshes[i];
            if (id < scene.mNumMeshes && scene.mMeshes[id]) add(*scene.mMeshes[id], m, material_of[id]);
        }
        for (unsigned c = 0; c < node.mNumChildren; ++c)
            if (node.mChildren[c]) walk(*node.mChildren[c], m, material_of);
    }
};

}  // namespace

namespace {

accel::Affine to_affine(const aiMatrix4x4& m) {
    accel::Affine a;
    a.m = {m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4};
    return a;
}

/// The file's meshes once each and their placements, when some mesh is placed twice or more and
/// every placement is an affine, invertible transform; false (nothing added) otherwise.
bool import_instanced(Converter& conv, const std::vector<std::uint32_t>& material_of, MeshInstances& out) {
    std::vector<std::pair<unsigned, aiMatrix4x4>> uses;
    if (conv.scene.mRootNode) conv.placements(*conv.scene.mRootNode, aiMatrix4x4(), uses);
    std::vector<unsigned> times(conv.scene.mNumMeshes, 0);
    bool repeated = false;
    for (const auto& [id, m] : uses) {
        repeated |= ++times[id] > 1;
        // glTF's matrices are affine; a projective row or a singular placement is flattened.
        if (m.d1 != 0.0f || m.d2 != 0.0f || m.d3 != 0.0f || m.d4 != 1.0f || !accel::check_affine(to_affine(m)).empty())
            return false;
    }
    if (!repeated) return false;
    std::vector<std::int64_t> part_of(conv.scene.mNumMeshes, -1);
    for (const auto& [id, m] : uses) {
        if (part_of[id] < 0) {
            const Mesh& held = conv.mesh;
            const auto first = std::uint32_t(held.triangle_count()), v = std::uint32_t(held.vertex_count()),
                       n = std::uint32_t(held.normals.size()), t = std::uint32_t(held.uvs.size());
            conv.add(*conv.scene.mMeshes[id], aiMatrix4x4(), material_of[id]);
            part_of[id] = std::int64_t(out.parts.size());
            out.parts.push_back({first, std::uint32_t(held.triangle_count()) - first,
                                 std::uint32_t(held.vertex_count()) - v, std::uint32_t(held.normals.size()) - n,
                                 std::uint32_t(held.uvs.size()) - t});
        }
        const MeshPart& part = out.parts[std::size_t(part_of[id])];
        if (part.count > 0) out.instances.push_back({std::uint32_t(part_of[id]), to_affine(m)});
    }
    return true;
}

}  // namespace

Mesh import_with_assimp(std::string_view bytes, MeshFormat format, const std::string& name, const std::string& base_dir,
                        Warnings& warnings, ImportCounts& counts, MeshInstances* instances) {
    Assimp::Importer importer;
    const std::string virtual_name = base_dir + "arbor-input." + extension(format);
    importer.SetIOHandler(new BufferIOSystem(virtual_name, bytes, !base_dir.empty()));  // the importer owns it
    const aiScene* scene = importer.ReadFile(virtual_name, 0);
    if (!scene) throw InputError(name, 0, std::string(format_name(format)) + ": " + one_line(importer.GetErrorString()));
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        const aiMesh* am = scene->mMeshes[i];
        if (!am) continue;
        counts.vertices += am->mNumVertices;
        for (unsigned f = 0; f < am->mNumFaces; ++f) ++(am->mFaces[f].mNumIndices < 3 ? counts.point_line_faces : counts.polygons);
    }
    Mesh mesh;
    // STL has no materials Assimp does not invent; glTF's base colours are read.
    std::vector<std::uint32_t> material_of(scene->mNumMeshes, 0);
    const bool gltf = format == MeshFormat::gltf || format == MeshFormat::glb;
    if (gltf && scene->mNumMaterials > 0) {
        std::vector<std::int64_t> converted(scene->mNumMaterials, -1);
        for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
            const unsigned id = scene->mMeshes[i] ? scene->mMeshes[i]->mMaterialIndex : 0;
            if (id >= scene->mNumMaterials || !scene->mMaterials[id]) continue;
            if (converted[id] < 0) {
                converted[id] = std::int64_t(mesh.materials.size());
                mesh.materials.push_back(convert_material(*scene, *scene->mMaterials[id], name, base_dir, mesh, warnings));
            }
            material_of[i] = std::uint32_t(converted[id]);
        }
    }
    Converter conv{name, *scene, format, mesh, {}, {}};
    if (instances) *instances = {};
    if (!(instances && gltf && import_instanced(conv, material_of, *instances)) && scene->mRootNode)
        conv.walk(*scene->mRootNode, aiMatrix4x4(), material_of);
    if (mesh.materials.size() > 1) mesh.material.resize(mesh.triangle_count(), 0);
    else mesh.material.clear();
    if (!mesh.colors.empty()) mesh.colors.resize(mesh.vertex_count(), Vec3f{1.0f});
    if (mesh.normal_index.empty()) mesh.normals.clear();
    if (mesh.uv_index.empty()) mesh.uvs.clear();
    return mesh;
}

}  // namespace arbor::engine::formats
