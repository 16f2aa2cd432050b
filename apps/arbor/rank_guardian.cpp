#include "apps/arbor/rank_guardian.h"

#include "mpi/launcher.h"

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace arbor::app {

namespace {

/// The signals passed on to the rank: mpirun's way of stopping a job (SIGTERM, then SIGKILL after
/// a second), an interrupt, and the two it forwards on request.
constexpr int passed_on[] = {SIGTERM, SIGINT, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2};

volatile sig_atomic_t rank_pid = 0;
volatile sig_atomic_t launcher_pid = 0;
volatile sig_atomic_t stopped_by_launcher = 0;

/// Async-signal-safe: sigqueue only.
void pass_on(int sig, siginfo_t* info, void*) {
    const bool from_launcher = info->si_pid == launcher_pid;
    if (from_launcher) stopped_by_launcher = 1;
    sigval v{};
    v.sival_int = from_launcher ? 0 : info->si_pid > 0 ? int(info->si_pid) : -1;
    if (rank_pid > 0) ::sigqueue(pid_t(rank_pid), sig, v);
}

std::string signal_name(int sig) {
    const char* abbrev = ::sigabbrev_np(sig);
    std::string s = abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
    if (sig == SIGKILL) return s + " (kill -9, or the out-of-memory killer)";
    if (const char* text = ::strsignal(sig)) s += std::string(" (") + text + ")";
    return s;
}

[[noreturn]] void wait_for_rank(pid_t child, int rank) {
    int status = 0;
    while (::waitpid(child, &status, 0) < 0) {
        if (errno != EINTR) {
            std::fprintf(stderr, "arbor: rank %d: its guardian lost it (waitpid: %s)\n", rank, std::strerror(errno));
            ::_exit(4);
        }
    }
    if (WIFEXITED(status)) ::_exit(WEXITSTATUS(status));
    // Killed by a signal. When the launcher is stopping the job, that is why: it says so itself.
    if (!stopped_by_launcher) {
        char host[256] = {};
        ::gethostname(host, sizeof host - 1);
        std::fprintf(stderr, "arbor: rank %d (pid %ld on %s) was killed by %s; the job stops\n", rank, long(child), host,
                     signal_name(WTERMSIG(status)).c_str());
        std::fflush(stderr);
    }
    ::_exit(4);
}

}  // namespace

void guard_rank() {
    const mpi::Launch launch = mpi::detect_launch();
    if (!launch.launched) return;
    const pid_t guardian = ::getpid(), launcher = ::getppid();
    // Held from before the fork until the handlers are in place, so that none is lost.
    sigset_t held, before;
    sigemptyset(&held);
    for (int sig : passed_on) sigaddset(&held, sig);
    ::sigprocmask(SIG_BLOCK, &held, &before);
    const pid_t child = ::fork();
    if (child == 0) {
        ::prctl(PR_SET_PDEATHSIG, mpi::guardian_lost_signal());
        if (::getppid() != guardian) ::_exit(4);  // the guardian was gone before the line above
        const std::string ids = std::to_string(long(guardian)) + " " + std::to_string(long(launcher));
        ::setenv(mpi::guardian_variable, ids.c_str(), 1);
        ::sigprocmask(SIG_SETMASK, &before, nullptr);
        return;
    }
    if (child < 0) {  // no process to spare: run unguarded (a SIGKILL then makes mpirun exit 137)
        ::sigprocmask(SIG_SETMASK, &before, nullptr);
        return;
    }
    rank_pid = child;
    launcher_pid = launcher;
    struct sigaction sa = {};
    sigemptyset(&sa.sa_mask);
    sa.sa_sigaction = pass_on;
    sa.sa_flags = SA_SIGINFO | SA_RESTART;
    for (int sig : passed_on) ::sigaction(sig, &sa, nullptr);
    ::sigprocmask(SIG_SETMASK, &before, nullptr);
    wait_for_rank(child, launch.rank);
}

}  // namespace arbor::app
