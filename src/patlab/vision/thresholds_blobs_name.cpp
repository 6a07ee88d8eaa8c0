// Colour classes from patch blobs (thresholds_blobs.h), stages 3 and 4: the blobs' clusters
// named by the vocabulary, and each class's box.
#include <algorithm>
#include <cmath>
#include <limits>

#include "patlab/core/error.h"
#include "patlab/core/portable_math.h"
#include "patlab/vision/thresholds_blobs.h"
#include "patlab/vision/thresholds_noise_internal.h"
#include "patlab/vision/thresholds_options_internal.h"

namespace patlab::vision {

namespace {

constexpr double kDegPerRad = 57.29577951308232;

// An entry is achromatic (white, black, grey) when its typical colour has almost no chroma.
bool Achromatic(const ColourEntry& entry) { return entry.saturation < 0.15; }

double Chroma(const std::array<double, 3>& lab) { return std::hypot(lab[1], lab[2]); }

}  // namespace

double NameCost(const std::array<double, 3>& lab, const ColourEntry& entry,
                const BlobThresholdsOptions& o) {
  const std::array<double, 3> typical = SrgbToLab(entry.rgb);
  const double dl = (lab[0] - typical[0]) / o.lightness_spread;
  const double chroma = Chroma(lab);
  if (Achromatic(entry)) {
    const double c = chroma / o.achromatic_chroma;
    return c * c + dl * dl;
  }
  if (chroma < o.achromatic_chroma) return std::numeric_limits<double>::infinity();
  double dh = (pmath::Atan2(lab[2], lab[1]) - pmath::Atan2(typical[2], typical[1])) * kDegPerRad;
  while (dh > 180.0) dh -= 360.0;
  while (dh < -180.0) dh += 360.0;
  const double h = dh / o.hue_spread_deg;
  const double c =
      pmath::Log(std::max(chroma, 1.0) / std::max(Chroma(typical), 1.0)) / o.chroma_spread;
  return h * h + dl * dl + c * c;
}

namespace {

std::array<double, 3> Feature(const std::array<double, 3>& lab, const BlobThresholdsOptions& o) {
  return {o.lightness_weight * lab[0], lab[1], lab[2]};
}

double Distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

// Complete linkage: the two clusters whose farthest blobs lie closest merge while those lie
// closer than the option, so every cluster's blobs lie within cluster_distance of each other.
// (Centroid linkage chained: a cluster's centre drifted towards what it had taken in and took in
// what lay beyond, until the dark sectors, dull rims, shadows, walls and a dull orange ball of
// a real frame were one cluster spanning 60 L*.) A cluster's colour is its blobs' mean.
std::vector<BlobCluster> ClusterBlobs(const BlobThresholdsOptions& o,
                                      std::vector<ColourBlob>* blobs) {
  const size_t n = blobs->size();
  std::vector<double> far(n * n, 0.0);  // the farthest pair's distance between two clusters
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = a + 1; b < n; ++b) {
      far[a * n + b] = far[b * n + a] =
          Distance(Feature((*blobs)[a].lab, o), Feature((*blobs)[b].lab, o));
    }
  }
  std::vector<BlobCluster> clusters;
  for (size_t i = 0; i < n; ++i) {
    (*blobs)[i].cluster = static_cast<int>(i);
    clusters.push_back({(*blobs)[i].lab, 1, -1});
  }
  std::vector<int> alias(n);
  for (size_t i = 0; i < n; ++i) alias[i] = static_cast<int>(i);
  std::vector<bool> alive(n, true);
  for (;;) {
    size_t best_a = n, best_b = n;
    double best = o.cluster_distance;
    for (size_t a = 0; a < n; ++a) {
      if (!alive[a]) continue;
      for (size_t b = a + 1; b < n; ++b) {
        if (alive[b] && far[a * n + b] < best) best = far[a * n + b], best_a = a, best_b = b;
      }
    }
    if (best_a == n) break;
    BlobCluster& a = clusters[best_a];
    const BlobCluster& b = clusters[best_b];
    const double wa = a.blobs, wb = b.blobs;
    for (int k = 0; k < 3; ++k) a.lab[k] = (wa * a.lab[k] + wb * b.lab[k]) / (wa + wb);
    a.blobs += b.blobs;
    for (size_t c = 0; c < n; ++c) {
      far[best_a * n + c] = far[c * n + best_a] =
          std::max(far[best_a * n + c], far[best_b * n + c]);
    }
    alive[best_b] = false;
    alias[best_b] = static_cast<int>(best_a);
  }
  // Renumber the survivors in order and point every blob at its cluster.
  std::vector<int> number(n, -1);
  std::vector<BlobCluster> out;
  for (size_t i = 0; i < n; ++i) {
    if (alive[i]) number[i] = static_cast<int>(out.size()), out.push_back(clusters[i]);
  }
  for (ColourBlob& blob : *blobs) {
    int c = blob.cluster;
    while (!alive[static_cast<size_t>(c)]) c = alias[static_cast<size_t>(c)];
    blob.cluster = number[static_cast<size_t>(c)];
  }
  return out;
}

