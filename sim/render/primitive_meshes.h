// Triangle meshes of the primitives robot descriptions and furniture are made of, in the shape's
// own frame (centred at its origin), with outward normals and counter-clockwise faces.
#pragma once

#include <Eigen/Geometry>

#include "sim/render/triangle_mesh.h"

namespace culinarycut::render {

// Full extents `size_m`; flat-shaded faces (24 vertices).
TriangleMesh MakeBoxMesh(const Eigen::Vector3d& size_m);
// Axis along local z, centred; smooth sides and flat caps.
TriangleMesh MakeCylinderMesh(double radius_m, double length_m, int segments = 32);
TriangleMesh MakeSphereMesh(double radius_m, int rings = 16, int segments = 32);

// Moves every vertex and normal by `transform` (rigid, optionally uniformly scaled).
void TransformMesh(const Eigen::Isometry3d& transform, TriangleMesh* mesh);
// Appends `part` to `mesh`, offsetting its indices.
void AppendMesh(const TriangleMesh& part, TriangleMesh* mesh);

}  // namespace culinarycut::render
