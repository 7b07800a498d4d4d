#include "sim/render/robot_visuals.h"

#include <cmath>

#include "sim/render/mesh_file.h"
#include "sim/render/primitive_meshes.h"
#include "sim/render/render_error.h"

namespace culinarycut::render {
namespace {

// A Panda-like look: white shells, dark grey joint housings, a steel blade with a black handle.
Material DefaultMaterial(const std::string& link_name, bool is_knife, VisualShape::Kind kind) {
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
  } else if (kind == VisualShape::Kind::kSphere) {
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

TriangleMesh ShapeMesh(const VisualShape& shape) {
  switch (shape.kind) {
    case VisualShape::Kind::kBox: return MakeBoxMesh(shape.box_size_m);
    case VisualShape::Kind::kCylinder: return MakeCylinderMesh(shape.radius_m, shape.length_m);
    case VisualShape::Kind::kSphere: return MakeSphereMesh(shape.radius_m);
    case VisualShape::Kind::kMesh: return LoadMeshFile(shape.mesh_path, shape.mesh_scale);
  }
  throw RenderError("unknown visual shape kind");
}

}  // namespace

RobotVisuals BuildRobotVisuals(const RobotVisualDescription& description) {
  RobotVisuals visuals;
  visuals.urdf_path = description.urdf_path;
  visuals.owner_names = description.owner_names;
  visuals.link_frames = description.link_frames;
  for (const RobotVisual& visual : description.visuals) {
    const bool is_knife = visual.link_name.rfind("knife", 0) == 0;
    RobotVisualPart part;
    part.link_name = visual.link_name;
    part.owner = visual.owner;
    part.in_owner = visual.in_owner;
    part.mesh = ShapeMesh(visual.shape);
    part.material = DefaultMaterial(visual.link_name, is_knife, visual.shape.kind);
    if (visual.srgb_color) {  // URDF colours are sRGB; shading is linear
      const Eigen::Vector3f& c = *visual.srgb_color;
      part.material.color = {std::pow(c.x(), 2.2f), std::pow(c.y(), 2.2f), std::pow(c.z(), 2.2f)};
    }
    part.segment = is_knife ? kKnifeSegment : kRobotSegment;
    visuals.parts.push_back(std::move(part));
  }
  return visuals;
}

}  // namespace culinarycut::render
