// One frame's measurements as the detector sees them: unordered blobs of colour-labelled regions
// on the world plane. The simulator (sim/scene.h) and the vision pipeline (vision/) both
// produce them; the detector never knows which.
#pragma once

#include "patlab/core/geometry.h"

namespace patlab::detect {

struct Blob {
  Vec2 position_mm = Vec2::Zero();  // region centroid on the world plane
  int colour = 0;                   // colour label: index into the detector's palette
  double area_mm2 = 0.0;            // region area on the world plane
};

}  // namespace patlab::detect
