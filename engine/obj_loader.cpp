#include "engine/obj_loader.h"

#include "engine/error.h"
#include "engine/file_io.h"
#include "engine/memory_budget.h"
#include "engine/polygon.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>

namespace arbor::engine {

namespace {

/// Line bookkeeping over the in-memory text, so that callbacks can find "their" line from the
/// stream position tinyobjloader has reached (just past the line it hands us).
class Lines {
public:
    explicit Lines(std::string_view text) : text_(text) {
        starts_.push_back(0);
        for (std::size_t i = 0; i < text.size(); ++i) {
            if (text[i] == '\n' || (text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n')))
                starts_.push_back(i + 1);
        }
    }
    /// 1-based number of the line that ends just before stream position `pos` (-1 = end of text).
    std::size_t line_before(std::streamoff pos) const {
        std::size_t end = pos < 0 ? text_.size() : std::size_t(pos);
        if (end > 0) --end;  // step back onto the line's last byte (its terminator, if any)
        return std::size_t(std::upper_bound(starts_.begin(), starts_.end(), end) - starts_.begin());
    }
    /// True for the last line of a text that does not end in a line break: a cut-off file.
    bool is_unterminated_last(std::size_t number) const {
        return number == starts_.size() && !text_.empty() && text_.back() != '\n' && text_.back() != '\r';
    }
    std::size_t count() const { return starts_.size(); }
    std::string_view line(std::size_t number) const {
        const std::size_t b = starts_[number - 1];
        std::size_t e = number < starts_.size() ? starts_[number] : text_.size();
        while (e > b && (text_[e - 1] == '\n' || text_[e - 1] == '\r')) --e;
        return text_.substr(b, e - b);
    }

private:
    std::string_view text_;
    std::vector<std::size_t> starts_;
};

std::vector<std::string_view> split_ws(std::string_view s) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
        std::size_t j = i;
        while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
        if (j > i) out.push_back(s.substr(i, j - i));
        i = j;
    }
    return out;
}

/// A leading '+' before a digit or '.', which C's strtod accepts and from_chars does not.
std::string_view drop_plus(std::string_view s) {
    if (s.size() >= 2 && s[0] == '+' && (std::isdigit(static_cast<unsigned char>(s[1])) || s[1] == '.')) s.remove_prefix(1);
    return s;
}

std::optional<long long> parse_int(std::string_view s) {
    s = drop_plus(s);
    long long v = 0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size()) return std::nullopt;
    return v;
}

struct State {
    std::string name;
    const Lines* lines = nullptr;
    std::istream* stream = nullptr;
    Mesh mesh;
    Warnings* warnings = nullptr;
    std::uint32_t current_material = 0;
    std::string base_dir;  // where map_Kd textures are looked for
    std::size_t dangling_uv = 0, dangling_normal = 0;  // corners whose vt / vn index is out of range
    std::vector<std::uint32_t> face, face_uv, face_normal;  // scratch: one face's corners
    std::vector<Vec3f> corners;                             // scratch: their positions
    std::vector<std::array<std::uint32_t, 3>> triangles;    // scratch: the face cut into triangles
    std::optional<InputError> error;  // first error; later callbacks do nothing

    std::size_t current_line() const { return lines->line_before(stream->tellg()); }
    /// Records the first error. A malformed last line without a line break is taken for a cut-off
    /// file instead: it is ignored with a warning.
    void fail(std::size_t line, const std::string& problem) {
        if (lines->is_unterminated_last(line)) {
            warnings->add(name + ":" + std::to_string(line) + ": incomplete last line ignored (" + problem + ")");
            return;
        }
        if (!error) error.emplace(name, line, problem);
    }
};

/// Parses tokens [first, first + n) of `line` as finite floats into `out`; false after recording the
/// problem (`what`: "vertex coordinate", "normal component", ...).
bool parse_floats(State& s, std::size_t line, const std::vector<std::string_view>& tokens, std::size_t first,
                  std::size_t n, float* out, const char* what) {
    for (std::size_t k = 0; k < n; ++k) {
        const std::string_view t = drop_plus(tokens[first + k]);
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), out[k]);
        if (ec == std::errc::result_out_of_range) {
            s.fail(line, std::string(what) + " '" + std::string(tokens[first + k]) + "' is out of float range");
            return false;
        }
        if (ec != std::errc() || end != t.data() + t.size()) {
            s.fail(line, "malformed " + std::string(what) + " '" + std::string(tokens[first + k]) + "'");
            return false;
        }
        if (!std::isfinite(out[k])) {
            s.fail(line, std::string(what) + " is not finite (" + std::string(tokens[first + k]) + ")");
            return false;
        }
    }
    return true;
}

