#include "engine/formats/ply_read.h"

#include "engine/error.h"
#include "engine/formats/tristrip.h"
#include "engine/polygon.h"
#include "engine/texture.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <span>

namespace arbor::engine::formats {

namespace {

/// Reads the body's values one after the other, in either encoding. check_ply_body has walked the
/// same records, so running out of data here would be a defect; it is still an InputError.
class Values {
public:
    Values(const PlyHeader& h, std::string_view bytes, const std::string& name)
        : bytes_(bytes),
          pos_(h.body_offset),
          name_(name),
          ascii_(h.encoding == PlyHeader::Encoding::ascii),
          swap_((h.encoding == PlyHeader::Encoding::binary_big_endian) != (std::endian::native == std::endian::big)) {}

    /// Where messages say the value was read ("element 'face' record 3, property vertex_indices").
    void at(const PlyElement& e, std::uint64_t record, const PlyProperty& p) {
        element_ = &e;
        record_ = record;
        property_ = &p;
    }

    double number(PlyType t) {
        if (ascii_) {
            const std::string_view tok = token();
            double v = 0.0;
            const auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
            if (ec == std::errc::result_out_of_range) return tok[0] == '-' ? -HUGE_VAL : HUGE_VAL;
            if (ec != std::errc() || end != tok.data() + tok.size()) fail("'" + std::string(tok) + "' is not a number");
            return v;
        }
        switch (t) {
            case PlyType::int8:
                return double(load<std::int8_t>());
            case PlyType::uint8:
                return double(load<std::uint8_t>());
            case PlyType::int16:
                return double(load<std::int16_t>());
            case PlyType::uint16:
                return double(load<std::uint16_t>());
            case PlyType::int32:
                return double(load<std::int32_t>());
            case PlyType::uint32:
                return double(load<std::uint32_t>());
            case PlyType::float32:
                return double(load<float>());
            case PlyType::float64:
                return load<double>();
        }
        return 0.0;
    }

    /// An integer value (list counts, vertex indices); a value of a float type must be integral.
    std::int64_t integer(PlyType t) {
        if (ascii_) {
            const std::string_view tok = token();
            std::int64_t v = 0;
            const auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
            if (ec == std::errc() && end == tok.data() + tok.size()) return v;
            pos_ -= tok.size();  // read it again as a number ("3.0" is an integer too)
        }
        const double v = number(t);
        if (!(v == std::floor(v)) || std::fabs(v) > 9.0e15)
            fail("the value " + std::to_string(v) + " is not an integer");
        return std::int64_t(v);
    }

    [[noreturn]] void fail(const std::string& problem) const {
        if (!element_ || !property_) throw InputError(name_, 0, problem);
        throw InputError(name_, 0,
                         problem + " in element '" + element_->name + "' record " + std::to_string(record_ + 1) +
                             ", property " + property_->name);
    }

private:
    std::string_view token() {
        auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
        while (pos_ < bytes_.size() && space(bytes_[pos_])) ++pos_;
        const std::size_t b = pos_;
        while (pos_ < bytes_.size() && !space(bytes_[pos_])) ++pos_;
        if (pos_ == b) fail("the ASCII PLY body ends");
        return bytes_.substr(b, pos_ - b);
    }

    template <class T>
    T load() {
        if (bytes_.size() - pos_ < sizeof(T)) fail("the binary PLY body ends");
        unsigned char b[sizeof(T)];
        std::memcpy(b, bytes_.data() + pos_, sizeof(T));
        if (swap_) std::reverse(b, b + sizeof(T));
        pos_ += sizeof(T);
        T v;
        std::memcpy(&v, b, sizeof(T));
        return v;
    }

