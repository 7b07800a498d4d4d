// What cc-cut writes: the per-substep CSV, summary.json and the human summary on stdout.
#pragma once

#include <ostream>
#include <string>

#include "tools/cc_cut/cut_model.h"
#include "tools/cc_cut/cut_run.h"
#include "tools/cc_cut/cut_scene.h"

namespace culinarycut::cc_cut {

// steps.csv: the header line, then one row per substep.
void WriteStepsHeader(std::ostream& out);
void WriteStepRow(const CutStepRecord& record, std::ostream& out);

// particles.csv: every particle's rest and final position (m) and piece label, one row each.
void WriteFinalParticles(const FinalParticles& particles, std::ostream& out);

// summary.json: the scene with every default filled in, every value the run resolved to, and the
// summary.
std::string SummaryJson(const std::string& scene_path, const CutScene& scene, const CutModel& model,
                        const CutSummary& summary);

// A few lines for people: pieces, cut positions, peak force, momentum balance, runtime.
void PrintSummary(const CutModel& model, const CutSummary& summary, std::ostream& out);

}  // namespace culinarycut::cc_cut