void on_vertex(void* user, tinyobj::real_t, tinyobj::real_t, tinyobj::real_t, tinyobj::real_t) {
    auto& s = *static_cast<State*>(user);
    if (s.error) return;
    const std::size_t line = s.current_line();
    const auto tokens = split_ws(s.lines->line(line));
    // tokens[0] is "v"; x y z are required, w or r g b may follow.
    if (tokens.size() < 4) return s.fail(line, "vertex needs 3 coordinates");
    float p[3];
    if (!parse_floats(s, line, tokens, 1, 3, p, "vertex coordinate")) return;
    s.mesh.add_vertex({p[0], p[1], p[2]});
    // "v x y z r g b": a vertex colour (a common extension); colours that do not parse are ignored.
    if (tokens.size() == 7) {
        float c[3];
        bool ok = true;
        for (int k = 0; k < 3 && ok; ++k) {
            const std::string_view t = drop_plus(tokens[4 + std::size_t(k)]);
            const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), c[k]);
            ok = ec == std::errc() && end == t.data() + t.size() && std::isfinite(c[k]);
        }
        if (ok) {
            s.mesh.colors.resize(s.mesh.vertex_count() - 1, Vec3f{1.0f});
            s.mesh.colors.push_back({std::clamp(c[0], 0.0f, 1.0f), std::clamp(c[1], 0.0f, 1.0f), std::clamp(c[2], 0.0f, 1.0f)});
        }
    }
}

void on_normal(void* user, tinyobj::real_t, tinyobj::real_t, tinyobj::real_t) {
    auto& s = *static_cast<State*>(user);
    if (s.error) return;
    const std::size_t line = s.current_line();
    const auto tokens = split_ws(s.lines->line(line));
    if (tokens.size() < 4) return s.fail(line, "normal needs 3 components");
    float n[3];
    if (!parse_floats(s, line, tokens, 1, 3, n, "normal component")) return;
    // Zero-length normals stay zero: the corner falls back to the flat normal when shading.
    const Vec3f v{n[0], n[1], n[2]};
    const float len = simd::length(v);
    s.mesh.normals.push_back(len > 0.0f && std::isfinite(len) ? v / len : Vec3f{0.0f});
}

void on_texcoord(void* user, tinyobj::real_t, tinyobj::real_t, tinyobj::real_t) {
    auto& s = *static_cast<State*>(user);
    if (s.error) return;
    const std::size_t line = s.current_line();
    const auto tokens = split_ws(s.lines->line(line));
    if (tokens.size() < 2) return s.fail(line, "texture coordinate needs at least u");
    float t[2] = {0.0f, 0.0f};
    if (!parse_floats(s, line, tokens, 1, std::min<std::size_t>(2, tokens.size() - 1), t, "texture coordinate")) return;
    s.mesh.uvs.push_back({t[0], t[1]});
}

/// Resolves an OBJ index (1-based; negative counts back from the last one read).
std::optional<std::uint32_t> resolve_index(long long idx, std::size_t vertex_count) {
    const long long n = static_cast<long long>(vertex_count);
    long long i = idx > 0 ? idx - 1 : n + idx;
    if (idx == 0 || i < 0 || i >= n) return std::nullopt;
    return std::uint32_t(i);
}

