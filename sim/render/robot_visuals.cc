#include "sim/render/robot_visuals.h"

#include <cmath>
#include <functional>

#include <urdf_parser/urdf_parser.h>

#include "sim/render/mesh_file.h"
#include "sim/render/primitive_meshes.h"
#include "sim/render/render_error.h"
#include "sim/robot/urdf_pose.h"

namespace culinarycut::render {
namespace {

bool IsMovable(const urdf::Joint& joint) {
  return joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS ||
         joint.type == urdf::Joint::PRISMATIC;
}

std::string Directory(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

// A Panda-like look: white shells, dark grey joint housings, a steel blade with a black handle.
Material DefaultMaterial(const std::string& link_name, bool is_knife, int type) {
  Material material;
  if (is_knife && link_name.find("blade") != std::string::npos) {
    material.kind = MaterialKind::kMetal;
    material.color = {0.62f, 0.64f, 0.66f};
    material.specular = 0.9f;
    material.shininess = 90.0f;
  } else if (is_knife) {
    material.color = {0.025f, 0.02f, 0.018f};
    material.specular = 0.25f;
    material.shininess = 40.0f;
  } else if (type == urdf::Geometry::SPHERE) {
    material.color = {0.16f, 0.16f, 0.17f};
    material.specular = 0.3f;
    material.shininess = 48.0f;
  } else {
    material.color = {0.80f, 0.80f, 0.78f};
    material.specular = 0.35f;
    material.shininess = 48.0f;
  }
  return material;
}

TriangleMesh VisualMesh(const urdf::Geometry& geometry, const std::string& urdf_path, const std::string& link) {
  switch (geometry.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(geometry);
      return MakeBoxMesh(Eigen::Vector3d(box.dim.x, box.dim.y, box.dim.z));
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
      return MakeCylinderMesh(cylinder.radius, cylinder.length);
    }
    case urdf::Geometry::SPHERE:
      return MakeSphereMesh(static_cast<const urdf::Sphere&>(geometry).radius);
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(geometry);
      std::string file = mesh.filename;
      if (file.rfind("file://", 0) == 0) file = file.substr(7);
      if (file.rfind("package://", 0) == 0) {
        throw RenderError(urdf_path + ": link '" + link + "' names mesh '" + mesh.filename +
                          "'; package:// paths are not resolved, use a path relative to the URDF");
      }
      if (!file.empty() && file[0] != '/') file = Directory(urdf_path) + "/" + file;
      return LoadMeshFile(file, Eigen::Vector3d(mesh.scale.x, mesh.scale.y, mesh.scale.z));
    }
  }
  throw RenderError(urdf_path + ": link '" + link + "' has an unknown visual geometry type");
}

}  // namespace

RobotVisuals LoadRobotVisuals(const std::string& urdf_path) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(urdf_path);
  if (!model) throw RenderError(urdf_path + ": cannot read or parse the URDF file");
  const urdf::LinkConstSharedPtr root = model->getRoot();
  if (!root) throw RenderError(urdf_path + ": the URDF has no root link");

  RobotVisuals visuals;
  visuals.urdf_path = urdf_path;
  visuals.owner_names.push_back(root->name);

  // Depth first from the root; a movable joint starts a new owner, a fixed one merges into the parent's.
  std::function<void(const urdf::Link&, int, const Eigen::Isometry3d&)> visit =
      [&](const urdf::Link& link, int owner, const Eigen::Isometry3d& link_in_owner) {
        visuals.link_frames[link.name] = {owner, link_in_owner};
        const bool is_knife = link.name.rfind("knife", 0) == 0;
        for (const auto& visual : link.visual_array) {
          if (!visual || !visual->geometry) continue;
          RobotVisualPart part;
          part.link_name = link.name;
          part.owner = owner;
          part.in_owner = link_in_owner * IsometryFromUrdf(visual->origin);
          part.mesh = VisualMesh(*visual->geometry, urdf_path, link.name);
          part.material = DefaultMaterial(link.name, is_knife, visual->geometry->type);
          if (visual->material && visual->material->color.r + visual->material->color.g + visual->material->color.b > 0) {
            const auto& c = visual->material->color;  // URDF colours are sRGB
            part.material.color = {std::pow(c.r, 2.2f), std::pow(c.g, 2.2f), std::pow(c.b, 2.2f)};
          }
          part.segment = is_knife ? kKnifeSegment : kRobotSegment;
          visuals.parts.push_back(std::move(part));
        }
        for (const auto& joint : link.child_joints) {
          const urdf::LinkConstSharedPtr child = model->getLink(joint->child_link_name);
          if (!child) continue;
          const Eigen::Isometry3d joint_origin = IsometryFromUrdf(joint->parent_to_joint_origin_transform);
          if (IsMovable(*joint)) {
            visuals.owner_names.push_back(child->name);
            visit(*child, static_cast<int>(visuals.owner_names.size()) - 1, Eigen::Isometry3d::Identity());
          } else if (joint->type == urdf::Joint::FIXED) {
            visit(*child, owner, link_in_owner * joint_origin);
          } else {
            throw RenderError(urdf_path + ": joint '" + joint->name + "' is floating or planar; not supported");
          }
        }
      };
  visit(*root, 0, Eigen::Isometry3d::Identity());
  return visuals;
}

}  // namespace culinarycut::render
