#include "patlab/formats/thresholds_file.h"

#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <sstream>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/colour_vocabulary.h"
#include "patlab/io/csv.h"
#include "patlab/io/name.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace {

// A cursor over one line of colors.txt. Each Expect* returns false on a mismatch so the caller
// can report the whole line with the expected form.
class LineCursor {
 public:
  explicit LineCursor(std::string_view line) : line_(line) {}

  void SkipSpace() {
    while (pos_ < line_.size() && std::isspace(static_cast<unsigned char>(line_[pos_]))) ++pos_;
  }
  bool Char(char c) {
    SkipSpace();
    if (pos_ < line_.size() && line_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  bool Integer(long* value) {
    return Number([](const char* text, char** end) { return std::strtol(text, end, 10); }, value);
  }
  // A decimal number at the cursor (std::from_chars: the "C" form whatever the locale; a leading
  // '+' allowed); false when there is none.
  bool Real(double* value) {
    SkipSpace();
    const std::string_view rest = line_.substr(pos_);
    const size_t sign = !rest.empty() && rest.front() == '+' ? 1 : 0;
    const auto [end, ec] = std::from_chars(rest.data() + sign, rest.data() + rest.size(), *value);
    if (ec == std::errc::invalid_argument) return false;
    const size_t used = static_cast<size_t>(end - rest.data());
    if (ec == std::errc::result_out_of_range) *value = *io::ParseDouble(rest.substr(0, used));
    pos_ += used;
    return true;
  }
  std::string Rest() {
    SkipSpace();
    std::string rest(line_.substr(pos_));
    while (!rest.empty() && std::isspace(static_cast<unsigned char>(rest.back()))) rest.pop_back();
    pos_ = line_.size();
    return rest;
  }
  bool AtEnd() {
    SkipSpace();
    return pos_ == line_.size();
  }

 private:
  // One number at the cursor, read by `convert` (strtol or strtod); false when there is none.
  template <typename T, typename Convert>
  bool Number(Convert convert, T* value) {
    SkipSpace();
    const std::string rest(line_.substr(pos_));
    char* end = nullptr;
    *value = convert(rest.c_str(), &end);
    if (end == rest.c_str()) return false;
    pos_ += static_cast<size_t>(end - rest.c_str());
    return true;
  }

  std::string_view line_;
  size_t pos_ = 0;
};

constexpr const char* kChannelNames[2][3] = {{"Y", "U", "V"}, {"R", "G", "B"}};

std::string TrimSpace(std::string_view s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return std::string(s.substr(b, e - b));
}

void CheckRange(const FileLoc& loc, const char* channel, long lo, long hi) {
  for (long v : {lo, hi}) {
    if (v < 0 || v > 255) {
      throw InputError(loc, std::string(channel) + " bound " + std::to_string(v) +
                                " out of range; expected 0..255");
    }
  }
  if (lo > hi) {
    throw InputError(loc, std::string("empty ") + channel + " range " + std::to_string(lo) + ":" +
                              std::to_string(hi) + "; expected lo <= hi");
  }
}

// CMVision's merge is a density, a fraction of a region's bounding box; expected_num counts the
// regions a frame holds; the areas are at most a frame's pixel budget (vision/frame_io.cpp).
constexpr long kMaxExpectedNum = 1'000'000;
constexpr int64_t kMaxAreaPx = int64_t{1} << 28;

// What is wrong with a class's merge density (a number in [0, 1]; NaN fails both comparisons),
// "is <value>; expected ...", or "" when nothing is.
std::string MergeProblem(double merge) {
  if (merge >= 0.0 && merge <= 1.0) return "";
  return "is " + FormatNumber(merge) + "; expected a density in [0, 1]";
}

std::string ExpectedNumProblem(int64_t expected) {
  if (expected >= 0 && expected <= kMaxExpectedNum) return "";
  return "is " + std::to_string(expected) + "; expected an integer in [0, " +
         std::to_string(kMaxExpectedNum) + "]";
}

enum class Section { kNone, kColors, kThresholds };

// CMVision compares section names without regard to case ([colors], [COLORS], [Colors]).
bool EqualsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  }
  return true;
}

// The section a trimmed line opens, or kNone when it is no CMVision section header.
Section SectionOf(std::string_view line) {
  if (EqualsIgnoreCase(line, "[Colors]")) return Section::kColors;
  if (EqualsIgnoreCase(line, "[Thresholds]")) return Section::kThresholds;
  return Section::kNone;
}

