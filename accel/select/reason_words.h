#pragma once
/// Numbers in the words of the reason lines: auto's choice of structure (auto_reason.cpp), the
/// refit-or-rebuild decision (refit_select.cpp) and update_vertices' bracket (api/update.cpp).
/// One implementation; the options keep each line as it was written before they shared it.
#include <cstdio>
#include <string>

namespace arbor::accel {

struct MsWords {
    /// From 1 s on, "1.23 s" (else still milliseconds: "1234 ms"; update's bracket, which
    /// scripts/bench_refit.py reads back in ms).
    bool seconds = true;
    /// Below 0.1 ms, three decimals ("0.012 ms"; else two, as above it).
    bool thousandths = true;
};

/// Milliseconds: "1.23 s", "12 ms" from 10 ms, "1.23 ms" below, as `style` says.
inline std::string ms_words(double ms, MsWords style = {}) {
    char buf[32];
    if (style.seconds && ms >= 1000.0)
        std::snprintf(buf, sizeof buf, "%.2f s", ms * 1e-3);
    else if (ms >= 10.0)
        std::snprintf(buf, sizeof buf, "%.0f ms", ms);
    else if (!style.thousandths || ms >= 0.1)
        std::snprintf(buf, sizeof buf, "%.2f ms", ms);
    else
        std::snprintf(buf, sizeof buf, "%.3f ms", ms);
    return buf;
}

/// A count in three significant digits: "1.23G" (when `giga`), "1.23M", "12.3k", "123".
inline std::string count_words(double n, bool giga = true) {
    char buf[32];
    if (giga && n >= 1e9)
        std::snprintf(buf, sizeof buf, "%.3gG", n * 1e-9);
    else if (n >= 1e6)
        std::snprintf(buf, sizeof buf, "%.3gM", n * 1e-6);
    else if (n >= 1e3)
        std::snprintf(buf, sizeof buf, "%.3gk", n * 1e-3);
    else
        std::snprintf(buf, sizeof buf, "%.0f", n);
    return buf;
}

}  // namespace arbor::accel
