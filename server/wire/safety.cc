#include "server/wire/safety.h"

namespace culinarycut::server {

void ForceModelToWire(const std::string& path, const safety::ForceModel* model, const std::string& load_error,
                      v1::SafetyModelInfo* wire) {
  wire->set_path(path);
  wire->set_loaded(model != nullptr);
  wire->set_load_error(load_error);
  if (!model) return;
  wire->set_version(static_cast<std::uint32_t>(model->version));
  for (int j = 0; j < safety::kForceInputCount; ++j) {
    v1::ValueRange& range = (*wire->mutable_ranges())[safety::kForceInputNames[j]];
    range.set_low(model->ranges[j].low);
    range.set_high(model->ranges[j].high);
  }
  wire->set_out_of_range_factor(model->out_of_range_factor);
  wire->set_r2_held_out(model->fit.r2_held_out);
  wire->set_max_abs_error_n(model->fit.max_abs_error_n);
  wire->set_rmse_n(model->fit.rmse_n);
  wire->set_samples(static_cast<std::uint64_t>(model->fit.samples));
  wire->set_held_out(static_cast<std::uint64_t>(model->fit.held_out));
  wire->set_quality(model->quality);
  wire->set_terms(static_cast<std::uint32_t>(model->terms.size()));
}

}  // namespace culinarycut::server
