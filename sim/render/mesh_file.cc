#include "sim/render/mesh_file.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "sim/render/render_error.h"

namespace culinarycut::render {

TriangleMesh LoadMeshFile(const std::string& path, const Eigen::Vector3d& scale) {
  Assimp::Importer importer;
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals |
                         aiProcess_PreTransformVertices | aiProcess_SortByPType;
  const aiScene* scene = importer.ReadFile(path, flags);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    throw RenderError("cannot load mesh file '" + path + "': " + importer.GetErrorString());
  }
  TriangleMesh mesh;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh& part = *scene->mMeshes[m];
    if (!(part.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;  // points and lines: nothing to shade
    const auto offset = static_cast<std::uint32_t>(mesh.vertex_count());
    for (unsigned v = 0; v < part.mNumVertices; ++v) {
      const aiVector3D& p = part.mVertices[v];
      mesh.positions_m.insert(mesh.positions_m.end(), {static_cast<float>(p.x * scale.x()),
                                                        static_cast<float>(p.y * scale.y()),
                                                        static_cast<float>(p.z * scale.z())});
      // A non-uniform scale turns normals by the inverse scale.
      Eigen::Vector3d n(part.mNormals[v].x / scale.x(), part.mNormals[v].y / scale.y(), part.mNormals[v].z / scale.z());
      n = n.norm() > 0.0 ? n.normalized() : Eigen::Vector3d::UnitZ();
      mesh.normals.insert(mesh.normals.end(),
                          {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())});
    }
    for (unsigned f = 0; f < part.mNumFaces; ++f) {
      const aiFace& face = part.mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (int corner = 0; corner < 3; ++corner) mesh.indices.push_back(offset + face.mIndices[corner]);
    }
  }
  if (mesh.indices.empty()) throw RenderError("mesh file '" + path + "' has no triangles");
  return mesh;
}

}  // namespace culinarycut::render
