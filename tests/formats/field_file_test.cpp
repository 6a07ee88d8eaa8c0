// The shipped field models (experiments/fields/*.toml) against their geometry and against the
// rule books' numbers, written here independently of the files; the field file's arcs.
#include "patlab/formats/field_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include "../expect_error.h"
#include "patlab/calib/field.h"

namespace patlab::formats {
namespace {

const std::vector<std::string> kRoots = {PATLAB_SOURCE_DIR};
constexpr double kTol = 1e-6;  // mm

// The rule books' numbers (mm), typed from the sources each file cites: length and width
// between the lines' centres, centre circle radius, goal width and depth, penalty mark from the
// goal centre (0: none), and the defense area: quarter circles (radius, stretch) or a rectangle
// (depth, width).
struct Rules {
  double length, width, circle, goal_width, goal_depth, penalty;
  bool arcs;
  double a, b;  // arcs: radius, stretch; rectangle: depth, width
};

const std::map<std::string, Rules>& RuleBook() {
  static const std::map<std::string, Rules> rules = {
      {"ssl-2008", {4900, 3400, 500, 700, 180, 450, true, 500, 350}},
      {"ssl-2009", {6050, 4050, 500, 700, 180, 450, true, 500, 350}},
      {"ssl-2012", {6050, 4050, 500, 700, 180, 750, true, 800, 350}},
      {"ssl-2014", {8090, 6050, 500, 1000, 180, 1000, true, 1000, 500}},
      {"ssl-2015", {9000, 6000, 500, 1000, 180, 1000, true, 1000, 500}},
      {"ssl-2018", {12000, 9000, 500, 1200, 180, 1200, false, 1200, 2400}},
      {"ssl-2019-div-b", {9000, 6000, 500, 1000, 180, 1000, false, 1000, 2000}},
      {"ssl-div-a", {12000, 9000, 500, 1800, 180, 8000, false, 1800, 3600}},
      {"ssl-div-b", {9000, 6000, 500, 1000, 180, 6000, false, 1000, 2000}},
      {"vss", {1500, 1300, 200, 400, 100, 0, false, 150, 700}},
      {"vss-5v5", {2200, 1800, 250, 400, 150, 0, false, 150, 500}},
  };
  return rules;
}

// A straight segment or an arc, for the brute-force intersections.
struct Feature {
  std::string name;
  bool arc = false;
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();  // segment ends
  calib::FieldCircle circle;
};

std::vector<Feature> FeaturesOf(const calib::Field& f) {
  std::vector<Feature> out;
  for (const calib::FieldLine& l : f.lines) out.push_back({l.name, false, l.from_mm, l.to_mm, {}});
  for (const calib::FieldCircle& c : f.circles) out.push_back({c.name, true, {}, {}, c});
  return out;
}

double AngleDeg(const Vec2& v) { return std::atan2(v.y(), v.x()) * 180.0 / std::numbers::pi; }

bool OnFeature(const Feature& e, const Vec2& p) {
  if (e.arc) {
    return std::abs((p - e.circle.centre_mm).norm() - e.circle.radius_mm) < kTol &&
           e.circle.Covers(AngleDeg(p - e.circle.centre_mm), 1e-6);
  }
  const Vec2 d = e.b - e.a;
  const double t = (p - e.a).dot(d) / d.squaredNorm();
  return t >= -1e-9 && t <= 1 + 1e-9 && (e.a + t * d - p).norm() < kTol;
}

// Every point where two features cross or touch (segments: non-parallel; arcs: on both).
std::vector<std::pair<Vec2, std::string>> Intersections(const std::vector<Feature>& fs) {
  std::vector<std::pair<Vec2, std::string>> out;
  auto add = [&](const Feature& x, const Feature& y, const Vec2& p) {
    if (OnFeature(x, p) && OnFeature(y, p)) out.emplace_back(p, x.name + " x " + y.name);
  };
  for (size_t i = 0; i < fs.size(); ++i) {
    for (size_t j = i + 1; j < fs.size(); ++j) {
      const Feature *x = &fs[i], *y = &fs[j];
      if (x->arc && !y->arc) std::swap(x, y);
      if (!x->arc && !y->arc) {
        const Vec2 d1 = x->b - x->a, d2 = y->b - y->a;
        const double den = d1.x() * d2.y() - d1.y() * d2.x();
        if (std::abs(den) < 1e-12) continue;
        const Vec2 r = y->a - x->a;
        add(*x, *y, x->a + ((r.x() * d2.y() - r.y() * d2.x()) / den) * d1);
      } else if (!x->arc) {  // segment x, arc y
        const Vec2 d = x->b - x->a, m = x->a - y->circle.centre_mm;
        const double a = d.squaredNorm(), b = 2 * m.dot(d),
                     c = m.squaredNorm() - y->circle.radius_mm * y->circle.radius_mm;
        const double disc = b * b - 4 * a * c;
        if (disc < -1e-6) continue;
        for (double s : {-1.0, 1.0})
          add(*x, *y, x->a + ((-b + s * std::sqrt(std::max(0.0, disc))) / (2 * a)) * d);
      } else {  // two arcs
        const Vec2 c0 = x->circle.centre_mm, c1 = y->circle.centre_mm;
        const double r0 = x->circle.radius_mm, r1 = y->circle.radius_mm, dist = (c1 - c0).norm();
        if (dist < kTol || dist > r0 + r1 || dist < std::abs(r0 - r1)) continue;
        const double a = (r0 * r0 - r1 * r1 + dist * dist) / (2 * dist);
        const double h = std::sqrt(std::max(0.0, r0 * r0 - a * a));
        const Vec2 u = (c1 - c0) / dist, mid = c0 + a * u, n(-u.y(), u.x());
        add(*x, *y, mid + h * n);
        add(*x, *y, mid - h * n);
      }
    }
  }
  return out;
}

const calib::FieldPoint* PointAt(const calib::Field& f, const Vec2& p) {
  for (const calib::FieldPoint& q : f.points)
    if ((q.at_mm - p).norm() < kTol) return &q;
  return nullptr;
}

bool SameSegment(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  return ((a - c).norm() < kTol && (b - d).norm() < kTol) ||
         ((a - d).norm() < kTol && (b - c).norm() < kTol);
}

// `c` mirrored by (sx, sy) in {-1, 1}^2 is an arc (or circle) of the field. A mirror reverses the
// direction of travel: the mirrored arc runs anticlockwise from the image of its end.
bool HasMirroredArc(const calib::Field& f, const calib::FieldCircle& c, double sx, double sy) {
  const auto m = [&](const Vec2& p) { return Vec2(sx * p.x(), sy * p.y()); };
  const bool flipped = sx * sy < 0;
  const Vec2 start = flipped ? m(c.ArcTo()) : m(c.ArcFrom());
  const Vec2 end = flipped ? m(c.ArcFrom()) : m(c.ArcTo());
  for (const calib::FieldCircle& d : f.circles) {
    if ((d.centre_mm - m(c.centre_mm)).norm() > kTol || d.radius_mm != c.radius_mm) continue;
    if (c.IsFullCircle() || d.IsFullCircle()) {
      if (c.IsFullCircle() && d.IsFullCircle()) return true;
      continue;
    }
    if ((d.ArcFrom() - start).norm() < kTol && (d.ArcTo() - end).norm() < kTol &&
        std::abs((d.to_deg - d.from_deg) - (c.to_deg - c.from_deg)) < 1e-9)
      return true;
  }
  return false;
}

TEST(FieldFile, EveryShippedModelParsesAndIsInTheRuleBookTable) {
  const std::vector<calib::Field> fields = ShippedFields(kRoots);
  ASSERT_EQ(fields.size(), RuleBook().size());
  for (const calib::Field& f : fields) {
    SCOPED_TRACE(f.name);
    EXPECT_EQ(RuleBook().count(f.name), 1u);
    EXPECT_FALSE(f.source.empty());
    EXPECT_TRUE(f.family == "ssl" || f.family == "vss");
    EXPECT_GE(f.year, 2008);
    EXPECT_TRUE(f.boundary_mm.has_value() || f.name == "ssl-2008");
  }
}

TEST(FieldFile, FamiliesListTheirModelsNewestFirst) {
  EXPECT_EQ(FieldFamilies(kRoots), (std::vector<std::string>{"ssl", "vss"}));
  std::vector<std::string> ssl, vss;
  for (const calib::Field& f : FieldFamily("ssl", kRoots)) ssl.push_back(f.name);
  for (const calib::Field& f : FieldFamily("vss", kRoots)) vss.push_back(f.name);
  EXPECT_EQ(ssl,
            (std::vector<std::string>{"ssl-div-a", "ssl-div-b", "ssl-2019-div-b", "ssl-2018",
                                      "ssl-2015", "ssl-2014", "ssl-2012", "ssl-2009", "ssl-2008"}));
  EXPECT_EQ(vss, (std::vector<std::string>{"vss-5v5", "vss"}));
  EXPECT_TRUE(FieldFamily("msl", kRoots).empty());
}

TEST(FieldFile, DimensionsAgreeWithTheRuleBooks) {
  for (const calib::Field& f : ShippedFields(kRoots)) {
    SCOPED_TRACE(f.name);
    const Rules& r = RuleBook().at(f.name);
    const double x = r.length / 2, y = r.width / 2;
    EXPECT_EQ(f.length_mm, r.length);
    EXPECT_EQ(f.width_mm, r.width);
    EXPECT_EQ(f.goal_width_mm, r.goal_width);
    EXPECT_EQ(f.goal_depth_mm, r.goal_depth);
    ASSERT_NE(f.FindLine("touch_left"), nullptr);
    EXPECT_EQ(f.FindLine("touch_left")->from_mm.y(), y);
    EXPECT_EQ(f.FindLine("goal_line_pos")->from_mm.x(), x);
    EXPECT_EQ(f.FindPoint("corner_neg_right")->at_mm, Vec2(-x, -y));
    EXPECT_EQ(f.FindCircle("centre_circle")->radius_mm, r.circle);
    EXPECT_TRUE(f.FindCircle("centre_circle")->IsFullCircle());
    EXPECT_EQ(f.FindPoint("goal_post_left_pos")->at_mm, Vec2(x, r.goal_width / 2));
    EXPECT_EQ(f.FindPoint("goal_back_right_neg")->at_mm,
              Vec2(-x - r.goal_depth, -r.goal_width / 2));
    if (r.penalty > 0) {
      EXPECT_EQ(f.FindPoint("penalty_mark_pos")->at_mm, Vec2(x - r.penalty, 0));
    } else {
      EXPECT_EQ(f.FindPoint("penalty_mark_pos"), nullptr);
    }
    const std::string area = f.family == "vss" ? "goal_area" : "defense";
    if (r.arcs) {
      const calib::FieldCircle* arc = f.FindCircle("defense_arc_left_pos");
      ASSERT_NE(arc, nullptr);
      EXPECT_EQ(arc->radius_mm, r.a);
      EXPECT_EQ(arc->centre_mm, Vec2(x, r.b / 2));
      EXPECT_EQ(f.FindPoint("defense_front_left_pos")->at_mm, Vec2(x - r.a, r.b / 2));
      EXPECT_EQ(f.FindPoint("defense_goal_right_neg")->at_mm, Vec2(-x, -r.b / 2 - r.a));
      EXPECT_EQ(f.circles.size(), 5u);
    } else {
      EXPECT_EQ(f.FindPoint(area + "_front_left_pos")->at_mm, Vec2(x - r.a, r.b / 2));
      EXPECT_EQ(f.FindPoint(area + "_goal_right_neg")->at_mm, Vec2(-x, -r.b / 2));
      EXPECT_EQ(f.circles.size(), 1u);
    }
  }
  // The 5 vs 5 field's penalty areas: 350 mm deep, 800 mm wide.
  const calib::Field five =
      LoadField(std::string(PATLAB_SOURCE_DIR) + "/experiments/fields/vss-5v5.toml");
  EXPECT_EQ(five.FindPoint("penalty_area_front_left_neg")->at_mm, Vec2(-750, 400));
}

TEST(FieldFile, LandmarksLieOnTheLinesAndEveryCrossingIsALandmark) {
  for (const calib::Field& f : ShippedFields(kRoots)) {
    SCOPED_TRACE(f.name);
    const std::vector<Feature> features = FeaturesOf(f);
    // Every line's and arc's ends are landmarks (the corners at line ends).
    for (const Feature& e : features) {
      const Vec2 a = e.arc ? e.circle.ArcFrom() : e.a, b = e.arc ? e.circle.ArcTo() : e.b;
      if (e.arc && e.circle.IsFullCircle()) continue;
      EXPECT_NE(PointAt(f, a), nullptr) << e.name << " starts at " << a.transpose();
      EXPECT_NE(PointAt(f, b), nullptr) << e.name << " ends at " << b.transpose();
    }
    // Every crossing of two features is a landmark, on both.
    for (const auto& [p, what] : Intersections(features)) {
      EXPECT_NE(PointAt(f, p), nullptr) << what << " at " << p.transpose();
    }
    // Every landmark but the penalty marks (painted dots) lies on a line or arc; corners, posts
    // and crossings on two.
    for (const calib::FieldPoint& q : f.points) {
      int on = 0;
      for (const Feature& e : features) on += OnFeature(e, q.at_mm);
      if (q.name.starts_with("penalty_mark")) {
        EXPECT_EQ(q.at_mm.y(), 0.0) << q.name;
        continue;
      }
      EXPECT_GE(on, 1) << q.name;
      if (q.name.starts_with("corner") || q.name.starts_with("goal_post") ||
          q.name.starts_with("halfway_") ||
          (q.name == "centre" && f.FindLine("midline") != nullptr)) {
        EXPECT_GE(on, 2) << q.name;
      }
    }
  }
}

TEST(FieldFile, EveryModelIsSymmetricAboutBothAxes) {
  for (const calib::Field& f : ShippedFields(kRoots)) {
    SCOPED_TRACE(f.name);
    for (const double sx : {-1.0, 1.0}) {
      for (const double sy : {-1.0, 1.0}) {
        const auto m = [&](const Vec2& p) { return Vec2(sx * p.x(), sy * p.y()); };
        for (const calib::FieldPoint& q : f.points)
          EXPECT_NE(PointAt(f, m(q.at_mm)), nullptr) << q.name << " mirrored " << sx << sy;
        for (const calib::FieldLine& l : f.lines) {
          bool found = false;
          for (const calib::FieldLine& k : f.lines)
            found |= SameSegment(m(l.from_mm), m(l.to_mm), k.from_mm, k.to_mm);
          EXPECT_TRUE(found) << l.name << " mirrored " << sx << sy;
        }
        for (const calib::FieldCircle& c : f.circles)
          EXPECT_TRUE(HasMirroredArc(f, c, sx, sy)) << c.name << " mirrored " << sx << sy;
      }
    }
  }
}

TEST(FieldFile, ArcsHaveAnExtentAndCirclesAreFull) {
  const calib::Field f = ParseField(
      "name = \"t\"\n[[circle]]\nname = \"arc\"\ncentre_mm = [0, 0]\nradius_mm = 100\n"
      "from_deg = 90\nto_deg = 180\n[[circle]]\nname = \"full\"\ncentre_mm = [0, 0]\n"
      "radius_mm = 50\n",
      "f.toml");
  const calib::FieldCircle& arc = f.circles[0];
  EXPECT_FALSE(arc.IsFullCircle());
  EXPECT_NEAR((arc.ArcFrom() - Vec2(0, 100)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((arc.ArcTo() - Vec2(-100, 0)).norm(), 0.0, 1e-9);
  EXPECT_TRUE(arc.Covers(135));
  EXPECT_FALSE(arc.Covers(200));
  EXPECT_FALSE(arc.Covers(-45));
  EXPECT_TRUE(f.circles[1].IsFullCircle());
  EXPECT_TRUE(f.circles[1].Covers(-123));
  EXPECT_EQ(f.circles[1].from_deg, 0.0);
  EXPECT_EQ(f.circles[1].to_deg, 360.0);
  // An arc across 0 degrees.
  const calib::FieldCircle wrap{"w", Vec2::Zero(), 10.0, 270.0, 450.0};
  EXPECT_TRUE(wrap.Covers(0.0));
  EXPECT_TRUE(wrap.Covers(-80.0));
  EXPECT_FALSE(wrap.Covers(180.0));
}

TEST(FieldFile, BadArcsAndFactsAreInputErrors) {
  const std::string head =
      "name = \"t\"\n[[circle]]\nname = \"arc\"\ncentre_mm = [0, 0]\n"
      "radius_mm = 100\n";
  EXPECT_INPUT_ERROR(ParseField(head + "from_deg = 90\n", "f.toml"),
                     "f.toml:6: from_deg in [[circle]] 1 is given alone; expected both from_deg "
                     "and to_deg (an arc) or neither (the full circle)");
  EXPECT_INPUT_ERROR(ParseField(head + "from_deg = 90\nto_deg = 90\n", "f.toml"),
                     "f.toml:7: to_deg in [[circle]] 1 is 90; expected more than from_deg (90) and "
                     "at most from_deg + 360 (the arc runs anticlockwise)");
  EXPECT_INPUT_ERROR(ParseField("name = \"t\"\nwidth_mm = -3\n[[point]]\nname = \"p\"\n"
                                "at_mm = [0, 0]\n",
                                "f.toml"),
                     "f.toml:2: width_mm is -3; expected a length > 0 mm");
}

// `patlab setup --field`: a family fits its every model and lends nothing; one model named is
// fitted alone, the rest of its family (newest first) searched only to lend it their views; a
// model of no family has no lenders.
TEST(FieldFile, SetupFitsAFamilyOrOneModelWithTheRestOfItsFamilyAsLenders) {
  auto names = [](const std::vector<calib::Field>& fields) {
    std::vector<std::string> out;
    for (const calib::Field& f : fields) out.push_back(f.name);
    return out;
  };
  const SetupFieldModels family = SetupFields("ssl", kRoots);
  EXPECT_EQ(names(family.fields), names(FieldFamily("ssl", kRoots)));
  EXPECT_TRUE(family.lenders.empty());
  const SetupFieldModels named = SetupFields("ssl-2015", kRoots);
  EXPECT_EQ(names(named.fields), std::vector<std::string>{"ssl-2015"});
  EXPECT_EQ(names(named.lenders),
            (std::vector<std::string>{"ssl-div-a", "ssl-div-b", "ssl-2019-div-b", "ssl-2018",
                                      "ssl-2014", "ssl-2012", "ssl-2009", "ssl-2008"}));
  EXPECT_EQ(names(SetupFields("vss", kRoots).fields), (std::vector<std::string>{"vss-5v5", "vss"}));
  EXPECT_EQ(names(SetupFields("vss", kRoots).lenders), std::vector<std::string>{});
  EXPECT_EQ(names(SetupFields("vss-5v5", kRoots).lenders), std::vector<std::string>{"vss"});
  // A user's file of no family: fitted alone.
  std::ifstream in(std::string(PATLAB_SOURCE_DIR) + "/experiments/fields/ssl-2015.toml");
  std::ostringstream own;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("family", 0) == 0) continue;
    own << (line == "name = \"ssl-2015\"" ? "name = \"our-lab\"" : line) << "\n";
  }
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("our-lab-" + std::to_string(::getpid()) + ".toml");
  std::ofstream(path) << own.str();
  const SetupFieldModels lab = SetupFields(path.string(), kRoots);
  std::filesystem::remove(path);
  EXPECT_EQ(names(lab.fields), std::vector<std::string>{"our-lab"});
  EXPECT_TRUE(lab.lenders.empty());
  EXPECT_INPUT_ERROR_STARTS_WITH(SetupFields("ssl-2016", kRoots),
                                 "field 'ssl-2016' not found; expected an existing file or a name "
                                 "in ");
}

}  // namespace
}  // namespace patlab::formats
