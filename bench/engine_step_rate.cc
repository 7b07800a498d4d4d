#include "bench/engine_step_rate.h"

#include <chrono>

#include "sim/world/step.h"

namespace culinarycut::bench {

EngineStepRates MeasureEngineStepRates(int steps, double control_hz) {
  using Clock = std::chrono::steady_clock;
  const RobotDescription robot = LoadRobotDescription(DefaultRobotUrdfPath(), kTcpFrame);
  SceneConfig config;
  config.robot.control_frequency_hz = control_hz;
  const std::shared_ptr<const Model> model = CompileModel(config, robot);
  State state;
  ResetState(*model, &state, 0, {});
  const Action joint_action{ControlMode::kJointDeltaPosition, Eigen::VectorXd::Zero(7)};
  const Action ee_action{ControlMode::kEndEffectorDeltaPose, Eigen::VectorXd::Zero(6)};
  EngineStepRates rates;
  rates.substeps_per_step = model->substeps_per_control_step;
  auto start = Clock::now();
  for (int i = 0; i < steps; ++i) Step(*model, &state, joint_action);
  rates.joint_steps_per_s = steps / std::chrono::duration<double>(Clock::now() - start).count();
  start = Clock::now();
  for (int i = 0; i < steps; ++i) Step(*model, &state, ee_action);
  rates.ee_steps_per_s = steps / std::chrono::duration<double>(Clock::now() - start).count();
  return rates;
}

}  // namespace culinarycut::bench
