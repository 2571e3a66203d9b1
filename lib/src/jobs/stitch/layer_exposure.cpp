// The layers' photometric corrections and nona's exposure groups (stitch.hpp).
#include <cmath>

#include "jobs/stitch/stitch.hpp"

namespace panoproj {

void correct_layers(StitchPlan& plan, const PhotometricOutput& output) {
  for (StitchLayer& l : plan.layers) {
    PhotometricOutput out = output;
    if (plan.ignore_exposure) out.exposure = l.model.exposure;
    l.photometry.emplace(l.model, out, l.model_size, l.model_of);
  }
}

std::vector<std::vector<size_t>> exposure_groups(const StitchPlan& plan) {
  std::vector<std::vector<size_t>> groups;
  std::vector<bool> taken(plan.layers.size(), false);
  for (size_t i = 0; i < plan.layers.size(); ++i) {
    if (taken[i]) continue;
    groups.push_back({i});
    const double ev = plan.layers[i].model.exposure;
    for (size_t j = i + 1; j < plan.layers.size(); ++j)
      if (!taken[j] && std::fabs(plan.layers[j].model.exposure - ev) < kExposureLayerStep)
        groups.back().push_back(j), taken[j] = true;
  }
  return groups;
}

}  // namespace panoproj
