// The prescribed knife of a cc-cut run: the blade stands across the food's long axis (blade normal
// along it), edge down, descends from above the food's top to below its bottom, lifts straight
// back and waits. The long axis and its left end are the task logic's (task::LongAxisOf), so a
// cut fraction here means what a task's "ratio from the left" means on the server.
#pragma once

#include <optional>

namespace culinarycut::cc_cut {

struct KnifePath {
  // Where the blade crosses the long axis: a fraction of the food's length from its left end, or
  // a signed distance from the food's centre towards its right end (m). At most one is given;
  // default: fraction 0.5.
  std::optional<double> cut_fraction;
  std::optional<double> cut_from_centre_m;
  double start_above_top_m = 0.006;   // edge height above the food's top at the start
  double end_below_bottom_m = 0.001;  // lowest edge position below the food's bottom
  double descent_speed_m_s = 0.5;
  double saw_amplitude_m = 0.0;  // back and forth along the blade while descending
  double saw_frequency_hz = 0.0;
  double lift_speed_m_s = 1.0;  // back up to the start height after the descent
  double settle_s = 0.02;       // simulated after the knife is back up
  // The paper's output-accumulation window: the blade force is also reported as the impulse over
  // this window divided by it, which removes the sawtooth of the edge crossing cells.
  double force_window_s = 0.005;
  // Slow the descent by the solver's knife_speed_factor (quadratic speed resistance), never below
  // min_speed_fraction of descent_speed_m_s.
  bool apply_speed_resistance = false;
  double min_speed_fraction = 0.1;
  double max_time_s = 10.0;  // the run stops here whatever the knife's phase
};

}  // namespace culinarycut::cc_cut
