// One robot episode of the example cut (the scripted oracle cuts a real cucumber 0.3 from the left;
// robot, MPM, damage, friction, topology and force sensing; no cameras) with MPM woken either 2 cm
// from the food, as it was, or kActivationMarginCells grid cells from it, as it is now, run until the
// oracle's plan ends (as examples/cut_cucumber.py runs it): the totals are until the task succeeds,
// the episode_ ones to the end. Prints one JSON object; bench/wake_margin_report.py runs the settings
// side by side and writes the page.
//
//   bench_wake_margin QUALITY MARGIN [CFL PPC]     MARGIN: "cells" (now) or "2cm" (before)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "sim/policy/scripted_oracle.h"
#include "sim/world/model.h"
#include "sim/world/step.h"

using namespace culinarycut;

namespace {

constexpr char kInstruction[] = "cut the cucumber at 0.3 ratio from the left";  // examples/cut_cucumber.py
constexpr double kMarginBefore_m = 0.02;  // the wake margin before it followed the grid

int Usage() {
  std::cerr << "usage: bench_wake_margin QUALITY cells|2cm [CFL PPC]\n";
  return 2;
}

// A JSON array of numbers, one appended per control step.
struct JsonList {
  std::string text;
  void Add(double value) { text += (text.empty() ? "" : ",") + std::to_string(value); }
  std::string Str() const { return "[" + text + "]"; }
};

int Run(const std::string& quality, const std::string& margin, int argc, char** argv) {
  SceneConfig config;
  config.quality = quality;
  config.effects = EffectsConfig{true, false, true, true, true, true, false};
  config.foods.push_back(FoodConfig{});
  config.foods.back().food = "cucumber";  // its real material preset
  config.task.instruction = kInstruction;
  if (argc == 5) {
    config.mpm.cfl = std::stod(argv[3]);
    config.mpm.particles_per_cell = std::stoi(argv[4]);
  }
  const RobotDescription robot = LoadRobotDescription(DefaultRobotUrdfPath(), kTcpFrame);
  auto model = std::make_shared<Model>(*CompileModel(config, robot));
  if (margin == "2cm") model->food->activation_margin_m = kMarginBefore_m;

  State state;
  ResetState(*model, &state, 0, {});
  OracleConfig oracle_config;
  oracle_config.instruction = kInstruction;
  oracle_config.objects = model->food->objects;
  const ScriptedOracle oracle(*model, oracle_config, state.physics->JointPositions(), state.sim_time_s);

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  int steps = 0, mpm_substeps = 0, substeps_before_contact = 0, first_contact_step = 0;
  int episode_steps = 0, episode_mpm_substeps = 0;
  double peak_force_n = 0.0, wall_s = 0.0, sim_s = 0.0;
  JsonList force_n, step_wall_s, step_mpm_substeps;
  StepResult last;
  std::optional<task::TaskScore> score;  // when the task succeeded, else at the end
  while (!oracle.Finished(state.sim_time_s)) {
    const Eigen::VectorXd action = oracle.Act(*model, state.physics->JointPositions(), state.sim_time_s);
    const auto step_start = Clock::now();
    last = Step(*model, &state, Action{oracle.control_mode(), action});
    step_wall_s.Add(std::chrono::duration<double>(Clock::now() - step_start).count());
    ++episode_steps;
    episode_mpm_substeps += last.mpm_substeps;
    step_mpm_substeps.Add(last.mpm_substeps);
    if (score && score->success) continue;  // after success: only the episode's totals
    score = last.task_score;
    ++steps;
    mpm_substeps += last.mpm_substeps;
    wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    sim_s = state.sim_time_s;
    if (last.first_contact) first_contact_step = steps;
    if (first_contact_step == 0) substeps_before_contact += last.mpm_substeps;
    const double force = state.food->control_step_wrench.force_n.norm();
    peak_force_n = std::max(peak_force_n, force);
    force_n.Add(force);
  }
  const double episode_wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  if (!score || score->required.empty()) throw std::runtime_error("the episode was not scored");
  std::printf(
      "{\"quality\": \"%s\", \"margin\": \"%s\", \"margin_m\": %.4f, \"cfl\": %g, \"particles_per_cell\": %d, "
      "\"particles\": %zu, \"steps\": %d, \"sim_s\": %.3f, \"wall_s\": %.3f, \"mpm_substeps\": %d, "
      "\"substeps_before_contact\": %d, \"first_contact_step\": %d, \"success\": %s, \"pieces\": %zu, "
      "\"position_error_fraction\": %.6f, \"peak_force_n\": %.4f, \"force_n\": %s, \"step_wall_s\": %s, "
      "\"step_mpm_substeps\": %s, \"episode_steps\": %d, \"episode_wall_s\": %.3f, \"episode_mpm_substeps\": %d}\n",
      quality.c_str(), margin.c_str(), model->food->activation_margin_m, model->food->resolution.cfl,
      model->food->resolution.particles_per_cell, model->food->initial_particles.size(), steps, sim_s,
      wall_s, mpm_substeps, substeps_before_contact, first_contact_step, score->success ? "true" : "false",
      state.food->pieces.size(), score->required.front().position_error_fraction, peak_force_n,
      force_n.Str().c_str(), step_wall_s.Str().c_str(), step_mpm_substeps.Str().c_str(), episode_steps,
      episode_wall_s, episode_mpm_substeps);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 5) return Usage();
  const std::string margin = argv[2];
  if (margin != "cells" && margin != "2cm") return Usage();
  try {
    return Run(argv[1], margin, argc, argv);
  } catch (const std::exception& error) {  // a bad preset, CFL or ppc is refused with the field named
    std::cerr << "bench_wake_margin: " << error.what() << "\n";
    return 1;
  }
}