    std::string_view bytes_;
    std::size_t pos_;
    const std::string& name_;
    bool ascii_, swap_;
    const PlyElement* element_ = nullptr;
    std::uint64_t record_ = 0;
    const PlyProperty* property_ = nullptr;
};

/// What a vertex property is read into.
enum class Slot { none, x, y, z, nx, ny, nz, red, green, blue, u, v };

Slot vertex_slot(const PlyProperty& p) {
    if (p.count_size) return Slot::none;
    const std::string& n = p.name;
    if (n == "x") return Slot::x;
    if (n == "y") return Slot::y;
    if (n == "z") return Slot::z;
    if (n == "nx") return Slot::nx;
    if (n == "ny") return Slot::ny;
    if (n == "nz") return Slot::nz;
    if (n == "red" || n == "r" || n == "diffuse_red") return Slot::red;
    if (n == "green" || n == "g" || n == "diffuse_green") return Slot::green;
    if (n == "blue" || n == "b" || n == "diffuse_blue") return Slot::blue;
    if (n == "u" || n == "s" || n == "texture_u" || n == "texture_s") return Slot::u;
    if (n == "v" || n == "t" || n == "texture_v" || n == "texture_t") return Slot::v;
    return Slot::none;
}

bool is_index_list(const PlyProperty& p) {
    return p.count_size && (p.name == "vertex_indices" || p.name == "vertex_index");
}

/// A colour value as an 8-bit sRGB code: integer types scaled from their range, floats from [0, 1].
std::uint8_t colour_code(double v, PlyType t) {
    double scale = 255.0;
    if (t == PlyType::uint16 || t == PlyType::int16)
        scale = 65535.0;
    else if (t == PlyType::uint32 || t == PlyType::int32)
        scale = 4294967295.0;
    const double unit = t == PlyType::float32 || t == PlyType::float64 ? v : v / scale;
    return std::uint8_t(std::lround(255.0 * (std::isfinite(unit) ? std::clamp(unit, 0.0, 1.0) : 1.0)));
}

/// The vertex index lists of one face or tristrips element, one list per record.
struct IndexLists {
    const PlyElement* element = nullptr;
    std::vector<std::int64_t> flat;
    std::vector<std::size_t> start;  ///< of each record's list in `flat`, and one past the last
};

struct Reader {
    Reader(const PlyHeader& h, std::string_view bytes, const std::string& n) : name(n), values(h, bytes, n) {}

    const std::string& name;
    Values values;
    PlyMesh out;
    std::vector<Vec3f> normals, colours;
    std::vector<Vec2f> uvs;
    bool have_normals = false, have_colours = false, have_uvs = false, have_vertices = false;
    std::vector<IndexLists> lists;  ///< in the file's element order
    std::vector<std::string> skipped;

    void skip(const PlyProperty& p) {
        if (!p.count_size) {
            (void)values.number(p.type);
            return;
        }
        const std::int64_t n = values.integer(p.count_type);
        for (std::int64_t k = 0; k < n; ++k) (void)values.number(p.type);
    }

