#include "sim/robot/robot_description.h"

#include <stdexcept>

#include <urdf_parser/urdf_parser.h>

#include "sim/robot/kinematics.h"
#include "sim/robot/rigid_bodies.h"
#include "sim/robot/robot_visuals_from_urdf.h"
#include "sim/robot/urdf_pose.h"

namespace culinarycut {
namespace {

std::vector<CollisionShape> ReadShapes(const urdf::Link& link, const Eigen::Isometry3d& link_to_owner,
                                       const std::string& path) {
  std::vector<CollisionShape> shapes;
  for (const auto& collision : link.collision_array) {
    if (!collision || !collision->geometry) continue;
    CollisionShape shape;
    shape.origin = link_to_owner * IsometryFromUrdf(collision->origin);
    switch (collision->geometry->type) {
      case urdf::Geometry::BOX: {
        const auto& box = static_cast<const urdf::Box&>(*collision->geometry);
        shape.kind = CollisionShape::Kind::kBox;
        shape.box_size_m << box.dim.x, box.dim.y, box.dim.z;
        break;
      }
      case urdf::Geometry::CYLINDER: {
        const auto& cylinder = static_cast<const urdf::Cylinder&>(*collision->geometry);
        shape.kind = CollisionShape::Kind::kCylinder;
        shape.radius_m = cylinder.radius;
        shape.length_m = cylinder.length;
        break;
      }
      case urdf::Geometry::SPHERE: {
        shape.kind = CollisionShape::Kind::kSphere;
        shape.radius_m = static_cast<const urdf::Sphere&>(*collision->geometry).radius;
        break;
      }
      default:
        throw std::runtime_error(path + ": link '" + link.name +
                                 "' has a mesh collision geometry; only box, cylinder and sphere are supported");
    }
    shapes.push_back(shape);
  }
  return shapes;
}

// Adds a link (its frame given in the owner's frame) to an owner, combining mass properties.
// Inertia: parallel-axis terms on the diagonal; off-diagonal products are dropped (primitives only).
void MergeInto(RigidLink* owner, const urdf::Link& link, const Eigen::Isometry3d& link_to_owner,
               const std::string& path) {
  const auto shapes = ReadShapes(link, link_to_owner, path);
  owner->shapes.insert(owner->shapes.end(), shapes.begin(), shapes.end());
  if (!link.inertial || link.inertial->mass <= 0.0) return;
  const double m = link.inertial->mass;
  const Eigen::Vector3d com = link_to_owner * IsometryFromUrdf(link.inertial->origin).translation();
  const Eigen::Vector3d own_inertia(link.inertial->ixx, link.inertial->iyy, link.inertial->izz);
  const double total = owner->mass_kg + m;
  const Eigen::Vector3d new_com = (owner->mass_kg * owner->center_of_mass_m + m * com) / total;
  auto shifted = [&new_com](const Eigen::Vector3d& inertia, double mass, const Eigen::Vector3d& at) {
    const Eigen::Vector3d r = at - new_com;
    return Eigen::Vector3d(inertia.x() + mass * (r.y() * r.y() + r.z() * r.z()),
                           inertia.y() + mass * (r.x() * r.x() + r.z() * r.z()),
                           inertia.z() + mass * (r.x() * r.x() + r.y() * r.y()));
  };
  owner->inertia_diagonal_kgm2 = shifted(owner->inertia_diagonal_kgm2, owner->mass_kg, owner->center_of_mass_m) +
                                 shifted(own_inertia, m, com);
  owner->center_of_mass_m = new_com;
  owner->mass_kg = total;
}

}  // namespace

const Eigen::Isometry3d& RobotDescription::TipFrame(const std::string& frame_name) const {
  const auto it = tip_frames.find(frame_name);
  if (it != tip_frames.end()) return it->second;
  std::string known;
  for (const auto& [key, value] : tip_frames) known += (known.empty() ? "" : ", ") + key;
  throw std::out_of_range("unknown tip frame '" + frame_name + "'; known: " + known);
}

RobotDescription LoadRobotDescription(const std::string& urdf_path, const std::string& tip_link) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(urdf_path);
  if (!model) throw std::runtime_error(urdf_path + ": cannot read or parse the URDF file");
  urdf::LinkConstSharedPtr tip = model->getLink(tip_link);
  if (!tip) throw std::runtime_error(urdf_path + ": no link named '" + tip_link + "'");

  RobotDescription robot;
  robot.name = model->getName();
  const RigidBodies chain = GroupRigidBodies(*model, tip.get());
  robot.links.reserve(chain.bodies.size());  // keeps `owner` valid while links grow
  RigidLink* owner = &robot.base;
  owner->name = chain.links.front().link->name;
  for (const LinkInBody& entry : chain.links) {
    const urdf::Link& link = *entry.link;
    if (entry.starts_body && entry.body > 0) {
      const RigidBody& body = chain.bodies[entry.body];
      const urdf::Joint& joint = *body.joint;
      if (joint.type != urdf::Joint::REVOLUTE) {
        throw std::runtime_error(urdf_path + ": joint '" + joint.name + "' is not revolute or fixed");
      }
      if (!joint.limits) throw std::runtime_error(urdf_path + ": revolute joint '" + joint.name + "' has no <limit>");
      robot.joint_names.push_back(joint.name);
      robot.joint_origins.push_back(body.joint_origin);
      robot.joint_axes.push_back(Eigen::Vector3d(joint.axis.x, joint.axis.y, joint.axis.z).normalized());
      robot.limits.push_back({joint.limits->lower, joint.limits->upper, joint.limits->velocity, joint.limits->effort});
      robot.links.emplace_back();
      owner = &robot.links.back();
      owner->name = link.name;
    }
    MergeInto(owner, link, entry.in_body, urdf_path);
    // Fixed links past the first movable joint are frames a caller may ask for (flange, knife, ...).
    if (!entry.starts_body && entry.body > 0) robot.tip_frames[link.name] = entry.in_body;
  }
  if (robot.links.empty()) throw std::runtime_error(urdf_path + ": no movable joint between the root and '" + tip_link + "'");
  if (robot.dof() > kMaxJoints) {
    throw std::runtime_error(urdf_path + ": " + std::to_string(robot.dof()) + " movable joints; at most " +
                             std::to_string(kMaxJoints) + " are supported");
  }
  robot.tip_frames[robot.links.back().name] = Eigen::Isometry3d::Identity();
  robot.visuals = RobotVisualsFromUrdf(*model, urdf_path);
  return robot;
}

}  // namespace culinarycut
