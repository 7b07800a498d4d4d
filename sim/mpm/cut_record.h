// Which side of each cut a particle ended up on. When the knife's edge passes a particle, the
// particle records the blade side it was on, for that cut; two particles on opposite sides of one
// cut never belong to one piece again, however close the pieces lie afterwards (a thin slice the
// blade left touching its neighbour stays a slice). Two bits per cut in one 32-bit word.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include <Eigen/Core>

namespace culinarycut::mpm {

// Cuts a particle can remember; later cuts share the last slot (their sides are still told apart
// from every earlier cut, but not from each other).
constexpr int kMaxRecordedCuts = 16;

constexpr std::uint32_t kPassedBits = 0x55555555u;  // bit 2k: the edge passed it in cut k

constexpr std::uint32_t PassedBit(int cut) { return 1u << (2 * cut); }
constexpr std::uint32_t PositiveSideBit(int cut) { return 2u << (2 * cut); }

// `record` with cut `cut` set: passed, on the blade's positive (TCP +y) side or not.
constexpr std::uint32_t RecordCut(std::uint32_t record, int cut, bool positive_side) {
  return (record & ~(3u << (2 * cut))) | PassedBit(cut) | (positive_side ? PositiveSideBit(cut) : 0u);
}

// Whether no cut that both particles passed put them on opposite sides.
constexpr bool SameSideOfEveryCut(std::uint32_t a, std::uint32_t b) {
  return (((a ^ b) >> 1) & (a & b & kPassedBits)) == 0;
}

// A side bit is only ever set together with its passed bit.
constexpr bool ValidCutRecord(std::uint32_t record) { return ((record >> 1) & ~record & kPassedBits) == 0; }

// The blade's orientation over one cut, from the knife's pose on every substep its edge passed
// food: the time-weighted sum of n n^T for the blade's face normal n (TCP +y). The sum does not
// care which way n points; its principal axis is the cut's mean blade normal.
struct BladeNormalMoment {
  Eigen::Matrix3d normal_outer_s = Eigen::Matrix3d::Zero();  // sum of dt n n^T (s)
  double duration_s = 0.0;                                    // time the edge was passing food (s)

  void Add(const Eigen::Vector3d& blade_normal, double dt_s);
  // The mean blade normal (unit; its sign is arbitrary), or nothing if the edge never passed food.
  std::optional<Eigen::Vector3d> MeanNormal() const;
};

// The solver's count of cuts: a cut begins when the blade comes near the food after it was clear
// of it, and lasts while any particle is near the blade.
struct CutProgress {
  std::uint32_t cuts_made = 0;   // cuts that recorded at least one particle
  std::uint32_t current = 0;     // the cut this substep records into
  bool blade_in_food = false;    // particles were near the blade last substep
  std::array<BladeNormalMoment, kMaxRecordedCuts> blade_normals;  // per cut (later cuts share the last)
};

// What one chunk of particles saw while labelling: particles near the blade, and those that
// recorded the current cut.
struct CutCounts {
  std::int64_t labelled = 0;
  std::int64_t recorded = 0;
};

}  // namespace culinarycut::mpm
