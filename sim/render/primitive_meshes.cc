#include "sim/render/primitive_meshes.h"

#include <cmath>

namespace culinarycut::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::uint32_t AddVertex(const Eigen::Vector3d& position, const Eigen::Vector3d& normal, TriangleMesh* mesh) {
  const auto index = static_cast<std::uint32_t>(mesh->vertex_count());
  for (int axis = 0; axis < 3; ++axis) {
    mesh->positions_m.push_back(static_cast<float>(position[axis]));
    mesh->normals.push_back(static_cast<float>(normal[axis]));
  }
  return index;
}

void AddTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, TriangleMesh* mesh) {
  mesh->indices.insert(mesh->indices.end(), {a, b, c});
}

}  // namespace

TriangleMesh MakeBoxMesh(const Eigen::Vector3d& size_m) {
  TriangleMesh mesh;
  const Eigen::Vector3d half = 0.5 * size_m;
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      normal[axis] = sign;
      // Two tangents with u x v = normal, so the quad winds counter-clockwise seen from outside.
      Eigen::Vector3d u = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
      u[(axis + 1) % 3] = 1.0;
      v[(axis + 2) % 3] = sign;
      const Eigen::Vector3d center = normal.cwiseProduct(half);
      const Eigen::Vector3d du = u.cwiseProduct(half), dv = v.cwiseProduct(half);
      const auto a = AddVertex(center - du - dv, normal, &mesh);
      const auto b = AddVertex(center + du - dv, normal, &mesh);
      const auto c = AddVertex(center + du + dv, normal, &mesh);
      const auto d = AddVertex(center - du + dv, normal, &mesh);
      AddTriangle(a, b, c, &mesh);
      AddTriangle(a, c, d, &mesh);
    }
  }
  return mesh;
}

TriangleMesh MakeCylinderMesh(double radius_m, double length_m, int segments) {
  TriangleMesh mesh;
  const double half = 0.5 * length_m;
  // Side: a ring of vertices at each end with radial normals.
  for (int i = 0; i <= segments; ++i) {
    const double angle = 2.0 * kPi * i / segments;
    const Eigen::Vector3d radial(std::cos(angle), std::sin(angle), 0.0);
    AddVertex(radius_m * radial + Eigen::Vector3d(0, 0, -half), radial, &mesh);
    AddVertex(radius_m * radial + Eigen::Vector3d(0, 0, half), radial, &mesh);
  }
  for (int i = 0; i < segments; ++i) {
    const auto bottom = static_cast<std::uint32_t>(2 * i), top = bottom + 1, next_bottom = bottom + 2,
               next_top = bottom + 3;
    AddTriangle(bottom, next_bottom, next_top, &mesh);
    AddTriangle(bottom, next_top, top, &mesh);
  }
  // Caps: a fan around a centre vertex each.
  for (int sign = -1; sign <= 1; sign += 2) {
    const Eigen::Vector3d normal(0, 0, sign);
    const auto center = AddVertex(Eigen::Vector3d(0, 0, sign * half), normal, &mesh);
    for (int i = 0; i <= segments; ++i) {
      const double angle = 2.0 * kPi * i / segments;
      AddVertex(Eigen::Vector3d(radius_m * std::cos(angle), radius_m * std::sin(angle), sign * half), normal, &mesh);
    }
    for (int i = 0; i < segments; ++i) {
      const auto a = center + 1 + i, b = center + 2 + i;
      if (sign > 0) AddTriangle(center, a, b, &mesh);
      else AddTriangle(center, b, a, &mesh);
    }
  }
  return mesh;
}

TriangleMesh MakeSphereMesh(double radius_m, int rings, int segments) {
  TriangleMesh mesh;
  for (int ring = 0; ring <= rings; ++ring) {
    const double polar = kPi * ring / rings;
    for (int i = 0; i <= segments; ++i) {
      const double azimuth = 2.0 * kPi * i / segments;
      const Eigen::Vector3d normal(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                                   std::cos(polar));
      AddVertex(radius_m * normal, normal, &mesh);
    }
  }
  const auto stride = static_cast<std::uint32_t>(segments + 1);
  for (int ring = 0; ring < rings; ++ring) {
    for (int i = 0; i < segments; ++i) {
      const auto a = ring * stride + i, b = a + stride, c = b + 1, d = a + 1;
      if (ring != 0) AddTriangle(a, b, d, &mesh);
      if (ring != rings - 1) AddTriangle(d, b, c, &mesh);
    }
  }
  return mesh;
}

void TransformMesh(const Eigen::Isometry3d& transform, TriangleMesh* mesh) {
  const Eigen::Matrix3d normal_matrix = transform.linear().inverse().transpose();
  for (std::size_t v = 0; v < mesh->vertex_count(); ++v) {
    float* p = &mesh->positions_m[3 * v];
    const Eigen::Vector3d moved = transform * Eigen::Vector3d(p[0], p[1], p[2]);
    for (int axis = 0; axis < 3; ++axis) p[axis] = static_cast<float>(moved[axis]);
    if (mesh->normals.size() < 3 * (v + 1)) continue;
    float* n = &mesh->normals[3 * v];
    const Eigen::Vector3d turned = (normal_matrix * Eigen::Vector3d(n[0], n[1], n[2])).normalized();
    for (int axis = 0; axis < 3; ++axis) n[axis] = static_cast<float>(turned[axis]);
  }
}

void AppendMesh(const TriangleMesh& part, TriangleMesh* mesh) {
  const auto offset = static_cast<std::uint32_t>(mesh->vertex_count());
  mesh->positions_m.insert(mesh->positions_m.end(), part.positions_m.begin(), part.positions_m.end());
  mesh->normals.insert(mesh->normals.end(), part.normals.begin(), part.normals.end());
  mesh->flesh.insert(mesh->flesh.end(), part.flesh.begin(), part.flesh.end());
  for (const std::uint32_t index : part.indices) mesh->indices.push_back(index + offset);
}

}  // namespace culinarycut::render
