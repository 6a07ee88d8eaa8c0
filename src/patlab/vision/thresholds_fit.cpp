#include "patlab/vision/thresholds_fit.h"

#include <algorithm>
#include <cmath>

#include "patlab/core/error.h"
#include "patlab/core/format.h"

namespace patlab::vision {

std::vector<OptionsProblem> Check(const ThresholdsFitOptions& o) {
  OptionsChecker check;
  check
      .Require("lower_percentile", o.lower_percentile,
               o.lower_percentile >= 0.0 && o.lower_percentile < 50.0, "in [0, 50)")
      .Require("upper_percentile", o.upper_percentile,
               o.upper_percentile > 50.0 && o.upper_percentile <= 100.0, "in (50, 100]")
      .IntegerInRange("margin_levels", o.margin_levels, 0, 128);
  return check.Take();
}

void Validate(const ThresholdsFitOptions& options) { ThrowFirstProblem(Check(options)); }

void CheckClassesKnown(const Labels& labels, const std::vector<std::string>& known) {
  for (const LabelClass& c : labels.classes) {
    if (std::find(known.begin(), known.end(), c.name) != known.end()) continue;
    std::string list;
    for (const std::string& k : known) list.append(list.empty() ? "" : ", ").append(k);
    throw InputError(FileLoc{labels.source, c.line},
                     "unknown class \"" + EscapeForMessage(c.name) +
                         "\"; expected one of the detector palette: " + list);
  }
}

namespace {

std::string PixelText(int x, int y) {
  std::string s = "[";
  s.append(std::to_string(x)).append(", ").append(std::to_string(y)).append("]");
  return s;
}

void CheckInside(const Labels& labels, const LabelClass& c, int line, int x, int y, int w, int h,
                 const char* what) {
  if (x >= 0 && y >= 0 && x < w && y < h) return;
  throw InputError(FileLoc{labels.source, line},
                   std::string(what) + " " + PixelText(x, y) + " of class \"" +
                       EscapeForMessage(c.name) + "\" lies outside the " + std::to_string(w) + "x" +
                       std::to_string(h) + " image; expected 0 <= x < " + std::to_string(w) +
                       " and 0 <= y < " + std::to_string(h));
}

void Label(std::vector<int>* out, int w, int x, int y, int k) {
  int& cell = (*out)[static_cast<size_t>(y) * w + x];
  if (cell < 0 || cell > k) cell = k;
}

void LabelPointsAndRectangles(const Labels& labels, int k, int w, int h, std::vector<int>* out) {
  const LabelClass& c = labels.classes[static_cast<size_t>(k)];
  const int rad = labels.point_radius_px;
  for (size_t i = 0; i < c.points.size(); ++i) {
    const auto [px, py] = c.points[i];
    CheckInside(labels, c, c.point_lines[i], px, py, w, h, "point");
    for (int y = std::max(0, py - rad); y <= std::min(h - 1, py + rad); ++y) {
      for (int x = std::max(0, px - rad); x <= std::min(w - 1, px + rad); ++x) {
        if ((x - px) * (x - px) + (y - py) * (y - py) <= rad * rad) Label(out, w, x, y, k);
      }
    }
  }
  for (size_t i = 0; i < c.rectangles.size(); ++i) {
    const auto [x0, y0, x1, y1] = c.rectangles[i];
    CheckInside(labels, c, c.rectangle_lines[i], x0, y0, w, h, "rectangle corner");
    CheckInside(labels, c, c.rectangle_lines[i], x1, y1, w, h, "rectangle corner");
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) Label(out, w, x, y, k);
    }
  }
}

}  // namespace

