#include "view/structures.h"

#include "accel/factory/make_accel.h"
#include "accel/util/timer.h"

#include <stdexcept>

namespace arbor::view {

StructureCache::Entry StructureCache::get(accel::AccelKind kind, bool counting) {
    // The two-level structure of a scene of instances has no counting walk: say so before building
    // one only to have the cost integrator's first pass refuse it.
    if (counting && placed_)
        throw std::logic_error("cost integrator: a scene of instances cannot count (its two-level structure has no "
                               "counting walk); choose another integrator");
    const std::lock_guard lock(mutex_);
    Slot& slot = slots_[{kind, counting}];
    if (auto live = slot.accel.lock()) return {std::move(live), slot.build_ms, true};
    accel::BuildConfig cfg = base_;
    cfg.layouts = counting ? accel::Layouts::all : accel::Layouts::simd;
    const accel::Timer timer;
    std::shared_ptr<const accel::Accel> built =
        placed_ ? engine::make_instanced_accel(*mesh_, *placed_, kind, cfg) : accel::make_accel(kind, tris_, cfg);
    slot.build_ms = timer.ms();
    slot.accel = built;
    return {std::move(built), slot.build_ms, false};
}

}  // namespace arbor::view
