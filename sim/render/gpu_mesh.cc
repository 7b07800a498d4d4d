#include "sim/render/gpu_mesh.h"

#include "sim/render/gl.h"

namespace culinarycut::render {
namespace {

// Writes `bytes` into a buffer, growing it only when it is too small.
void Fill(GLenum target, GLuint buffer, const void* data, std::size_t bytes, std::size_t* capacity) {
  glBindBuffer(target, buffer);
  if (bytes > *capacity) {
    glBufferData(target, static_cast<GLsizeiptr>(bytes), data, GL_DYNAMIC_DRAW);
    *capacity = bytes;
  } else if (bytes > 0) {
    glBufferSubData(target, 0, static_cast<GLsizeiptr>(bytes), data);
  }
}

}  // namespace

GpuMesh::GpuMesh() {
  glGenVertexArrays(1, &vertex_array_);
  glGenBuffers(4, buffers_);
}

GpuMesh::~GpuMesh() {
  glDeleteBuffers(4, buffers_);
  glDeleteVertexArrays(1, &vertex_array_);
}

void GpuMesh::Upload(const TriangleMesh& mesh) {
  glBindVertexArray(vertex_array_);
  Fill(GL_ARRAY_BUFFER, buffers_[0], mesh.positions_m.data(), mesh.positions_m.size() * sizeof(float), &capacity_bytes_[0]);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  Fill(GL_ARRAY_BUFFER, buffers_[1], mesh.normals.data(), mesh.normals.size() * sizeof(float), &capacity_bytes_[1]);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(1);
  if (mesh.flesh.size() == mesh.vertex_count() && !mesh.flesh.empty()) {
    Fill(GL_ARRAY_BUFFER, buffers_[2], mesh.flesh.data(), mesh.flesh.size() * sizeof(float), &capacity_bytes_[2]);
    glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(2);
  } else {
    glDisableVertexAttribArray(2);  // the constant attribute value (0) applies
  }
  Fill(GL_ELEMENT_ARRAY_BUFFER, buffers_[3], mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t),
       &capacity_bytes_[3]);
  index_count_ = mesh.indices.size();
  glBindVertexArray(0);
}

void GpuMesh::Draw() const {
  if (index_count_ == 0) return;
  glBindVertexArray(vertex_array_);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(index_count_), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace culinarycut::render
