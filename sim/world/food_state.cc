#include "sim/world/food_state.h"

namespace culinarycut {

void ResetFood(const FoodModel& model, const SceneLayout& layout, FoodState* state) {
  *state = FoodState{};
  state->solver = std::make_unique<mpm::Solver<float>>(model.solver);
  state->solver->particles() = model.initial_particles;
  mpm::RigidMotion board;
  board.pose.translation() = layout.board_center_m;
  state->solver->SetBoard(layout.board_size_m, board);
  state->solver->SetTable(layout.table_center_m.z() + 0.5 * layout.table_size_m.z());
  state->solver->SetKnife(model.knife);
  state->particle_bounds = ParticleBounds(state->solver->particles());
  UpdatePieces(model, state);
}

void UpdatePieces(const FoodModel& model, FoodState* state) {
  state->pieces = mpm::DetectPieces(model.topology, &state->solver->particles());
}

std::vector<mpm::Piece> MeasurePieces(const FoodModel& model, const FoodState& state) {
  if (model.topology_update) return state.pieces;
  mpm::Particles<float> scratch = state.solver->particles();
  return mpm::DetectPieces(model.topology, &scratch);
}

Eigen::AlignedBox3f ParticleBounds(const mpm::Particles<float>& particles) {
  Eigen::AlignedBox3f bounds;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    bounds.extend(Eigen::Vector3f(particles.position[0][i], particles.position[1][i], particles.position[2][i]));
  }
  return bounds;
}

}  // namespace culinarycut