// How far a further cluster lies from a class's named cluster. Lightness counts less than chroma
// (lightness_weight: light changes it first) for a colour; for white and black it is what the
// name says (a grey is neither), so it counts in full: a wall's or a shadow's grey 26-37 L*
// above a real frame's black sectors joined black, and the black box, pulled to the greys' middle,
// held none of the sectors.
double JoinDistance(const std::array<double, 3>& cluster, const std::array<double, 3>& named,
                    const ColourEntry& entry, const BlobThresholdsOptions& o) {
  if (!Achromatic(entry)) return Distance(Feature(cluster, o), Feature(named, o));
  return Distance(cluster, named);
}

// The class a further (unnamed) cluster joins, or -1: that of the named cluster nearest it, when
// within cluster_distance (JoinDistance), fitting the class's entry (`cost`: the cluster's name
// cost per class) and no other class's better.
int FurtherClusterClass(const std::array<double, 3>& lab, const double* cost,
                        const std::vector<BlobCluster>& clusters, const std::vector<int>& owner,
                        const std::vector<const ColourEntry*>& entries,
                        const BlobThresholdsOptions& o) {
  int joins = -1;
  double best = o.cluster_distance;
  for (size_t k = 0; k < entries.size(); ++k) {
    if (owner[k] < 0) continue;
    const double d = JoinDistance(lab, clusters[static_cast<size_t>(owner[k])].lab, *entries[k], o);
    if (d < best) best = d, joins = static_cast<int>(k);
  }
  if (joins < 0 || cost[joins] > o.max_name_cost) return -1;
  for (size_t k = 0; k < entries.size(); ++k)
    if (cost[k] < cost[joins]) return -1;
  return joins;
}

}  // namespace

std::vector<BlobCluster> NameBlobClusters(const std::vector<const ColourEntry*>& entries,
                                          const BlobThresholdsOptions& o,
                                          std::vector<ColourBlob>* blobs) {
  std::vector<BlobCluster> clusters = ClusterBlobs(o, blobs);
  const size_t nc = clusters.size(), nk = entries.size();
  std::vector<double> cost(nc * nk);
  for (size_t c = 0; c < nc; ++c)
    for (size_t k = 0; k < nk; ++k) cost[c * nk + k] = NameCost(clusters[c].lab, *entries[k], o);
  // One cluster per class, the cheapest pairs first.
  std::vector<int> owner(nk, -1);
  for (;;) {
    double best = o.max_name_cost;
    int bc = -1, bk = -1;
    for (size_t c = 0; c < nc; ++c) {
      if (clusters[c].name >= 0) continue;
      for (size_t k = 0; k < nk; ++k) {
        if (owner[k] < 0 && cost[c * nk + k] <= best)
          best = cost[c * nk + k], bc = static_cast<int>(c), bk = static_cast<int>(k);
      }
    }
    if (bc < 0) break;
    clusters[static_cast<size_t>(bc)].name = bk;
    owner[static_cast<size_t>(bk)] = bc;
  }
  // Further clusters join the class of the nearest named cluster when close to it and fitting the
  // class's entry.
  std::vector<int> extra(nc, -1);
  for (size_t c = 0; c < nc; ++c) {
    if (clusters[c].name < 0) {
      extra[c] = FurtherClusterClass(clusters[c].lab, &cost[c * nk], clusters, owner, entries, o);
    }
  }
  for (size_t c = 0; c < nc; ++c)
    if (extra[c] >= 0) clusters[c].name = extra[c];
  for (ColourBlob& b : *blobs) b.name = clusters[static_cast<size_t>(b.cluster)].name;
  return clusters;
}