    void read_vertices(const PlyElement& e) {
        if (have_vertices) throw InputError(name, 0, "a second element 'vertex' (arbor reads one vertex list)");
        have_vertices = true;
        std::vector<Slot> slots;
        bool has[12] = {};
        std::vector<std::string> unread;
        for (const PlyProperty& p : e.properties) {
            slots.push_back(vertex_slot(p));
            has[int(slots.back())] = true;
            if (slots.back() == Slot::none) unread.push_back(p.name);
        }
        if (!has[int(Slot::x)] || !has[int(Slot::y)] || !has[int(Slot::z)])
            throw InputError(name, 0,
                             std::string("element 'vertex' has no property ") + (!has[int(Slot::x)]   ? "x"
                                                                                 : !has[int(Slot::y)] ? "y"
                                                                                                      : "z"));
        have_normals = has[int(Slot::nx)] && has[int(Slot::ny)] && has[int(Slot::nz)];
        have_colours = has[int(Slot::red)] && has[int(Slot::green)] && has[int(Slot::blue)];
        have_uvs = has[int(Slot::u)] && has[int(Slot::v)];
        // Part of a set (nx without nz) is not read either.
        auto note_unread = [&](bool have, Slot first, Slot last, const char* label) {
            bool any = false;
            for (int s = int(first); s <= int(last); ++s) any |= has[s];
            if (any && !have) unread.push_back(std::string(label) + " (incomplete set)");
        };
        note_unread(have_normals, Slot::nx, Slot::nz, "nx/ny/nz");
        note_unread(have_colours, Slot::red, Slot::blue, "red/green/blue");
        note_unread(have_uvs, Slot::u, Slot::v, "u/v");
        if (!unread.empty()) {
            std::string s = "vertex properties";
            for (std::size_t k = 0; k < unread.size(); ++k) s += (k ? ", " : " ") + unread[k];
            skipped.push_back(s);
        }
        Mesh& m = out.mesh;
        for (std::uint64_t r = 0; r < e.count; ++r) {
            double v[12] = {0, 0, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0};
            std::uint8_t code[3] = {255, 255, 255};
            for (std::size_t k = 0; k < e.properties.size(); ++k) {
                const PlyProperty& p = e.properties[k];
                values.at(e, r, p);
                if (slots[k] == Slot::none) {
                    skip(p);
                    continue;
                }
                v[int(slots[k])] = values.number(p.type);
                if (slots[k] >= Slot::red && slots[k] <= Slot::blue)
                    code[int(slots[k]) - int(Slot::red)] = colour_code(v[int(slots[k])], p.type);
            }
            m.add_vertex({float(v[int(Slot::x)]), float(v[int(Slot::y)]), float(v[int(Slot::z)])});
            if (have_normals) {
                const Vec3f n{float(v[int(Slot::nx)]), float(v[int(Slot::ny)]), float(v[int(Slot::nz)])};
                const float len = simd::length(n);
                normals.push_back(len > 0.0f && std::isfinite(len) ? n / len : Vec3f{0.0f});
            }
            if (have_colours)
                colours.push_back({srgb_to_linear(code[0]), srgb_to_linear(code[1]), srgb_to_linear(code[2])});
            if (have_uvs) uvs.push_back({float(v[int(Slot::u)]), float(v[int(Slot::v)])});
        }
    }

    void read_lists(const PlyElement& e) {
        const auto list = std::find_if(e.properties.begin(), e.properties.end(), is_index_list);
        if (list == e.properties.end())
            throw InputError(
                name, 0,
                "element '" + e.name + "' has no list property vertex_indices (nothing to read its surfaces from)");
        std::string unread;
        for (const PlyProperty& p : e.properties)
            if (&p != &*list) unread += (unread.empty() ? " " : ", ") + p.name;
        if (!unread.empty()) skipped.push_back(e.name + " properties" + unread);
        IndexLists& l = lists.emplace_back();
        l.element = &e;
        for (std::uint64_t r = 0; r < e.count; ++r) {
            l.start.push_back(l.flat.size());
            for (const PlyProperty& p : e.properties) {
                values.at(e, r, p);
                if (&p != &*list) {
                    skip(p);
                    continue;
                }
                const std::int64_t n = values.integer(p.count_type);
                for (std::int64_t k = 0; k < n; ++k) l.flat.push_back(values.integer(p.type));
            }
        }
        l.start.push_back(l.flat.size());
    }

    void read_other(const PlyElement& e) {
        for (const PlyProperty& p : e.properties)
            if (is_index_list(p))
                throw InputError(name, 0,
                                 "element '" + e.name + "' holds " + p.name +
                                     " lists that arbor does not read as surfaces (it reads 'face' and 'tristrips')");
        skipped.push_back("element '" + e.name + "' (" + std::to_string(e.count) +
                          (e.count == 1 ? " record)" : " records)"));
        if (e.properties.empty()) return;  // records of no values: nothing to skip, whatever the count
        for (std::uint64_t r = 0; r < e.count; ++r)
            for (const PlyProperty& p : e.properties) {
                values.at(e, r, p);
                skip(p);
            }
    }

