#pragma once
/// one_line: a diagnostic made safe to print as one line. Text taken from a file (a material name,
/// a header line, a library's message) may hold line breaks or other control bytes; each becomes a
/// visible escape (\n, \r, \t, \xNN) so that an error or warning is always exactly one line.
#include <string>
#include <string_view>

namespace arbor::engine {

inline std::string one_line(std::string_view s) {
    static constexpr char hex[] = "0123456789abcdef";
    std::string out;
    out.reserve(s.size());
    for (const char c : s) {
        const auto b = static_cast<unsigned char>(c);
        if (b >= 0x20 && b != 0x7f)
            out += c;
        else if (c == '\n')
            out += "\\n";
        else if (c == '\r')
            out += "\\r";
        else if (c == '\t')
            out += "\\t";
        else
            out += {'\\', 'x', hex[b >> 4], hex[b & 15]};
    }
    return out;
}

}  // namespace arbor::engine
