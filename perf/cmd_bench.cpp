/// `arbor-bench bench` (= `arbor bench`; perf/README.md): the benchmark matrix. Validates every
/// configuration first, then times it, and writes bench.json, bench.csv and bench.md into --out.
/// Under mpirun
/// (spec/cli.md, "Across machines") the scenes are handed out to the ranks one at a time, each
/// scene wholly on one rank (its builds, its interleaved repeats and its rows stay one machine's),
/// and rank 0 merges every scene's rows, in plan order, into the same report. Only
/// --ranks-per-node ranks of one machine (MPI_COMM_TYPE_SHARED, i.e. mpirun's host list) time
/// rows at once, so that rows sharing a machine do not share its cores unless asked to.
#include "apps/arbor/cluster.h"
#include "apps/arbor/program.h"
#include "perf/commands.h"
#include "engine/scene_hash.h"
#include "perf/bench_cli.h"
#include "perf/bench_wire.h"

namespace arbor::perf {

using app::Cluster;

namespace {

struct BenchMpi {
    bool mpi = false;
    int ranks_per_node = 1;
};

std::vector<BenchResult> share_scenes(Cluster& c, int ranks_per_node, std::size_t count,
                                            const std::function<BenchResult(std::size_t)>& job) {
    std::vector<std::string> received(count);  // rank 0: other ranks' scenes
    mpi::FarmSpec spec;
    spec.items = count;
    spec.batch = 1;
    spec.low_water = 0;  // ask for the next scene only when idle: no scene waits behind a long one
    spec.take = c.job().node_rank() < ranks_per_node;
    auto farm = c.job().farm(spec, [&](std::uint64_t i, std::string_view bytes) { received[i] = bytes; });
    std::vector<BenchResult> mine(c.root() ? count : 0);
    std::uint64_t i = 0;
    while (farm->next(i)) {
        BenchResult part = job(std::size_t(i));
        if (c.root()) {
            mine[i] = std::move(part);
            farm->done(i, {});
        } else {
            farm->done(i, to_wire(part));
        }
    }
    farm->finish();
    if (!c.root()) return {};
    for (std::size_t k = 0; k < count; ++k)
        if (!received[k].empty()) mine[k] = from_wire(received[k]);
    return mine;
}

}  // namespace

std::function<int()> add_bench_command(CLI::App& cmd) {
    const auto command = add_bench_options(cmd);
    auto m = std::make_shared<BenchMpi>();
    app::add_mpi_option(cmd, m->mpi);
    cmd.add_option("--ranks-per-node", m->ranks_per_node,
                   "under mpirun: how many ranks of one machine time rows at the same time (default 1: rows never "
                   "share a machine's cores; more only when each rank has cores of its own, e.g. mpirun --bind-to "
                   "core, and --threads fits them)")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    return [command, m] {
        BenchRunContext ctx;
        ctx.program = app::program_name() + " bench";
        ctx.command = app::command_line();
        Cluster* const cluster = Cluster::join(m->mpi);
        if (cluster) {
            const BenchOptions o = bench_options(*command);
            std::string settings = std::to_string(o.rays) + " rays, " + std::to_string(o.repeats) + " repeats, seed " +
                                   std::to_string(o.seed) + ", scenes";
            for (const auto& s : o.scenes) settings += " " + s;
            for (const auto& k : o.kinds) settings += " " + k;
            for (const auto& s : o.structures) settings += " " + s;
            for (const int t : o.threads) settings += " " + std::to_string(t);
            engine::Hasher h;
            h.text(settings);
            cluster->job().require_same("its benchmark options are not rank 0's", h.value(),
                                        "every rank must be given the same options (rank 0: " + settings + ")");
            ctx.share = [cluster, m](std::size_t count, const std::function<BenchResult(std::size_t)>& job) {
                return share_scenes(*cluster, m->ranks_per_node, count, job);
            };
            ctx.writes = cluster->root();
            ctx.on_ranks = cluster->on_ranks();
            ctx.rank = cluster->rank();
        }
        return run_bench_command(*command, ctx);
    };
}

}  // namespace arbor::perf
