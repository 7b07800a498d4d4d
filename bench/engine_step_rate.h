// The engine-only half of bench_step_latency: robot-only control steps per second with no
// networking. Its own file because the C++ client's types share names with the engine's.
#pragma once

namespace culinarycut::bench {

struct EngineStepRates {
  int substeps_per_step = 0;
  double joint_steps_per_s = 0.0;  // pd_joint_delta_pos
  double ee_steps_per_s = 0.0;     // pd_ee_delta_pose (IK every step)
};

// Throws culinarycut::SceneError for a control rate the engine refuses.
EngineStepRates MeasureEngineStepRates(int steps, double control_hz);

}  // namespace culinarycut::bench
