#include <cmath>

#include <catch2/catch.hpp>

#include "sim/render/primitive_meshes.h"

namespace culinarycut::render {
namespace {

// Signed volume by the divergence theorem: positive only for closed, outward-wound meshes.
double SignedVolume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    Eigen::Vector3d corner[3];
    for (int k = 0; k < 3; ++k) {
      const float* p = &mesh.positions_m[3 * mesh.indices[3 * t + k]];
      corner[k] = Eigen::Vector3d(p[0], p[1], p[2]);
    }
    volume += corner[0].dot(corner[1].cross(corner[2])) / 6.0;
  }
  return volume;
}

// Every triangle's geometric normal agrees with its vertex normals.
bool NormalsPointOut(const TriangleMesh& mesh) {
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    Eigen::Vector3d corner[3], normal_sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.indices[3 * t + k];
      corner[k] = Eigen::Vector3d(mesh.positions_m[3 * v], mesh.positions_m[3 * v + 1], mesh.positions_m[3 * v + 2]);
      normal_sum += Eigen::Vector3d(mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]);
    }
    if ((corner[1] - corner[0]).cross(corner[2] - corner[0]).dot(normal_sum) <= 0.0) return false;
  }
  return true;
}

TEST_CASE("Primitive meshes are closed, wound outward, with the right volume") {
  const double pi = 3.14159265358979;
  const TriangleMesh box = MakeBoxMesh({0.2, 0.3, 0.4});
  CHECK(SignedVolume(box) == Approx(0.024).epsilon(1e-5));
  CHECK(NormalsPointOut(box));
  const TriangleMesh cylinder = MakeCylinderMesh(0.1, 0.5, 64);
  CHECK(SignedVolume(cylinder) == Approx(pi * 0.01 * 0.5).epsilon(0.01));
  CHECK(NormalsPointOut(cylinder));
  const TriangleMesh sphere = MakeSphereMesh(0.1, 32, 64);
  CHECK(SignedVolume(sphere) == Approx(4.0 / 3.0 * pi * 1e-3).epsilon(0.01));
  CHECK(NormalsPointOut(sphere));
}

TEST_CASE("TransformMesh moves positions and turns normals") {
  TriangleMesh box = MakeBoxMesh({1.0, 1.0, 1.0});
  Eigen::Isometry3d move = Eigen::Isometry3d::Identity();
  move.translate(Eigen::Vector3d(1.0, 2.0, 3.0));
  move.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  TransformMesh(move, &box);
  CHECK(SignedVolume(box) == Approx(1.0).epsilon(1e-5));
  CHECK(NormalsPointOut(box));
  TriangleMesh both = MakeBoxMesh({1.0, 1.0, 1.0});
  AppendMesh(box, &both);
  CHECK(SignedVolume(both) == Approx(2.0).epsilon(1e-5));
}

}  // namespace
}  // namespace culinarycut::render
