#include "perf/mesh_files.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace arbor::perf {

namespace {

template <class T> void put(std::string& out, T v, bool big_endian = false) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
}

std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        const unsigned v = (unsigned(std::uint8_t(in[i])) << 16) | (unsigned(std::uint8_t(in[i + 1])) << 8) | std::uint8_t(in[i + 2]);
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
    }
    if (i + 1 == in.size()) {
        const unsigned v = unsigned(std::uint8_t(in[i])) << 16;
        out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
        const unsigned v = (unsigned(std::uint8_t(in[i])) << 16) | (unsigned(std::uint8_t(in[i + 1])) << 8);
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
    }
    return out;
}

void pad4(std::string& s, char c) {
    while (s.size() % 4) s += c;
}

/// Per-vertex attribute i of vertex v, from the per-corner index (the first corner that names v).
template <class T>
std::vector<T> per_vertex(const engine::Mesh& m, const std::vector<std::uint32_t>& index, const std::vector<T>& values, T fallback) {
    std::vector<T> out(m.vertex_count(), fallback);
    for (std::size_t k = 0; k < index.size(); ++k)
        if (index[k] != engine::no_attribute) out[m.indices[k]] = values[index[k]];
    return out;
}

}  // namespace

std::string ply_bytes(const engine::Mesh& m, PlyEncoding enc, bool normals, bool colors) {
    normals = normals && m.has_normals();
    colors = colors && !m.colors.empty();
    const auto n = per_vertex(m, m.normal_index, m.normals, engine::Vec3f{0.0f, 0.0f, 1.0f});
    const char* format = enc == PlyEncoding::ascii ? "ascii" : enc == PlyEncoding::binary_little_endian ? "binary_little_endian" : "binary_big_endian";
    std::string out = "ply\nformat " + std::string(format) + " 1.0\ncomment written by arbor's perf/mesh_files\nelement vertex " +
                      std::to_string(m.vertex_count()) + "\nproperty float x\nproperty float y\nproperty float z\n";
    if (normals) out += "property float nx\nproperty float ny\nproperty float nz\n";
    if (colors) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    out += "element face " + std::to_string(m.triangle_count()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    const bool big = enc == PlyEncoding::binary_big_endian;
    auto code = [](float c) { return std::uint8_t(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f)); };
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        if (enc == PlyEncoding::ascii) {
            char buf[160];
            std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g", double(m.x[v]), double(m.y[v]), double(m.z[v]));
            out += buf;
            if (normals) std::snprintf(buf, sizeof buf, " %.9g %.9g %.9g", double(n[v].x), double(n[v].y), double(n[v].z)), out += buf;
            if (colors) std::snprintf(buf, sizeof buf, " %d %d %d", code(m.colors[v].x), code(m.colors[v].y), code(m.colors[v].z)), out += buf;
            out += '\n';
            continue;
        }
        for (float c : {m.x[v], m.y[v], m.z[v]}) put(out, c, big);
        if (normals)
            for (float c : {n[v].x, n[v].y, n[v].z}) put(out, c, big);
        if (colors)
            for (float c : {m.colors[v].x, m.colors[v].y, m.colors[v].z}) put(out, code(c));
    }
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        if (enc == PlyEncoding::ascii) {
            out += "3 " + std::to_string(m.indices[3 * t]) + " " + std::to_string(m.indices[3 * t + 1]) + " " +
                   std::to_string(m.indices[3 * t + 2]) + "\n";
            continue;
        }
        put(out, std::uint8_t(3));
        for (int k = 0; k < 3; ++k) put(out, std::int32_t(m.indices[3 * t + std::size_t(k)]), big);
    }
    return out;
}