Section ParseSectionHeader(const FileLoc& loc, const std::string& line) {
  const Section section = SectionOf(line);
  if (section != Section::kNone) return section;
  throw InputError(loc, "unknown section " + EscapeForMessage(line) +
                            "; expected [Colors] or [Thresholds] (any case)");
}

// `num_classes` is how many [Colors] lines came before this one.
vision::ColorClass ParseColorsLine(const FileLoc& loc, const std::string& line,
                                   size_t num_classes) {
  LineCursor c(line);
  long r, g, b, expected;
  double merge;
  if (!(c.Char('(') && c.Integer(&r) && c.Char(',') && c.Integer(&g) && c.Char(',') &&
        c.Integer(&b) && c.Char(')') && c.Real(&merge) && c.Integer(&expected))) {
    throw InputError(loc, "bad [Colors] line '" + EscapeForMessage(line) +
                              "'; expected (R,G,B) merge expected_num Name");
  }
  const std::string class_name = c.Rest();
  if (class_name.empty()) {
    throw InputError(loc, "bad [Colors] line '" + EscapeForMessage(line) +
                              "': no name; expected (R,G,B) merge expected_num Name");
  }
  for (long v : {r, g, b}) {
    if (v < 0 || v > 255) {
      throw InputError(
          loc, "display colour component " + std::to_string(v) + " out of range; expected 0..255");
    }
  }
  if (const std::string problem = MergeProblem(merge); !problem.empty()) {
    throw InputError(loc, "merge " + problem);
  }
  if (const std::string problem = ExpectedNumProblem(expected); !problem.empty()) {
    throw InputError(loc, "expected_num " + problem);
  }
  if (num_classes == vision::kMaxColorClasses) {
    throw InputError(loc, "colour " + std::to_string(vision::kMaxColorClasses + 1) +
                              "; expected at most " + std::to_string(vision::kMaxColorClasses) +
                              " colour classes");
  }
  vision::ColorClass cls;
  cls.name = io::CanonicalClassName(class_name, loc);
  cls.display_rgb = {static_cast<uint8_t>(r), static_cast<uint8_t>(g), static_cast<uint8_t>(b)};
  cls.merge = merge;
  cls.expected_num = static_cast<int>(expected);
  return cls;
}

// Sets the ranges of classes[index]: [Thresholds] lines pair with [Colors] lines in order.
void ParseThresholdsLine(const FileLoc& loc, const std::string& line, size_t index,
                         std::vector<vision::ColorClass>* classes) {
  LineCursor c(line);
  long v[6];
  if (!(c.Char('(') && c.Integer(&v[0]) && c.Char(':') && c.Integer(&v[1]) && c.Char(',') &&
        c.Integer(&v[2]) && c.Char(':') && c.Integer(&v[3]) && c.Char(',') && c.Integer(&v[4]) &&
        c.Char(':') && c.Integer(&v[5]) && c.Char(')') && c.AtEnd())) {
    throw InputError(loc, "bad [Thresholds] line '" + EscapeForMessage(line) +
                              "'; expected (Ylo:Yhi, Ulo:Uhi, Vlo:Vhi)");
  }
  if (index >= classes->size()) {
    throw InputError(loc, "threshold " + std::to_string(index + 1) + " but only " +
                              std::to_string(classes->size()) +
                              " colours; expected one [Thresholds] line per [Colors] line");
  }
  vision::ColorClass& cls = (*classes)[index];
  for (int ch = 0; ch < 3; ++ch) {
    CheckRange(loc, kChannelNames[0][ch], v[2 * ch], v[2 * ch + 1]);
    cls.range[ch] = {static_cast<int>(v[2 * ch]), static_cast<int>(v[2 * ch + 1])};
  }
}

// Only the whole file tells whether every colour got its threshold line.
void CheckCmvisionCounts(const std::string& name, size_t num_classes, size_t num_thresholds,
                         int last_threshold_line) {
  if (num_classes == 0) {
    throw InputError(FileLoc{name, 0},
                     "no colours; expected a [Colors] section with at least one line");
  }
  if (num_thresholds != num_classes) {
    throw InputError(FileLoc{name, last_threshold_line},
                     std::to_string(num_classes) + " colours but " +
                         std::to_string(num_thresholds) +
                         " thresholds; expected one [Thresholds] line per [Colors] line");
  }
}

}  // namespace