std::vector<int> LabelPixels(const Labels& labels, int width_px, int height_px,
                             const camera::Image* mask) {
  std::vector<int> out(static_cast<size_t>(width_px) * height_px, -1);
  const int nc = static_cast<int>(labels.classes.size());
  for (int k = 0; k < nc; ++k) LabelPointsAndRectangles(labels, k, width_px, height_px, &out);
  if (mask != nullptr) {
    if (mask->width_px != width_px || mask->height_px != height_px) {
      throw InputError(FileLoc{labels.source, labels.mask_line},
                       "mask " + EscapeForMessage(labels.mask_path) + " is " +
                           std::to_string(mask->width_px) + "x" + std::to_string(mask->height_px) +
                           "; expected the image's size " + std::to_string(width_px) + "x" +
                           std::to_string(height_px));
    }
    const camera::Image rgb = camera::ToRgb(*mask);
    for (int y = 0; y < height_px; ++y) {
      const uint8_t* row = rgb.Row(y);
      for (int x = 0; x < width_px; ++x) {
        const std::array<uint8_t, 3> p = {row[3 * x], row[3 * x + 1], row[3 * x + 2]};
        for (int k = 0; k < nc; ++k) {
          const LabelClass& c = labels.classes[static_cast<size_t>(k)];
          if (c.has_mask_rgb && c.mask_rgb == p) {
            Label(&out, width_px, x, y, k);
            break;
          }
        }
      }
    }
  }
  std::vector<char> seen(static_cast<size_t>(nc), 0);
  for (int v : out) {
    if (v >= 0) seen[static_cast<size_t>(v)] = 1;
  }
  for (int k = 0; k < nc; ++k) {
    if (seen[static_cast<size_t>(k)]) continue;
    const LabelClass& c = labels.classes[static_cast<size_t>(k)];
    throw InputError(FileLoc{labels.source, c.line},
                     "class \"" + EscapeForMessage(c.name) +
                         "\" labels no pixel (its mask colour is not in the mask, or classes "
                         "listed before it took its pixels); expected at least one sample pixel");
  }
  return out;
}

namespace {

// Each pixel's three channel values in `space`, as the segmenter's lookup sees them.
std::vector<std::array<uint8_t, 3>> PixelValues(const camera::Image& image, ColorSpace space) {
  std::vector<std::array<uint8_t, 3>> values;
  values.reserve(static_cast<size_t>(image.width_px) * image.height_px);
  for (int y = 0; y < image.height_px; ++y) {
    const uint8_t* row = image.Row(y);
    for (int x = 0; x < image.width_px; ++x) {
      int a, b, c;
      if (image.format == camera::PixelFormat::kRgb8) {
        a = row[3 * x], b = row[3 * x + 1], c = row[3 * x + 2];
        if (space == ColorSpace::kYuv) camera::RgbToYuv(a, b, c, &a, &b, &c);
      } else {
        const uint8_t* pair = row + 4 * (x / 2);
        a = pair[1 + 2 * (x % 2)], b = pair[0], c = pair[2];
        if (space == ColorSpace::kRgb) camera::YuvToRgb(a, b, c, &a, &b, &c);
      }
      values.push_back({static_cast<uint8_t>(a), static_cast<uint8_t>(b), static_cast<uint8_t>(c)});
    }
  }
  return values;
}

// The robust box of one class's sample (ThresholdsFitOptions).
std::array<ChannelRange, 3> FitBox(std::array<std::vector<int>, 3>& samples,
                                   const ThresholdsFitOptions& o) {
  std::array<ChannelRange, 3> box;
  for (int ch = 0; ch < 3; ++ch) {
    std::vector<int>& v = samples[ch];
    std::sort(v.begin(), v.end());
    const double last = static_cast<double>(v.size() - 1);
    const auto lo_index = static_cast<size_t>(std::floor(o.lower_percentile / 100.0 * last));
    const auto hi_index = static_cast<size_t>(std::ceil(o.upper_percentile / 100.0 * last));
    box[ch].lo = std::max(0, v[lo_index] - o.margin_levels);
    box[ch].hi = std::min(255, v[std::min(hi_index, v.size() - 1)] + o.margin_levels);
  }
  return box;
}

bool InBox(const std::array<ChannelRange, 3>& box, const std::array<uint8_t, 3>& p) {
  for (int ch = 0; ch < 3; ++ch) {
    if (p[ch] < box[ch].lo || p[ch] > box[ch].hi) return false;
  }
  return true;
}

void FindOverlaps(const std::vector<std::array<uint8_t, 3>>& values,
                  const std::vector<int>& pixel_labels, ThresholdsFit* fit) {
  const int nc = static_cast<int>(fit->classes.size());
  for (int a = 0; a < nc; ++a) {
    for (int b = a + 1; b < nc; ++b) {
      const auto& ra = fit->classes[a].range;
      const auto& rb = fit->classes[b].range;
      double volume = 1.0;
      for (int ch = 0; ch < 3; ++ch) {
        volume *= std::max(0, std::min(ra[ch].hi, rb[ch].hi) - std::max(ra[ch].lo, rb[ch].lo) + 1);
      }
      if (volume == 0.0) continue;
      ClassOverlap o{.a = a, .b = b, .volume = volume};
      for (size_t i = 0; i < values.size(); ++i) {
        if (pixel_labels[i] == a && InBox(rb, values[i])) ++o.a_in_b;
        if (pixel_labels[i] == b && InBox(ra, values[i])) ++o.b_in_a;
      }
      fit->overlaps.push_back(o);
    }
  }
}

}  // namespace

