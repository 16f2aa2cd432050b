#pragma once
/// Was this process started by an MPI launcher? Read from the environment the launcher sets, so
/// that a plain `arbor` call never loads or initialises MPI. Header-only, no MPI dependency: the
/// benchmark binary and builds without MPI use it too.
#include <csignal>
#include <cstdlib>
#include <string>

namespace arbor::mpi {

struct Launch {
    bool launched = false;  ///< a launcher's variables are set
    int size = 0;           ///< processes in the job (0: the launcher does not say)
    int rank = 0;           ///< this process's rank (0 when unknown)
    std::string variable;   ///< the variable that told
};

/// Open MPI's mpirun sets OMPI_COMM_WORLD_SIZE/RANK; MPICH's and Intel MPI's Hydra PMI_SIZE/RANK;
/// PMIx launchers (Open MPI 4+, Slurm's srun --mpi=pmix) PMIX_RANK.
inline Launch detect_launch() {
    auto get = [](const char* name) -> const char* {
        const char* v = std::getenv(name);
        return v && *v ? v : nullptr;
    };
    auto number = [](const char* v) { return v ? std::atoi(v) : 0; };
    Launch l;
    if (const char* s = get("OMPI_COMM_WORLD_SIZE")) {
        l = {true, number(s), number(get("OMPI_COMM_WORLD_RANK")), "OMPI_COMM_WORLD_SIZE"};
    } else if (const char* p = get("PMI_SIZE")) {
        l = {true, number(p), number(get("PMI_RANK")), "PMI_SIZE"};
    } else if (const char* x = get("PMIX_RANK")) {
        l = {true, 0, number(x), "PMIX_RANK"};
    }
    return l;
}

/// Under a launcher each rank runs under a guardian process (apps/arbor/rank_guardian.h), which
/// tells the rank its own and the launcher's process ids in this variable: "GUARDIAN LAUNCHER".
inline constexpr const char* guardian_variable = "ARBOR_RANK_GUARDIAN";
/// A signal the guardian passes on (sigqueue) carries 0 when it came from the launcher (mpirun
/// stopping the job), otherwise the process id of its sender (-1: unknown).

/// The signal a rank receives when its guardian dies (PR_SET_PDEATHSIG). Its default action ends
/// the rank, as SIGKILL would; once MPI is up the rank catches it and reports its guardian's death
/// (mpi/faults_mpi.cpp). A real-time signal, so that nothing else sends it.
inline int guardian_lost_signal() { return SIGRTMIN + 2; }

}  // namespace arbor::mpi
