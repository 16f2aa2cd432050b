// libFuzzer entry point: the ray- and hit-file readers, then tracing (see fuzz_targets.h).
#include "fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    arbor::fuzz::fuzz_rays(data, size);
    return 0;
}