/// Resolves corner part `part` (1: texture coordinate, 2: normal) of face token `tok` against the
/// `count` such items read so far. A malformed part is an error; an index out of range only drops
/// the attribute (counted in `dangling`, one warning per file): other readers accept such files,
/// and the corner still has its position.
bool resolve_part(State& s, std::size_t line, std::string_view tok, std::string_view text, std::size_t count,
                  std::size_t& dangling, std::vector<std::uint32_t>& out) {
    if (text.empty()) {
        out.push_back(no_attribute);
        return true;
    }
    const auto v = parse_int(text);
    if (!v) {
        s.fail(line, "malformed face token '" + std::string(tok) + "'");
        return false;
    }
    const auto idx = resolve_index(*v, count);
    if (!idx) ++dangling;
    out.push_back(idx ? *idx : no_attribute);
    return true;
}

void on_face(void* user, tinyobj::index_t*, int) {
    auto& s = *static_cast<State*>(user);
    if (s.error) return;
    const std::size_t line = s.current_line();
    const auto tokens = split_ws(s.lines->line(line));
    s.face.clear();
    s.face_uv.clear();
    s.face_normal.clear();
    for (std::size_t k = 1; k < tokens.size(); ++k) {
        const std::string_view tok = tokens[k];
        // v, v/vt, v//vn or v/vt/vn: every part present must be an integer.
        std::string_view parts[3];
        int nparts = 0;
        std::size_t b = 0;
        while (nparts < 3) {
            const std::size_t e = tok.find('/', b);
            parts[nparts++] = tok.substr(b, e == std::string_view::npos ? std::string_view::npos : e - b);
            if (e == std::string_view::npos) break;
            b = e + 1;
            if (nparts == 3) return s.fail(line, "malformed face token '" + std::string(tok) + "'");
        }
        const auto v = parse_int(parts[0]);
        bool ok = v.has_value();
        for (int p = 1; p < nparts; ++p) ok = ok && (parts[p].empty() ? p == 1 && nparts == 3 : parse_int(parts[p]).has_value());
        if (!ok) return s.fail(line, "malformed face token '" + std::string(tok) + "'");
        if (*v == 0) return s.fail(line, "face index 0 is invalid (OBJ indices start at 1)");
        const auto idx = resolve_index(*v, s.mesh.vertex_count());
        if (!idx)
            return s.fail(line, "face index " + std::to_string(*v) + " is out of range (" +
                                    std::to_string(s.mesh.vertex_count()) + " vertices defined so far)");
        s.face.push_back(*idx);
        if (!resolve_part(s, line, tok, nparts > 1 ? parts[1] : std::string_view(), s.mesh.uvs.size(), s.dangling_uv, s.face_uv) ||
            !resolve_part(s, line, tok, nparts > 2 ? parts[2] : std::string_view(), s.mesh.normals.size(), s.dangling_normal,
                          s.face_normal))
            return;
    }
    if (s.face.size() < 3) {
        s.warnings->add(s.name + ":" + std::to_string(line) + ": face with fewer than 3 vertices skipped");
        return;
    }
    s.corners.clear();
    for (std::uint32_t i : s.face) s.corners.push_back({s.mesh.x[i], s.mesh.y[i], s.mesh.z[i]});
    s.triangles.clear();
    triangulate_polygon(s.corners, s.triangles);
    for (const auto& t : s.triangles) {
        CornerAttributes attr;
        for (int c = 0; c < 3; ++c) {
            attr.normal[c] = s.face_normal[t[std::size_t(c)]];
            attr.uv[c] = s.face_uv[t[std::size_t(c)]];
        }
        s.mesh.add_triangle(s.face[t[0]], s.face[t[1]], s.face[t[2]], s.current_material, attr);
    }
}

Vec3f to_vec(const tinyobj::real_t* c) { return {float(c[0]), float(c[1]), float(c[2])}; }

