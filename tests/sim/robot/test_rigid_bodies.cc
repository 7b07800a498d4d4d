#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <unistd.h>
#include <urdf_parser/urdf_parser.h>

#include "sim/robot/rigid_bodies.h"
#include "sim/robot/robot_description.h"

using namespace culinarycut;

namespace {

// A chain base -f0- mount -j1- arm1 -f1- elbow -j2- arm2 -f2- tool -f3- tcp, with a fixed side
// branch arm1 -s1- camera and a prismatic side branch tool -p_finger- finger (f = fixed, j = revolute).
std::string Link(const std::string& name) {
  return "<link name=\"" + name + "\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" "
         "ixz=\"0\" iyz=\"0\"/></inertial><visual><geometry><box size=\"0.1 0.1 0.1\"/></geometry></visual></link>";
}
std::string Joint(const std::string& name, const std::string& type, const std::string& parent, const std::string& child,
                  const std::string& origin) {
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/><origin " + origin + "/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" velocity=\"1\" effort=\"1\"/></joint>";
}
std::string TestUrdf() {
  std::string urdf = "<robot name=\"walk\">";
  for (const char* link : {"base", "mount", "arm1", "elbow", "camera", "arm2", "tool", "tcp", "finger"}) urdf += Link(link);
  urdf += Joint("f0", "fixed", "base", "mount", "xyz=\"0 0 0.05\"");
  urdf += Joint("j1", "revolute", "mount", "arm1", "xyz=\"0 0 0.1\"");
  urdf += Joint("f1", "fixed", "arm1", "elbow", "xyz=\"0 0 0.3\" rpy=\"0 0 1.5707963267948966\"");
  urdf += Joint("s1", "fixed", "arm1", "camera", "xyz=\"0.02 0 0\"");
  urdf += Joint("j2", "revolute", "elbow", "arm2", "xyz=\"0.2 0 0\"");
  urdf += Joint("f2", "fixed", "arm2", "tool", "xyz=\"0 0 0.25\"");
  urdf += Joint("f3", "fixed", "tool", "tcp", "xyz=\"0.1 0 0\" rpy=\"0 1.5707963267948966 0\"");
  urdf += Joint("p_finger", "prismatic", "tool", "finger", "xyz=\"0 0.04 0\"");
  return urdf + "</robot>";
}

Eigen::Isometry3d Pose(const Eigen::Vector3d& translation, const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = translation;
  return pose;
}
const Eigen::Matrix3d kRz90 = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
const Eigen::Matrix3d kRy90 = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();

std::map<std::string, const LinkInBody*> ByName(const RigidBodies& bodies) {
  std::map<std::string, const LinkInBody*> out;
  for (const LinkInBody& entry : bodies.links) out[entry.link->name] = &entry;
  return out;
}

}  // namespace

