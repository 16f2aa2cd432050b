#pragma once
/// A benchmark result as bytes and back, exactly (every field, NaN kept): how the ranks of `mpirun
/// arbor bench` send their scenes' rows to rank 0 (CBOR through nlohmann::json; CBOR keeps NaN,
/// which JSON text cannot).
#include "perf/bench_result.h"

#include <string>
#include <string_view>

namespace arbor::perf {

std::string to_wire(const BenchResult& r);
/// Throws std::runtime_error on bytes that are not a to_wire() result.
BenchResult from_wire(std::string_view bytes);

}  // namespace arbor::perf
