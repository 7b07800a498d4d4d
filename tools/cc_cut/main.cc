// cc-cut SCENE.json --out DIR [--threads N] [--simd LEVEL] [--particles] [--quiet]: runs a knife-cut scene, writes
// DIR/steps.csv (one row per substep), DIR/summary.json and with --particles DIR/particles.csv (every
// particle's rest and final position and piece), and prints progress and a summary.
// cc-cut --presets: prints the engine's quality presets, MPM bounds and kernels' instruction set as JSON
// (GetServerInfo's fields).
// Exit codes: 0 done, 2 bad arguments, scene file or output directory, 1 the simulation failed.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "server/wire/scene.h"
#include "sim/mpm/kernel_instruction_set.h"
#include "tools/cc_cut/cut_model.h"
#include "tools/cc_cut/cut_run.h"
#include "tools/cc_cut/cut_scene.h"
#include "tools/cc_cut/outputs.h"
#include "tools/cc_cut/scene_spec_json.h"

namespace {

namespace fs = std::filesystem;
using culinarycut::cc_cut::CutModel;
using culinarycut::cc_cut::CutScene;
using culinarycut::cc_cut::CutStepRecord;
using culinarycut::cc_cut::CutSummary;

constexpr int kBadInput = 2;
constexpr double kProgressPeriodS = 0.5;

int Fail(const std::string& message) {
  std::cerr << "cc-cut: " << message << "\n";
  return kBadInput;
}

// The presets and bounds as the server publishes them, so that scripts read them from the engine.
void PrintPresets() {
  culinarycut::v1::ServerInfo info;
  culinarycut::server::ResolutionCatalogueToWire(&info);
  const nlohmann::json all = culinarycut::cc_cut::MessageToJson(info);
  const nlohmann::json out = {
      {"quality_presets", all["quality_presets"]},
      {"max_mass_scaling", all["limits"]["max_mass_scaling"]},
      {"min_activity_radius_cells", all["limits"]["min_activity_radius_cells"]},
      {"simd", culinarycut::mpm::KernelInstructionSet()}};
  std::cout << out.dump(1) << "\n";
}

bool ReadFile(const std::string& path, std::string* text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  *text = buffer.str();
  return !in.bad();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Runs a knife-cut scene (JSON) in the MLS-MPM engine and writes its diagnostics."};
  std::string scene_path;
  std::string out_dir;
  int threads = 0;
  bool quiet = false;
  bool write_particles = false;
  bool presets = false;
  app.add_option("scene", scene_path, "scene file (JSON; see tools/cc_cut/README.md)");
  app.add_option("--out", out_dir, "output directory (created if missing)");
  app.add_flag("--presets", presets, "print the engine's quality presets and MPM bounds (JSON) and exit");
  app.add_option("--threads", threads, "OpenMP threads (overrides solver.threads)")
      ->check(CLI::Range(1, 1024));
  std::string simd = "auto";
  app.add_option("--simd", simd, "instruction set of the MPM kernels: auto or a level of this build, e.g. x86-64")
      ->capture_default_str();
  app.add_flag("--particles", write_particles, "also write particles.csv: each particle's rest and final position and piece");
  app.add_flag("--quiet", quiet, "no progress lines and no summary");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);
  } catch (const CLI::ParseError& error) {
    app.exit(error);
    return kBadInput;
  }
  try {
    culinarycut::mpm::RequireInstructionSet(simd, argv);  // may start cc-cut again
  } catch (const std::exception& failure) {
    return Fail(failure.what());
  }
  if (presets) {
    PrintPresets();
    return 0;
  }
  if (scene_path.empty() || out_dir.empty()) return Fail("a scene file and --out are required (or --presets); see --help");

  std::string text;
  if (!ReadFile(scene_path, &text)) return Fail("cannot read scene file '" + scene_path + "'");
  CutScene scene;
  CutModel model;
  try {
    scene = culinarycut::cc_cut::CutSceneFromJson(text);
    if (threads > 0) scene.solver.threads = threads;
    model = culinarycut::cc_cut::CompileCut(scene);
  } catch (const std::invalid_argument& error) {
    return Fail(scene_path + ": " + error.what());
  }

  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error) return Fail("cannot create output directory '" + out_dir + "': " + error.message());
  const fs::path steps_path = fs::path(out_dir) / "steps.csv";
  const fs::path summary_path = fs::path(out_dir) / "summary.json";
  std::ofstream steps(steps_path);
  std::ofstream summary_file(summary_path);
  if (!steps || !summary_file) return Fail("cannot write to output directory '" + out_dir + "'");
  culinarycut::cc_cut::WriteStepsHeader(steps);

  auto last_progress = std::chrono::steady_clock::now();
  const auto on_step = [&](const CutStepRecord& record) {
    culinarycut::cc_cut::WriteStepRow(record, steps);
    if (quiet) return;
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_progress).count() < kProgressPeriodS) return;
    last_progress = now;
    std::printf("t = %.4f s  knife z = %.4f m  blade force = %.3f N  (step %d)\n", record.time_s,
                record.knife_height_m, record.diagnostics.force_on_blade_n.norm(), record.step);
    std::fflush(stdout);
  };
  CutSummary summary;
  try {
    summary = culinarycut::cc_cut::RunCut(model, on_step);
  } catch (const std::exception& failure) {
    std::cerr << "cc-cut: simulation failed: " << failure.what() << "\n";
    return 1;
  }
  summary_file << culinarycut::cc_cut::SummaryJson(scene_path, scene, model, summary);
  steps.close();
  summary_file.close();
  if (!steps || !summary_file) return Fail("writing the outputs in '" + out_dir + "' failed");
  if (write_particles) {
    std::ofstream particles(fs::path(out_dir) / "particles.csv");
    culinarycut::cc_cut::WriteFinalParticles(summary.final_particles, particles);
    particles.close();
    if (!particles) return Fail("writing particles.csv in '" + out_dir + "' failed");
  }
  if (!quiet) {
    culinarycut::cc_cut::PrintSummary(model, summary, std::cout);
    std::cout << "wrote " << steps_path.string() << " and " << summary_path.string() << "\n";
  }
  return 0;
}