ThresholdsFit FitThresholds(const camera::Image& image, const std::vector<int>& pixel_labels,
                            const Labels& labels, const ThresholdsFitOptions& options) {
  Validate(options);
  PATLAB_CHECK(pixel_labels.size() == static_cast<size_t>(image.width_px) * image.height_px);
  const std::vector<std::array<uint8_t, 3>> values = PixelValues(image, options.space);
  const size_t nc = labels.classes.size();
  std::vector<std::array<std::vector<int>, 3>> samples(nc);
  std::vector<std::array<double, 3>> rgb_sum(nc, {0.0, 0.0, 0.0});
  ThresholdsFit fit;
  fit.thresholds.space = options.space;
  fit.thresholds.source = labels.source;
  for (size_t i = 0; i < values.size(); ++i) {
    const int k = pixel_labels[i];
    if (k < 0) {
      ++fit.unlabelled_px;
      continue;
    }
    ++fit.labelled_px;
    for (int ch = 0; ch < 3; ++ch) samples[k][ch].push_back(values[i][ch]);
  }
  for (size_t k = 0; k < nc; ++k) {
    const LabelClass& lc = labels.classes[k];
    PATLAB_CHECK(!samples[k][0].empty());
    ClassFit cf;
    cf.name = lc.name;
    cf.samples = static_cast<long>(samples[k][0].size());
    double mean[3];
    for (int ch = 0; ch < 3; ++ch) {
      double s = 0.0;
      for (int v : samples[k][ch]) s += v;
      mean[ch] = s / static_cast<double>(cf.samples);
    }
    cf.range = FitBox(samples[k], options);
    ColorClass cc;
    cc.name = lc.name;
    cc.range = cf.range;
    cc.min_area_px = lc.min_area_px;
    cc.max_area_px = lc.max_area_px;
    int r = static_cast<int>(std::lround(mean[0])), g = static_cast<int>(std::lround(mean[1])),
        b = static_cast<int>(std::lround(mean[2]));
    if (options.space == ColorSpace::kYuv) camera::YuvToRgb(r, g, b, &r, &g, &b);
    cc.display_rgb = lc.has_display
                         ? lc.display_rgb
                         : std::array<uint8_t, 3>{static_cast<uint8_t>(r), static_cast<uint8_t>(g),
                                                  static_cast<uint8_t>(b)};
    fit.thresholds.classes.push_back(cc);
    fit.classes.push_back(cf);
  }
  const ColorLut lut(fit.thresholds);
  for (size_t i = 0; i < values.size(); ++i) {
    const int got = lut.Classify(values[i][0], values[i][1], values[i][2]);
    if (got < 0) continue;
    const int k = pixel_labels[i];
    ClassFit& cf = fit.classes[static_cast<size_t>(got)];
    if (k == got) {
      ++cf.caught_own;
    } else if (k >= 0) {
      ++cf.caught_other;
    } else {
      ++cf.caught_unlabelled;
    }
  }
  FindOverlaps(values, pixel_labels, &fit);
  return fit;
}

