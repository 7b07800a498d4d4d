// Robot-only step cost, measured in one run on one machine:
//   1. engine only: culinarycut::Step on a State (no networking), steps per second;
//   2. round trip: Step calls from the C++ client to an in-process server over loopback gRPC.
// Usage: bench_step_latency [--steps N] [--control-hz F] [--listen ADDRESS] [--json out.json]
// Physics runs at 500 Hz; --control-hz 20 (default) means 25 substeps per Step, 500 means one.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "culinarycut/client.h"
#include "server/simulation_server.h"
#include "bench/engine_step_rate.h"

namespace {

using Clock = std::chrono::steady_clock;

double Percentile(std::vector<double> samples, double fraction) {
  std::sort(samples.begin(), samples.end());
  return samples[static_cast<size_t>(fraction * (samples.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  int steps = 2000;
  double control_hz = 20.0;
  std::string listen = "127.0.0.1:0";
  std::string json_path;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) steps = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--control-hz") && i + 1 < argc) control_hz = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--listen") && i + 1 < argc) listen = argv[++i];
    else if (!std::strcmp(argv[i], "--json") && i + 1 < argc) json_path = argv[++i];
    else {
      std::fprintf(stderr, "usage: %s [--steps N] [--control-hz F] [--listen ADDRESS] [--json out.json]\n", argv[0]);
      return 2;
    }
  }
  if (steps < 10) {
    std::fprintf(stderr, "--steps must be at least 10\n");
    return 2;
  }
  const std::vector<double> hold(7, 0.0);

  // 1. Engine only.
  culinarycut::bench::EngineStepRates engine;
  try {
    engine = culinarycut::bench::MeasureEngineStepRates(steps, control_hz);
  } catch (const std::invalid_argument& error) {
    std::fprintf(stderr, "bench_step_latency: %s\n", error.what());
    return 2;
  }

  // 2. Round trip through gRPC on loopback.
  culinarycut::server::ServerOptions options;
  options.listen_address = listen;
  options.telemetry_endpoint = "";
  culinarycut::server::SimulationServer server(options);
  culinarycut::client::Client client(server.address());
  culinarycut::v1::SceneSpec scene;
  scene.mutable_robot()->set_control_frequency_hz(control_hz);
  auto session = client.CreateSession(scene);
  session->Reset(0);
  for (int i = 0; i < 100; ++i) session->Step("pd_joint_delta_pos", hold);  // warm-up
  std::vector<double> round_trip_ms, observe_ms;
  round_trip_ms.reserve(steps);
  observe_ms.reserve(steps);
  for (int i = 0; i < steps; ++i) {
    auto t0 = Clock::now();
    session->Step("pd_joint_delta_pos", hold);
    round_trip_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    // Observe does no physics: its round trip is the transport's share.
    t0 = Clock::now();
    session->Observe();
    observe_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }

  const double engine_rate = engine.joint_steps_per_s;
  const double engine_ee_rate = engine.ee_steps_per_s;
  const double p50 = Percentile(round_trip_ms, 0.50), p90 = Percentile(round_trip_ms, 0.90),
               p99 = Percentile(round_trip_ms, 0.99);
  std::printf("robot-only control steps (%d substeps each), %d samples\n", engine.substeps_per_step, steps);
  std::printf("  engine, pd_joint_delta_pos : %8.0f steps/s  (%.3f ms/step)\n", engine_rate, 1e3 / engine_rate);
  std::printf("  engine, pd_ee_delta_pose   : %8.0f steps/s  (%.3f ms/step)\n", engine_ee_rate, 1e3 / engine_ee_rate);
  std::printf("  C++ client round trip      : p50 %.3f ms  p90 %.3f ms  p99 %.3f ms\n", p50, p90, p99);
  const double observe_p50 = Percentile(observe_ms, 0.50);
  std::printf("  C++ client Observe (no physics) round trip: p50 %.3f ms\n", observe_p50);
  std::printf("  round trip / engine step   : %.2f\n", p50 / (1e3 / engine_rate));
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << "{\"steps\": " << steps << ", \"control_hz\": " << control_hz << ", \"substeps\": " << engine.substeps_per_step
        << ", \"engine_joint_steps_per_s\": " << engine_rate << ", \"engine_ee_steps_per_s\": " << engine_ee_rate
        << ", \"cpp_round_trip_ms\": {\"p50\": " << p50 << ", \"p90\": " << p90 << ", \"p99\": " << p99 << "}, \"cpp_observe_round_trip_p50_ms\": " << observe_p50 << "}\n";
  }
  return 0;
}
