#include "sim/robot/rigid_bodies.h"

#include <set>

#include "sim/robot/urdf_pose.h"

namespace culinarycut {
namespace {

// `only`, when set, holds the links on the root-to-tip path: the walk descends into no others.
void Visit(const urdf::ModelInterface& model, const urdf::Link& link, int body, const Eigen::Isometry3d& in_body,
           bool starts_body, const std::set<const urdf::Link*>* only, RigidBodies* out) {
  out->links.push_back({&link, body, in_body, starts_body});
  for (const auto& joint : link.child_joints) {
    const urdf::LinkConstSharedPtr child = model.getLink(joint->child_link_name);
    if (!child || (only && only->count(child.get()) == 0)) continue;
    const Eigen::Isometry3d origin = in_body * IsometryFromUrdf(joint->parent_to_joint_origin_transform);
    if (joint->type == urdf::Joint::FIXED) {
      Visit(model, *child, body, origin, false, only, out);
      continue;
    }
    out->bodies.push_back({child.get(), joint.get(), body, origin});
    Visit(model, *child, static_cast<int>(out->bodies.size()) - 1, Eigen::Isometry3d::Identity(), true, only, out);
  }
}

}  // namespace

RigidBodies GroupRigidBodies(const urdf::ModelInterface& model, const urdf::Link* tip_link) {
  std::set<const urdf::Link*> path;
  for (const urdf::Link* link = tip_link; link; link = link->getParent().get()) path.insert(link);
  const urdf::LinkConstSharedPtr root = model.getRoot();
  RigidBodies out;
  out.bodies.push_back({root.get()});
  Visit(model, *root, 0, Eigen::Isometry3d::Identity(), true, tip_link ? &path : nullptr, &out);
  return out;
}

}  // namespace culinarycut
