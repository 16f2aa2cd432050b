#pragma once
/// Racing the two SIMD paths on the one kind of batch the coherence measure cannot call.
///
/// The path policy (path_policy.h) reads the rays: groups that share an octant and a place are
/// coherent (packets win), scattered origins are not (single rays win). Groups that start together
/// but go every way (bounces from an image tile: diffuse rays) are neither. Which path wins on
/// them depends on the model and the machine: on held-out diffuse rays the single path beats the
/// packet path on some models and loses to it several times over on others (docs/benchmarks.md).
/// No rule read off the rays calls that, so such a batch, when it is large enough, is raced: a few
/// chunks spread over the batch are each traced half on one path and half on the other, the halves
/// interleaved by blocks of 64 rays (whole 8x8 tiles of a camera), so that both paths see the same
/// parts of the picture; each half is timed on its thread's CPU clock, and the rest of the batch
/// runs on the path that took less time per ray. (Neighbouring whole chunks, one per path, differ
/// in what they hold, a quarter row of tiles apart, and can pick the slower path.)
///
/// Only closest-hit batches are raced: every path returns the same closest hit bit for bit (the
/// tests hold each path to brute force), so a race changes the time and never the answers. An
/// any-hit answer may name a different blocking triangle on each path, so those batches keep the
/// policy's own choice, and a run's answers stay the same run to run.
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "accel/interface/path_policy.h"

namespace arbor::accel {

class Accel;

/// What a race measured.
struct RaceOutcome {
    /// The path the rest of the batch ran on; `best` when no race was run.
    TracePath path = TracePath::best;
    /// Chunks the race split between the paths.
    std::size_t chunks = 0;
    /// Thread CPU time per ray on each path's halves, in nanoseconds.
    double single_ns = 0.0, packet_ns = 0.0;
    bool raced() const { return path != TracePath::best; }
};

/// Rays per block of a race chunk's halves (8x8 tiles of a camera, four 16-ray packets).
inline constexpr std::size_t race_block = 64;

/// Which rays of a chunk a call traces: all, or the blocks of race_block rays with an even or odd
/// number (0, 2, 4, ... or 1, 3, 5, ... counted from the chunk's start).
enum class ChunkPart : std::uint8_t { all, even_blocks, odd_blocks };

/// Whether ray i of a chunk belongs to `part`.
inline bool in_part(std::size_t i, ChunkPart part) {
    return part == ChunkPart::all || ((i / race_block) % 2 == 0) == (part == ChunkPart::even_blocks);
}

/// Chunks a race of a batch of `chunks` chunks splits (0: too small to race): 0 below 32 chunks,
/// 4 up to 127 chunks, 8 from 128 on.
std::size_t race_chunk_count(std::size_t chunks);

/// Whether a batch the policy answered with `c`, asked as `req`, is one a race settles: closest-hit
/// rays measured as starting together without sharing an octant (PathChoice::Why::measured, not
/// one_octant, together >= the packet share), on a structure offering both SIMD paths for them.
bool race_settles(const PathChoice& c, const PathOffer& offer, const TraceRequest& req);

/// The race's chunks of a batch of `chunks` (chunks >= count): i * chunks / count for i < count.
std::vector<std::size_t> race_chunk_ids(std::size_t chunks, std::size_t count);

/// Runs every ray of chunks [0, chunks) once with run(k, path, part), which traces the `part` of
/// chunk k on `path` and returns how many rays it traced: first the race's chunks (race_chunk_ids,
/// in parallel), the i-th one's even blocks on single and odd blocks on packet for even i, the
/// other way round (and the other path first) for odd i, each half timed on its thread's CPU
/// clock; then all other chunks whole, in parallel, on the path with less CPU time per ray (ties:
/// packet). Uses tbb::parallel_for: call it inside the task arena that is to run it.
RaceOutcome race_chunks(std::size_t chunks, std::size_t count,
                        const std::function<std::size_t(std::size_t chunk, TracePath path, ChunkPart part)>& run);

/// Traces the `part` of one chunk's rays into hits[i] for the rays i in it (the others untouched),
/// on the path `req` names: the part's blocks gathered into this thread's buffers, one Accel::trace
/// call, the answers scattered back. Returns the number of rays traced.
std::size_t trace_part(const Accel& accel, std::span<const Ray> rays, std::span<Hit> hits, const TraceRequest& req,
                       ChunkPart part);

/// One line for a path_reason: "raced on N chunks: single X ns/ray, packet Y ns/ray (CPU): PATH".
std::string race_reason(const RaceOutcome& r);

}  // namespace arbor::accel