namespace {

constexpr int kBins = 64;  // 4 levels per bin and channel

// Counts of pixels per YUV bin, summed so that any box's count is 8 lookups.
class BoxCounts {
 public:
  BoxCounts() : sum_(static_cast<size_t>(kBins + 1) * (kBins + 1) * (kBins + 1), 0) {}
  void Add(const std::array<uint8_t, 3>& yuv) {
    ++At(yuv[0] / 4 + 1, yuv[1] / 4 + 1, yuv[2] / 4 + 1);
  }
  void Accumulate() {
    for (int a = 1; a <= kBins; ++a)
      for (int b = 0; b <= kBins; ++b)
        for (int c = 0; c <= kBins; ++c) At(a, b, c) += At(a - 1, b, c);
    for (int a = 0; a <= kBins; ++a)
      for (int b = 1; b <= kBins; ++b)
        for (int c = 0; c <= kBins; ++c) At(a, b, c) += At(a, b - 1, c);
    for (int a = 0; a <= kBins; ++a)
      for (int b = 0; b <= kBins; ++b)
        for (int c = 1; c <= kBins; ++c) At(a, b, c) += At(a, b, c - 1);
  }
  // Pixels in bins lo..hi (inclusive) per channel.
  long Count(const std::array<int, 3>& lo, const std::array<int, 3>& hi) const {
    const int a0 = lo[0], a1 = hi[0] + 1, b0 = lo[1], b1 = hi[1] + 1, c0 = lo[2], c1 = hi[2] + 1;
    return Get(a1, b1, c1) - Get(a0, b1, c1) - Get(a1, b0, c1) - Get(a1, b1, c0) + Get(a0, b0, c1) +
           Get(a0, b1, c0) + Get(a1, b0, c0) - Get(a0, b0, c0);
  }

