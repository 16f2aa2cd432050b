#include "apps/arbor/program.h"

#include <cstdio>
#include <new>

#include "accel/factory/memory_estimate.h"
#include "apps/arbor/cluster.h"
#include "mpi/launcher.h"

namespace arbor::app {

int failure(int code, const std::string& what) {
    if (Cluster* c = Cluster::current()) c->fail(code, what);
    const mpi::Launch launch = mpi::detect_launch();
    if (!launch.launched || launch.rank == 0) std::fprintf(stderr, "%s: %s\n", program_name().c_str(), what.c_str());
    return code;
}

int run_guarded(CLI::App& app, const std::function<int()>& parse_and_run) {
    try {
        const int status = parse_and_run();
        Cluster* cluster = Cluster::current();
        if (status != 0 && cluster) cluster->fail(status, "stopped with exit status " + std::to_string(status));
        Cluster::leave();
        return status;
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return failure(2, e.what());
    } catch (const accel::MemoryLimitError& e) {
        return failure(1, std::string("--max-memory: ") + e.what());
    } catch (const OptionError& e) {
        return failure(2, e.what());
    } catch (const engine::InputError& e) {
        return failure(1, e.what());
    } catch (const std::bad_alloc&) {
        return failure(3, "out of memory");
    } catch (const std::exception& e) {
        return failure(4, e.what());
    }
}

}  // namespace arbor::app
