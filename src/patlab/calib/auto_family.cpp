// The automatic calibration against a family of field models (auto_calibrate.h,
// AutoCalibrateFamily): every model searched, the best few fitted.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

#include "patlab/calib/auto_calibrate_internal.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"

namespace patlab::calib {
namespace {

bool SameMarks(const FieldMarks& a, const FieldMarks& b) {
  auto same = [](const Vec2& p, const Vec2& q) { return (p - q).norm() < 1e-9; };
  if (a.segments.size() != b.segments.size() || a.arcs.size() != b.arcs.size()) return false;
  for (size_t i = 0; i < a.segments.size(); ++i) {
    if (!same(a.segments[i].from_mm, b.segments[i].from_mm) ||
        !same(a.segments[i].to_mm, b.segments[i].to_mm))
      return false;
  }
  for (size_t i = 0; i < a.arcs.size(); ++i) {
    const MarkArc &x = a.arcs[i], &y = b.arcs[i];
    if (!same(x.centre_mm, y.centre_mm) || std::abs(x.radius_mm - y.radius_mm) > 1e-9 ||
        std::abs(x.start_rad - y.start_rad) > 1e-12 || std::abs(x.sweep_rad - y.sweep_rad) > 1e-12)
      return false;
  }
  return true;
}

// The index of an earlier model with the same painted marks and symmetry as `i`, or -1.
int SameAs(const std::vector<Field>& fields, const std::vector<FieldMarks>& marks, size_t i) {
  for (size_t j = 0; j < i; ++j) {
    if (SameMarks(marks[i], marks[j]) &&
        internal::PointSymmetric(fields[i]) == internal::PointSymmetric(fields[j]))
      return static_cast<int>(j);
  }
  return -1;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Frame {
  const std::vector<LinePixel>* pixels;
  int width_px, height_px;
  const std::string* source;
  const AutoOptions* options;
};

// The screen: each distinct geometry searched once (steps 1-3); `same` the twins.
std::vector<std::optional<internal::Searched>> Screen(const Frame& f,
                                                      const std::vector<Field>& fields,
                                                      std::vector<int>* same,
                                                      FamilyCalibration* out) {
  std::vector<FieldMarks> marks;
  for (const Field& field : fields) marks.push_back(PaintedMarks(field));
  std::vector<std::optional<internal::Searched>> searched(fields.size());
  same->assign(fields.size(), -1);
  out->tries.resize(fields.size());
  for (size_t i = 0; i < fields.size(); ++i) {
    FamilyTry& t = out->tries[i];
    t.field = fields[i].name;
    t.screen_px = t.score_px = t.held_out_mapping_mm = kNaN;
    (*same)[i] = SameAs(fields, marks, i);
    if ((*same)[i] >= 0) continue;
    try {
      searched[i] = internal::SearchField(*f.pixels, f.width_px, f.height_px, *f.source, fields[i],
                                          *f.options);
      t.screen_px = searched[i]->views.front().score;
    } catch (const InputError& e) {
      t.failure = e.what();
    }
  }
  return searched;
}

// A view another model's search found that explains this model's own marks better than the
// best its own search found is put first in its list, with that score: the fit starts from it and
// the screen ranks the model by it. Models whose lines in view are alike find the same camera
// from different hypotheses, and one model's search can miss it (fresh rendered seed 205: the
// camera looks straight down at the centre circle, halfway line and a goal line; ssl-2015's best
// view explains 843 px, ssl-div-b's best explains 1833 px of ssl-2015's marks, and only from it
// does ssl-2015, the true model, fit). Only views of each search's own list are lent, and only
// where they beat the borrower's best, so a model whose search found its camera is unchanged.
// The first `borrowers` models borrow; the rest (AutoCalibrateFamily's lenders) only lend.
void LendViews(const internal::LineDistance& dt, size_t borrowers,
               std::vector<std::optional<internal::Searched>>& searched, FamilyCalibration* out) {
  std::vector<std::optional<internal::ScoredView>> lent(borrowers);
  std::vector<size_t> lender(borrowers);
  for (size_t i = 0; i < borrowers; ++i) {
    if (!searched[i]) continue;
    double best = searched[i]->views.front().score;
    for (size_t j = 0; j < searched.size(); ++j) {
      if (j == i || !searched[j]) continue;
      for (const internal::ScoredView& v : searched[j]->views) {
        const double score = internal::CameraScore(v.camera, searched[i]->marks, dt);
        if (score > best) {
          best = score;
          lent[i] = v;
          lent[i]->score = score;
          lender[i] = j;
        }
      }
    }
  }
  for (size_t i = 0; i < borrowers; ++i) {
    if (!lent[i]) continue;
    searched[i]->views.insert(searched[i]->views.begin(), *lent[i]);
    out->tries[i].screen_px = lent[i]->score;
    out->tries[i].screen_view_of = out->tries[lender[i]].field;
  }
}

constexpr size_t kLender = std::numeric_limits<size_t>::max();

// A model named alone borrows more than the single best view LendViews gives it: each lender's
// views, scored against the model's own marks (best first), become one more search of that model,
// fitted like another model of a family, so every camera the family would have fitted is fitted
// as the named model. (Rendered seed 3: the frame shows two lines that ssl-2018 paints where the
// true model, ssl-div-a, does; the family fits ssl-2018 from its own views, a camera that maps
// the true floor within 10 mm and through which 6 robots decode, while ssl-div-a's own search and
// the one view lent to it find only cameras through which no robot decodes.) Appends the lent
// searches to `fields`, `searched` and the tries; returns, for every search, the model it stands
// for (kLender for the lenders' own).
std::vector<size_t> AddLentSearches(const internal::LineDistance& dt, size_t models,
                                    std::vector<Field>& fields,
                                    std::vector<std::optional<internal::Searched>>& searched,
                                    FamilyCalibration* out) {
  const size_t searches = searched.size();
  std::vector<size_t> owner(searches, kLender);
  std::iota(owner.begin(), owner.begin() + static_cast<std::ptrdiff_t>(models), size_t{0});
  if (searches == models) return owner;
  for (size_t i = 0; i < models; ++i) {
    const Field model = fields[i];
    const FieldMarks marks = PaintedMarks(model);
    for (size_t j = models; j < searches; ++j) {
      if (!searched[j]) continue;
      internal::Searched lent{marks, internal::PointSymmetric(model), 0, searched[j]->views};
      for (internal::ScoredView& v : lent.views)
        v.score = internal::CameraScore(v.camera, marks, dt);
      std::stable_sort(lent.views.begin(), lent.views.end(),
                       [](const auto& a, const auto& b) { return a.score > b.score; });
      FamilyTry t;
      t.field = model.name;
      t.screen_px = lent.views.front().score;
      t.score_px = t.held_out_mapping_mm = kNaN;
      t.screen_view_of = out->tries[j].field;
      fields.push_back(model);
      searched.push_back(std::move(lent));
      out->tries.push_back(std::move(t));
      owner.push_back(i);
    }
  }
  return owner;
}

// The lent searches folded back into the models they stand for (`owner`, AddLentSearches): the
// kept camera's, the rivals' and the runners-up's model, and the model's try where a lent
// search's fit scored more than its own; then the tries of the models only.
void FoldLentSearches(const std::vector<size_t>& owner, size_t models, FamilyCalibration* out) {
  for (size_t e = models; e < owner.size(); ++e) {
    const FamilyTry& lent = out->tries[e];
    if (owner[e] == kLender || !lent.fitted || !lent.failure.empty()) continue;
    FamilyTry& own = out->tries[owner[e]];
    const bool kept = out->kept == static_cast<int>(e);
    if (kept || !(lent.score_px <= own.score_px)) {
      own.fitted = true;
      own.score_px = lent.score_px;
      own.screen_px = lent.screen_px;
      own.screen_view_of = lent.screen_view_of;
      own.failure.clear();
      if (kept) own.held_out_mapping_mm = lent.held_out_mapping_mm;
    }
  }
  const auto fold = [&](int& model) {
    if (model >= 0) model = static_cast<int>(owner[static_cast<size_t>(model)]);
  };
  fold(out->kept);
  for (FamilyRival& r : out->rivals) fold(r.model);
  for (FamilyRival& r : out->runners_up) fold(r.model);
  out->tries.resize(models);
}

// The runners-up from `pool` (best first): cameras explaining at least runner_up_ratio of the kept
// one's line that map the frame differently from it, from every rival and from every runner-up
// kept before (the kept camera and the rivals are in the pool too, and map as themselves).
void KeepRunnersUp(const Frame& f, const FamilyOptions& family, std::vector<FamilyRival>& pool,
                   FamilyCalibration* out) {
  const AutoCalibration& kept = out->calibration;
  const auto differs = [&](const AutoCalibration& a, const AutoCalibration& b, double* differ) {
    return !internal::SameMap(a.fit.camera, b.fit.camera, kept.point_symmetric, f.width_px,
                              f.height_px, differ);
  };
  for (FamilyRival& r : pool) {
    if (out->runners_up.size() >= static_cast<size_t>(family.max_rivals)) break;
    const AutoCalibration& c = r.calibration;
    if (!(c.score_px >= family.runner_up_ratio * kept.score_px)) break;  // the rest score less
    double differ = 0.0, other = 0.0;
    if (!differs(kept, c, &differ)) continue;
    const auto apart = [&](const FamilyRival& o) { return differs(o.calibration, c, &other); };
    if (!std::all_of(out->rivals.begin(), out->rivals.end(), apart) ||
        !std::all_of(out->runners_up.begin(), out->runners_up.end(), apart))
      continue;
    r.floor_difference_mm = differ;
    out->runners_up.push_back(std::move(r));
  }
}

// The full fit (steps 4-5) in `order`: until min_fitted models fitted, then every model whose
// screen reaches screen_ratio of the best fitted score.
void FitInOrder(const Frame& f, const std::vector<Field>& fields,
                const std::vector<std::optional<internal::Searched>>& searched,
                const std::vector<size_t>& order, const FamilyOptions& family,
                FamilyCalibration* out) {
  int fitted = 0;
  double best = -INFINITY;
  std::vector<FamilyRival> pool;  // every fitted camera, rivals to be
  for (size_t i : order) {
    FamilyTry& t = out->tries[i];
    if (!searched[i]) continue;
    if (fitted >= family.min_fitted && t.screen_px < family.screen_ratio * best) {
      t.failure = "not fitted: its best camera of the search explains " +
                  FormatSignificant(t.screen_px, 5) + " px of line, below " +
                  FormatSignificant(100.0 * family.screen_ratio, 3) + "% of " +
                  fields[static_cast<size_t>(out->kept)].name + "'s fitted " +
                  FormatSignificant(best, 5) + " px";
      continue;
    }
    t.fitted = true;
    try {
      std::vector<AutoCalibration> undecided;
      AutoCalibration a =
          internal::FitSearched(*searched[i], *f.pixels, f.width_px, f.height_px, *f.source,
                                fields[i], *f.options, family.keep_rivals ? &undecided : nullptr);
      t.score_px = a.score_px;
      ++fitted;
      const int model = static_cast<int>(i);
      if (a.score_px > best) {
        best = a.score_px;
        out->kept = model;
        out->calibration = a;
      }
      pool.push_back({model, 0.0, std::move(a)});
      for (AutoCalibration& u : undecided) pool.push_back({model, 0.0, std::move(u)});
    } catch (const InputError& e) {
      t.failure = e.what();
    }
  }
  if (out->kept < 0) return;
  internal::MeasureHeldOut(out->calibration);
  out->tries[static_cast<size_t>(out->kept)].held_out_mapping_mm =
      out->calibration.held_out_mapping_mm;
  if (!family.keep_rivals) return;
  // The rivals: the cameras the lines do not decide from the kept one (by length, or by a piece
  // of line only the kept one explains), best first, each mapping the frame differently from the
  // kept one and from every rival kept before it.
  std::stable_sort(pool.begin(), pool.end(), [](const FamilyRival& a, const FamilyRival& b) {
    return a.calibration.score_px > b.calibration.score_px;
  });
  const AutoCalibration& kept = out->calibration;
  for (FamilyRival& r : pool) {
    if (out->rivals.size() >= static_cast<size_t>(family.max_rivals)) break;
    const AutoCalibration& c = r.calibration;
    double differ = 0.0;
    if (!internal::Undecided(kept.fit.camera, kept.score_px, c.fit.camera, c.score_px,
                             kept.point_symmetric, f.width_px, f.height_px, &differ))
      continue;
    const internal::ExclusiveLines own = internal::ExclusiveLinePixels(
        kept.fit.camera, searched[static_cast<size_t>(out->kept)]->marks, c.fit.camera,
        searched[static_cast<size_t>(r.model)]->marks, *f.pixels, f.width_px, f.height_px);
    if (internal::OwnLinesDecide(own)) continue;
    r.floor_difference_mm = differ;
    const bool new_map = std::all_of(out->rivals.begin(), out->rivals.end(), [&](const auto& o) {
      double d = 0.0;
      return internal::Undecided(o.calibration.fit.camera, o.calibration.score_px, c.fit.camera,
                                 c.score_px, kept.point_symmetric, f.width_px, f.height_px, &d);
    });
    if (new_map) out->rivals.push_back(r);  // a copy: the runners-up are told apart from it
  }
  for (FamilyRival& r : out->rivals) internal::MeasureHeldOut(r.calibration);
  if (family.runner_up_ratio > 0.0) KeepRunnersUp(f, family, pool, out);
}

}  // namespace

FamilyCalibration AutoCalibrateFamily(const std::vector<LinePixel>& pixels, int width_px,
                                      int height_px, const std::string& source,
                                      const std::vector<Field>& fields, const AutoOptions& options,
                                      const FamilyOptions& family,
                                      const std::vector<Field>& lenders) {
  const auto t0 = std::chrono::steady_clock::now();
  if (fields.empty()) throw InputError("no field model to fit; expected a model or a family");
  if (!(family.screen_ratio > 0.0 && family.screen_ratio <= 1.0) || family.min_fitted < 1 ||
      family.max_rivals < 0 || !(family.runner_up_ratio >= 0.0 && family.runner_up_ratio <= 1.0)) {
    throw InputError(
        "family calibration: screen_ratio must be in (0, 1], min_fitted >= 1, max_rivals >= 0 "
        "and runner_up_ratio in [0, 1]");
  }
  const Frame frame{&pixels, width_px, height_px, &source, &options};
  FamilyCalibration out;
  std::vector<int> same;
  // The lenders are searched after the models, so a lender of the same marks as a model shares
  // its search (and lends nothing new), never the other way round.
  std::vector<Field> searched_fields = fields;
  searched_fields.insert(searched_fields.end(), lenders.begin(), lenders.end());
  auto searched = Screen(frame, searched_fields, &same, &out);
  // The line pixels' distance image, which every lent view is scored against.
  const internal::LineDistance dt(pixels, width_px, height_px);
  LendViews(dt, fields.size(), searched, &out);
  const std::vector<size_t> owner =
      AddLentSearches(dt, fields.size(), searched_fields, searched, &out);
  same.resize(fields.size());
  // The models' searches and the lent ones, by their screen.
  std::vector<size_t> order;
  for (size_t e = 0; e < owner.size(); ++e) {
    if (owner[e] != kLender) order.push_back(e);
  }
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const double x = out.tries[a].screen_px, y = out.tries[b].screen_px;
    return std::isfinite(x) && (!std::isfinite(y) || x > y);
  });
  FitInOrder(frame, searched_fields, searched, order, family, &out);
  FoldLentSearches(owner, fields.size(), &out);
  order.erase(
      std::remove_if(order.begin(), order.end(), [&](size_t e) { return e >= fields.size(); }),
      order.end());
  // Models of the same geometry share their twin's result.
  for (size_t i = 0; i < fields.size(); ++i) {
    if (same[i] < 0) continue;
    const FamilyTry& twin = out.tries[static_cast<size_t>(same[i])];
    FamilyTry& t = out.tries[i];
    t = twin;
    t.field = fields[i].name;
    t.same_as = twin.field;
  }
  if (out.kept < 0) {
    const auto failed = std::find_if(order.begin(), order.end(),
                                     [&](size_t i) { return !out.tries[i].failure.empty(); });
    throw InputError(out.tries[*failed].failure +
                     (fields.size() > 1 ? " (and every other model of the family failed)" : ""));
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.calibration.seconds = out.seconds;
  return out;
}

void MeasureHeldOut(AutoCalibration& a) { internal::MeasureHeldOut(a); }

}  // namespace patlab::calib
