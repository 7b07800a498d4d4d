// Reads a parsed URDF's visuals into the plain RobotVisualDescription (sim/core), their owners the
// rigid bodies of sim/robot/rigid_bodies.h, the grouping the robot description uses too.
#pragma once

#include <string>

#include <urdf_model/model.h>

#include "sim/core/robot_visual_description.h"

namespace culinarycut {

// Mesh paths are resolved against the URDF's folder ("file://" accepted). Throws
// std::runtime_error naming the file and link for package:// paths or floating/planar joints.
RobotVisualDescription RobotVisualsFromUrdf(const urdf::ModelInterface& model, const std::string& urdf_path);

// Parses `urdf_path` for its visuals alone (tools and tests that draw a robot with no joint chain);
// the server takes RobotDescription::visuals from the parse it already made.
RobotVisualDescription ReadRobotVisuals(const std::string& urdf_path);

}  // namespace culinarycut
