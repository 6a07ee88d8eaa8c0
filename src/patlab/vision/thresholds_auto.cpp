#include "patlab/vision/thresholds_auto.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/portable_math.h"
#include "patlab/vision/thresholds_options_internal.h"

namespace patlab::vision {

std::vector<OptionsProblem> Check(const AutoThresholdsOptions& o) {
  OptionsChecker check;
  check
      .Require("min_chroma_levels", o.min_chroma_levels,
               o.min_chroma_levels >= 0.0 && o.min_chroma_levels <= 128.0, "in [0, 128]")
      .Require("gate_sigmas", o.gate_sigmas, o.gate_sigmas > 0.0 && o.gate_sigmas <= 10.0,
               "in (0, 10]")
      .IntegerInRange("iterations", o.iterations, 0, 50);
  internal::CheckBoxOptions(check, o).Require(
      "max_patch_fraction", o.max_patch_fraction,
      o.max_patch_fraction > 0.0 && o.max_patch_fraction <= 1.0, "in (0, 1]");
  return check.Take();
}

void Validate(const AutoThresholdsOptions& options) { ThrowFirstProblem(Check(options)); }

namespace {

constexpr double kPi = 3.14159265358979323846;

// One pixel in YUV and in the features the clustering uses.
struct Pixel {
  uint8_t y, u, v;
  float hue;       // atan2(V - 128, U - 128), rad
  float sat;       // chroma / max(Y, 16)
  float log_luma;  // log(max(Y, 8))
  float chroma;    // |(U, V) - 128|, levels
  int label;       // -2 carpet, -1 none, else class index
  int hand;        // hand label (class index) or -1
};

void AppendPixels(const camera::Image& image, const std::vector<int>* hand,
                  std::vector<Pixel>* out) {
  for (int y = 0; y < image.height_px; ++y) {
    const uint8_t* row = image.Row(y);
    for (int x = 0; x < image.width_px; ++x) {
      int a, b, c;
      if (image.format == camera::PixelFormat::kRgb8) {
        camera::RgbToYuv(row[3 * x], row[3 * x + 1], row[3 * x + 2], &a, &b, &c);
      } else {
        const uint8_t* pair = row + 4 * (x / 2);
        a = pair[1 + 2 * (x % 2)], b = pair[0], c = pair[2];
      }
      Pixel p;
      p.y = static_cast<uint8_t>(a), p.u = static_cast<uint8_t>(b), p.v = static_cast<uint8_t>(c);
      const double du = b - 128.0, dv = c - 128.0;
      p.chroma = static_cast<float>(std::sqrt(du * du + dv * dv));
      p.hue = static_cast<float>(pmath::Atan2(dv, du));
      p.sat = static_cast<float>(p.chroma / std::max(a, 16));
      p.log_luma = static_cast<float>(pmath::Log(std::max(a, 8)));
      p.label = -1;
      p.hand = hand == nullptr ? -1 : (*hand)[static_cast<size_t>(y) * image.width_px + x];
      out->push_back(p);
    }
  }
}

// A class's centre and spread in the clustering features.
struct Centre {
  double hue = 0.0, sat = 0.0, log_luma = 0.0;
  double s_hue = 0.25, s_sat = 0.3, s_log_luma = 0.5;
  bool chromatic = true;
};

double WrappedDelta(double a, double b) {
  double d = a - b;
  while (d > kPi) d -= 2.0 * kPi;
  while (d < -kPi) d += 2.0 * kPi;
  return d;
}

double Distance2(const Pixel& p, const Centre& c) {
  const double s = (p.sat - c.sat) / c.s_sat, l = (p.log_luma - c.log_luma) / c.s_log_luma;
  if (!c.chromatic) return s * s + l * l;
  const double h = WrappedDelta(p.hue, c.hue) / c.s_hue;
  return h * h + s * s + l * l;
}

Centre SeedOf(int y, int u, int v) {
  Centre c;
  const double du = u - 128.0, dv = v - 128.0, chroma = std::sqrt(du * du + dv * dv);
  c.hue = pmath::Atan2(dv, du);
  c.sat = chroma / std::max(y, 16);
  c.log_luma = pmath::Log(std::max(y, 8));
  c.chromatic = chroma >= 12.0;
  if (!c.chromatic) c.s_sat = 0.12;
  return c;
}

// The centre and spread of the pixels labelled k (floors keep a tight cluster from collapsing).
void Update(const std::vector<Pixel>& pixels, int k, Centre* c) {
  double n = 0, sx = 0, sy = 0, ss = 0, sl = 0;
  for (const Pixel& p : pixels) {
    if (p.label != k) continue;
    n += 1, sx += pmath::Cos(p.hue), sy += pmath::Sin(p.hue), ss += p.sat, sl += p.log_luma;
  }
  if (n < 5) return;
  c->hue = pmath::Atan2(sy, sx), c->sat = ss / n, c->log_luma = sl / n;
  double vh = 0, vs = 0, vl = 0;
  for (const Pixel& p : pixels) {
    if (p.label != k) continue;
    const double h = WrappedDelta(p.hue, c->hue);
    vh += h * h, vs += (p.sat - c->sat) * (p.sat - c->sat);
    vl += (p.log_luma - c->log_luma) * (p.log_luma - c->log_luma);
  }
  c->s_hue = std::clamp(std::sqrt(vh / n), 0.06, 0.3);
  c->s_sat = std::clamp(std::sqrt(vs / n), c->chromatic ? 0.05 : 0.03, 0.4);
  c->s_log_luma = std::clamp(std::sqrt(vl / n), 0.08, 0.6);
}

// The carpet: the fullest 16-level YUV cell, then the pixels within `gate` spreads per channel.
void FindCarpet(std::vector<Pixel>* pixels, double gate) {
  std::vector<long> cells(4096, 0);
  for (const Pixel& p : *pixels) ++cells[(p.y >> 4) * 256 + (p.u >> 4) * 16 + (p.v >> 4)];
  const int mode = static_cast<int>(std::max_element(cells.begin(), cells.end()) - cells.begin());
  std::array<double, 3> mean = {(mode / 256) * 16 + 7.5, ((mode / 16) % 16) * 16 + 7.5,
                                (mode % 16) * 16 + 7.5};
  std::array<double, 3> sigma = {16.0, 6.0, 6.0};
  const std::array<double, 3> floor = {8.0, 3.0, 3.0};
  for (int round = 0; round < 4; ++round) {
    std::array<double, 3> s{}, s2{};
    double n = 0;
    for (Pixel& p : *pixels) {
      const double d[3] = {(p.y - mean[0]) / sigma[0], (p.u - mean[1]) / sigma[1],
                           (p.v - mean[2]) / sigma[2]};
      const bool in =
          p.hand < 0 && std::abs(d[0]) <= gate && std::abs(d[1]) <= gate && std::abs(d[2]) <= gate;
      p.label = in ? -2 : -1;
      if (!in) continue;
      const double v[3] = {static_cast<double>(p.y), static_cast<double>(p.u),
                           static_cast<double>(p.v)};
      for (int ch = 0; ch < 3; ++ch) s[ch] += v[ch], s2[ch] += v[ch] * v[ch];
      n += 1;
    }
    if (n < 1) break;
    for (int ch = 0; ch < 3; ++ch) {
      mean[ch] = s[ch] / n;
      sigma[ch] = std::max(floor[ch], std::sqrt(std::max(0.0, s2[ch] / n - mean[ch] * mean[ch])));
    }
  }
}

// A frame's pixels within `pixels`: [offset, offset + width * height), row-major.
struct FrameSpan {
  size_t offset = 0;
  int width = 0, height = 0;
};

// The 4-connected region of `start`'s label in one frame (`base`, width x height), marking it
// seen.
void CollectRegion(const Pixel* base, const FrameSpan& f, int start, std::vector<bool>* seen,
                   std::vector<int>* stack, std::vector<int>* region) {
  const int label = base[start].label;
  region->clear();
  stack->assign(1, start);
  (*seen)[start] = true;
  while (!stack->empty()) {
    const int i = stack->back();
    stack->pop_back();
    region->push_back(i);
    const int x = i % f.width, y = i / f.width;
    const int next[4] = {x > 0 ? i - 1 : -1, x + 1 < f.width ? i + 1 : -1, y > 0 ? i - f.width : -1,
                         y + 1 < f.height ? i + f.width : -1};
    for (const int j : next) {
      if (j >= 0 && !(*seen)[j] && base[j].label == label) (*seen)[j] = true, stack->push_back(j);
    }
  }
}

// Patches are small: a 4-connected region of one class larger than max_area pixels (a field line,
// a lit patch of carpet, a wall) is taken out of the class (label -1), so that it neither moves
// the class's centre nor widens its box. Hand-labelled pixels stay.
void DropLargeRegions(const std::vector<FrameSpan>& spans, double max_fraction,
                      std::vector<Pixel>* pixels) {
  std::vector<int> stack;
  std::vector<int> region;
  for (const FrameSpan& f : spans) {
    const int count = f.width * f.height;
    const auto max_area = static_cast<size_t>(max_fraction * count);
    std::vector<bool> seen(static_cast<size_t>(count), false);
    Pixel* base = pixels->data() + f.offset;
    for (int start = 0; start < count; ++start) {
      if (seen[start] || base[start].label < 0) continue;
      CollectRegion(base, f, start, &seen, &stack, &region);
      if (region.size() <= max_area) continue;
      for (const int i : region) {
        if (base[i].hand < 0) base[i].label = -1;
      }
    }
  }
}

// Pixel count, mean, spread and box of the pixels labelled k.
AutoClassFit Summarise(const std::vector<Pixel>& pixels, int k, const AutoThresholdsOptions& o) {
  AutoClassFit f;
  std::array<std::array<long, 256>, 3> hist{};
  std::array<double, 3> s{}, s2{};
  for (const Pixel& p : pixels) {
    if (p.label != k) continue;
    ++f.pixels;
    if (p.hand >= 0) ++f.labelled;
    const int v[3] = {p.y, p.u, p.v};
    for (int ch = 0; ch < 3; ++ch) ++hist[ch][v[ch]], s[ch] += v[ch], s2[ch] += 1.0 * v[ch] * v[ch];
  }
  if (f.pixels == 0) {
    for (auto& r : f.range) r = {255, 0};  // empty: catches nothing (fixed below)
    return f;
  }
  double var = 0;
  for (int ch = 0; ch < 3; ++ch) {
    f.mean_yuv[ch] = s[ch] / f.pixels;
    var += std::max(0.0, s2[ch] / f.pixels - f.mean_yuv[ch] * f.mean_yuv[ch]);
  }
  f.spread_levels = std::sqrt(var / 3.0);
  const double last = static_cast<double>(f.pixels - 1);
  const long lo_rank = static_cast<long>(std::floor(o.lower_percentile / 100.0 * last));
  const long hi_rank = static_cast<long>(std::ceil(o.upper_percentile / 100.0 * last));
  for (int ch = 0; ch < 3; ++ch) {
    int lo = 0, hi = 255;
    long seen = 0;
    for (int v = 0; v < 256; ++v) {
      if (seen <= lo_rank && seen + hist[ch][v] > lo_rank) lo = v;
      if (seen <= hi_rank && seen + hist[ch][v] > hi_rank) hi = v;
      seen += hist[ch][v];
    }
    f.range[ch] = internal::StretchForLight(lo, hi, ch, o.lighting_min_gain, o.lighting_max_gain,
                                            o.margin_levels);
  }
  return f;
}

// The carpet's core, mean +- 2.5 sd per channel (at least 3 levels) under every light from
// lighting_min_gain to lighting_max_gain: the box of a class whose hue the carpet shares (green on
// a green carpet) and that the lighting stretch widened would catch the whole field. Each such box
// is cut, on the one channel and side that keeps most of the class's pixels, to end where the core
// begins.
void CarveOutCarpet(const std::vector<Pixel>& pixels, int k, const AutoThresholdsOptions& o,
                    std::array<ChannelRange, 3>* range) {
  std::array<double, 3> s{}, s2{};
  double n = 0;
  std::array<std::array<long, 256>, 3> hist{};
  for (const Pixel& p : pixels) {
    const int v[3] = {p.y, p.u, p.v};
    if (p.label == -2) {
      for (int ch = 0; ch < 3; ++ch) s[ch] += v[ch], s2[ch] += 1.0 * v[ch] * v[ch];
      n += 1;
    } else if (p.label == k) {
      for (int ch = 0; ch < 3; ++ch) ++hist[ch][v[ch]];
    }
  }
  if (n < 1) return;
  std::array<int, 3> core_lo{}, core_hi{};
  for (int ch = 0; ch < 3; ++ch) {
    const double mean = s[ch] / n;
    const double half = std::max(3.0, 2.5 * std::sqrt(std::max(0.0, s2[ch] / n - mean * mean)));
    // The core under every light of the range, as the boxes are stretched (Summarise).
    const double offset = ch == 0 ? 0.0 : 128.0;
    double lo = 255, hi = 0;
    for (const double gain : {o.lighting_min_gain, o.lighting_max_gain}) {
      for (const double v : {mean - half, mean + half}) {
        lo = std::min(lo, offset + gain * (v - offset)),
        hi = std::max(hi, offset + gain * (v - offset));
      }
    }
    core_lo[ch] = static_cast<int>(std::floor(lo));
    core_hi[ch] = static_cast<int>(std::ceil(hi));
  }
  for (int ch = 0; ch < 3; ++ch) {
    const ChannelRange& r = (*range)[ch];
    if (r.hi < core_lo[ch] || r.lo > core_hi[ch]) return;  // already apart on this channel
  }
  int best_ch = -1;
  ChannelRange best{};
  long best_kept = -1;
  for (int ch = 0; ch < 3; ++ch) {
    const ChannelRange r = (*range)[ch];
    const ChannelRange cuts[2] = {{r.lo, std::min(r.hi, core_lo[ch] - 1)},
                                  {std::max(r.lo, core_hi[ch] + 1), r.hi}};
    for (const ChannelRange& c : cuts) {
      if (c.lo > c.hi) continue;
      long kept = 0;
      for (int v = c.lo; v <= c.hi; ++v) kept += hist[ch][v];
      if (kept > best_kept) best_kept = kept, best_ch = ch, best = c;
    }
  }
  if (best_ch >= 0) (*range)[best_ch] = best;
}

}  // namespace

void ComputeSeparability(AutoThresholdsFit* fit) {
  std::vector<AutoClassFit*> all;
  for (AutoClassFit& c : fit->classes) all.push_back(&c);
  all.push_back(&fit->carpet);
  for (AutoClassFit& c : fit->classes) {
    c.separability = std::numeric_limits<double>::infinity();
    if (c.pixels == 0) continue;
    for (const AutoClassFit* other : all) {
      if (other == &c || other->pixels == 0 || other->name == c.name) continue;
      double d2 = 0;
      for (int ch = 0; ch < 3; ++ch) d2 += std::pow(c.mean_yuv[ch] - other->mean_yuv[ch], 2);
      const double spread = std::sqrt(c.spread_levels * c.spread_levels +
                                      other->spread_levels * other->spread_levels);
      const double sep = std::sqrt(d2) / std::max(spread, 1.0);
      if (sep < c.separability) c.separability = sep, c.nearest = other->name;
    }
  }
}

namespace {

// Every frame's pixels, then every labelled frame's with its hand labels mapped to the classes.
void CollectPixels(const std::vector<const camera::Image*>& frames,
                   const std::vector<LabelledFrame>& labels,
                   const std::vector<const ColourEntry*>& entries,
                   const ColourVocabulary& vocabulary, std::vector<Pixel>* pixels,
                   std::vector<FrameSpan>* spans) {
  for (const camera::Image* frame : frames) {
    spans->push_back({pixels->size(), frame->width_px, frame->height_px});
    AppendPixels(*frame, nullptr, pixels);
  }
  for (const LabelledFrame& lf : labels) {
    std::vector<int> mapped(lf.labels.size(), -1);
    std::vector<int> index;
    for (const std::string& name : lf.class_names) {
      const ColourEntry* e = vocabulary.Find(name);
      const auto it = std::find(entries.begin(), entries.end(), e);
      if (e == nullptr || it == entries.end()) {
        throw InputError("labelled class '" + EscapeForMessage(name) +
                         "' is not among the classes asked for; expected one of them");
      }
      index.push_back(static_cast<int>(it - entries.begin()));
    }
    for (size_t i = 0; i < lf.labels.size(); ++i) {
      if (lf.labels[i] >= 0) mapped[i] = index[static_cast<size_t>(lf.labels[i])];
    }
    spans->push_back({pixels->size(), lf.image->width_px, lf.image->height_px});
    AppendPixels(*lf.image, &mapped, pixels);
  }
}

// Seeds: the vocabulary's typical colour, or the mean of the class's labelled pixels.
std::vector<Centre> SeedCentres(const std::vector<const ColourEntry*>& entries,
                                std::vector<Pixel>* pixels) {
  const size_t n = entries.size();
  std::vector<Centre> centres(n);
  std::vector<bool> has_hand(n, false);
  for (size_t k = 0; k < n; ++k) {
    int y, u, v;
    camera::RgbToYuv(entries[k]->rgb[0], entries[k]->rgb[1], entries[k]->rgb[2], &y, &u, &v);
    centres[k] = SeedOf(y, u, v);
  }
  for (Pixel& p : *pixels) {
    if (p.hand >= 0) p.label = p.hand, has_hand[static_cast<size_t>(p.hand)] = true;
  }
  for (size_t k = 0; k < n; ++k) {
    if (!has_hand[k]) continue;
    const bool chromatic = centres[k].chromatic;
    Update(*pixels, static_cast<int>(k), &centres[k]);
    centres[k].chromatic = chromatic;
  }
  return centres;
}

// The nearest centre within the gate, or -1; hand-labelled and carpet pixels keep their label.
void AssignPixels(const std::vector<Centre>& centres, int carpet_class,
                  const AutoThresholdsOptions& options, std::vector<Pixel>* pixels) {
  const double gate2 = options.gate_sigmas * options.gate_sigmas;
  const int n = static_cast<int>(centres.size());
  for (Pixel& p : *pixels) {
    if (p.hand >= 0 || p.label == -2) continue;
    int best = -1;
    double best_d2 = gate2;
    for (int k = 0; k < n; ++k) {
      if (k == carpet_class) continue;
      if (centres[k].chromatic && p.chroma < options.min_chroma_levels) continue;
      const double d2 = Distance2(p, centres[k]);
      if (d2 <= best_d2) best = k, best_d2 = d2;
    }
    p.label = best;
  }
}

}  // namespace

std::vector<const ColourEntry*> PaletteEntries(const std::vector<std::string>& class_names,
                                               const ColourVocabulary& vocabulary) {
  if (class_names.empty() || class_names.size() > static_cast<size_t>(kMaxColorClasses)) {
    throw InputError(std::to_string(class_names.size()) + " colour classes; expected 1 to " +
                     std::to_string(kMaxColorClasses));
  }
  std::vector<const ColourEntry*> entries;
  for (const std::string& name : class_names) {
    const ColourResolution r = ResolveColourName(vocabulary, name);
    if (!r.known) throw InputError(UnknownColourMessage(vocabulary, r));
    for (const ColourEntry* e : entries) {
      if (e->name == r.name) {
        throw InputError("colour '" + r.name + "' asked for twice; expected distinct classes");
      }
    }
    entries.push_back(vocabulary.Find(r.name));
  }
  return entries;
}

AutoThresholdsFit FitThresholdsAuto(const std::vector<const camera::Image*>& frames,
                                    const std::vector<std::string>& class_names,
                                    const ColourVocabulary& vocabulary,
                                    const AutoThresholdsOptions& options,
                                    const std::vector<LabelledFrame>& labels) {
  Validate(options);
  if (frames.empty() && labels.empty()) throw InputError("no frames; expected at least one frame");
  const std::vector<const ColourEntry*> entries = PaletteEntries(class_names, vocabulary);
  const auto carpet_entry = std::find(entries.begin(), entries.end(), vocabulary.Find("carpet"));
  const int carpet_class =
      carpet_entry == entries.end() ? -1 : static_cast<int>(carpet_entry - entries.begin());

  std::vector<Pixel> pixels;
  std::vector<FrameSpan> spans;
  CollectPixels(frames, labels, entries, vocabulary, &pixels, &spans);
  AutoThresholdsFit fit;
  fit.frame_pixels = static_cast<long>(pixels.size());
  FindCarpet(&pixels, options.gate_sigmas);

  const int n = static_cast<int>(entries.size());
  std::vector<Centre> centres = SeedCentres(entries, &pixels);
  for (int round = 0; round <= options.iterations; ++round) {
    AssignPixels(centres, carpet_class, options, &pixels);
    DropLargeRegions(spans, options.max_patch_fraction, &pixels);
    if (round == options.iterations) break;
    for (int k = 0; k < n; ++k) {
      if (k != carpet_class) Update(pixels, k, &centres[k]);
    }
  }

  fit.thresholds.space = ColorSpace::kYuv;
  fit.carpet = Summarise(pixels, -2, options);
  fit.carpet.name = "carpet";
  for (int k = 0; k < n; ++k) {
    AutoClassFit c = k == carpet_class ? fit.carpet : Summarise(pixels, k, options);
    if (k != carpet_class && c.pixels > 0) CarveOutCarpet(pixels, k, options, &c.range);
    c.name = entries[k]->name;
    ColorClass cls;
    cls.name = c.name;
    cls.display_rgb = entries[k]->rgb;
    cls.range = c.range;
    if (c.pixels == 0) cls.range = {ChannelRange{0, 0}, ChannelRange{0, 0}, ChannelRange{0, 0}};
    fit.thresholds.classes.push_back(cls);
    fit.classes.push_back(c);
  }
  ComputeSeparability(&fit);
  return fit;
}

}  // namespace patlab::vision
