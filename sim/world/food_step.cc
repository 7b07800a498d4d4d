#include "sim/world/food_step.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/mpm/physics/speed_resistance.h"

namespace culinarycut {
namespace {

// Whether any part of the knife at `tcp` is within `margin_m` of `box`.
bool KnifeNear(const Eigen::Isometry3d& tcp, double margin_m, const Eigen::AlignedBox3d& box, FoodState* state) {
  mpm::RigidMotion motion;
  motion.pose = tcp;
  state->solver->SetKnifeMotion(motion);
  const mpm::KnifeSdf& knife = *state->solver->knife();
  return knife.BladeBounds(margin_m).intersects(box) || knife.HandleBounds(margin_m).intersects(box);
}

// Whether any part of the knife at `tcp` is within the model's activation margin of the food.
bool KnifeNearFood(const FoodModel& model, const Eigen::Isometry3d& tcp, FoodState* state) {
  return KnifeNear(tcp, model.activation_margin_m, state->particle_bounds.cast<double>(), state);
}

// One food object's particles: their bounds and how many of them sleep.
struct ObjectParticles {
  Eigen::AlignedBox3d bounds;
  std::size_t count = 0;
  std::size_t asleep = 0;
};

std::vector<ObjectParticles> ParticlesByObject(const mpm::Particles<float>& p, std::size_t objects) {
  std::vector<ObjectParticles> by_object(objects);
  const bool has_activity = p.activity.size() == p.size();
  for (std::size_t q = 0; q < p.size(); ++q) {
    if (p.object[q] >= objects) continue;
    ObjectParticles& object = by_object[p.object[q]];
    object.bounds.extend(Eigen::Vector3d(p.position[0][q], p.position[1][q], p.position[2][q]));
    ++object.count;
    object.asleep += has_activity && p.activity[q] == mpm::kFrozen;
  }
  return by_object;
}

// With several foods, only those the knife comes near are simulated: the others sleep (frozen, a fixed
// load on the grid) until it comes within activity's least radius of them or moving food pushes them,
// so resting distractors cost nothing, as the whole food costs nothing while the knife is away. When
// the food wakes, the objects away from the knife are put to sleep; while it is awake, a sleeping one
// the knife nears, or one part-woken by a push, wakes whole. Activity's radius, when set, decides instead.
void SleepObjectsAwayFromKnife(const FoodModel& model, const Eigen::Isometry3d& tcp_start,
                               const Eigen::Isometry3d& tcp_end, bool food_was_asleep, FoodState* state) {
  mpm::Solver<float>& solver = *state->solver;
  if (!model.objects_sleep || model.objects.size() < 2 || solver.config().activity.radius_m > 0.0) return;
  const double margin_m = mpm::kMinActivityRadiusCells * solver.config().dx_m;
  const std::vector<ObjectParticles> objects = ParticlesByObject(solver.particles(), model.objects.size());
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const ObjectParticles& object = objects[i];
    if (object.count == 0) continue;
    const bool near = KnifeNear(tcp_start, margin_m, object.bounds, state) ||
                      KnifeNear(tcp_end, margin_m, object.bounds, state);
    const auto id = static_cast<std::uint16_t>(i);
    if (food_was_asleep) {
      if (near ? object.asleep > 0 : object.asleep < object.count) solver.SetObjectAsleep(id, !near);
    } else if (object.asleep > 0 && (near || object.asleep < object.count)) {
      solver.SetObjectAsleep(id, false);
    }
  }
}

// The knife's pose at fraction s in [0, 1] of the step: position linear, rotation spherical.
Eigen::Isometry3d Interpolate(const Eigen::Isometry3d& start, const Eigen::Isometry3d& end, double s) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = (1.0 - s) * start.translation() + s * end.translation();
  const Eigen::Quaterniond q0(start.linear());
  const Eigen::Quaterniond q1(end.linear());
  pose.linear() = q0.slerp(s, q1).toRotationMatrix();
  return pose;
}

// The mass of the particles the last substep integrated (the frozen ones are stored after them).
double MovingMass(const mpm::Solver<float>& solver) {
  double mass_kg = 0.0;
  for (std::size_t q = 0; q < solver.active_count(); ++q) mass_kg += solver.particles().mass[q];
  return mass_kg;
}

}  // namespace

