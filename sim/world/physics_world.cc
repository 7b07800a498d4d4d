#include "sim/world/physics_world.h"

#include <cmath>

#include <btBulletDynamicsCommon.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

namespace culinarycut {
namespace {

// Collision groups: the robot collides with the furniture, never with itself.
constexpr int kStaticGroup = 1;
constexpr int kRobotGroup = 2;

btVector3 ToBullet(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }

btQuaternion ToBullet(const Eigen::Matrix3d& rotation) {
  const Eigen::Quaterniond q(rotation);
  return btQuaternion(q.x(), q.y(), q.z(), q.w());
}

btTransform ToBullet(const Eigen::Isometry3d& pose) {
  return btTransform(ToBullet(Eigen::Matrix3d(pose.linear())), ToBullet(Eigen::Vector3d(pose.translation())));
}

}  // namespace

PhysicsWorld::PhysicsWorld(const RobotDescription& robot, const SceneLayout& layout, double physics_timestep_s)
    : physics_timestep_s_(physics_timestep_s),
      collision_configuration_(std::make_unique<btDefaultCollisionConfiguration>()),
      dispatcher_(std::make_unique<btCollisionDispatcher>(collision_configuration_.get())),
      broadphase_(std::make_unique<btDbvtBroadphase>()),
      solver_(std::make_unique<btMultiBodyConstraintSolver>()) {
  world_ = std::make_unique<btMultiBodyDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                                      collision_configuration_.get());
  world_->setGravity(ToBullet(layout.gravity_m_s2));
  // No warm starting: a step then depends only on the joint state, so restored snapshots replay exactly.
  world_->getSolverInfo().m_solverMode &= ~SOLVER_USE_WARMSTARTING;
  AddStaticBox(layout.table_size_m, layout.table_center_m);
  AddStaticBox(layout.board_size_m, layout.board_center_m);
  BuildRobot(robot, layout);
}

PhysicsWorld::~PhysicsWorld() {
  for (auto& motor : motors_) world_->removeMultiBodyConstraint(motor.get());
  for (auto& limit : limit_constraints_) world_->removeMultiBodyConstraint(limit.get());
  for (auto& collider : link_colliders_) world_->removeCollisionObject(collider.get());
  for (auto& body : static_bodies_) world_->removeRigidBody(body.get());
  if (robot_) world_->removeMultiBody(robot_.get());
}

void PhysicsWorld::AddStaticBox(const Eigen::Vector3d& size_m, const Eigen::Vector3d& center_m) {
  shapes_.push_back(std::make_unique<btBoxShape>(ToBullet(Eigen::Vector3d(size_m / 2.0))));
  btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, shapes_.back().get());
  info.m_startWorldTransform.setIdentity();
  info.m_startWorldTransform.setOrigin(ToBullet(center_m));
  static_bodies_.push_back(std::make_unique<btRigidBody>(info));
  world_->addRigidBody(static_bodies_.back().get(), kStaticGroup, kRobotGroup);
}

void PhysicsWorld::BuildRobot(const RobotDescription& robot, const SceneLayout& layout) {
  const int dof = robot.dof();
  robot_ = std::make_unique<btMultiBody>(dof, 0.0, btVector3(0, 0, 0), /*fixedBase=*/true, /*canSleep=*/false);
  btTransform base_pose;
  base_pose.setIdentity();
  base_pose.setOrigin(ToBullet(layout.robot_base_position_m));
  robot_->setBaseWorldTransform(base_pose);
  // Bullet defaults to 0.04 damping on every body; the real arm's damping is in its controller.
  robot_->setLinearDamping(0.0);
  robot_->setAngularDamping(0.0);
  robot_->setHasSelfCollision(false);

  Eigen::Vector3d parent_com = Eigen::Vector3d::Zero();  // the fixed base has no COM offset in Bullet
  for (int i = 0; i < dof; ++i) {
    const RigidLink& link = robot.links[i];
    const Eigen::Isometry3d& origin = robot.joint_origins[i];
    link_com_offsets_m_.push_back(link.center_of_mass_m);
    max_effort_nm_.push_back(robot.limits[i].max_effort_nm);
    lower_limits_rad_.push_back(robot.limits[i].lower_rad);
    upper_limits_rad_.push_back(robot.limits[i].upper_rad);
    // rotParentToThis maps parent-frame vectors into this frame: the inverse of the joint origin rotation.
    robot_->setupRevolute(i, link.mass_kg, ToBullet(link.inertia_diagonal_kgm2), i - 1,
                          ToBullet(Eigen::Matrix3d(origin.linear().transpose())), ToBullet(robot.joint_axes[i]),
                          ToBullet(Eigen::Vector3d(origin.translation() - parent_com)),
                          ToBullet(link.center_of_mass_m), /*disableParentCollision=*/true);
    parent_com = link.center_of_mass_m;
  }
  robot_->finalizeMultiDof();
  world_->addMultiBody(robot_.get());

  // Colliders: one compound per link, shapes placed relative to the link COM frame.
  for (int i = 0; i < dof; ++i) {
    const RigidLink& link = robot.links[i];
    auto compound = std::make_unique<btCompoundShape>();
    for (const CollisionShape& shape : link.shapes) {
      std::unique_ptr<btCollisionShape> child;
      switch (shape.kind) {
        case CollisionShape::Kind::kBox:
          child = std::make_unique<btBoxShape>(ToBullet(Eigen::Vector3d(shape.box_size_m / 2.0)));
          break;
        case CollisionShape::Kind::kCylinder:
          child = std::make_unique<btCylinderShapeZ>(btVector3(shape.radius_m, shape.radius_m, shape.length_m / 2.0));
          break;
        case CollisionShape::Kind::kSphere:
          child = std::make_unique<btSphereShape>(shape.radius_m);
          break;
      }
      Eigen::Isometry3d in_com = shape.origin;
      in_com.translation() -= link.center_of_mass_m;
      compound->addChildShape(ToBullet(in_com), child.get());
      shapes_.push_back(std::move(child));
    }
    auto collider = std::make_unique<btMultiBodyLinkCollider>(robot_.get(), i);
    collider->setCollisionShape(compound.get());
    shapes_.push_back(std::move(compound));
    world_->addCollisionObject(collider.get(), kRobotGroup, kStaticGroup);
    // Motors act only on links that have a collider (a Bullet quirk).
    robot_->getLink(i).m_collider = collider.get();
    link_colliders_.push_back(std::move(collider));
  }

  for (int i = 0; i < dof; ++i) {
    motors_.push_back(std::make_unique<btMultiBodyJointMotor>(robot_.get(), i, 0.0,
                                                              max_effort_nm_[i] * physics_timestep_s_));
    motors_.back()->setPositionTarget(0.0, 0.0);  // pure velocity servo: the position loop is ours
    world_->addMultiBodyConstraint(motors_.back().get());
    limit_constraints_.push_back(std::make_unique<btMultiBodyJointLimitConstraint>(
        robot_.get(), i, robot.limits[i].lower_rad, robot.limits[i].upper_rad));
    world_->addMultiBodyConstraint(limit_constraints_.back().get());
  }
  SetJointState(Eigen::VectorXd::Zero(dof), Eigen::VectorXd::Zero(dof));
}

