#include "accel/interface/path_race.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <ctime>

#include "accel/interface/accel.h"

namespace arbor::accel {

namespace {
/// This thread's CPU time in nanoseconds: a preempted thread (a shared machine) does not count
/// the time it waited against the path it was running.
std::uint64_t thread_cpu_ns() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return std::uint64_t(ts.tv_sec) * 1000000000u + std::uint64_t(ts.tv_nsec);
}
}  // namespace

std::size_t race_chunk_count(std::size_t chunks) { return chunks < 32 ? 0 : chunks < 128 ? 4 : 8; }

bool race_settles(const PathChoice& c, const PathOffer& offer, const TraceRequest& req) {
    return req.query == Query::closest && req.counters == nullptr && c.why == PathChoice::Why::measured &&
           !c.one_octant && c.path == TracePath::packet && offer.runs(TracePath::single, req.query) &&
           offer.runs(TracePath::packet, req.query);
}

std::vector<std::size_t> race_chunk_ids(std::size_t chunks, std::size_t count) {
    std::vector<std::size_t> ids;
    for (std::size_t i = 0; i < count; ++i) ids.push_back(i * chunks / count);
    return ids;
}

RaceOutcome race_chunks(std::size_t chunks, std::size_t count,
                        const std::function<std::size_t(std::size_t chunk, TracePath path, ChunkPart part)>& run) {
    const std::vector<std::size_t> ids = race_chunk_ids(chunks, count);
    // Per path (0 single, 1 packet): CPU nanoseconds and rays of its halves.
    std::atomic<std::uint64_t> ns[2] = {0, 0}, rays[2] = {0, 0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ids.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            // Even i: single on the even blocks, first; odd i: packet on the even blocks, first.
            for (int half = 0; half < 2; ++half) {
                const int side = int((i + std::size_t(half)) % 2);  // 0 single, 1 packet
                const ChunkPart part = half == 0 ? ChunkPart::even_blocks : ChunkPart::odd_blocks;
                const std::uint64_t t0 = thread_cpu_ns();
                const std::size_t n = run(ids[i], side ? TracePath::packet : TracePath::single, part);
                ns[side] += thread_cpu_ns() - t0;
                rays[side] += n;
            }
        }
    });
    RaceOutcome out;
    out.chunks = count;
    out.single_ns = rays[0] ? double(ns[0]) / double(rays[0]) : 0.0;
    out.packet_ns = rays[1] ? double(ns[1]) / double(rays[1]) : 0.0;
    out.path = out.single_ns < out.packet_ns ? TracePath::single : TracePath::packet;
    std::vector<char> raced(chunks, 0);
    for (const std::size_t k : ids) raced[k] = 1;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t k = r.begin(); k != r.end(); ++k)
            if (!raced[k]) run(k, out.path, ChunkPart::all);
    });
    return out;
}

std::size_t trace_part(const Accel& accel, std::span<const Ray> rays, std::span<Hit> hits, const TraceRequest& req,
                       ChunkPart part) {
    if (part == ChunkPart::all) {
        accel.trace(rays, hits, req);
        return rays.size();
    }
    thread_local std::vector<Ray> in;
    thread_local std::vector<Hit> out;
    in.clear();
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (in_part(i, part)) in.push_back(rays[i]);
    out.resize(in.size());
    accel.trace(in, out, req);
    std::size_t j = 0;
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (in_part(i, part)) hits[i] = out[j++];
    return in.size();
}

std::string race_reason(const RaceOutcome& r) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "raced on %zu chunks: single %.1f ns/ray, packet %.1f ns/ray (CPU): %s", r.chunks,
                  r.single_ns, r.packet_ns, r.path == TracePath::single ? "single" : "packet");
    return buf;
}

}  // namespace arbor::accel