FoodStepReport AdvanceFood(const FoodModel& model, const Eigen::Isometry3d& tcp_start,
                           const Eigen::Isometry3d& tcp_end, double duration_s, FoodState* state,
                           const std::function<bool()>& cancelled,
                           const std::function<void()>& before_body_changes) {
  FoodStepReport report;
  state->wrench = KnifeWrench{};
  state->knife_speed_factor = 1.0;
  const bool near = KnifeNearFood(model, tcp_end, state) || KnifeNearFood(model, tcp_start, state);
  if (!near && !state->awake) return report;
  if (before_body_changes) before_body_changes();
  SleepObjectsAwayFromKnife(model, tcp_start, tcp_end, !state->awake, state);
  state->awake = true;

  mpm::Solver<float>& solver = *state->solver;
  mpm::RigidMotion motion;
  motion.linear_velocity_m_s = (tcp_end.translation() - tcp_start.translation()) / duration_s;
  const Eigen::AngleAxisd turn(tcp_end.linear() * tcp_start.linear().transpose());
  motion.angular_velocity_rad_s = turn.axis() * (turn.angle() / duration_s);
  // The fastest point of the knife: the TCP's speed plus the turn at the blade's far end.
  const double knife_reach_m = 0.5 * model.knife.blade_length_m + model.knife.blade_height_m;
  const double knife_speed_m_s = motion.linear_velocity_m_s.norm() + motion.angular_velocity_rad_s.norm() * knife_reach_m;
  // Substeps short enough for sound, the knife's fastest point and the fastest particle: the step
  // (or what is left of it) is split evenly into the fewest substeps that bound allows, and split
  // again at the new bound when a particle speeds up past it, so the knife still ends at tcp_end.
  // The particles' speed is scanned here rather than kept from the last step: a restored
  // snapshot then chooses the same substeps.
  double fastest_particle_m_s = mpm::FastestParticleSpeed(solver.particles());
  auto substeps_for = [&](double time_s) {
    const double dt_bound_s = mpm::StableTimestep(*model.solver, knife_speed_m_s, fastest_particle_m_s);
    return std::max(1, static_cast<int>(std::ceil(time_s / dt_bound_s)));
  };
  double done = 0.0;                       // fraction of the step done before this stretch
  int stretch = substeps_for(duration_s);  // even substeps in this stretch
  int k = 0;                               // substeps taken of this stretch
  int substeps = 0;
  double resistance_sum = 0.0;  // sum over substeps of k2 c-hat dt (1/(m/s)): the speed resistance
  double kinetic_energy_j = 0.0;
  while (k < stretch) {
    if (cancelled && cancelled()) {
      report.cancelled = true;
      return report;
    }
    const double dt_s = duration_s * (1.0 - done) / stretch;  // duration_s / stretch while done = 0
    motion.pose = Interpolate(tcp_start, tcp_end, done + (1.0 - done) * (k + 0.5) / stretch);
    solver.SetKnifeMotion(motion);
    const mpm::SubstepDiagnostics d = solver.Substep(dt_s);
    ++k;
    ++substeps;
    state->wrench.force_n += (d.force_on_blade_n + d.force_on_handle_n) * (dt_s / duration_s);
    resistance_sum += mpm::SubstepResistance(d);
    report.max_c_hat = std::max(report.max_c_hat, d.c_hat);
    report.contact = report.contact || d.c_hat > 0.0 || d.force_on_blade_n.squaredNorm() > 0.0;
    kinetic_energy_j = d.kinetic_energy_j;
    fastest_particle_m_s = d.fastest_particle_m_s;
    if (k < stretch && dt_s > mpm::StableTimestep(*model.solver, knife_speed_m_s, fastest_particle_m_s)) {
      done += (1.0 - done) * k / stretch;
      stretch = substeps_for(duration_s * (1.0 - done));
      k = 0;
    }
  }
  report.substeps = substeps;
  state->substeps += substeps;
  state->mpm_time_s += duration_s;
  state->particle_bounds = ParticleBounds(solver.particles());
  // At the knife's own speed u (m/s) the step's slow-down is u / (1 + u sum(k2 c-hat dt)).
  const double speed_m_s = motion.linear_velocity_m_s.norm();
  state->knife_speed_factor = mpm::SpeedResistanceFactor(speed_m_s, resistance_sum);

  // Sleep again once the knife has gone and the food has come to rest (what moves: frozen food is at rest).
  const double moving_mass_kg = MovingMass(solver);
  const double rms_speed_m_s = moving_mass_kg > 0.0 ? std::sqrt(2.0 * kinetic_energy_j / moving_mass_kg) : 0.0;
  const bool still_near = KnifeNearFood(model, tcp_end, state);
  state->quiet_time_s = (!still_near && rms_speed_m_s < model.rest_speed_m_s) ? state->quiet_time_s + duration_s : 0.0;
  if (state->quiet_time_s >= model.rest_duration_s) {
    state->awake = false;
    state->quiet_time_s = 0.0;
  }
  return report;
}

}  // namespace culinarycut
