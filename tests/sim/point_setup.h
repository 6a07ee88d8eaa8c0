// A point of the Monte-Carlo kernel on the paper's field, as the kernel's tests set it up.
#pragma once

#include <cstdint>

#include "patlab/sim/batch.h"

namespace patlab::testing {

// `model` at patch sigma `sigma_mm` on the 2800 x 2300 mm field, trials seeded from `seed`,
// isotropic Gaussian noise and no estimator run (the caller picks them in `run`).
inline sim::PointSetup FieldPoint(const estimate::Model& model, double sigma_mm, uint64_t seed) {
  sim::PointSetup setup;
  setup.model = &model;
  setup.sigma_mm = sigma_mm;
  setup.field_length_mm = 2800;
  setup.field_width_mm = 2300;
  setup.seed = seed;
  return setup;
}

}  // namespace patlab::testing
