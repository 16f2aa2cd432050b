// libFuzzer entry point: the message parser of `arbor view` (see fuzz_targets.h).
#include "fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    arbor::fuzz::fuzz_view_message(data, size);
    return 0;
}