vision::Thresholds ParseCmvisionColors(std::string_view text, const std::string& name) {
  vision::Thresholds t;
  t.space = vision::ColorSpace::kYuv;
  t.source = name;
  Section section = Section::kNone;
  size_t num_thresholds = 0;
  int line_number = 0;
  int last_threshold_line = 0;
  std::istringstream in{std::string(text)};
  std::string raw;
  while (std::getline(in, raw)) {
    ++line_number;
    const FileLoc loc{name, line_number};
    const std::string line = TrimSpace(raw);
    if (line.empty() || line[0] == '#' || line[0] == ';') continue;
    if (line[0] == '[') {
      section = ParseSectionHeader(loc, line);
      continue;
    }
    if (section == Section::kNone) {
      throw InputError(loc, "line outside a section; expected [Colors] or [Thresholds] first");
    }
    if (section == Section::kColors) {
      vision::ColorClass cls = ParseColorsLine(loc, line, t.classes.size());
      if (t.Find(cls.name) >= 0) {
        throw InputError(loc, "colour '" + EscapeForMessage(cls.name) +
                                  "' listed twice (names that differ only in case, spaces, "
                                  "hyphens or underscores, or are aliases, are one colour); "
                                  "expected distinct colours");
      }
      t.classes.push_back(std::move(cls));
    } else {
      ParseThresholdsLine(loc, line, num_thresholds, &t.classes);
      ++num_thresholds;
      last_threshold_line = line_number;
    }
  }
  CheckCmvisionCounts(name, t.classes.size(), num_thresholds, last_threshold_line);
  return t;
}

