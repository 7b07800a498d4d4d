// The food's force on the arm, kept passive along each knife axis (time-domain passivity, Hannaford
// and Ryu 2002, "Time-domain passivity control of haptic interfaces"). The coupling is explicit: the
// force of one physics step acts on the arm during the next. Against the arm's slightly compliant
// servos that one-step lag can pump energy into the knife from a stiff food (a melon's slot drives a
// growing sideways oscillation); real food cannot. So along each axis the food may give the arm back
// at most the energy it has taken from it through the coupling.
#pragma once

#include <Eigen/Core>

namespace culinarycut {

// The force (N, world frame) to put on the arm this physics step: the food's force, each component
// along the knife's axes (`knife_axes` columns: along the blade, the blade normal, the cutting
// direction) scaled down where, at the TCP's velocity now (m/s), it would do more work on the arm
// over `timestep_s` than that axis's `absorbed_j` (J).
Eigen::Vector3d PassiveCouplingForce(const Eigen::Vector3d& food_force_n, const Eigen::Matrix3d& knife_axes,
                                     const Eigen::Vector3d& tcp_velocity_m_s, double timestep_s,
                                     const Eigen::Vector3d& absorbed_j);

// Books the step's work per knife axis: the force the arm felt over the TCP's displacement (m). The
// food absorbs what the arm does against it and spends what it gives back.
void BookCouplingWork(const Eigen::Vector3d& applied_force_n, const Eigen::Matrix3d& knife_axes,
                      const Eigen::Vector3d& tcp_displacement_m, Eigen::Vector3d* absorbed_j);

}  // namespace culinarycut