std::string ThresholdsToml(const Thresholds& t, const std::string& comment) {
  std::string out;
  size_t start = 0;
  while (start < comment.size()) {
    const size_t end = comment.find('\n', start);
    const size_t stop = end == std::string::npos ? comment.size() : end;
    out.append("# ").append(comment, start, stop - start).append("\n");
    start = stop + 1;
  }
  out.append("space = \"").append(NameOf(t.space, kColorSpaceNames)).append("\"\n");
  const char* keys[2][3] = {{"y", "u", "v"}, {"r", "g", "b"}};
  const int sp = t.space == ColorSpace::kYuv ? 0 : 1;
  for (const ColorClass& c : t.classes) {
    out.append("\n[[class]]\nname = \"").append(c.name).append("\"\n");
    out.append(StringPrintf("display = [%d, %d, %d]\n", c.display_rgb[0], c.display_rgb[1],
                            c.display_rgb[2]));
    for (int ch = 0; ch < 3; ++ch) {
      out.append(StringPrintf("%s = [%d, %d]\n", keys[sp][ch], c.range[ch].lo, c.range[ch].hi));
    }
    if (c.min_area_px > 0) out.append(StringPrintf("min_area_px = %d\n", c.min_area_px));
    if (c.max_area_px > 0) out.append(StringPrintf("max_area_px = %d\n", c.max_area_px));
  }
  return out;
}

std::string ThresholdsFitReport(const ThresholdsFit& fit) {
  const int sp = fit.thresholds.space == ColorSpace::kYuv ? 0 : 1;
  std::string out = StringPrintf("%-12s %8s  %-9s %-9s %-9s  %9s %7s  %9s  %10s\n", "class",
                                 "samples", sp == 0 ? "Y" : "R", sp == 0 ? "U" : "G",
                                 sp == 0 ? "V" : "B", "own", "recall", "other", "unlabelled");
  for (const ClassFit& c : fit.classes) {
    auto range = [&](int ch) { return StringPrintf("%d:%d", c.range[ch].lo, c.range[ch].hi); };
    out.append(StringPrintf("%-12s %8ld  %-9s %-9s %-9s  %9ld %6s%%  %9ld  %10ld\n", c.name.c_str(),
                            c.samples, range(0).c_str(), range(1).c_str(), range(2).c_str(),
                            c.caught_own, FormatFixed(100.0 * c.caught_own / c.samples, 1).c_str(),
                            c.caught_other, c.caught_unlabelled));
  }
  out.append(
      StringPrintf("labelled %ld px, unlabelled %ld px\n", fit.labelled_px, fit.unlabelled_px));
  if (fit.overlaps.empty()) {
    out.append("no overlapping classes\n");
    return out;
  }
  out.append(
      "overlapping classes (box volume in levels^3; samples of one inside the other's box):\n");
  for (const ClassOverlap& o : fit.overlaps) {
    const std::string& a = fit.classes[static_cast<size_t>(o.a)].name;
    const std::string& b = fit.classes[static_cast<size_t>(o.b)].name;
    out.append(
        StringPrintf("  %s / %s: volume %s, %ld %s samples in %s's box, %ld %s samples in "
                     "%s's box\n",
                     a.c_str(), b.c_str(), FormatSignificant(o.volume, 6).c_str(), o.a_in_b,
                     a.c_str(), b.c_str(), o.b_in_a, b.c_str(), a.c_str()));
  }
  return out;
}

}  // namespace patlab::vision