TEST_CASE("the rigid-body walk merges fixed links into the body a revolute joint starts", "[robot]") {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(TestUrdf());
  REQUIRE(model);

  SECTION("the whole tree") {
    const RigidBodies tree = GroupRigidBodies(*model);
    REQUIRE(tree.links.size() == 9);
    REQUIRE(tree.bodies.size() == 4);  // base, arm1, arm2, finger
    const auto links = ByName(tree);
    const std::map<std::string, std::pair<std::string, Eigen::Isometry3d>> expected = {
        {"base", {"base", Pose({0, 0, 0})}},       {"mount", {"base", Pose({0, 0, 0.05})}},
        {"arm1", {"arm1", Pose({0, 0, 0})}},       {"elbow", {"arm1", Pose({0, 0, 0.3}, kRz90)}},
        {"camera", {"arm1", Pose({0.02, 0, 0})}},  {"arm2", {"arm2", Pose({0, 0, 0})}},
        {"tool", {"arm2", Pose({0, 0, 0.25})}},    {"tcp", {"arm2", Pose({0.1, 0, 0.25}, kRy90)}},
        {"finger", {"finger", Pose({0, 0, 0})}}};
    for (const auto& [name, body_and_pose] : expected) {
      INFO(name);
      const LinkInBody& entry = *links.at(name);
      CHECK(tree.bodies[entry.body].first_link->name == body_and_pose.first);
      CHECK(entry.starts_body == (name == body_and_pose.first));
      CHECK(entry.in_body.isApprox(body_and_pose.second, 1e-12));
    }
    // Each joint that starts a body: its parent body and its origin in that body's frame.
    CHECK(tree.bodies[0].joint == nullptr);
    const std::map<std::string, std::pair<std::string, Eigen::Isometry3d>> joints = {
        {"arm1", {"base", Pose({0, 0, 0.15})}}, {"arm2", {"arm1", Pose({0, 0.2, 0.3}, kRz90)}},
        {"finger", {"arm2", Pose({0, 0.04, 0.25})}}};
    for (const auto& [child, parent_and_origin] : joints) {
      INFO(child);
      const RigidBody& body = tree.bodies[links.at(child)->body];
      CHECK(tree.bodies[body.parent].first_link->name == parent_and_origin.first);
      CHECK(body.joint_origin.isApprox(parent_and_origin.second, 1e-12));
    }
  }

  SECTION("only the path to a tip link, root first") {
    const RigidBodies chain = GroupRigidBodies(*model, model->getLink("tcp").get());
    std::vector<std::string> names;
    for (const LinkInBody& entry : chain.links) names.push_back(entry.link->name);
    CHECK(names == std::vector<std::string>{"base", "mount", "arm1", "elbow", "arm2", "tool", "tcp"});
    REQUIRE(chain.bodies.size() == 3);
    CHECK(chain.bodies[1].joint->name == "j1");
    CHECK(chain.bodies[2].joint->name == "j2");
    CHECK(chain.bodies[2].joint_origin.isApprox(Pose({0, 0.2, 0.3}, kRz90), 1e-12));
  }
}

TEST_CASE("the robot description and its visuals put each link in the same body", "[robot]") {
  const auto path = std::filesystem::temp_directory_path() / ("culinarycut_walk_" + std::to_string(getpid()) + ".urdf");
  std::ofstream(path) << TestUrdf();
  const RobotDescription robot = LoadRobotDescription(path.string(), "tcp");
  std::filesystem::remove(path);
  REQUIRE(robot.joint_names == std::vector<std::string>{"j1", "j2"});
  CHECK(robot.joint_origins[1].isApprox(Pose({0, 0.2, 0.3}, kRz90), 1e-12));
  CHECK(robot.base.mass_kg == Approx(2.0));      // base + mount
  CHECK(robot.links[0].mass_kg == Approx(2.0));  // arm1 + elbow; the camera is off the chain
  CHECK(robot.links[1].mass_kg == Approx(3.0));  // arm2 + tool + tcp; the finger is off the chain
  CHECK(robot.tip_frames.count("mount") == 0);   // fixed to the world, before the first joint
  CHECK(robot.TipFrame("tcp").isApprox(Pose({0.1, 0, 0.25}, kRy90), 1e-12));

  // Body names: the description's chain, and the visuals' owners over the whole tree.
  const std::map<std::string, std::string> description_body = {
      {"base", "base"}, {"mount", "base"}, {"arm1", "arm1"}, {"elbow", "arm1"},
      {"arm2", "arm2"}, {"tool", "arm2"}, {"tcp", "arm2"}};
  const RobotVisualDescription& visuals = robot.visuals;
  CHECK(visuals.owner_names.size() == 4);  // the finger moves, so it is an owner of its own
  CHECK(robot.base.name == "base");
  CHECK(robot.links[0].name == "arm1");
  CHECK(robot.links[1].name == "arm2");
  for (const auto& [link, body] : description_body) {
    INFO(link);
    const auto& [owner, in_owner] = visuals.link_frames.at(link);
    CHECK(visuals.owner_names.at(owner) == body);
    if (robot.tip_frames.count(link)) CHECK(in_owner.isApprox(robot.TipFrame(link), 1e-12));
  }
  CHECK(visuals.owner_names.at(visuals.link_frames.at("camera").first) == "arm1");
  for (const RobotVisual& part : visuals.visuals) CHECK(part.owner == visuals.link_frames.at(part.link_name).first);
}