    void check_index(const IndexLists& l, std::size_t record, std::int64_t i) const {
        const std::uint64_t n = out.mesh.vertex_count();
        const bool strips = l.element->name == "tristrips";
        if (i >= 0 && std::uint64_t(i) < n) return;
        if (strips && i == -1) return;
        const std::string what = (strips ? "tristrips record " : l.element->name + " ") + std::to_string(record + 1);
        if (i < 0) throw InputError(name, 0, what + " has the negative vertex index " + std::to_string(i));
        throw InputError(name, 0,
                         what + " refers to vertex " + std::to_string(i) + ", past the " + std::to_string(n) +
                             " vertices of its mesh");
    }

    void add(std::int64_t a, std::int64_t b, std::int64_t c) {
        const auto i = std::uint32_t(a), j = std::uint32_t(b), k = std::uint32_t(c);
        // Normals and texture coordinates are per vertex: a corner's index is its vertex's.
        CornerAttributes attr;
        const std::uint32_t vertex[3] = {i, j, k};
        for (int corner = 0; corner < 3; ++corner) {
            if (have_normals) attr.normal[corner] = vertex[corner];
            if (have_uvs) attr.uv[corner] = vertex[corner];
        }
        out.mesh.add_triangle(i, j, k, 0, attr);
    }

    void triangulate(const IndexLists& l) {
        const bool strips = l.element->name == "tristrips";
        std::vector<Vec3f> corners;
        std::vector<std::array<std::uint32_t, 3>> tris;
        std::vector<std::array<std::int64_t, 3>> strip_tris;
        const Mesh& m = out.mesh;
        for (std::size_t r = 0; r + 1 < l.start.size(); ++r) {
            const std::span<const std::int64_t> idx(l.flat.data() + l.start[r], l.start[r + 1] - l.start[r]);
            for (const std::int64_t i : idx) check_index(l, r, i);
            if (strips) {
                strip_tris.clear();
                strip_triangles(idx, strip_tris);
                for (const auto& t : strip_tris) add(t[0], t[1], t[2]);
            } else if (idx.size() < 3) {
                ++out.point_line_faces;
            } else if (idx.size() == 3) {
                add(idx[0], idx[1], idx[2]);
            } else {
                corners.clear();
                for (const std::int64_t i : idx)
                    corners.push_back({m.x[std::size_t(i)], m.y[std::size_t(i)], m.z[std::size_t(i)]});
                tris.clear();
                triangulate_polygon(corners, tris);
                for (const auto& t : tris) add(idx[t[0]], idx[t[1]], idx[t[2]]);
            }
        }
    }
};

}  // namespace

PlyMesh read_ply(const PlyHeader& header, std::string_view bytes, const std::string& name, Warnings& warnings) {
    Reader rd(header, bytes, name);
    for (const PlyElement& e : header.elements) {
        if (e.name == "vertex")
            rd.read_vertices(e);
        else if (e.name == "face" || e.name == "tristrips")
            rd.read_lists(e);
        else
            rd.read_other(e);
    }
    for (const IndexLists& l : rd.lists) rd.triangulate(l);
    Mesh& m = rd.out.mesh;
    if (m.has_normals()) m.normals = std::move(rd.normals);
    if (m.has_uvs()) m.uvs = std::move(rd.uvs);
    if (rd.have_colours) m.colors = std::move(rd.colours);
    if (!rd.skipped.empty()) {
        std::string s = name + ": PLY data not read (no surfaces): ";
        for (std::size_t k = 0; k < rd.skipped.size(); ++k) s += (k ? "; " : "") + rd.skipped[k];
        warnings.add(s);
    }
    if (rd.out.point_line_faces > 0 && m.triangle_count() > 0)
        warnings.add(name + ": " + std::to_string(rd.out.point_line_faces) +
                     " faces with fewer than 3 vertices skipped");
    return std::move(rd.out);
}

}  // namespace arbor::engine::formats
