/// The frame's tiles over the ranks of an MPI job: a TileSource (engine/tile_source.h) on a farm
/// of mpi/job.h. Every rank renders the tiles rank 0 grants it with all its threads (asking for
/// as many tiles as it has threads whenever fewer are queued, so a slow rank takes fewer) and
/// sends each finished tile's pixels to rank 0 at once; rank 0 renders too, stores what arrives
/// and shows the whole frame's progress. The tiles' pixels are the single-process render's, so
/// the assembled image is the same bit for bit.
#include "apps/arbor/cluster.h"

#include "mpi/launcher.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>

namespace arbor::app {

namespace {

/// The pixels of `tile` in `img`, channel by channel, row by row.
std::string pack_tile(const engine::TileGrid& grid, const engine::Image& img, int tile) {
    int x0, y0, x1, y1;
    grid.bounds(tile, x0, y0, x1, y1);
    const std::size_t row = std::size_t(x1 - x0) * sizeof(float);
    std::string out(img.planes.size() * std::size_t(y1 - y0) * row, '\0');
    char* p = out.data();
    for (const auto& plane : img.planes)
        for (int y = y0; y < y1; ++y, p += row)
            std::memcpy(p, plane.data() + std::size_t(y) * std::size_t(img.width) + std::size_t(x0), row);
    return out;
}

void unpack_tile(const engine::TileGrid& grid, engine::Image& img, int tile, std::string_view bytes) {
    int x0, y0, x1, y1;
    grid.bounds(tile, x0, y0, x1, y1);
    const std::size_t row = std::size_t(x1 - x0) * sizeof(float);
    if (bytes.size() != img.planes.size() * std::size_t(y1 - y0) * row) return;  // not this frame's
    const char* p = bytes.data();
    for (auto& plane : img.planes)
        for (int y = y0; y < y1; ++y, p += row)
            std::memcpy(plane.data() + std::size_t(y) * std::size_t(img.width) + std::size_t(x0), p, row);
}

class FarmTiles final : public engine::TileSource {
public:
    explicit FarmTiles(Cluster& c) : cluster_(c) {}

    void run(const engine::TileGrid& grid, engine::Image& image, engine::Progress& progress,
             const std::function<void(int)>& render_tile) override {
        threads_ = int(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
        const bool root = cluster_.root();
        mpi::FarmSpec spec;
        spec.items = std::uint64_t(grid.count());
        spec.batch = spec.low_water = threads_;
        spec.take = !(root && cluster_.size() > 1 && root_idle());
        auto farm = cluster_.job().farm(spec, [&](std::uint64_t tile, std::string_view pixels) {
            unpack_tile(grid, image, int(tile), pixels);
            progress.tick();
        });
        std::atomic<long> rendered{0};
        tbb::parallel_for(
            tbb::blocked_range<int>(0, threads_, 1),
            [&](const tbb::blocked_range<int>& slots) {
                for (int s = slots.begin(); s < slots.end(); ++s) {
                    std::uint64_t tile = 0;
                    while (farm->next(tile)) {
                        render_tile(int(tile));
                        inject_test_fault(cluster_.rank(), ++rendered);
                        if (root) {
                            farm->done(tile, {});
                            progress.tick();
                        } else {
                            farm->done(tile, pack_tile(grid, image, int(tile)));
                        }
                    }
                }
            },
            tbb::simple_partitioner());
        farm->finish();
    }

    void gather(engine::RenderStats& stats) override {
        std::vector<double> v{double(stats.threads)};
        for (std::size_t k = 0; k < engine::render_ray_kind_count; ++k) v.push_back(double(stats.rays[k]));
        for (std::size_t k = 0; k < engine::render_ray_kind_count; ++k) v.push_back(stats.trace_seconds[k]);
        v = cluster_.job().sum(v);
        // Rays and trace times summed over every thread of every rank; the wall time stays rank
        // 0's, which covers the whole frame.
        stats.threads = int(v[0]);
        for (std::size_t k = 0; k < engine::render_ray_kind_count; ++k) {
            stats.rays[k] = std::uint64_t(v[1 + k]);
            stats.trace_seconds[k] = v[1 + engine::render_ray_kind_count + k];
        }
    }

    bool shows_progress() const override { return cluster_.root(); }
    /// Rank 0's stderr is a pipe to mpirun, which copies it to its own: a terminal, when mpirun
    /// runs on one and is this process's parent (rank 0 on mpirun's machine).
    bool progress_to_terminal() const override {
        char path[64];
        std::snprintf(path, sizeof path, "/proc/%d/fd/2", int(::getppid()));
        const int fd = ::open(path, O_WRONLY | O_NOCTTY);
        if (fd < 0) return false;
        const bool tty = ::isatty(fd) == 1;
        ::close(fd);
        return tty;
    }

private:
    /// ARBOR_MPI_ROOT_RENDERS=0: rank 0 only hands out tiles (to measure what its rendering costs).
    static bool root_idle() {
        const char* v = std::getenv("ARBOR_MPI_ROOT_RENDERS");
        return v && std::string(v) == "0";
    }

    Cluster& cluster_;
    int threads_ = 1;
};

}  // namespace

std::unique_ptr<engine::TileSource> Cluster::frame_tiles() { return std::make_unique<FarmTiles>(*this); }

void inject_test_fault(int rank, long tiles_done) {
    struct Fault {
        int rank = -1;
        long tiles = 0;
        std::string kind;
    };
    static const Fault fault = [] {
        Fault f;
        const char* v = std::getenv("ARBOR_MPI_TEST_FAULT");
        if (!v) return f;
        char kind[16] = {};
        if (std::sscanf(v, "%d:%ld:%15s", &f.rank, &f.tiles, kind) == 3) f.kind = kind;
        return f;
    }();
    if (rank != fault.rank || tiles_done != fault.tiles) return;
    if (fault.kind == "abort") std::abort();
    if (fault.kind == "segv") std::raise(SIGSEGV);
    if (fault.kind == "kill") std::raise(SIGKILL);
    if (fault.kind == "term") std::raise(SIGTERM);                    // as a user's `kill PID` would
    if (fault.kind == "term-guardian") ::kill(::getppid(), SIGTERM);  // a `kill` of the rank's guardian
    // A rank that stops (as SIGSTOP or Ctrl-Z on its machine would) and stays stopped.
    if (fault.kind == "stop") std::raise(SIGSTOP);
    // mpirun interrupted (as by Ctrl-C in its terminal), or the rank's guardian killed: this
    // thread then holds its tile, so the frame cannot end before the job is stopped.
    if (fault.kind == "interrupt" || fault.kind == "kill-guardian") {
        long guardian = 0, launcher = 0;
        if (const char* ids = std::getenv(mpi::guardian_variable)) std::sscanf(ids, "%ld %ld", &guardian, &launcher);
        if (fault.kind == "interrupt" && launcher > 0) ::kill(pid_t(launcher), SIGINT);
        if (fault.kind == "kill-guardian" && guardian > 0) ::kill(pid_t(guardian), SIGKILL);
        ::sleep(30);
    }
    if (fault.kind == "throw") throw std::runtime_error("test fault after " + std::to_string(tiles_done) + " tiles");
    if (fault.kind == "oom") throw std::bad_alloc();
}

}  // namespace arbor::app