 private:
  long& At(int a, int b, int c) {
    return sum_[(static_cast<size_t>(a) * (kBins + 1) + b) * (kBins + 1) + c];
  }
  long Get(int a, int b, int c) const {
    return sum_[(static_cast<size_t>(a) * (kBins + 1) + b) * (kBins + 1) + c];
  }
  std::vector<long> sum_;
};

// The box of a class's pixels: percentiles per channel, stretched for the range of light, plus
// the margin (as thresholds_auto.cpp's boxes).
std::array<ChannelRange, 3> PercentileBox(const std::vector<std::array<uint8_t, 3>>& pixels,
                                          const BlobThresholdsOptions& o) {
  std::array<ChannelRange, 3> box{};
  std::vector<int> values;
  for (int ch = 0; ch < 3; ++ch) {
    values.clear();
    for (const auto& p : pixels) values.push_back(p[ch]);
    std::sort(values.begin(), values.end());
    const double last = static_cast<double>(values.size() - 1);
    const int lo = values[static_cast<size_t>(std::floor(o.lower_percentile / 100.0 * last))];
    const int hi = values[static_cast<size_t>(std::ceil(o.upper_percentile / 100.0 * last))];
    box[ch] = internal::StretchForLight(lo, hi, ch, o.lighting_min_gain, o.lighting_max_gain,
                                        o.margin_levels);
  }
  return box;
}

// The box's sides pulled in (in whole bins) while a move drops more other pixels than
// negative_weight times the class's own: every side and position short of the class's median colour
// (`median`, bins per channel) is tried, the best move taken.
// `own`: the class's pixels as fitted; `kept`: those and what brighter frames' clipping makes of
// them at each gain (internal::WithClipping), the pixels the box is to keep; `spared`: pixels of
// `all` that are not counted against the class (its colour's patches too narrow for a blob).
void TightenBox(const BoxCounts& own, const BoxCounts& kept, const BoxCounts& all,
                const BoxCounts& spared, double negative_weight, const std::array<int, 3>& median,
                std::array<ChannelRange, 3>* box) {
  std::array<int, 3> lo{}, hi{};
  for (int ch = 0; ch < 3; ++ch) lo[ch] = (*box)[ch].lo / 4, hi[ch] = (*box)[ch].hi / 4;
  const auto score = [&](const std::array<int, 3>& l, const std::array<int, 3>& h) {
    return static_cast<double>(kept.Count(l, h)) -
           static_cast<double>(all.Count(l, h) - own.Count(l, h) - spared.Count(l, h)) /
               negative_weight;
  };
  std::array<bool, 6> moved{};
  double current = score(lo, hi);
  for (int round = 0; round < 6 * kBins; ++round) {
    int best_side = -1, best_at = 0;
    double best = current;
    for (int side = 0; side < 6; ++side) {
      const int ch = side / 2;
      const int first = side % 2 == 0 ? lo[ch] : std::max(lo[ch], median[ch]);
      const int last = side % 2 == 0 ? std::min(hi[ch], median[ch]) : hi[ch];
      for (int at = first; at <= last; ++at) {
        std::array<int, 3> l = lo, h = hi;
        (side % 2 == 0 ? l : h)[ch] = at;
        const double s = score(l, h);
        if (s > best + 1e-9) best = s, best_side = side, best_at = at;
      }
    }
    if (best_side < 0) break;
    (best_side % 2 == 0 ? lo : hi)[best_side / 2] = best_at;
    moved[static_cast<size_t>(best_side)] = true;
    current = best;
  }
  for (int ch = 0; ch < 3; ++ch) {
    if (moved[2 * ch]) (*box)[ch].lo = 4 * lo[ch];
    if (moved[2 * ch + 1]) (*box)[ch].hi = 4 * hi[ch] + 3;
  }
}

void Describe(const std::vector<std::array<uint8_t, 3>>& pixels, AutoClassFit* c) {
  c->pixels = static_cast<long>(pixels.size());
  if (pixels.empty()) return;
  std::array<double, 3> s{}, s2{};
  for (const auto& p : pixels)
    for (int ch = 0; ch < 3; ++ch) s[ch] += p[ch], s2[ch] += 1.0 * p[ch] * p[ch];
  double var = 0;
  for (int ch = 0; ch < 3; ++ch) {
    c->mean_yuv[ch] = s[ch] / c->pixels;
    var += std::max(0.0, s2[ch] / c->pixels - c->mean_yuv[ch] * c->mean_yuv[ch]);
  }
  c->spread_levels = std::sqrt(var / 3.0);
}

// The pixels a box is pulled in against: every pixel of the frames but those of regions larger
// than a patch (field lines, walls, people, the frame's dark margins), whose blobs the detector's
// area test rejects whatever their class. Counting them, a class that shares a colour with them
// lost its patches: the real SSL frame's white box cut the sectors whose white is yellowish
// (the lines' tint) and its black box the darkest sector pixels (the dark margins' levels).
BoxCounts NegativeCounts(const std::vector<NormalisedFrame>& frames,
                         const std::vector<std::vector<uint8_t>>& oversize) {
  BoxCounts counts;
  for (size_t f = 0; f < frames.size(); ++f) {
    for (size_t i = 0; i < frames[f].yuv.size(); ++i)
      if (oversize[f][i] == 0) counts.Add(frames[f].yuv[i]);
  }
  counts.Accumulate();
  return counts;
}

// A frame's region too narrow for a blob (FindColourBlobs' `narrow`).
struct NarrowRegion {
  size_t frame = 0;
  std::vector<int> pixels;
};

// Adds to `spared` the pixels of the regions too narrow for a blob that hold a pixel inside
// `noise_box` (the class's median colour spread by the camera's noise): patches of the class's
// colour small enough for the segmentation to cut their bright cores to slivers (a random
// camera's green ID patches, 2.4 px in radius: cores of 0.58-0.70 px spread against a
// min_blob_sigma_px of 0.71, 7 of 9 patches no blob). Counted against the class, they pulled its
// box in until it held none of those cores. A sliver of another colour, a rim where two colours
// blend, seldom reaches the noise box. Returns the pixels added.
long SpareNarrowAlike(const std::vector<NarrowRegion>& narrow,
                      const std::vector<NormalisedFrame>& frames,
                      const std::array<ChannelRange, 3>& noise_box, BoxCounts* spared) {
  long count = 0;
  for (const NarrowRegion& r : narrow) {
    const std::vector<std::array<uint8_t, 3>>& yuv = frames[r.frame].yuv;
    const bool alike = std::any_of(r.pixels.begin(), r.pixels.end(), [&](int i) {
      const std::array<uint8_t, 3>& p = yuv[static_cast<size_t>(i)];
      for (int ch = 0; ch < 3; ++ch)
        if (p[ch] < noise_box[ch].lo || p[ch] > noise_box[ch].hi) return false;
      return true;
    });
    if (!alike) continue;
    for (const int i : r.pixels) spared->Add(yuv[static_cast<size_t>(i)]);
    count += static_cast<long>(r.pixels.size());
  }
  spared->Accumulate();
  return count;
}

// A class's box from its blobs' pixels `own` (stage 4 of thresholds_blobs.h): the percentile
// box widened for clipping, tightened against the frames' other pixels (`all`) but those of
// narrow regions alike to the class, widened towards the camera's noise; c gets the pixels spared
// and the levels widened.
std::array<ChannelRange, 3> FitClassBox(const std::vector<std::array<uint8_t, 3>>& own,
                                        const std::vector<NarrowRegion>& narrow,
                                        const std::vector<NormalisedFrame>& normalised,
                                        const BoxCounts& all, const internal::CameraNoise& noise,
                                        const BlobThresholdsOptions& options, AutoClassFit* c) {
  // What a brighter frame's clipping does to the class's colours, scaled back, is the class's.
  const std::vector<std::array<uint8_t, 3>> clipped =
      internal::WithClipping(own, internal::kBrighterFramesGain);
  BoxCounts counts, kept;
  for (const auto& p : own) counts.Add(p);
  for (const auto& p : clipped) kept.Add(p);
  counts.Accumulate();
  kept.Accumulate();
  std::array<ChannelRange, 3> box = PercentileBox(own, options);
  const std::array<ChannelRange, 3> wide = PercentileBox(clipped, options);
  for (int ch = 0; ch < 3; ++ch) {
    box[ch] = {std::min(box[ch].lo, wide[ch].lo), std::max(box[ch].hi, wide[ch].hi)};
  }
  // A tightened box keeps the bins of the class's median colour. (Where every box of a dark
  // class holds more of the frame's dark margins and shadows than of the class, the best
  // single move used to shut the box on a bin that holds nothing: the class caught no pixel.)
  const std::array<int, 3> median = internal::MedianColour(own);
  BoxCounts spared;
  if (noise.pixels > 0) {
    c->thin_alike =
        SpareNarrowAlike(narrow, normalised, internal::NoiseBox(median, noise, options), &spared);
  }
  TightenBox(counts, kept, all, spared, options.negative_weight,
             {median[0] / 4, median[1] / 4, median[2] / 4}, &box);
  // The noise's box weighs as one blob against the class's own (a shrinkage towards it).
  c->widened_levels = internal::WidenToNoise(median, noise, 1.0 / (1.0 + c->blobs), options, &box);
  return box;
}

}  // namespace

