#include "sim/robot/robot_visuals_from_urdf.h"

#include <functional>
#include <stdexcept>

#include <urdf_parser/urdf_parser.h>

#include "sim/robot/urdf_pose.h"

namespace culinarycut {
namespace {

bool IsMovable(const urdf::Joint& joint) {
  return joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS ||
         joint.type == urdf::Joint::PRISMATIC;
}

std::string Directory(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

VisualShape ShapeFromUrdf(const urdf::Geometry& geometry, const std::string& urdf_path, const std::string& link) {
  VisualShape shape;
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(geometry);
      shape.kind = VisualShape::Kind::kBox;
      shape.box_size_m = Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z);
      return shape;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      shape.kind = VisualShape::Kind::kCylinder;
      shape.radius_m = cylinder.radius;
      shape.length_m = cylinder.length;
      return shape;
    }
    case urdf::Geometry::SPHERE:
      shape.kind = VisualShape::Kind::kSphere;
      shape.radius_m = static_cast<const urdf::Sphere&>(geometry).radius;
      return shape;
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
      std::string file = mesh.filename;
      if (file.rfind("file://", 0) == 0) file = file.substr(7);
      if (file.rfind("package://", 0) == 0) {
        throw std::runtime_error(urdf_path + ": link '" + link + "' names mesh '" + mesh.filename +
                                 "'; package:// paths are not resolved, use a path relative to the URDF");
      }
      if (!file.empty() && file[0] != '/') file = Directory(urdf_path) + "/" + file;
      shape.kind = VisualShape::Kind::kMesh;
      shape.mesh_path = file;
      shape.mesh_scale = Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z);
      return shape;
    }
  }
  throw std::runtime_error(urdf_path + ": link '" + link + "' has an unknown visual geometry type");
}

}  // namespace

RobotVisualDescription RobotVisualsFromUrdf(const urdf::ModelInterface& model, const std::string& urdf_path) {
  const urdf::LinkConstSharedPtr root = model.getRoot();
  if (!root) throw std::runtime_error(urdf_path + ": the URDF has no root link");
  RobotVisualDescription description;
  description.urdf_path = urdf_path;
  description.owner_names.push_back(root->name);
  // Depth first from the root; a movable joint starts a new owner, a fixed one merges into the parent's.
  std::function<void(const urdf::Link&, int, const Eigen::Isometry3d&)> visit =
      [&](const urdf::Link& link, int owner, const Eigen::Isometry3d& link_in_owner) {
        description.link_frames[link.name] = {owner, link_in_owner};
        for (const auto& visual : link.visual_array) {
          if (!visual || !visual->geometry) continue;
          RobotVisual part;
          part.link_name = link.name;
          part.owner = owner;
          part.in_owner = link_in_owner * IsometryFromUrdf(visual->origin);
          part.shape = ShapeFromUrdf(*visual->geometry, urdf_path, link.name);
          if (visual->material && visual->material->color.r + visual->material->color.g + visual->material->color.b > 0) {
            const auto& c = visual->material->color;
            part.srgb_color = Eigen::Vector3f(c.r, c.g, c.b);
          }
          description.visuals.push_back(std::move(part));
        }
        for (const auto& joint : link.child_joints) {
          const urdf::LinkConstSharedPtr child = model.getLink(joint->child_link_name);
          if (!child) continue;
          const Eigen::Isometry3d joint_origin = IsometryFromUrdf(joint->parent_to_joint_origin_transform);
          if (IsMovable(*joint)) {
            description.owner_names.push_back(child->name);
            visit(*child, static_cast<int>(description.owner_names.size()) - 1, Eigen::Isometry3d::Identity());
          } else if (joint->type == urdf::Joint::FIXED) {
            visit(*child, owner, link_in_owner * joint_origin);
          } else {
            throw std::runtime_error(urdf_path + ": joint '" + joint->name + "' is floating or planar; not supported");
          }
        }
      };
  visit(*root, 0, Eigen::Isometry3d::Identity());
  return description;
}

RobotVisualDescription ReadRobotVisuals(const std::string& urdf_path) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(urdf_path);
  if (!model) throw std::runtime_error(urdf_path + ": cannot read or parse the URDF file");
  return RobotVisualsFromUrdf(*model, urdf_path);
}

}  // namespace culinarycut
