// libFuzzer entry point: the mesh loader of every format (see fuzz_targets.h).
#include "fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    arbor::fuzz::fuzz_mesh(data, size);  // a FuzzFinding escapes: libFuzzer reports the abort
    return 0;
}
