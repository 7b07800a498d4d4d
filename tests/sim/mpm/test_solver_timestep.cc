// The substep length (StableTimestep): at most a CFL fraction of a cell for sound, for the knife and
// for the fastest particle, which each substep reports the same as a scan of the particles.
#include <algorithm>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "cut_scenario.h"
#include "mpm_fixtures.h"
#include "sim/mpm/solver.h"

namespace culinarycut::mpm {
namespace {

using testing::SoftMaterial;

TEST_CASE("the substep is bounded by sound, the knife and the fastest particle", "[mpm][timestep]") {
  const SolverModel model{SolverConfig{}, {SoftMaterial(5e4, 0.3)}};
  const double c_m_s = model.materials[0].dilatational_wave_speed_m_s();  // 8.3 m/s
  const double cfl_dx_m = model.config.cfl * model.config.dx_m;
  const double wave_dt_s = StableTimestep(model);
  CHECK(wave_dt_s == Approx(cfl_dx_m / c_m_s));
  // Slower than sound: sound decides.
  CHECK(StableTimestep(model, 0.5, 0.5 * c_m_s) == wave_dt_s);
  // A particle (or a knife) faster than sound: it decides, whichever of the two is faster.
  CHECK(StableTimestep(model, 0.5, 15.0) == Approx(cfl_dx_m / 15.0));
  CHECK(StableTimestep(model, 15.0, 0.5) == StableTimestep(model, 0.5, 15.0));
  CHECK(StableTimestep(model, 12.0, 15.0) == Approx(cfl_dx_m / 15.0));
  CHECK(StableTimestep(model, 0.0, 15.0) < wave_dt_s);
}

// A soft block (E 5 kPa: sound at 2.6 m/s) on the board, thrown along it at 12 m/s, sliding for
// 20 ms; each substep as long as the fastest particle of the one before allows (sound alone would
// allow 0.31 ms: 0.93 of a cell per substep at 12 m/s).
struct Slide {
  std::vector<double> dt_s;
  std::vector<double> fastest_m_s;  // after each substep
  std::int64_t speed_caps = 0;
  std::int64_t j_clamps = 0;
  double j_min = 1.0;
  double lowest_m = 1.0;            // lowest particle at the end (m)
  double velocity_start_m_s = 0.0;  // the centre of mass's along the board
  double velocity_end_m_s = 0.0;
  double time_s = 0.0;
  bool same_as_scan = true;         // each substep's fastest particle is the scan's, bit for bit
};

Slide SlideAlongBoard(int threads) {
  SolverConfig config;
  config.threads = threads;
  Solver<float> solver(config, {SoftMaterial(5e3, 0.3)});
  testing::AddBlock<float>({0.31, -0.01, 0.02}, {0.33, 0.01, 0.04}, config.dx_m, 2, 1000.0,
                           &solver.particles());
  testing::AddBoardAndTable(&solver);
  auto& p = solver.particles();
  for (std::size_t q = 0; q < p.size(); ++q) p.velocity[0][q] = 12.0f;
  const SolverModel model{solver.config(), solver.materials()};
  Slide result;
  result.velocity_start_m_s = testing::Momentum(p).x() / p.size() / p.mass[0];
  double fastest_m_s = FastestParticleSpeed(p);
  while (result.time_s < 0.02) {
    const double dt_s = StableTimestep(model, 0.0, fastest_m_s);
    const SubstepDiagnostics d = solver.Substep(dt_s);
    fastest_m_s = d.fastest_particle_m_s;
    result.same_as_scan = result.same_as_scan && fastest_m_s == FastestParticleSpeed(p);
    result.dt_s.push_back(dt_s);
    result.fastest_m_s.push_back(fastest_m_s);
    result.speed_caps += d.speed_caps;
    result.j_clamps += d.j_clamps;
    result.j_min = std::min(result.j_min, d.j_min);
    result.time_s += dt_s;
  }
  result.velocity_end_m_s = testing::Momentum(p).x() / p.size() / p.mass[0];
  for (std::size_t q = 0; q < p.size(); ++q) result.lowest_m = std::min<double>(result.lowest_m, p.position[2][q]);
  return result;
}

TEST_CASE("food thrown faster than its sound gets shorter substeps and no speed caps", "[mpm][timestep]") {
  const SolverModel model{SolverConfig{}, {SoftMaterial(5e3, 0.3)}};
  const double cfl_dx_m = model.config.cfl * model.config.dx_m;
  const double wave_dt_s = StableTimestep(model);  // 0.31 ms
  const Slide slide = SlideAlongBoard(1);
  INFO("substeps " << slide.dt_s.size() << ", shortest " << *std::min_element(slide.dt_s.begin(), slide.dt_s.end())
                   << " s (sound alone: " << wave_dt_s << " s), speed caps " << slide.speed_caps << ", J clamps "
                   << slide.j_clamps << ", lowest particle " << slide.lowest_m << " m, velocity "
                   << slide.velocity_start_m_s << " -> " << slide.velocity_end_m_s << " m/s");
  CHECK(slide.same_as_scan);
  // While it slides at 12 m/s, a substep is a CFL fraction of a cell at 12 m/s: a quarter of sound's.
  CHECK(slide.dt_s.front() == Approx(cfl_dx_m / 12.0).epsilon(1e-6));
  CHECK(slide.dt_s.front() < 0.25 * wave_dt_s);
  for (std::size_t s = 1; s < slide.dt_s.size(); ++s) {
    CHECK(slide.fastest_m_s[s - 1] * slide.dt_s[s] <= cfl_dx_m * (1.0 + 1e-12));
  }
  CHECK(slide.speed_caps == 0);
  CHECK(slide.j_clamps == 0);
  CHECK(slide.lowest_m > 0.02 - 0.25 * model.config.dx_m);  // the board's top at 2 cm
  // The board's friction slows it (0.05 m/s in 20 ms; Coulomb's mu g t would be 0.1 m/s).
  CHECK(slide.velocity_end_m_s < slide.velocity_start_m_s);
  CHECK(slide.velocity_end_m_s > 0.98 * slide.velocity_start_m_s);
}

TEST_CASE("the thrown block takes the same substeps on 1 and 2 threads", "[mpm][timestep][determinism]") {
  const Slide one = SlideAlongBoard(1);
  const Slide two = SlideAlongBoard(2);
  CHECK(one.dt_s == two.dt_s);
  CHECK(one.fastest_m_s == two.fastest_m_s);
  CHECK(one.velocity_end_m_s == two.velocity_end_m_s);
}

}  // namespace
}  // namespace culinarycut::mpm
