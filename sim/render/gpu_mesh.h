// A triangle mesh in GPU buffers (vertex array: position 0, normal 1, flesh weight 2). Static meshes
// are uploaded once; the food mesh is re-uploaded into the same buffers every render call.
// Lives on the render thread.
#pragma once

#include <cstddef>

#include "sim/render/triangle_mesh.h"

namespace culinarycut::render {

class GpuMesh {
 public:
  GpuMesh();
  explicit GpuMesh(const TriangleMesh& mesh) : GpuMesh() { Upload(mesh); }
  ~GpuMesh();
  GpuMesh(const GpuMesh&) = delete;
  GpuMesh& operator=(const GpuMesh&) = delete;

  // Replaces the contents; buffers only grow, so a steady stream of similar meshes does not allocate.
  // A mesh without flesh weights draws with flesh 0.
  void Upload(const TriangleMesh& mesh);
  void Draw() const;
  std::size_t triangle_count() const { return index_count_ / 3; }

 private:
  unsigned vertex_array_ = 0;
  unsigned buffers_[4] = {0, 0, 0, 0};   // positions, normals, flesh, indices
  std::size_t capacity_bytes_[4] = {0, 0, 0, 0};
  std::size_t index_count_ = 0;
};

}  // namespace culinarycut::render
