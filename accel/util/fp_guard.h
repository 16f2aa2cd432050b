#pragma once
/// Scoped IEEE floating-point mode for code whose exact comparisons must not depend on the caller's
/// MXCSR: flush-to-zero and denormals-are-zero are switched off for the guard's lifetime and the
/// previous mode is restored afterwards (the idea of Mitsuba's FTZGuard, inverted). MXCSR is per
/// thread, so every TBB task that relies on it opens its own guard.
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace arbor::accel {

class IeeeFpGuard {
public:
#if defined(__SSE__)
    IeeeFpGuard() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ & ~(ftz_bit | daz_bit)); }
    ~IeeeFpGuard() { _mm_setcsr(saved_); }
#else
    IeeeFpGuard() = default;
#endif
    IeeeFpGuard(const IeeeFpGuard&) = delete;
    IeeeFpGuard& operator=(const IeeeFpGuard&) = delete;

private:
#if defined(__SSE__)
    static constexpr unsigned ftz_bit = 0x8000u, daz_bit = 0x0040u;
    unsigned saved_;
#endif
};

}  // namespace arbor::accel
