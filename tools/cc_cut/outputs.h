// What cc-cut writes: the per-substep CSV, summary.json and the human summary on stdout.
#pragma once

#include <ostream>
#include <string>

#include "tools/cc_cut/cut_scene.h"

namespace culinarycut::cc_cut {

// steps.csv: the header line, then one row per substep.
void WriteStepsHeader(std::ostream& out);
void WriteStepRow(const mpm::CutStepRecord& record, std::ostream& out);

// summary.json: the scene as read, every value the run resolved to, and the summary.
std::string SummaryJson(const std::string& scene_path, const mpm::CutScene& scene,
                        const mpm::CutSceneSummary& summary);

// A few lines for people: pieces, cut positions, peak force, momentum balance, runtime.
void PrintSummary(const mpm::CutScene& scene, const mpm::CutSceneSummary& summary,
                  std::ostream& out);

}  // namespace culinarycut::cc_cut
