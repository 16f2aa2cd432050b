#include "apps/arbor/cluster.h"

#include "engine/error.h"
#include "engine/file_io.h"
#include "engine/scene_hash.h"
#include "mpi/launcher.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace arbor::app {

namespace {

std::unique_ptr<Cluster>& the_cluster() {
    static std::unique_ptr<Cluster> c;
    return c;
}

#ifdef ARBOR_HAVE_MPI
/// Where arbor_mpi.so may be: $ARBOR_MPI_MODULE, beside the executable, where the build tree has it
/// (for arbor-bench, which is built in perf/), or where `cmake --install` put it.
std::vector<std::string> module_candidates() {
    if (const char* env = std::getenv("ARBOR_MPI_MODULE"); env && *env) return {env};
    std::vector<std::string> out;
    std::error_code ec;
    const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) out.push_back((exe.parent_path() / "arbor_mpi.so").string());
    if (out.empty() || out.front() != ARBOR_MPI_MODULE_BUILD) out.push_back(ARBOR_MPI_MODULE_BUILD);
    out.push_back(ARBOR_MPI_MODULE_INSTALLED);
    return out;
}

mpi::Job* open_job() {
    std::string tried;
    for (const std::string& path : module_candidates()) {
        if (!std::filesystem::exists(path)) {
            tried += (tried.empty() ? "" : ", ") + path;
            continue;
        }
        // RTLD_GLOBAL: Open MPI's own plugins look for libmpi's symbols in the global scope.
        void* module = ::dlopen(path.c_str(), RTLD_NOW | RTLD_GLOBAL);
        if (!module) throw engine::InputError("MPI: cannot load " + path + ": " + ::dlerror());
        using Open = mpi::Job* (*)(int, std::string*);
        auto open = reinterpret_cast<Open>(::dlsym(module, "arbor_mpi_open"));
        if (!open) throw engine::InputError("MPI: " + path + " has no arbor_mpi_open");
        std::string error;
        mpi::Job* job = open(mpi::job_abi_version, &error);
        if (!job) throw engine::InputError("MPI: " + error);
        return job;  // the module stays loaded for the life of the process
    }
    throw engine::InputError("MPI: the module arbor_mpi.so is missing (looked for " + tried +
                             "; set ARBOR_MPI_MODULE to its path)");
}
#else
mpi::Job* open_job() {
    throw engine::InputError(
        "MPI: this arbor was built without MPI (ARBOR_MPI off, or no MPI library found when it was configured): "
        "under mpirun every process would render the whole frame alone; install libopenmpi-dev and rebuild, or "
        "run without mpirun");
}
#endif

}  // namespace

Cluster* Cluster::join(bool force) {
    if (the_cluster()) return the_cluster().get();
    if (!force && !mpi::detect_launch().launched) return nullptr;
    the_cluster().reset(new Cluster(open_job()));
    // A job stopped by MPI_Abort or by mpirun ends without unwinding: no half-written output may stay.
    the_cluster()->job_->set_cleanup(engine::remove_unfinished_files);
    if (!the_cluster()->root()) {
        // "The other ranks print nothing on standard output": the same code runs on every rank.
        std::fflush(stdout);
        const int devnull = ::open("/dev/null", O_WRONLY);
        if (devnull >= 0) {
            ::dup2(devnull, 1);
            ::close(devnull);
        }
    }
    return the_cluster().get();
}

Cluster* Cluster::current() { return the_cluster().get(); }

void Cluster::leave() {
    std::fflush(stdout);
    the_cluster().reset();
}

std::string Cluster::on_ranks() const { return " on " + std::to_string(size()) + (size() == 1 ? " rank" : " ranks"); }

void Cluster::require_same(const engine::Scene& scene, const std::string& settings) {
    job_->require_same("its scene is not rank 0's", engine::scene_hash(scene),
                       "every rank must load the same scene (the same file contents on every machine); refused "
                       "before rendering");
    engine::Hasher h;
    h.text(settings);
    job_->require_same("its settings are not rank 0's", h.value(),
                       "every rank must be given the same options that change the result (rank 0: " + settings + ")");
}

std::string Cluster::root_choice(const std::string& value) { return job_->broadcast(value); }

void add_mpi_option(CLI::App& cmd, bool& flag) {
    cmd.add_flag("--mpi", flag,
                 "join an MPI job even when no launcher variable (OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK) is set; "
                 "under mpirun this happens by itself");
}

std::string settings_text(const engine::RenderSettings& s) {
    const engine::Layers l = s.resolved_layers();
    char buf[256];
    std::snprintf(buf, sizeof buf, "%dx%d, %d spp, %s, depth %d, tile %d, seed %u, jitter %d, layers %d%d%d, ao %d %g, rr %d",
                  s.width, s.height, s.spp, std::string(engine::to_string(s.integrator)).c_str(), s.depth(), s.tile,
                  s.seed, int(s.jitter), int(l.depth), int(l.normal), int(l.albedo), s.ao_samples, double(s.ao_radius),
                  s.rr_depth);
    return buf;
}

}  // namespace arbor::app