/// Clamps every component of `c` to [0, hi], non-finite ones to 0; true when something changed.
/// Reflectances above 1 would add energy at every bounce, negative or NaN ones would make
/// negative or NaN pixels.
bool clamp_colour(Vec3f& c, float hi) {
    bool changed = false;
    for (int k = 0; k < 3; ++k) {
        const float v = c[k];
        const float clamped = std::isfinite(v) ? std::clamp(v, 0.0f, hi) : 0.0f;
        changed |= !(clamped == v);
        c[k] = clamped;
    }
    return changed;
}

void on_mtllib(void* user, const tinyobj::material_t* mats, int n) {
    auto& s = *static_cast<State*>(user);
    s.mesh.materials.assign(1, Material{});  // index 0: the default, for faces before any usemtl
    for (int i = 0; i < n; ++i) {
        Material m;
        m.name = mats[i].name;
        m.diffuse = to_vec(mats[i].diffuse);
        m.emission = to_vec(mats[i].emission);
        // illum 3..7 turn ray-traced reflection on: Ks is then the mirror reflectance.
        if (mats[i].illum >= 3 && mats[i].illum <= 7) m.mirror = to_vec(mats[i].specular);
        if (!mats[i].diffuse_texname.empty()) {
            // map_Kd: a missing or undecodable image leaves the material untextured, with a warning.
            try {
                s.mesh.textures.push_back(load_texture(s.base_dir + mats[i].diffuse_texname));
                m.diffuse_texture = int(s.mesh.textures.size() - 1);
            } catch (const InputError& e) {
                s.warnings->add(s.name + ": material '" + m.name + "': texture not used: " + e.what());
            }
        }
        bool clamped = clamp_colour(m.diffuse, 1.0f);
        clamped |= clamp_colour(m.mirror, 1.0f);
        clamped |= clamp_colour(m.emission, std::numeric_limits<float>::max());
        if (clamped)
            s.warnings->add(s.name + ": material '" + m.name +
                            "': Kd/Ks clamped to [0, 1] and Ke to [0, max], non-finite values set to 0");
        s.mesh.materials.push_back(m);
    }
}

void on_usemtl(void* user, const char*, int material_id) {
    auto& s = *static_cast<State*>(user);
    // Unknown names (id -1) fall back to the default material.
    s.current_material = material_id >= 0 && std::size_t(material_id) + 1 < s.mesh.materials.size()
                             ? std::uint32_t(material_id + 1)
                             : 0;
}

/// The OBJ elements arbor does not turn into triangles: points, lines and free-form curves are no
/// surfaces (skipped with a warning); free-form surfaces are (refused).
struct OtherElements {
    struct Kind {
        const char* keyword;
        const char* what;
        std::size_t count = 0, first_line = 0;
    };
    Kind kinds[5] = {{"p", "point"}, {"l", "line"}, {"curv", "curve"}, {"curv2", "2D curve"}, {"surf", "surface"}};

    std::size_t points_and_lines() const { return kinds[0].count + kinds[1].count; }
};

OtherElements other_elements(const Lines& lines) {
    OtherElements o;
    for (std::size_t n = 1; n <= lines.count(); ++n) {
        const std::string_view line = lines.line(n);
        std::size_t b = 0;
        while (b < line.size() && (line[b] == ' ' || line[b] == '\t')) ++b;
        // Only lines starting with p, l, c or s can be one of them: the rest costs one compare.
        if (b == line.size() || (line[b] != 'p' && line[b] != 'l' && line[b] != 'c' && line[b] != 's')) continue;
        std::size_t e = b;
        while (e < line.size() && line[e] != ' ' && line[e] != '\t') ++e;
        const std::string_view keyword = line.substr(b, e - b);
        for (auto& k : o.kinds)
            if (keyword == k.keyword && k.count++ == 0) k.first_line = n;
    }
    return o;
}

