// The Bullet world of one session: the robot as a fixed-base btMultiBody with joint motors and
// limit constraints, plus the table and the cutting board as static bodies. Not thread-safe;
// one session owns one PhysicsWorld. Rebuilt from (Model, joint state) on reset and restore, so
// no solver cache from the past leaks into a restored trajectory.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "sim/robot/kinematics.h"
#include "sim/robot/robot_description.h"
#include "sim/core/scene_layout.h"

class btCollisionShape;
class btMultiBody;
class btMultiBodyJointMotor;
class btMultiBodyJointLimitConstraint;
class btMultiBodyDynamicsWorld;
class btMultiBodyLinkCollider;
class btRigidBody;
class btDefaultCollisionConfiguration;
class btCollisionDispatcher;
class btBroadphaseInterface;
class btMultiBodyConstraintSolver;

namespace culinarycut {

class PhysicsWorld {
 public:
  PhysicsWorld(const RobotDescription& robot, const SceneLayout& layout, double physics_timestep_s);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  void SetJointState(const Eigen::VectorXd& q_rad, const Eigen::VectorXd& qdot_rad_s);
  JointVector JointPositions() const;
  JointVector JointVelocities() const;

  // Joint motors drive each joint towards a velocity (rad/s) with at most its effort limit.
  void SetJointVelocityCommand(JointValues qdot_rad_s);

  // Adds joint torques (N m) for the next physics timestep only (Bullet clears them after a step).
  void AddJointTorques(JointValues torques_nm);

  // Advances by one physics timestep; joints never end it outside their limits.
  void StepOnce();
  // Whether any joint motor used its whole effort (the largest impulse it may apply) in the last step.
  bool AnyMotorAtEffortLimit() const;

  // World pose of movable link i's frame (URDF link frame, not the COM frame) as Bullet sees it.
  Eigen::Isometry3d LinkPose(int link_index) const;

 private:
  void AddStaticBox(const Eigen::Vector3d& size_m, const Eigen::Vector3d& center_m);
  void BuildRobot(const RobotDescription& robot, const SceneLayout& layout);
  // Projects joints past a limit back onto it (an end stop).
  void EnforceJointLimits();
  // Recomputes link and collider poses after joint positions were set directly.
  void UpdateLinkTransforms();

  double physics_timestep_s_;
  std::vector<Eigen::Vector3d> link_com_offsets_m_;  // COM in link frame, to recover link poses
  std::vector<double> max_effort_nm_;
  std::vector<double> lower_limits_rad_;
  std::vector<double> upper_limits_rad_;
  std::unique_ptr<btDefaultCollisionConfiguration> collision_configuration_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btMultiBodyConstraintSolver> solver_;
  std::unique_ptr<btMultiBodyDynamicsWorld> world_;
  std::unique_ptr<btMultiBody> robot_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> link_colliders_;
  std::vector<std::unique_ptr<btMultiBodyJointMotor>> motors_;
  std::vector<std::unique_ptr<btMultiBodyJointLimitConstraint>> limit_constraints_;
  std::vector<std::unique_ptr<btRigidBody>> static_bodies_;
};

}  // namespace culinarycut
