#include "sim/robot/robot_visuals_from_urdf.h"

#include <stdexcept>

#include <urdf_parser/urdf_parser.h>

#include "sim/robot/rigid_bodies.h"
#include "sim/robot/urdf_pose.h"

namespace culinarycut {
namespace {

// The joints the renderer can pose; the grouping itself only tells fixed from the rest.
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
  const RigidBodies tree = GroupRigidBodies(model);
  for (const LinkInBody& entry : tree.links) {
    const urdf::Link& link = *entry.link;
    if (entry.starts_body) {
      const urdf::Joint* joint = tree.bodies[entry.body].joint;
      if (joint && !IsMovable(*joint)) {
        throw std::runtime_error(urdf_path + ": joint '" + joint->name + "' is floating or planar; not supported");
      }
      description.owner_names.push_back(link.name);
    }
    description.link_frames[link.name] = {entry.body, entry.in_body};
    for (const auto& visual : link.visual_array) {
      if (!visual || !visual->geometry) continue;
      RobotVisual part;
      part.link_name = link.name;
      part.owner = entry.body;
      part.in_owner = entry.in_body * IsometryFromUrdf(visual->origin);
      part.shape = ShapeFromUrdf(*visual->geometry, urdf_path, link.name);
      if (visual->material && visual->material->color.r + visual->material->color.g + visual->material->color.b > 0) {
        const auto& c = visual->material->color;
        part.srgb_color = Eigen::Vector3f(c.r, c.g, c.b);
      }
      description.visuals.push_back(std::move(part));
    }
  }
  return description;
}

RobotVisualDescription ReadRobotVisuals(const std::string& urdf_path) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(urdf_path);
  if (!model) throw std::runtime_error(urdf_path + ": cannot read or parse the URDF file");
  return RobotVisualsFromUrdf(*model, urdf_path);
}

}  // namespace culinarycut
