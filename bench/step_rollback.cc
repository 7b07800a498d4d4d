// What a cancellable Step costs for its rollback with the food asleep (the approach, the retreat, the
// robot between cuts): today's lazy rollback against the full state copy every Step took before, at
// each quality preset, interleaved in one process. Every round times four things on one state, in turn:
//   plain      Step with no cancel check (nothing saved)
//   full copy  SaveSnapshot then Step: what a cancellable Step did before (the whole state saved first)
//   lazy       Step with a cancel check that never fires: what a server Step does now
//   rollback   StepRollback alone: the lazy rollback's own cost with the food asleep
// The knife holds still far above the food, so the food sleeps and no MPM substep runs.
// Usage: bench_step_rollback PRESET [ROUNDS]   (PRESET: draft, standard or fine). Prints JSON.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/world/model.h"
#include "sim/world/snapshot.h"
#include "sim/world/step.h"
#include "sim/world/step_rollback.h"

using namespace culinarycut;

namespace {

double MedianMs(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

std::string List(const std::vector<double>& values) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) text += (i ? ", " : "") + std::to_string(values[i]);
  return text + "]";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_step_rollback PRESET [ROUNDS]\n");
    return 2;
  }
  const std::string preset = argv[1];
  const int rounds = argc > 2 ? std::stoi(argv[2]) : 40;
  SceneConfig config;
  config.quality = preset;
  config.effects = EffectsConfig{true, false, true, true, true, true, false};
  config.foods.push_back(FoodConfig{});
  config.foods.back().food = "cucumber";
  const RobotDescription robot = LoadRobotDescription(DefaultRobotUrdfPath(), kTcpFrame);
  const auto model = CompileModel(config, robot);
  State state;
  ResetState(*model, &state, 0, {});
  const Action hold{ControlMode::kEndEffectorDeltaPose, Eigen::VectorXd::Zero(6)};
  const CancelCheck never = [] { return false; };
  using Clock = std::chrono::steady_clock;
  auto time_ms = [](auto&& work) {
    const auto start = Clock::now();
    work();
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  };
  std::vector<double> plain, full_copy, lazy, rollback;
  std::size_t snapshot_bytes = 0, rollback_bytes = 0;
  for (int round = 0; round < rounds; ++round) {
    plain.push_back(time_ms([&] { Step(*model, &state, hold); }));
    full_copy.push_back(time_ms([&] {
      const std::string before = SaveSnapshot(*model, state);
      snapshot_bytes = before.size();
      Step(*model, &state, hold, never);
    }));
    lazy.push_back(time_ms([&] { Step(*model, &state, hold, never); }));
    rollback.push_back(time_ms([&] { rollback_bytes = StepRollback(*model, state).saved_bytes(); }));
  }
  if (state.food->awake) {
    std::fprintf(stderr, "bench_step_rollback: the food woke; the knife was meant to stay away\n");
    return 1;
  }
  std::printf("{\"preset\": \"%s\", \"particles\": %zu, \"rounds\": %d, \"snapshot_bytes\": %zu, "
              "\"rollback_bytes\": %zu,\n \"plain_ms\": %.4f, \"full_copy_ms\": %.4f, \"lazy_ms\": %.4f, "
              "\"rollback_ms\": %.4f,\n \"plain_runs_ms\": %s,\n \"full_copy_runs_ms\": %s,\n \"lazy_runs_ms\": %s,\n"
              " \"rollback_runs_ms\": %s}\n",
              preset.c_str(), state.food->solver->particles().size(), rounds, snapshot_bytes, rollback_bytes,
              MedianMs(plain), MedianMs(full_copy), MedianMs(lazy), MedianMs(rollback), List(plain).c_str(),
              List(full_copy).c_str(), List(lazy).c_str(), List(rollback).c_str());
  return 0;
}
