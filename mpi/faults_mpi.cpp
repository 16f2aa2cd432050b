/// Signals under MPI. A crash (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT) on an application thread
/// is held in its handler while the service thread reports it to rank 0, which prints one line
/// and stops the job with exit status 4; after 10 s without that, the signal takes its default
/// course (the rank's guardian, apps/arbor/rank_guardian.h, then reports the death). SIGTERM,
/// SIGINT and SIGHUP are told apart by their sender: from the launcher (mpirun stopping the job
/// because a rank failed, which it reports itself, or rank 0's MPI_Abort) the service thread ends
/// the process quietly; from anyone else (a user's `kill`) they are a fault like any other,
/// reported by rank 0 with the sender, exit 4. The death of the rank's guardian (its parent, the
/// process the launcher started) is noted for the service thread too. Handlers only touch atomics and sleep
/// (async-signal-safe); everything else happens on the service thread. They replace Open MPI's
/// own crash handlers (which print a backtrace and die at once).
#include "mpi/job_mpi.h"
#include "mpi/launcher.h"

#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>

namespace arbor::mpi::detail {

namespace {

std::atomic<int> crash_signal{0}, stop_signal{0};
std::atomic<long> stop_sender{-1};
std::atomic<bool> launcher_stop{false}, guardian_gone{false};
pthread_t service_thread_handle;
long guardian_pid = 0, launcher_pid = 0;  ///< from mpi::guardian_variable (0: none)

void hold(int seconds) {
    for (int i = 0; i < seconds * 100; ++i) {
        timespec ts{0, 10'000'000};
        ::nanosleep(&ts, nullptr);
    }
}

void on_crash(int sig) {
    int none = 0;
    crash_signal.compare_exchange_strong(none, sig);
    // The service thread cannot report its own crash: it dies at once. Any other thread waits
    // to be stopped with the job (MPI_Abort, or mpirun's SIGTERM).
    if (!pthread_equal(pthread_self(), service_thread_handle)) hold(10);
    ::signal(sig, SIG_DFL);
    ::raise(sig);
}

void on_stop(int sig, siginfo_t* info, void*) {
    long sender = info->si_pid > 0 ? long(info->si_pid) : -1;
    if (info->si_code == SI_QUEUE && guardian_pid > 0 && sender == guardian_pid) {
        sender = info->si_value.sival_int;  // passed on by the guardian: its sender, 0 the launcher
    } else if (sender > 0 && (sender == launcher_pid || (guardian_pid == 0 && sender == long(::getppid())))) {
        sender = 0;  // the launcher signals the rank's process group too; without a guardian, its parent
    }
    if (sender == 0) {
        launcher_stop.store(true);
        return;
    }
    int none = 0;
    if (stop_signal.compare_exchange_strong(none, sig)) stop_sender.store(sender);
}

void on_guardian_lost(int) { guardian_gone.store(true); }

}  // namespace

void install_signal_handlers() {
    service_thread_handle = pthread_self();  // called on the service thread
    if (const char* ids = std::getenv(guardian_variable))
        if (std::sscanf(ids, "%ld %ld", &guardian_pid, &launcher_pid) != 2) guardian_pid = launcher_pid = 0;
    struct sigaction sa = {};
    sigemptyset(&sa.sa_mask);
    sa.sa_handler = on_crash;
    sa.sa_flags = SA_NODEFER;  // a second crash on another thread is held too
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::sigaction(sig, &sa, nullptr);
    sa.sa_handler = nullptr;
    sa.sa_sigaction = on_stop;
    sa.sa_flags = SA_RESTART | SA_SIGINFO;
    for (int sig : {SIGTERM, SIGINT, SIGHUP}) ::sigaction(sig, &sa, nullptr);
    if (guardian_pid > 0) {
        sa = {};
        sigemptyset(&sa.sa_mask);
        sa.sa_handler = on_guardian_lost;
        sa.sa_flags = SA_RESTART;
        ::sigaction(guardian_lost_signal(), &sa, nullptr);
        // The guardian may have died before the handler was in place (its signal then ended this
        // process, unless it died in the instant between the two).
        if (::getppid() != pid_t(guardian_pid)) guardian_gone.store(true);
    }
}

int caught_crash_signal() { return crash_signal.load(); }
int caught_stop_signal() { return stop_signal.load(); }
long stop_signal_sender() { return stop_sender.load(); }
bool stopped_by_launcher() { return launcher_stop.load(); }
bool guardian_lost() { return guardian_gone.load(); }
long guardian_process() { return guardian_pid; }

std::string signal_text(int sig) {
    switch (sig) {
        case SIGSEGV: return "SIGSEGV (segmentation fault)";
        case SIGBUS: return "SIGBUS (bus error)";
        case SIGFPE: return "SIGFPE (arithmetic exception)";
        case SIGILL: return "SIGILL (illegal instruction)";
        case SIGABRT: return "SIGABRT (aborted)";
        case SIGTERM: return "SIGTERM";
        case SIGINT: return "SIGINT";
        case SIGHUP: return "SIGHUP";
        default: return "signal " + std::to_string(sig);
    }
}

}  // namespace arbor::mpi::detail
