#include "engine/formats/ply_check.h"

#include "engine/error.h"

#include <algorithm>
#include <charconv>

namespace arbor::engine::formats {

namespace {

/// Bytes of a PLY scalar type, 0 for an unknown name.
int type_size(std::string_view t, bool* is_signed = nullptr, PlyType* type = nullptr) {
    struct Entry {
        const char* name;
        int size;
        bool is_signed;
        PlyType type;
    };
    using T = PlyType;
    static const Entry table[] = {
        {"char", 1, true, T::int8},      {"uchar", 1, false, T::uint8},   {"short", 2, true, T::int16},
        {"ushort", 2, false, T::uint16}, {"int", 4, true, T::int32},      {"uint", 4, false, T::uint32},
        {"float", 4, true, T::float32},  {"double", 8, true, T::float64}, {"int8", 1, true, T::int8},
        {"uint8", 1, false, T::uint8},   {"int16", 2, true, T::int16},    {"uint16", 2, false, T::uint16},
        {"int32", 4, true, T::int32},    {"uint32", 4, false, T::uint32}, {"float32", 4, true, T::float32},
        {"float64", 8, true, T::float64}};
    for (const Entry& e : table)
        if (t == e.name) {
            if (is_signed) *is_signed = e.is_signed;
            if (type) *type = e.type;
            return e.size;
        }
    return 0;
}

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
        if (j > i) out.push_back(line.substr(i, j - i));
        i = j;
    }
    return out;
}

std::string at(const PlyElement& e, std::uint64_t record) {
    return "element '" + e.name + "' record " + std::to_string(record + 1) + " of " + std::to_string(e.count);
}

/// The list count at `p` (size 1, 2 or 4 bytes, either byte order); negative counts come back as -1.
long long read_count(const unsigned char* p, int size, bool is_signed, bool big_endian) {
    std::uint32_t v = 0;
    for (int k = 0; k < size; ++k) v |= std::uint32_t(p[big_endian ? size - 1 - k : k]) << (8 * k);
    if (is_signed && size < 4 && (v >> (8 * size - 1))) return -1;
    if (is_signed && size == 4 && (v >> 31)) return -1;
    return (long long)v;
}

void walk_binary(const PlyHeader& h, std::string_view bytes, const std::string& name) {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    std::size_t pos = h.body_offset;
    const std::size_t end = bytes.size();
    const bool big = h.encoding == PlyHeader::Encoding::binary_big_endian;
    for (const PlyElement& e : h.elements) {
        if (e.properties.empty()) continue;  // records of no bytes: nothing to walk, whatever the count
        for (std::uint64_t r = 0; r < e.count; ++r)
            for (const PlyProperty& p : e.properties) {
                if (!p.count_size) {
                    if (end - pos < std::size_t(p.size)) throw InputError(name, 0, "binary PLY body ends inside " + at(e, r) + " (truncated file?)");
                    pos += std::size_t(p.size);
                    continue;
                }
                if (end - pos < std::size_t(p.count_size)) throw InputError(name, 0, "binary PLY body ends inside " + at(e, r) + " (truncated file?)");
                const long long n = read_count(data + pos, p.count_size, p.count_signed, big);
                pos += std::size_t(p.count_size);
                if (n < 0) throw InputError(name, 0, "negative list length in " + at(e, r));
                if (std::uint64_t(end - pos) / std::uint64_t(p.size) < std::uint64_t(n))
                    throw InputError(name, 0, "binary PLY body ends inside " + at(e, r) + " (a list of " + std::to_string(n) +
                                                  " items; truncated file?)");
                pos += std::size_t(n) * std::size_t(p.size);
            }
    }
}

/// ASCII body: the numbers of every record must be there (values are not checked here: the
/// loader checks what it keeps).
void walk_ascii(const PlyHeader& h, std::string_view bytes, const std::string& name) {
    std::size_t pos = h.body_offset;
    auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    auto next = [&](std::string_view& token) {
        while (pos < bytes.size() && space(bytes[pos])) ++pos;
        const std::size_t b = pos;
        while (pos < bytes.size() && !space(bytes[pos])) ++pos;
        token = bytes.substr(b, pos - b);
        return !token.empty();
    };
    std::string_view tok;
    for (const PlyElement& e : h.elements) {
        if (e.properties.empty()) continue;  // records of no numbers: nothing to walk, whatever the count
        for (std::uint64_t r = 0; r < e.count; ++r)
            for (const PlyProperty& p : e.properties) {
                if (!next(tok)) throw InputError(name, 0, "ASCII PLY body ends inside " + at(e, r) + " (truncated file?)");
                if (!p.count_size) continue;
                long long n = -1;
                const auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), n);
                if (ec != std::errc() || end != tok.data() + tok.size() || n < 0)
                    throw InputError(name, 0, "list length '" + std::string(tok) + "' is not a count in " + at(e, r));
                for (long long k = 0; k < n; ++k)
                    if (!next(tok)) throw InputError(name, 0, "ASCII PLY body ends inside " + at(e, r) + " (truncated file?)");
            }
    }
}

}  // namespace

