/// `arbor view [SCENE] [--port N] [--listen ADDR] [--accel NAME] [--threads N]` (spec/cli.md): the
/// live viewer. Loads the scene, serves the page (view/server.h), prints its address as the first
/// line of standard output, and runs until SIGINT or SIGTERM, then closes every page (their renders
/// are cancelled) and exits 0.
#include "apps/arbor/commands.h"
#include "apps/arbor/common.h"
#include "apps/arbor/render_options.h"
#include "apps/arbor/scene_options.h"
#include "view/server.h"

#include <arpa/inet.h>

#include <csignal>
#include <cstdio>
#include <pthread.h>
#include <thread>

namespace arbor::app {

namespace {

struct ViewCommand {
    SceneOptions scene;
    std::string listen = "127.0.0.1", accel = "bvh-sah", integrator = "direct";
    int port = 8080, threads = 0, max_clients = 8, max_connections = 512;
    accel::BuildConfig build;
};

int run_view(const ViewCommand& o) {
    // Every thread started from here on (the connection loop, TBB's, the pages' workers) inherits this mask,
    // so SIGINT and SIGTERM reach only the sigwait below: the shutdown runs in this thread, never
    // inside a signal handler.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    const auto limit = limit_threads(o.threads);
    const engine::Scene scene = load_scene(o.scene, true, true);
    view::ServerOptions opt;
    opt.listen = o.listen;
    opt.port = o.port;
    opt.max_clients = o.max_clients;
    opt.connections.max_connections = o.max_connections;
    opt.limits.max_threads = active_threads();
    opt.initial.threads = opt.limits.max_threads;
    opt.initial.accel = *accel::parse_accel_kind(o.accel);
    opt.initial.integrator = parse_integrator_option(o.integrator);
    view::Server server(scene, o.build, opt);
    try {
        server.start();
    } catch (const std::runtime_error& e) {
        throw engine::InputError(e.what());
    }
    std::printf("%s\n", server.url().c_str());
    std::printf(
        "arbor view: %s, %llu triangles; up to %d pages and %d connections at once, %d threads; Ctrl-C stops\n",
        scene.name.c_str(),
        (unsigned long long)(scene.placed.empty() ? scene.mesh.triangle_count() : scene.placed.effective_triangles()),
        o.max_clients, server.max_connections(), opt.limits.max_threads);
    std::fflush(stdout);
    int sig = 0;
    sigwait(&stop_signals, &sig);
    std::fprintf(stderr, "arbor view: %s: closing every page\n", sig == SIGINT ? "SIGINT" : "SIGTERM");
    server.stop();
    std::fprintf(stderr, "arbor view: stopped\n");
    return 0;
}

}  // namespace

Run add_view(CLI::App& cmd) {
    auto o = std::make_shared<ViewCommand>();
    add_scene_options(cmd, o->scene);
    cmd.add_option("--port", o->port, "TCP port (0: any free port; the first line of output says which)")
        ->check(CLI::Range(0, 65535))
        ->capture_default_str();
    cmd.add_option("--listen", o->listen,
                   "address to listen on (numeric; default 127.0.0.1, this machine only; 0.0.0.0 opens the viewer to "
                   "the network)")
        ->check([](const std::string& v) -> std::string {
            unsigned char buf[16];
            const bool v6 = v.find(':') != std::string::npos;
            if (inet_pton(v6 ? AF_INET6 : AF_INET, v.c_str(), buf) == 1) return {};
            return "'" + v + "' is not a numeric IPv4 or IPv6 address";
        })
        ->capture_default_str();
    cmd.add_option("--accel", o->accel, "the structure a page starts with: " + accel::accel_kind_names())
        ->check([](const std::string& v) -> std::string {
            const auto k = accel::parse_accel_kind(v);
            if (k && *k != accel::AccelKind::automatic) return {};
            return "unknown structure '" + v + "' (auto is not offered here)";
        })
        ->capture_default_str();
    cmd.add_option("--integrator", o->integrator, "the integrator a page starts with: " + engine::integrator_names())
        ->check(parse_check("--integrator", parse_integrator_option))
        ->capture_default_str();
    cmd.add_option("--max-clients", o->max_clients, "pages served at once")->check(CLI::Range(1, 64))->capture_default_str();
    cmd.add_option(
           "--max-connections", o->max_connections,
           "connections open at once (pages, requests, idle sockets); at the cap the oldest idle one is dropped")
        ->check(CLI::Range(16, 65536))
        ->capture_default_str();
    add_build_options(cmd, o->build);
    add_threads_option(cmd, o->threads);
    return [o] { return run_view(*o); };
}

}  // namespace arbor::app
