#include "engine/memory_budget.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <unistd.h>

namespace arbor::engine {

std::uint64_t physical_memory_bytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || page <= 0) return std::numeric_limits<std::uint64_t>::max();
    return std::uint64_t(pages) * std::uint64_t(page);
}

std::uint64_t memory_budget(std::uint64_t max_bytes) { return max_bytes ? max_bytes : physical_memory_bytes(); }

std::optional<std::uint64_t> parse_byte_size(std::string_view s) {
    while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
    auto ends_with_ci = [&](std::string_view suffix) {
        if (s.size() < suffix.size()) return false;
        for (std::size_t i = 0; i < suffix.size(); ++i)
            if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) != suffix[i]) return false;
        return true;
    };
    if (ends_with_ci("ib")) s.remove_suffix(2);
    else if (ends_with_ci("b")) s.remove_suffix(1);
    double scale = 1.0;
    if (!s.empty()) {
        const char c = char(std::tolower(static_cast<unsigned char>(s.back())));
        const char* units = "kmgt";
        for (int i = 0; i < 4; ++i)
            if (c == units[i]) {
                scale = std::ldexp(1.0, 10 * (i + 1));
                s.remove_suffix(1);
                break;
            }
    }
    if (s.empty()) return std::nullopt;
    double value = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value, std::chars_format::fixed);
    if (ec != std::errc() || end != s.data() + s.size() || !(value > 0.0)) return std::nullopt;
    const double bytes = std::floor(value * scale);
    if (!(bytes >= 1.0) || bytes >= 18446744073709551616.0) return std::nullopt;
    return std::uint64_t(bytes);
}

std::string format_bytes(std::uint64_t bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double v = double(bytes);
    int u = 0;
    while (v >= 1024.0 && u < 6) v /= 1024.0, ++u;
    char buf[32];
    if (u == 0) std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(bytes));
    else std::snprintf(buf, sizeof buf, "%.1f %s", v, units[u]);
    return buf;
}

}  // namespace arbor::engine