std::string stl_bytes(const engine::Mesh& m, bool binary) {
    const auto v = m.view();
    std::string out;
    if (binary) {
        out.assign(80, ' ');
        std::memcpy(out.data(), "binary STL written by arbor", 27);
        put(out, std::uint32_t(m.triangle_count()));
    } else {
        out = "solid arbor\n";
    }
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const engine::Vec3f a = v.corner(t, 0), b = v.corner(t, 1), c = v.corner(t, 2);
        engine::Vec3f n = simd::cross(b - a, c - a);
        const float len = simd::length(n);
        n = len > 0.0f ? n / len : engine::Vec3f{0.0f};
        if (binary) {
            for (const engine::Vec3f& p : {n, a, b, c})
                for (int k = 0; k < 3; ++k) put(out, p[k]);
            put(out, std::uint16_t(0));
            continue;
        }
        char buf[400];
        std::snprintf(buf, sizeof buf,
                      "facet normal %.9g %.9g %.9g\n outer loop\n  vertex %.9g %.9g %.9g\n  vertex %.9g %.9g %.9g\n"
                      "  vertex %.9g %.9g %.9g\n endloop\nendfacet\n",
                      double(n.x), double(n.y), double(n.z), double(a.x), double(a.y), double(a.z), double(b.x), double(b.y),
                      double(b.z), double(c.x), double(c.y), double(c.z));
        out += buf;
    }
    if (!binary) out += "endsolid arbor\n";
    return out;
}

std::string obj_text(const engine::Mesh& m) {
    std::string out;
    char buf[160];
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        std::snprintf(buf, sizeof buf, "v %.9g %.9g %.9g\n", double(m.x[v]), double(m.y[v]), double(m.z[v]));
        out += buf;
    }
    for (const auto& n : m.normals) std::snprintf(buf, sizeof buf, "vn %.9g %.9g %.9g\n", double(n.x), double(n.y), double(n.z)), out += buf;
    for (const auto& t : m.uvs) std::snprintf(buf, sizeof buf, "vt %.9g %.9g\n", double(t.u), double(t.v)), out += buf;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        out += "f";
        for (std::size_t k = 3 * t; k < 3 * t + 3; ++k) {
            // snprintf rather than string concatenation: GCC 12 warns about the latter (-Wrestrict, bug 105329).
            const bool uv = m.has_uvs() && m.uv_index[k] != engine::no_attribute;
            const bool n = m.has_normals() && m.normal_index[k] != engine::no_attribute;
            std::snprintf(buf, sizeof buf, " %u", m.indices[k] + 1);
            out += buf;
            if (uv || n) out += '/';
            if (uv) std::snprintf(buf, sizeof buf, "%u", m.uv_index[k] + 1), out += buf;
            if (n) std::snprintf(buf, sizeof buf, "/%u", m.normal_index[k] + 1), out += buf;
        }
        out += "\n";
    }
    return out;
}