namespace {

vision::ChannelRange ReadRange(const io::TomlReader& reader, std::string_view key,
                               const char* channel) {
  const toml::node* node = reader.table().get(key);
  if (node == nullptr) return vision::ChannelRange{};
  const auto* array = node->as_array();
  const FileLoc loc = reader.Loc(key);
  if (array == nullptr || array->size() != 2 || !(*array)[0].is_integer() ||
      !(*array)[1].is_integer()) {
    throw InputError(
        loc, reader.Describe(key) + " is not a pair of integers; expected [lo, hi] in 0..255");
  }
  const long lo = static_cast<long>((*array)[0].as_integer()->get());
  const long hi = static_cast<long>((*array)[1].as_integer()->get());
  CheckRange(loc, channel, lo, hi);
  return {static_cast<int>(lo), static_cast<int>(hi)};
}

vision::ColorSpace ReadSpace(const io::TomlReader& top) {
  const std::string space = top.OptionalString("space").value_or("yuv");
  const auto parsed = FindName(space, vision::kColorSpaceNames);
  if (!parsed) {
    top.Fail("space", "space is \"" + space + "\"; expected " + NameList(vision::kColorSpaceNames));
  }
  return *parsed;
}

// The [[class]] array: present, not empty, and no longer than a ColorLut mask holds.
const toml::array& ReadClassArray(const toml::table& root, const std::string& name) {
  const toml::node* classes_node = root.get("class");
  const toml::array* classes = classes_node ? classes_node->as_array() : nullptr;
  if (classes == nullptr || classes->empty()) {
    throw InputError(
        FileLoc{name, classes_node ? static_cast<int>(classes_node->source().begin.line) : 0},
        "no colour classes; expected at least one [[class]] table");
  }
  if (classes->size() > vision::kMaxColorClasses) {
    throw InputError(io::LocOf(name, (*classes)[vision::kMaxColorClasses]),
                     "[[class]] " + std::to_string(vision::kMaxColorClasses + 1) +
                         "; expected at most " + std::to_string(vision::kMaxColorClasses) +
                         " colour classes");
  }
  return *classes;
}

void ReadDisplay(const io::TomlReader& r, const std::string& context, vision::ColorClass* cls) {
  const toml::node* d = r.table().get("display");
  if (d == nullptr) return;
  const auto* a = d->as_array();
  bool ok = a != nullptr && a->size() == 3;
  for (size_t k = 0; ok && k < 3; ++k) {
    const auto* v = (*a)[k].as_integer();
    ok = v != nullptr && v->get() >= 0 && v->get() <= 255;
    if (ok) cls->display_rgb[k] = static_cast<uint8_t>(v->get());
  }
  if (!ok)
    r.Fail("display",
           "display in " + context + " is not [R, G, B]; expected three integers in 0..255");
}

void ReadAreas(const io::TomlReader& r, const std::string& context, vision::ColorClass* cls) {
  if (auto v = r.OptionalInteger("min_area_px")) {
    if (*v < 0 || *v > kMaxAreaPx)
      r.Fail("min_area_px", "min_area_px " + std::to_string(*v) + " in " + context +
                                "; expected 0.." + std::to_string(kMaxAreaPx) + " pixels");
    cls->min_area_px = static_cast<int>(*v);
  }
  if (auto v = r.OptionalInteger("max_area_px")) {
    if (*v < 0 || (*v > 0 && *v < cls->min_area_px) || *v > kMaxAreaPx)
      r.Fail("max_area_px", "max_area_px " + std::to_string(*v) + " in " + context +
                                "; expected 0 (no limit) or min_area_px.." +
                                std::to_string(kMaxAreaPx) + " pixels");
    cls->max_area_px = static_cast<int>(*v);
  }
}

// The [[class]] table at `index`; `t` holds the classes before it, for the duplicate-name check.
vision::ColorClass ReadClass(const toml::node& node, const std::string& name, size_t index,
                             const vision::Thresholds& t) {
  const toml::table* table = node.as_table();
  const std::string context = "[[class]] " + std::to_string(index + 1);
  if (table == nullptr) {
    throw InputError(io::LocOf(name, node), context + " is not a table; expected [[class]] tables");
  }
  const io::TomlReader r(*table, name, context);
  const int sp = t.space == vision::ColorSpace::kYuv ? 0 : 1;
  if (sp == 0) {
    r.CheckKeys(
        {"name", "display", "y", "u", "v", "min_area_px", "max_area_px", "merge", "expected_num"});
  } else {
    r.CheckKeys(
        {"name", "display", "r", "g", "b", "min_area_px", "max_area_px", "merge", "expected_num"});
  }
  vision::ColorClass cls;
  cls.name = r.String("name");
  if (cls.name.empty()) r.Fail("name", "empty name in " + context + "; expected a class name");
  if (const std::string problem = io::NameProblem(cls.name); !problem.empty()) {
    r.Fail("name", "name '" + EscapeForMessage(cls.name) + "' " + problem + "; expected " +
                       io::kNameExpected);
  }
  cls.name = io::CanonicalClassName(cls.name, r.Loc("name"));
  if (t.Find(cls.name) >= 0) {
    r.Fail("name", "duplicate class name \"" + cls.name + "\"; expected unique names");
  }
  const char* keys[2][3] = {{"y", "u", "v"}, {"r", "g", "b"}};
  for (int ch = 0; ch < 3; ++ch) cls.range[ch] = ReadRange(r, keys[sp][ch], kChannelNames[sp][ch]);
  ReadDisplay(r, context, &cls);
  ReadAreas(r, context, &cls);
  cls.merge = r.OptionalNumber("merge").value_or(0.0);
  if (const std::string problem = MergeProblem(cls.merge); !problem.empty()) {
    r.Fail("merge", r.Describe("merge") + " " + problem);
  }
  if (auto v = r.OptionalInteger("expected_num")) {
    if (const std::string problem = ExpectedNumProblem(*v); !problem.empty()) {
      r.Fail("expected_num", r.Describe("expected_num") + " " + problem);
    }
    cls.expected_num = static_cast<int>(*v);
  }
  return cls;
}

}  // namespace

vision::Thresholds ParseThresholdsToml(std::string_view text, const std::string& name) {
  const toml::table root = io::ParseTomlText(text, name);
  const io::TomlReader top(root, name);
  top.CheckKeys({"space", "class"});
  vision::Thresholds t;
  t.source = name;
  t.space = ReadSpace(top);
  const toml::array& classes = ReadClassArray(root, name);
  for (size_t i = 0; i < classes.size(); ++i)
    t.classes.push_back(ReadClass(classes[i], name, i, t));
  return t;
}

vision::Thresholds LoadThresholds(const std::string& path) {
  const std::string text = io::ReadTextFile(path, "thresholds file");
  // CMVision's format is recognised by its first non-blank, non-comment line.
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const std::string t = TrimSpace(line);
    if (t.empty() || t[0] == '#' || t[0] == ';') continue;
    if (SectionOf(t) != Section::kNone) return ParseCmvisionColors(text, path);
    break;
  }
  return ParseThresholdsToml(text, path);
}

}  // namespace patlab::formats
