/// Signals under MPI. A crash (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT) on an application thread
/// is held in its handler while the service thread reports it to rank 0, which prints one line
/// and stops the job with exit status 4; after 10 s without that, the signal takes its default
/// course (mpirun then reports the death itself). SIGTERM, SIGINT and SIGHUP (mpirun stopping the
/// job because a rank died, or an interrupt) are noted, and the service thread ends the process;
/// rank 0 first says which rank of its host is gone. Handlers only touch atomics and sleep
/// (async-signal-safe); everything else happens on the service thread. They replace Open MPI's
/// own crash handlers (which print a backtrace and die at once).
#include "mpi/job_mpi.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <pthread.h>
#include <string>

namespace arbor::mpi::detail {

namespace {

std::atomic<int> crash_signal{0}, stop_signal{0};
pthread_t service_thread_handle;

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

void on_stop(int sig) {
    int none = 0;
    stop_signal.compare_exchange_strong(none, sig);
}

}  // namespace

void install_signal_handlers() {
    service_thread_handle = pthread_self();  // called on the service thread
    struct sigaction sa = {};
    sigemptyset(&sa.sa_mask);
    sa.sa_handler = on_crash;
    sa.sa_flags = SA_NODEFER;  // a second crash on another thread is held too
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) ::sigaction(sig, &sa, nullptr);
    sa.sa_handler = on_stop;
    sa.sa_flags = SA_RESTART;
    for (int sig : {SIGTERM, SIGINT, SIGHUP}) ::sigaction(sig, &sa, nullptr);
}

int caught_crash_signal() { return crash_signal.load(); }
int caught_stop_signal() { return stop_signal.load(); }

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

bool process_gone(long pid) {
    if (::kill(pid_t(pid), 0) == -1 && errno == ESRCH) return true;
    char path[64];
    std::snprintf(path, sizeof path, "/proc/%ld/stat", pid);
    std::FILE* f = std::fopen(path, "r");
    if (!f) return false;
    char state = 0;
    const int got = std::fscanf(f, "%*d (%*[^)]) %c", &state);
    std::fclose(f);
    return got == 1 && state == 'Z';
}

}  // namespace arbor::mpi::detail
