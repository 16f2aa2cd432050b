#pragma once
/// Where the tiles of a frame are rendered: the renderer's one seam for scheduling. By default
/// (no source) render() runs this process's threads over every tile; a TileSource decides which
/// tiles this process renders and where their pixels go, e.g. the MPI tile farm of `mpirun arbor
/// render` (apps/arbor/cluster_tiles.h). Every tile is a pure function of its pixels' coordinates
/// (random numbers depend on seed, pixel, sample and dimension only), so any split of the tiles
/// over threads or processes gives the same image bit for bit.
#include "engine/image.h"
#include "engine/progress.h"
#include "engine/render_settings.h"

#include <algorithm>
#include <functional>

namespace arbor::engine {

/// The tiles of a width x height frame cut into size x size tiles, numbered row by row.
struct TileGrid {
    int width = 0, height = 0, size = 16;

    int columns() const { return (width + size - 1) / size; }
    int rows() const { return (height + size - 1) / size; }
    int count() const { return columns() * rows(); }
    /// Pixels [x0, x1) x [y0, y1) of tile `index`.
    void bounds(int index, int& x0, int& y0, int& x1, int& y1) const {
        const int tx = index % columns(), ty = index / columns();
        x0 = tx * size, y0 = ty * size;
        x1 = std::min(x0 + size, width), y1 = std::min(y0 + size, height);
    }
};

class TileSource {
public:
    virtual ~TileSource() = default;
    /// Calls `render_tile(i)` (from any thread, concurrently; it renders tile i into `image` and
    /// ticks nothing) for each tile this process renders, ticks `progress` for every tile of the
    /// frame it learns is finished, and returns once `image` holds every tile this process keeps
    /// (all of them on the process that writes the frame).
    virtual void run(const TileGrid& grid, Image& image, Progress& progress,
                     const std::function<void(int)>& render_tile) = 0;
    /// Called with this process's statistics once run() has returned; turns them into the
    /// frame's (e.g. rays summed over every process). The default keeps them.
    virtual void gather(RenderStats& stats) { (void)stats; }
    /// Whether this process shows the frame's progress (the one that writes it).
    virtual bool shows_progress() const { return true; }
    /// Whether that progress reaches a terminal although stderr is not one (Progress's `terminal`).
    virtual bool progress_to_terminal() const { return false; }
};

}  // namespace arbor::engine
