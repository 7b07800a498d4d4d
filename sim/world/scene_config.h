// What a client asks for, as a plain config struct with defaults (the wire's SceneSpec, minus the wire).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace culinarycut {

struct RobotConfig {
  double control_frequency_hz = 20.0;     // [1, 1000] Hz
  double physics_frequency_hz = 500.0;     // an integer multiple of control_frequency_hz
  std::vector<double> initial_qpos_rad;    // empty: the knife-down ready pose
  double joint_stiffness_per_s = 20.0;     // PD position gain (1/s): commanded qdot = k (q_target - q)
};

// Which parts of the simulation a scene asks for; what is not declared is not built.
struct EffectsConfig {
  bool mpm = false;            // simulate the food objects (MLS-MPM); required when there are objects
  bool plasticity = false;     // J2 plasticity of the food
  bool damage = false;         // fracture: without it the knife only presses the food
  bool friction = false;       // Coulomb friction between food and knife / board
  bool topology = false;       // detect the pieces after every control step (paper's topology update)
  bool force_sensing = false;  // food -> knife wrench, applied to the robot and reported at the wrist
  bool safety_limiter = false; // the paper's manipulation safety module (sim/safety, settings in SafetyConfig)
};

// The safety limiter's settings (used only with effects.safety_limiter; docs/safety.md).
struct SafetyConfig {
  double max_force_n = 100.0;          // F_max (N): the Panda's safe contact force
  double margin = 0.1;                 // in [0, 0.9]: caps at (1 - margin) of v_safe and of F_max
  std::vector<std::string> guards;     // speed, force, entry_angle; empty: all
  double max_entry_angle_deg = 15.0;   // (0, 90]: blade tilt from vertical allowed while entering the food
};

// One food object on the board.
// A reference specimen's shape in place of the food's (sim/mpm/specimen_shapes.h); the food still
// gives the material. Set by cc-cut for the reference cuts; the wire has no such field.
struct SpecimenConfig {
  std::string kind;        // box, half_cylinder
  Eigen::Vector3d size_m;  // (length along the long axis, width, height)
};

struct FoodConfig {
  std::string food;                                // banana, cucumber, apple, peach, melon, orange, strawberry
  double scale = 1.0;                              // multiplies the food's typical size
  std::optional<Eigen::Vector3d> position_m;       // bounding-box centre; default: on the board, resting on it
  std::optional<Eigen::Vector2d> board_xy_m;       // or only (x, y) of the centre, resting on the board
  std::optional<Eigen::Quaterniond> orientation;   // default: long axis left-right (world y), lying
  std::string material;                            // preset name; empty: the food's own
  std::map<std::string, double> material_overrides;  // youngs_modulus_pa, poisson_ratio, density_kg_m3, ...
  std::optional<SpecimenConfig> specimen;          // a reference specimen's shape instead of the food's
};

// Explicit MPM resolution; each set value overrides the quality preset's.
struct MpmResolutionConfig {
  std::optional<double> dx_m;
  std::optional<int> particles_per_cell;
  std::optional<double> cfl;
  std::optional<double> mass_scaling;
  std::optional<double> activity_radius_m;
};

// An accuracy target in place of a preset (docs/accuracy.md): the cheapest setting the accuracy study
// measured that meets every bound set here; an unset bound is free.
struct AccuracyTargetConfig {
  std::optional<double> force_error;            // peak (5 ms window) blade force, relative to the reference
  std::optional<double> force_curve_error;      // force-depth curve, relative L2
  std::optional<double> cut_position_error_mm;  // where the cut lands (mm)
};

// A cutting task: a free-form instruction, or the fields of a cut spec (not both).
struct TaskConfig {
  std::string instruction;
  std::string cut_style;      // normal, bias, guillotine, saw; empty: the paper's default rules
  std::string cut_state;      // middle, ratio, split
  double ratio = 0.0;         // ratio only: 0.1-0.9 from `reference`
  int split_pieces = 0;       // split only: 3, 4 or 5
  std::string target_object;  // a food of the scene; empty: the scene's only food
  std::string reference;      // none, left, right, top, along_length
  bool has_spec_fields() const {
    return !cut_style.empty() || !cut_state.empty() || ratio != 0.0 || split_pieces != 0 || !target_object.empty() ||
           !reference.empty();
  }
  bool empty() const { return instruction.empty() && !has_spec_fields(); }
};

// A camera. A default camera's name (front, left, right, wrist) without a pose takes its pose.
struct CameraConfig {
  std::string name;
  // OpenCV camera frame (x right, y down, z forward) in the world, or in `attached_link`'s frame.
  std::optional<Eigen::Isometry3d> pose;
  std::string attached_link;               // "": fixed in the world; else a robot link, e.g. "panda_link8"
  double fov_y_deg = 0.0;                  // vertical field of view; 0: the default camera's, else 55 deg
  int width = 0;                           // pixels; 0: 224
  int height = 0;                          // pixels; 0: 224
  std::vector<std::string> channels;       // rgb, depth, segmentation; empty: rgb
  std::string rgb_encoding;                // on the wire: raw (default), png or jpeg
};

struct SceneConfig {
  std::uint64_t seed = 0;
  RobotConfig robot;
  std::string scene = "table";
  std::string quality = "standard";        // MPM accuracy preset: draft, standard, fine (no effect without food)
  std::optional<AccuracyTargetConfig> accuracy_target;  // set: chooses the resolution instead of `quality`
  std::uint32_t max_episode_steps = 0;     // 0: never truncate
  EffectsConfig effects;
  SafetyConfig safety;
  std::vector<FoodConfig> foods;
  MpmResolutionConfig mpm;
  TaskConfig task;
  std::vector<CameraConfig> cameras;
};

// The knife-down "ready" pose (rad) used when initial_qpos is empty.
std::vector<double> ReadyPose();

// An error message naming the offending field, or nothing when the config is valid.
// (Joint positions are checked against the robot by CheckJointPositions in model.h.)
std::optional<std::string> ValidateSceneConfig(const SceneConfig& config);
// The same for the safety limiter's settings alone (fields scene.safety.*).
std::optional<std::string> ValidateSafetyConfig(const SafetyConfig& safety);

}  // namespace culinarycut