bool looks_like_ply(std::string_view b) { return b.size() >= 4 && b.substr(0, 3) == "ply" && (b[3] == '\n' || b[3] == '\r'); }

PlyHeader parse_ply_header(std::string_view bytes, const std::string& name) {
    if (!looks_like_ply(bytes)) throw InputError(name, 0, "not a PLY file (no 'ply' line)");
    PlyHeader h;
    bool have_format = false;
    std::size_t pos = 0;
    int line_no = 0;
    while (true) {
        if (pos >= bytes.size()) throw InputError(name, 0, "PLY header has no end_header line");
        std::size_t eol = bytes.find('\n', pos);
        if (eol == std::string_view::npos) eol = bytes.size();
        const std::string_view line = bytes.substr(pos, eol - pos);
        pos = eol + 1;
        ++line_no;
        if (line.find('\0') != std::string_view::npos) throw InputError(name, std::size_t(line_no), "binary data in the PLY header");
        const auto w = words(line);
        if (line_no == 1 || w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
        auto fail = [&](const std::string& problem) { throw InputError(name, std::size_t(line_no), problem); };
        if (w[0] == "format") {
            if (w.size() < 3 || w[2] != "1.0") fail("PLY format line must be 'format <encoding> 1.0'");
            if (w[1] == "ascii") h.encoding = PlyHeader::Encoding::ascii;
            else if (w[1] == "binary_little_endian") h.encoding = PlyHeader::Encoding::binary_little_endian;
            else if (w[1] == "binary_big_endian") h.encoding = PlyHeader::Encoding::binary_big_endian;
            else fail("unknown PLY format '" + std::string(w[1]) + "'");
            have_format = true;
        } else if (w[0] == "element") {
            if (w.size() != 3) fail("PLY element line must be 'element <name> <count>'");
            PlyElement e;
            e.name = std::string(w[1]);
            const auto [end, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
            if (ec != std::errc() || end != w[2].data() + w[2].size()) fail("element count '" + std::string(w[2]) + "' is not a count");
            h.elements.push_back(std::move(e));
        } else if (w[0] == "property") {
            if (h.elements.empty()) fail("PLY property before any element");
            PlyProperty p;
            if (w.size() == 5 && w[1] == "list") {
                p.count_size = type_size(w[2], &p.count_signed, &p.count_type);
                p.size = type_size(w[3], nullptr, &p.type);
                if (!p.count_size || !p.size || w[2] == "float" || w[2] == "double" || w[2] == "float32" || w[2] == "float64")
                    fail("unknown PLY list types '" + std::string(w[2]) + " " + std::string(w[3]) + "'");
                p.name = std::string(w[4]);
            } else if (w.size() == 3) {
                p.size = type_size(w[1], nullptr, &p.type);
                if (!p.size) fail("unknown PLY type '" + std::string(w[1]) + "'");
                p.name = std::string(w[2]);
            } else {
                fail("PLY property line must be 'property <type> <name>' or 'property list <type> <type> <name>'");
            }
            h.elements.back().properties.push_back(std::move(p));
        } else if (w[0] == "end_header") {
            if (!have_format) fail("PLY header has no format line");
            h.body_offset = std::min(pos, bytes.size());
            return h;
        } else {
            // Not a keyword: a line such as Blender's "Created by Blender3D 247 - ..." that carries
            // no data. Skipped, as other readers do, but said.
            std::string text(line.substr(0, std::min<std::size_t>(line.size(), 100)));
            while (!text.empty() && (text.back() == '\r' || text.back() == ' ')) text.pop_back();
            for (char& c : text)
                if (static_cast<unsigned char>(c) < 0x20) c = ' ';
            h.warnings.push_back(name + ":" + std::to_string(line_no) + ": not a PLY header keyword, line skipped: " +
                                 text + (line.size() > 100 ? "..." : ""));
        }
    }
}

void check_ply_body(const PlyHeader& h, std::string_view bytes, const std::string& name) {
    // Each record needs at least its fixed bytes (binary) or a digit and a separator per number
    // (ASCII, the last separator optional): an element whose count alone needs more than the file
    // holds is refused before walking.
    const std::uint64_t body = bytes.size() - h.body_offset;
    const bool binary = h.encoding != PlyHeader::Encoding::ascii;
    for (const PlyElement& e : h.elements) {
        std::uint64_t least = 0;
        for (const PlyProperty& p : e.properties) least += binary ? std::uint64_t(p.count_size ? p.count_size : p.size) : 2;
        if (least > 0 && e.count > (body + (binary ? 0 : 1)) / least)
            throw InputError(name, 0, "element '" + e.name + "' count " + std::to_string(e.count) + " needs at least " +
                                          std::to_string(least) + " bytes each, more than the " + std::to_string(body) +
                                          " bytes after the header");
    }
    if (binary) walk_binary(h, bytes, name);
    else walk_ascii(h, bytes, name);
}

}  // namespace arbor::engine::formats