/// Refuses free-form surfaces and warns, in one line, about the points, lines and curves skipped.
void check_other_elements(const OtherElements& o, const std::string& name, bool has_triangles, Warnings& warnings) {
    const auto& surf = o.kinds[4];
    if (surf.count)
        throw InputError(name, surf.first_line,
                         "free-form surface (surf) not read: arbor reads polygon faces (f) only");
    if (!has_triangles) return;
    std::string list;
    for (const auto& k : o.kinds)
        if (k.count)
            list += (list.empty() ? "" : ", ") + std::to_string(k.count) + " " + k.what + (k.count > 1 ? "s" : "") +
                    " (" + k.keyword + ", first on line " + std::to_string(k.first_line) + ")";
    if (!list.empty()) warnings.add(name + ": not read (no surfaces): " + list);
}

}  // namespace

Mesh load_obj_text(const std::string& text, const std::string& name, const std::string& base_dir,
                   Warnings& warnings) {
    if (const auto nul = text.find('\0'); nul != std::string::npos)
        throw InputError(name, 0, "binary data (NUL byte at offset " + std::to_string(nul) + "), not an OBJ text file");
    const Lines lines(text);
    std::istringstream stream(text);
    State s;
    s.name = name;
    s.lines = &lines;
    s.stream = &stream;
    s.warnings = &warnings;
    s.base_dir = base_dir;

    tinyobj::callback_t cb;
    cb.vertex_cb = on_vertex;
    cb.normal_cb = on_normal;
    cb.texcoord_cb = on_texcoord;
    cb.index_cb = on_face;
    cb.mtllib_cb = on_mtllib;
    cb.usemtl_cb = on_usemtl;
    tinyobj::MaterialFileReader mtl_reader(base_dir);
    std::string warn, err;
    try {
        tinyobj::LoadObjWithCallback(stream, cb, &s, &mtl_reader, &warn, &err);
    } catch (const std::exception& e) {
        throw InputError(name, 0, std::string("cannot parse: ") + e.what());
    }
    if (s.error) throw *s.error;
    if (warn.find("Failed to load material file") != std::string::npos)
        warnings.add(name + ": material library not found; using the default material");
    if (s.dangling_uv || s.dangling_normal)
        warnings.add(name + ": " + std::to_string(s.dangling_uv) + " texture coordinate and " + std::to_string(s.dangling_normal) +
                     " normal indices of face corners point past the vt/vn lines read so far; those corners have none");
    const OtherElements others = other_elements(lines);
    check_other_elements(others, name, s.mesh.triangle_count() > 0, warnings);
    if (s.mesh.triangle_count() == 0)
        throw InputError(name, 0,
                         others.points_and_lines() ? "no triangles: the file holds only points/lines" : "no triangles");
    if (!s.mesh.material.empty() || s.mesh.materials.size() > 1) s.mesh.material.resize(s.mesh.triangle_count(), 0);
    if (!s.mesh.colors.empty()) s.mesh.colors.resize(s.mesh.vertex_count(), Vec3f{1.0f});
    // Attributes no triangle refers to are dropped, so that "has normals" means some corner uses one.
    if (s.mesh.normal_index.empty()) s.mesh.normals.clear();
    if (s.mesh.uv_index.empty()) s.mesh.uvs.clear();
    s.mesh.compute_bounds();
    return std::move(s.mesh);
}

std::uint64_t obj_load_bytes(std::uint64_t file_bytes) { return 3 * file_bytes; }

Mesh load_obj(const std::string& path, Warnings& warnings, std::uint64_t max_bytes) {
    std::error_code ec;
    const auto size = std::filesystem::is_regular_file(path, ec) ? std::filesystem::file_size(path, ec) : 0;
    const std::uint64_t budget = memory_budget(max_bytes);
    if (!ec && size > 0 && obj_load_bytes(size) > budget)
        throw InputError(path, 0, "loading " + format_bytes(size) + " of OBJ text needs about " +
                                      format_bytes(obj_load_bytes(size)) + ", more than the " + format_bytes(budget) +
                                      (max_bytes ? " of --max-memory" : " of memory"));
    const std::string text = read_file(path);
    const auto slash = path.find_last_of('/');
    const std::string base_dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
    return load_obj_text(text, path, base_dir, warnings);
}

}  // namespace arbor::engine
