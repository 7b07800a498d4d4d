// culinarycut-server: a long-running simulation server. Start it once; clients connect over gRPC.
#include <malloc.h>
#include <pthread.h>

#include <chrono>
#include <csignal>

#include <sys/resource.h>
#include <cstdlib>
#include <cstdio>
#include <future>
#include <iostream>
#include <thread>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "server/simulation_server.h"
#include "server/version.h"
#include "sim/mpm/kernel_instruction_set.h"

namespace {

pthread_t main_thread;

// Async-signal-safe: pthread_kill only queues the signal for main, which has it blocked until it waits.
extern "C" void ForwardStopSignalToMain(int signal) { pthread_kill(main_thread, signal); }

}  // namespace

int main(int argc, char** argv) {
  // Many sessions run MPM on gRPC's threads at once: OpenMP threads that spin while waiting would
  // steal the cores from each other, so they sleep instead (unless the user chose otherwise).
  setenv("OMP_WAIT_POLICY", "PASSIVE", /*overwrite=*/0);
  culinarycut::server::ServerOptions options;
  std::string log_level = "info";
  CLI::App app{"CulinaryCut simulation server: a Franka Panda with a knife, served over gRPC (culinarycut.v1)"};
  app.add_option("--listen", options.listen_address, "gRPC listen address: host:port (port 0 picks a free one) or unix:///path.sock")
      ->capture_default_str();
  app.add_option("--telemetry", options.telemetry_endpoint,
                 "ZeroMQ PUB endpoint for telemetry, e.g. tcp://127.0.0.1:5556 or ipc:///path (default: off)")
      ->capture_default_str();
  app.add_option("--max-sessions", options.max_sessions, "most sessions served at once")
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  app.add_option("--max-sessions-per-owner", options.max_sessions_per_owner,
                 "most sessions one client (bearer token, or client certificate under mutual TLS) holds at once; "
                 "0: --max-sessions (clients on loopback without tokens count as one)")
      ->capture_default_str()
      ->check(CLI::Range(0, 4096));
  app.add_option("--idle-timeout", options.idle_timeout_s, "seconds after which an untouched session is closed")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 1e7));
  app.add_option("--snapshot-key-file", options.snapshot_key_file,
                 "file of >= 32 secret bytes that authenticates snapshots; servers sharing it accept each "
                 "other's snapshots (default: a random key per process)");
  app.add_option("--memory-budget-mb", options.memory_budget_mb,
                 "memory all sessions together may hold, estimated per scene at CreateSession (0: 3/4 of the machine)")
      ->capture_default_str();
  app.add_option("--max-handler-threads", options.max_handler_threads, "gRPC threads serving calls at once")
      ->capture_default_str()
      ->check(CLI::Range(4, 4096));
  app.add_option("--max-connections", options.connections.max_connections,
                 "TCP connections open at once, all clients together; past it new ones are closed at once (lowered "
                 "to what the descriptor limit allows, 3 per connection)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1'000'000));
  app.add_option("--max-connections-per-address", options.connections.max_per_address,
                 "TCP connections open at once from one client IP address")
      ->capture_default_str()
      ->check(CLI::Range(1, 1'000'000));
  app.add_option("--step-cores", options.step_cores,
                 "cores the Steps running at once share (0: every core of the machine)")
      ->capture_default_str()
      ->check(CLI::Range(0, 4096));
  app.add_option("--step-threads", options.step_threads,
                 "shared: each Step's MPM uses cores / Steps running at once (at least 1); model: each uses the "
                 "threads its food chose, however many run (oversubscribes a busy machine)")
      ->capture_default_str()
      ->check(CLI::IsMember({"shared", "model"}));
  app.add_option("--tls-cert", options.access.tls_cert_file, "PEM certificate chain: serve over TLS");
  app.add_option("--tls-key", options.access.tls_key_file, "PEM private key of --tls-cert");
  app.add_option("--tls-client-ca", options.access.tls_client_ca_file,
                 "PEM CA bundle: clients must present a certificate it signed (mutual TLS)");
  app.add_option("--token-file", options.access.token_file,
                 "bearer tokens, one per line (\"name token\" or the token alone); every call must carry one "
                 "(needs TLS); sessions belong to the token that created them");
  app.add_flag("--insecure", options.insecure,
               "allow a non-loopback --listen without TLS and authentication (anyone who reaches it controls every "
               "session)");
  app.add_option("--robot-urdf", options.robot_urdf_path, "robot description (default: the shipped Panda with knife)");
  app.add_option("--safety-model", options.safety_model_path,
                 "the safety limiter's fitted force model (default: assets/safety/force_model.json); when missing or "
                 "invalid the server starts without the limiter and says why");
  std::string simd = "auto";
  app.add_option("--simd", simd,
                 "instruction set of the MPM kernels: auto (the best this CPU runs) or a level of this build, e.g. "
                 "x86-64 (SSE2) or x86-64-v3 (AVX2, FMA); results are the same bits only within one level")
      ->capture_default_str();
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")
      ->capture_default_str()
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));
  app.set_version_flag("--version", std::string(culinarycut::server::kServerVersion) + " (" +
                                        culinarycut::server::kBuildId + ")");
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::from_str(log_level));
  try {
    culinarycut::mpm::RequireInstructionSet(simd, argv);  // may start this program again, before any thread
  } catch (const std::exception& err) {
    spdlog::error("{}", err.what());
    return 2;
  }

  // glibc's allocator: buffers over 64 KiB (MPM grids, particle arrays) from mmap at a fixed threshold,
  // and two arenas, so a closed session's memory goes back to the system. With glibc's defaults (a
  // threshold that rises after each freed buffer, an arena per thread) the RSS rose 14 MB over 50
  // cutting episodes; with these it stays flat (docs/benchmarks/soak.md).
  mallopt(M_MMAP_THRESHOLD, 64 * 1024);
  mallopt(M_ARENA_MAX, 2);

  // Every connection is a descriptor: at the soft limit gRPC 1.51's listener fails accept4 with EMFILE
  // and never accepts again, so take all the descriptors the hard limit allows.
  if (rlimit files{}; getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur < files.rlim_max) {
    const rlim_t before = files.rlim_cur;
    files.rlim_cur = files.rlim_max;
    if (setrlimit(RLIMIT_NOFILE, &files) == 0) {
      spdlog::info("descriptor limit raised from {} to {}", before, files.rlim_cur);
    }
  }

  // Block the stop signals in every thread (gRPC's included); the main thread waits for them.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  // A thread a library started before main (its mask not ours) would take a signal with the default
  // action, killing the process mid-shutdown: there the handler hands the signal on to main.
  main_thread = pthread_self();
  struct sigaction forward {};
  forward.sa_handler = ForwardStopSignalToMain;
  sigemptyset(&forward.sa_mask);
  sigaction(SIGINT, &forward, nullptr);
  sigaction(SIGTERM, &forward, nullptr);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  std::unique_ptr<culinarycut::server::SimulationServer> server;
  try {
    server = std::make_unique<culinarycut::server::SimulationServer>(options);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "culinarycut-server: %s\n", error.what());
    return 2;
  }
  // Scripts and tests wait for these two lines.
  std::cout << "culinarycut-server listening on " << server->address() << std::endl;
  if (!server->telemetry_endpoint().empty()) std::cout << "telemetry on " << server->telemetry_endpoint() << std::endl;
  spdlog::info("version {} build {}; MPM kernels {}; at most {} sessions, idle timeout {} s",
               culinarycut::server::kServerVersion, culinarycut::server::kBuildId,
               culinarycut::mpm::KernelInstructionSet(), options.max_sessions, options.idle_timeout_s);

  int received = 0;
  sigwait(&stop_signals, &received);
  spdlog::info("received {}, shutting down ({} sessions open); a second signal stops at once",
               received == SIGINT ? "SIGINT" : "SIGTERM", server->sessions().size());
  // Calls in flight are cancelled at the grace deadline and a Step stops between substeps, so the
  // shutdown ends soon after it; it runs on its own thread so that a second signal, or a call that
  // still will not end, cannot hold the process.
  std::promise<void> stopped;
  std::future<void> stopped_future = stopped.get_future();
  std::thread shutdown([&server, &stopped] {
    server->Shutdown();
    server.reset();
    stopped.set_value();
  });
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (stopped_future.wait_for(std::chrono::milliseconds(20)) != std::future_status::ready) {
    const timespec poll{0, 0};
    const bool second_signal = sigtimedwait(&stop_signals, nullptr, &poll) > 0;
    if (second_signal || std::chrono::steady_clock::now() > give_up) {
      spdlog::warn("{}: exiting now without waiting for calls in flight",
                   second_signal ? "second stop signal" : "shutdown did not end within 2 s");
      spdlog::shutdown();
      std::_Exit(1);
    }
  }
  shutdown.join();
  spdlog::info("stopped cleanly");
  return 0;
}
