// Triangle meshes from files (OBJ, STL, DAE, ... anything assimp reads), for URDF mesh visuals.
#pragma once

#include <string>

#include <Eigen/Core>

#include "sim/render/triangle_mesh.h"

namespace culinarycut::render {

// All of the file's meshes, node transforms applied, scaled per axis, with smooth normals where
// the file has none. Throws RenderError with the path and assimp's reason.
TriangleMesh LoadMeshFile(const std::string& path, const Eigen::Vector3d& scale = Eigen::Vector3d::Ones());

}  // namespace culinarycut::render