void PhysicsWorld::SetJointState(const Eigen::VectorXd& q_rad, const Eigen::VectorXd& qdot_rad_s) {
  for (int i = 0; i < robot_->getNumLinks(); ++i) {
    robot_->setJointPos(i, q_rad[i]);
    robot_->setJointVel(i, qdot_rad_s[i]);
  }
  UpdateLinkTransforms();
}

JointVector PhysicsWorld::JointPositions() const {
  JointVector q(robot_->getNumLinks());
  for (int i = 0; i < q.size(); ++i) q[i] = robot_->getJointPos(i);
  return q;
}

JointVector PhysicsWorld::JointVelocities() const {
  JointVector qdot(robot_->getNumLinks());
  for (int i = 0; i < qdot.size(); ++i) qdot[i] = robot_->getJointVel(i);
  return qdot;
}

void PhysicsWorld::SetJointVelocityCommand(JointValues qdot_rad_s) {
  for (size_t i = 0; i < motors_.size(); ++i) motors_[i]->setVelocityTarget(qdot_rad_s[i], 1.0);
}

void PhysicsWorld::AddJointTorques(JointValues torques_nm) {
  for (int i = 0; i < robot_->getNumLinks(); ++i) robot_->addJointTorque(i, torques_nm[i]);
}

void PhysicsWorld::StepOnce() {
  world_->stepSimulation(physics_timestep_s_, 0, physics_timestep_s_);
  EnforceJointLimits();
}

bool PhysicsWorld::AnyMotorAtEffortLimit() const {
  // The solver clamps each motor's impulse to its maximum; within 1 % of it counts as saturated.
  constexpr double kSaturatedFraction = 0.99;
  for (const auto& motor : motors_) {
    if (std::abs(motor->getAppliedImpulse(0)) >= kSaturatedFraction * motor->getMaxAppliedImpulse()) return true;
  }
  return false;
}

void PhysicsWorld::EnforceJointLimits() {
  // Contact (the arm pushed into the table) can beat Bullet's soft limit rows by ~0.02 rad; the real
  // arm has end stops, so project the joint back and drop its outward velocity.
  bool projected = false;
  for (int i = 0; i < robot_->getNumLinks(); ++i) {
    const double q = robot_->getJointPos(i);
    const double qdot = robot_->getJointVel(i);
    if (q < lower_limits_rad_[i]) {
      robot_->setJointPos(i, lower_limits_rad_[i]);
      if (qdot < 0) robot_->setJointVel(i, 0.0);
      projected = true;
    } else if (q > upper_limits_rad_[i]) {
      robot_->setJointPos(i, upper_limits_rad_[i]);
      if (qdot > 0) robot_->setJointVel(i, 0.0);
      projected = true;
    }
  }
  if (projected) UpdateLinkTransforms();
}

void PhysicsWorld::UpdateLinkTransforms() {
  btAlignedObjectArray<btQuaternion> world_to_local;
  btAlignedObjectArray<btVector3> local_origin;
  robot_->forwardKinematics(world_to_local, local_origin);
  robot_->updateCollisionObjectWorldTransforms(world_to_local, local_origin);
}

Eigen::Isometry3d PhysicsWorld::LinkPose(int link_index) const {
  const btTransform& com_pose = robot_->getLink(link_index).m_collider->getWorldTransform();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const btQuaternion q = com_pose.getRotation();
  pose.linear() = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()).toRotationMatrix();
  const btVector3 o = com_pose.getOrigin();
  pose.translation() = Eigen::Vector3d(o.x(), o.y(), o.z()) - pose.linear() * link_com_offsets_m_[link_index];
  return pose;
}

}  // namespace culinarycut
