#pragma once
/// Racing the two SIMD paths on the one kind of batch the coherence measure cannot call.
///
/// The path policy (path_policy.h) reads the rays: groups that share an octant and a place are
/// coherent (packets win), scattered origins are not (single rays win). Groups that start together
/// but go every way (bounces from an image tile: diffuse rays) are neither. Which path wins on
/// them depends on the model and the machine: on held-out diffuse rays the single path beat the
/// packet path by 10-18 % on four models and lost by 3x on two small ones (docs/benchmarks.md). No
/// rule read off the rays calls that, so such a batch, when it is large enough, is raced: a few
/// pairs of neighbouring chunks, spread over the batch, run one chunk on each path, timed on their
/// thread's CPU clock; the rest of the batch runs on the path that took less time per ray.
///
/// Only closest-hit batches are raced: every path returns the same closest hit bit for bit (the
/// tests hold each path to brute force), so a race changes the time and never the answers. An
/// any-hit answer may name a different blocking triangle on each path, so those batches keep the
/// policy's own choice, and a run's answers stay the same run to run.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "accel/interface/path_policy.h"

namespace arbor::accel {

/// What a race measured.
struct RaceOutcome {
    /// The path the rest of the batch ran on; `best` when no race was run.
    TracePath path = TracePath::best;
    /// Chunks each path ran during the race.
    std::size_t chunks_each = 0;
    /// Thread CPU time per ray on each path's race chunks, in nanoseconds.
    double single_ns = 0.0, packet_ns = 0.0;
    bool raced() const { return path != TracePath::best; }
};

/// Pairs of chunks a race of a batch of `chunks` chunks spends: 0 below 32 chunks (too few for a
/// race to pay), 4 up to 127 chunks, 8 from 128 on.
std::size_t race_pairs(std::size_t chunks);

/// Whether a batch the policy answered with `c`, asked as `req`, is one a race settles: closest-hit
/// rays measured as starting together without sharing an octant (PathChoice::Why::measured, not
/// one_octant, together >= the packet share), on a structure offering both SIMD paths for them.
bool race_settles(const PathChoice& c, const PathOffer& offer, const TraceRequest& req);

/// The race's chunks of a batch of `chunks` (chunks >= 2 * pairs): pair p is the neighbouring chunks
/// q and q + 1 at q = p * chunks / pairs (spread over the batch, each pair over nearly the same
/// rays), q run on `single`, q + 1 on `packet`. In pair order, q then q + 1.
std::vector<std::size_t> race_chunk_ids(std::size_t chunks, std::size_t pairs);

/// Runs every chunk k of [0, chunks) once with run_chunk(k, path), which traces chunk k on `path`
/// and returns its ray count: the race's chunks first (race_chunk_ids, in parallel, each timed on
/// its thread's CPU clock), then all others, in parallel, on the path with less CPU time per ray
/// (ties: packet). Uses tbb::parallel_for: call it inside the task arena that is to run it.
RaceOutcome race_chunks(std::size_t chunks, std::size_t pairs,
                        const std::function<std::size_t(std::size_t chunk, TracePath path)>& run_chunk);

/// One line for a path_reason: "raced on N chunk pairs: single X ns/ray, packet Y ns/ray (CPU): PATH".
std::string race_reason(const RaceOutcome& r);

}  // namespace arbor::accel
