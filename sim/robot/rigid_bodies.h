// How URDF links group into rigid bodies, the one rule the robot description and its visuals share:
// every non-fixed joint starts a new body; a fixed joint's child joins its parent's body, its frame
// given in the body's frame as parent_link_in_body * joint_origin. Which non-fixed joint types are
// supported is the caller's to decide (the description takes revolute only, the renderer any that moves).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <urdf_model/model.h>

namespace culinarycut {

struct RigidBody {
  const urdf::Link* first_link = nullptr;  // the link the body is named after and whose frame it has
  const urdf::Joint* joint = nullptr;      // the non-fixed joint that starts it; null for the root's body
  int parent = -1;                         // the body that joint hangs from; -1 for the root's body
  Eigen::Isometry3d joint_origin = Eigen::Isometry3d::Identity();  // in the parent body's frame
};

struct LinkInBody {
  const urdf::Link* link = nullptr;
  int body = 0;
  Eigen::Isometry3d in_body = Eigen::Isometry3d::Identity();  // the link's frame in its body's frame
  bool starts_body = false;  // the body's first link (the root, or the child of a non-fixed joint)
};

// Pointers into the model: valid while the model lives.
struct RigidBodies {
  std::vector<RigidBody> bodies;  // [0] = the root's body, then in the order the walk meets their joints
  std::vector<LinkInBody> links;  // depth first from the root, child joints in the model's order
};

// Walks `model` from its root (which it must have). With a `tip_link`, only the links on the path
// from the root to it (root first); without, the whole tree. Throws nothing of its own.
RigidBodies GroupRigidBodies(const urdf::ModelInterface& model, const urdf::Link* tip_link = nullptr);

}  // namespace culinarycut