std::string gltf_bytes(const engine::Mesh& m, const GltfOptions& o, std::string* bin_out) {
    const bool normals = o.normals && m.has_normals(), uvs = o.uvs && m.has_uvs();
    std::string bin;
    std::string views, accessors;
    int view_count = 0;
    auto add_view = [&](const std::string& data) {
        pad4(bin, '\0');
        views += std::string(view_count ? "," : "") + "{\"buffer\":0,\"byteOffset\":" + std::to_string(bin.size()) +
                 ",\"byteLength\":" + std::to_string(data.size()) + "}";
        bin += data;
        return view_count++;
    };
    int accessor_count = 0;
    auto add_accessor = [&](int view, int component, std::size_t count, const char* type, const std::string& extra = "") {
        accessors += std::string(accessor_count ? "," : "") + "{\"bufferView\":" + std::to_string(view) +
                     ",\"componentType\":" + std::to_string(component) + ",\"count\":" + std::to_string(count) +
                     ",\"type\":\"" + type + "\"" + extra + "}";
        return accessor_count++;
    };
    std::string pos;
    for (std::size_t v = 0; v < m.vertex_count(); ++v)
        for (float c : {m.x[v], m.y[v], m.z[v]}) put(pos, c);
    char mm[200];
    std::snprintf(mm, sizeof mm, ",\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]", double(m.bounds.lo.x), double(m.bounds.lo.y),
                  double(m.bounds.lo.z), double(m.bounds.hi.x), double(m.bounds.hi.y), double(m.bounds.hi.z));
    std::string attributes = "\"POSITION\":" + std::to_string(add_accessor(add_view(pos), 5126, m.vertex_count(), "VEC3", mm));
    if (normals) {
        std::string data;
        for (const auto& n : per_vertex(m, m.normal_index, m.normals, engine::Vec3f{0.0f, 0.0f, 1.0f}))
            for (float c : {n.x, n.y, n.z}) put(data, c);
        attributes += ",\"NORMAL\":" + std::to_string(add_accessor(add_view(data), 5126, m.vertex_count(), "VEC3"));
    }
    if (uvs) {
        std::string data;
        for (const auto& t : per_vertex(m, m.uv_index, m.uvs, engine::Vec2f{})) put(data, t.u), put(data, 1.0f - t.v);
        attributes += ",\"TEXCOORD_0\":" + std::to_string(add_accessor(add_view(data), 5126, m.vertex_count(), "VEC2"));
    }
    std::string idx;
    for (std::uint32_t i : m.indices) put(idx, i);
    const int indices = add_accessor(add_view(idx), 5125, m.indices.size(), "SCALAR");
    char colour[120];
    std::snprintf(colour, sizeof colour, "\"baseColorFactor\":[%.9g,%.9g,%.9g,1]", double(o.base_color[0]), double(o.base_color[1]),
                  double(o.base_color[2]));
    std::string material = "{\"pbrMetallicRoughness\":{" + std::string(colour) + ",\"metallicFactor\":0";
    std::string images;
    if (!o.png.empty()) {
        material += ",\"baseColorTexture\":{\"index\":0}";
        images = ",\"textures\":[{\"source\":0}],\"images\":[{\"bufferView\":" + std::to_string(add_view(o.png)) +
                 ",\"mimeType\":\"image/png\"}]";
    }
    material += "}}";
    pad4(bin, '\0');
    std::string matrix;
    for (float f : o.matrix) {
        char b[32];
        std::snprintf(b, sizeof b, "%s%.9g", matrix.empty() ? "" : ",", double(f));
        matrix += b;
    }
    std::string buffer = "{\"byteLength\":" + std::to_string(bin.size());
    if (!o.binary) buffer += o.external_buffer.empty() ? ",\"uri\":\"data:application/octet-stream;base64," + base64(bin) + "\""
                                                      : ",\"uri\":\"" + o.external_buffer + "\"";
    buffer += "}";
    std::string json = "{\"asset\":{\"version\":\"2.0\",\"generator\":\"arbor perf/mesh_files\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
                       "\"nodes\":[{\"mesh\":0,\"matrix\":[" + matrix + "]}],\"meshes\":[{\"primitives\":[{\"attributes\":{" +
                       attributes + "},\"indices\":" + std::to_string(indices) + ",\"material\":0}]}],\"materials\":[" + material +
                       "]" + images + ",\"accessors\":[" + accessors + "],\"bufferViews\":[" + views + "],\"buffers\":[" + buffer + "]}";
    if (!o.binary) {
        if (!o.external_buffer.empty() && bin_out) *bin_out = bin;
        return json;
    }
    pad4(json, ' ');
    std::string glb = "glTF";
    put(glb, std::uint32_t(2));
    put(glb, std::uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    put(glb, std::uint32_t(json.size()));
    glb += "JSON" + json;
    put(glb, std::uint32_t(bin.size()));
    glb += std::string("BIN\0", 4) + bin;
    return glb;
}

std::string png_bytes(int width, int height, const std::vector<std::uint8_t>& rgb) {
    std::string out;
    auto sink = [](void* context, void* data, int size) { static_cast<std::string*>(context)->append(static_cast<char*>(data), std::size_t(size)); };
    if (!stbi_write_png_to_func(sink, &out, width, height, 3, rgb.data(), width * 3)) throw std::runtime_error("PNG encoding failed");
    return out;
}

engine::Mesh replicate(const engine::Mesh& m, int copies) {
    engine::Mesh out;
    const float step = 1.1f * std::max(m.bounds.extent().x, 1e-3f);
    for (int c = 0; c < copies; ++c) {
        engine::Mesh copy = m;
        for (float& x : copy.x) x += step * float(c);
        copy.compute_bounds();
        if (c == 0) out = std::move(copy);
        else out.append(copy);
    }
    out.compute_bounds();
    return out;
}

}  // namespace arbor::perf