AutoThresholdsFit FitThresholdsFromBlobs(const std::vector<const camera::Image*>& frames,
                                         const std::vector<std::string>& class_names,
                                         const ColourVocabulary& vocabulary,
                                         const BlobThresholdsOptions& options,
                                         std::vector<BlobCluster>* clusters_out) {
  Validate(options);  // before NormaliseFrame uses them
  std::vector<NormalisedFrame> normalised;
  for (const camera::Image* frame : frames) normalised.push_back(NormaliseFrame(*frame, options));
  return FitThresholdsFromBlobs(normalised, class_names, vocabulary, options, clusters_out);
}

AutoThresholdsFit FitThresholdsFromBlobs(const std::vector<NormalisedFrame>& normalised,
                                         const std::vector<std::string>& class_names,
                                         const ColourVocabulary& vocabulary,
                                         const BlobThresholdsOptions& options,
                                         std::vector<BlobCluster>* clusters_out) {
  Validate(options);
  if (normalised.empty()) throw InputError("no frames; expected at least one frame");
  const std::vector<const ColourEntry*> entries = PaletteEntries(class_names, vocabulary);
  std::vector<std::vector<uint8_t>> oversize;
  std::vector<ColourBlob> blobs;
  std::vector<NarrowRegion> narrow;
  AutoThresholdsFit fit;
  std::vector<std::array<uint8_t, 3>> carpet;
  for (size_t f = 0; f < normalised.size(); ++f) {
    const NormalisedFrame& n = normalised[f];
    oversize.emplace_back();
    std::vector<std::vector<int>> thin;
    std::vector<ColourBlob> b =
        FindColourBlobs(n, static_cast<int>(f), options, &oversize.back(), &thin);
    for (std::vector<int>& t : thin) narrow.push_back({f, std::move(t)});
    blobs.insert(blobs.end(), std::make_move_iterator(b.begin()), std::make_move_iterator(b.end()));
    fit.frame_pixels += static_cast<long>(n.yuv.size());
    for (size_t i = 0; i < n.yuv.size(); ++i)
      if (n.carpet[i] != 0) carpet.push_back(n.yuv[i]);
  }
  std::vector<BlobCluster> clusters = NameBlobClusters(entries, options, &blobs);
  fit.carpet.name = "carpet";
  Describe(carpet, &fit.carpet);
  const BoxCounts all = NegativeCounts(normalised, oversize);
  fit.thresholds.space = ColorSpace::kYuv;
  const internal::CameraNoise noise = internal::MeasureCarpetNoise(normalised, options);
  for (int ch = 0; ch < 3; ++ch) fit.noise_levels[ch] = noise.below[ch] + noise.above[ch];
  for (size_t k = 0; k < entries.size(); ++k) {
    AutoClassFit c;
    c.name = entries[k]->name;
    std::vector<std::array<uint8_t, 3>> own;
    for (const ColourBlob& b : blobs) {
      if (b.name != static_cast<int>(k)) continue;
      ++c.blobs;
      for (const int i : b.pixels)
        own.push_back(normalised[static_cast<size_t>(b.frame)].yuv[static_cast<size_t>(i)]);
    }
    Describe(own, &c);
    ColorClass cls;
    cls.name = c.name;
    cls.display_rgb = entries[k]->rgb;
    cls.range = {ChannelRange{0, 0}, ChannelRange{0, 0}, ChannelRange{0, 0}};
    if (!own.empty()) cls.range = FitClassBox(own, narrow, normalised, all, noise, options, &c);
    c.range = cls.range;
    fit.thresholds.classes.push_back(cls);
    fit.classes.push_back(c);
  }
  ComputeSeparability(&fit);
  if (clusters_out != nullptr) *clusters_out = std::move(clusters);
  return fit;
}

}  // namespace patlab::vision
