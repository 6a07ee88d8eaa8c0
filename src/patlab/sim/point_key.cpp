#include "patlab/sim/point_key.h"

#include "patlab/core/format.h"
#include "patlab/core/rng.h"

namespace patlab::sim {

namespace {

// Sigma by its 12-significant-digit text, so that a grid's 0.30000000000000004 (3 x 0.1) and a
// flag's 0.3 are the same point.
void AddSigma(double sigma_mm, StreamKey* key) {
  key->Add(std::string_view(FormatSignificant(sigma_mm == 0.0 ? 0.0 : sigma_mm, 12)));
}

}  // namespace

void AddPattern(const Pattern& pattern, StreamKey* key) {
  key->Add(static_cast<uint64_t>(pattern.patches.size()));
  for (const Patch& p : pattern.patches) {
    key->Add(p.position_mm.x()).Add(p.position_mm.y()).Add(p.radius_mm);
    key->Add(static_cast<uint64_t>(p.role)).Add(std::string_view(p.colour));
  }
  key->Add(static_cast<uint64_t>(pattern.orientation_pairs.size()));
  for (const OrientationPair& o : pattern.orientation_pairs) {
    key->Add(static_cast<uint64_t>(o.from)).Add(static_cast<uint64_t>(o.to));
  }
  key->Add(static_cast<uint64_t>(pattern.key_index));
}

void AddNoise(const NoiseModel& noise, StreamKey* key) {
  key->Add(noise.sigma_y_ratio)
      .Add(noise.common_sigma_ratio)
      .Add(noise.outlier_probability)
      .Add(noise.outlier_sigma_ratio);
  // The camera-level models join the key only when on, so that every point of the four older
  // models keeps the stream (and the committed results) it had before them.
  if (noise.HasCameraModels()) {
    key->Add(std::string_view("camera"))
        .Add(noise.rotation_jitter_rad)
        .Add(noise.scale_jitter_ppm)
        .Add(noise.correlation_length_mm)
        .Add(noise.key_shift_x_mm)
        .Add(noise.id_shift_x_mm);
  }
}

uint64_t KnownPointKey(uint64_t seed, const Pattern& pattern, const NoiseModel& noise,
                       double sigma_mm) {
  StreamKey key(seed);
  key.Add(static_cast<uint64_t>(kKnownStream));
  AddPattern(pattern, &key);
  AddNoise(noise, &key);
  AddSigma(sigma_mm, &key);
  return key.value();
}

void AddDetectorPattern(const detect::DetectorPattern& pattern,
                        const std::vector<std::string>& palette, StreamKey* key) {
  const detect::Codebook& c = pattern.codebook;
  key->Add(static_cast<uint64_t>(c.colours.size()));
  for (const std::string& colour : c.colours) key->Add(std::string_view(colour));
  key->Add(static_cast<uint64_t>(c.num_slots)).Add(static_cast<uint64_t>(c.entries.size()));
  for (const detect::CodebookEntry& e : c.entries) {
    key->Add(static_cast<uint64_t>(e.id)).Add(static_cast<uint64_t>(e.colour.size()));
    for (const int colour : e.colour) key->Add(static_cast<uint64_t>(colour));
  }
  key->Add(static_cast<uint64_t>(pattern.key_colours.size()));
  for (const std::string& colour : pattern.key_colours) key->Add(std::string_view(colour));
  key->Add(static_cast<uint64_t>(palette.size()));
  for (const std::string& colour : palette) key->Add(std::string_view(colour));
}

uint64_t DetectPointKey(uint64_t seed, const Pattern& pattern, const NoiseModel& noise,
                        double sigma_mm, double false_blob_rate_per_m2,
                        const detect::DetectorPattern& detector,
                        const std::vector<std::string>& palette) {
  StreamKey key(seed);
  key.Add(static_cast<uint64_t>(kDetectStream));
  AddPattern(pattern, &key);
  AddNoise(noise, &key);
  AddSigma(sigma_mm, &key);
  key.Add(false_blob_rate_per_m2);
  AddDetectorPattern(detector, palette, &key);
  return key.value();
}

}  // namespace patlab::sim
