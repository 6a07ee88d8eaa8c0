// Reading track CSV files for `patlab analyze` (analyze.h).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>

#include "patlab/analysis/analyze.h"
#include "patlab/core/error.h"

namespace patlab::sim {

namespace {

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return s;
}

// Splits a line into trimmed cells (reusing `cells`).
void SplitCells(std::string_view line, std::vector<std::string_view>* cells) {
  cells->clear();
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      cells->push_back(Trim(line.substr(start)));
      return;
    }
    cells->push_back(Trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

bool Skipped(std::string_view line) {
  const std::string_view t = Trim(line);
  return t.empty() || t.front() == '#';
}

// Concatenation by append (GCC 12's -Wrestrict misfires on "literal" + std::string chains).
template <typename... Parts>
std::string Cat(const Parts&... parts) {
  std::string out;
  (out.append(parts), ...);
  return out;
}

std::string Quoted(std::string_view s) { return Cat("\"", EscapeForMessage(s, 60), "\""); }

// Index of each wanted column in the header (-1 for an optional one that is absent).
struct ColumnIndex {
  int frame = -1, subject = -1, run = -1, x = -1, y = -1, theta = -1;
  int needed = 0;  // cells a row must have
};

ColumnIndex FindColumns(const std::vector<std::string_view>& header, const TrackColumns& c,
                        const FileLoc& loc) {
  ColumnIndex idx;
  auto find = [&](const std::string& name, bool required, const char* what) {
    for (size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) {
        idx.needed = std::max(idx.needed, static_cast<int>(i) + 1);
        return static_cast<int>(i);
      }
    }
    if (required) {
      throw InputError(loc, Cat("no column ", Quoted(name), " in the header; expected the ", what,
                                " column (or name it with --", what, "-column)"));
    }
    return -1;
  };
  idx.frame = find(c.frame, true, "frame");
  idx.subject = find(c.subject, c.require_subject, "subject");
  idx.run = find(c.run, c.require_run, "run");
  idx.x = find(c.x, true, "x");
  idx.y = find(c.y, true, "y");
  idx.theta = find(c.theta, c.require_theta, "theta");
  return idx;
}

double ParseNumber(std::string_view cell, const std::string& column, const FileLoc& loc) {
  std::string_view s = cell;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty() || !std::isfinite(v)) {
    throw InputError(loc, Cat(column, " is ", Quoted(cell), "; expected a finite number"));
  }
  return v;
}

int64_t ParseFrame(std::string_view cell, const std::string& column, const FileLoc& loc) {
  std::string_view s = cell;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) {
    throw InputError(loc, Cat(column, " is ", Quoted(cell), "; expected an integer frame number"));
  }
  return v;
}

// Adds the samples of the rows to their tracks.
class TrackBuilder {
 public:
  TrackBuilder(const std::string& source, const TrackColumns& columns, const ColumnIndex& idx)
      : source_(source), columns_(columns), idx_(idx) {}

  void AddRow(const std::vector<std::string_view>& cells, int line) {
    const FileLoc loc{source_, line};
    if (static_cast<int>(cells.size()) < idx_.needed) {
      throw InputError(loc,
                       Cat("row has ", std::to_string(cells.size()), " cells; expected at least ",
                           std::to_string(idx_.needed), " as the header names them"));
    }
    MeasuredTrack& t = TrackOf(cells, line);
    const int64_t frame = ParseFrame(cells[idx_.frame], columns_.frame, loc);
    if (!t.frame.empty() && frame <= t.frame.back()) {
      throw InputError(
          loc, Cat(columns_.frame, " ", std::to_string(frame), " of subject ", Quoted(t.subject),
                   " run ", Quoted(t.run), " is not after ", std::to_string(t.frame.back()),
                   " (line ", std::to_string(last_line_[current_]),
                   "); expected increasing frame numbers within a subject and run"));
    }
    t.frame.push_back(frame);
    t.x.push_back(ParseNumber(cells[idx_.x], columns_.x, loc));
    t.y.push_back(ParseNumber(cells[idx_.y], columns_.y, loc));
    if (idx_.theta >= 0) t.theta.push_back(ParseNumber(cells[idx_.theta], columns_.theta, loc));
    last_line_[current_] = line;
  }

  std::vector<MeasuredTrack> Take() { return std::move(tracks_); }

 private:
  MeasuredTrack& TrackOf(const std::vector<std::string_view>& cells, int line) {
    const std::string_view subject = idx_.subject >= 0 ? cells[idx_.subject] : "track";
    const std::string_view run = idx_.run >= 0 ? cells[idx_.run] : std::string_view(source_);
    if (current_ < tracks_.size() && tracks_[current_].subject == subject &&
        tracks_[current_].run == run) {
      return tracks_[current_];
    }
    if (current_ < tracks_.size()) longest_ = std::max(longest_, tracks_[current_].frame.size());
    const auto key = std::pair(std::string(subject), std::string(run));
    const auto [it, inserted] = index_.emplace(key, tracks_.size());
    if (inserted) {
      MeasuredTrack t;
      t.subject = key.first;
      t.run = key.second;
      t.file = source_;
      t.first_line = line;
      // Tracks of one file tend to have one length: room for the longest so far saves the copies
      // (and fresh pages) of growing one sample at a time. Unused room is never touched.
      t.frame.reserve(longest_);
      t.x.reserve(longest_);
      t.y.reserve(longest_);
      if (idx_.theta >= 0) t.theta.reserve(longest_);
      tracks_.push_back(std::move(t));
      last_line_.push_back(line);
    }
    current_ = it->second;
    return tracks_[current_];
  }

  const std::string& source_;
  const TrackColumns& columns_;
  const ColumnIndex& idx_;
  std::vector<MeasuredTrack> tracks_;
  std::vector<int> last_line_;
  std::map<std::pair<std::string, std::string>, size_t> index_;
  size_t current_ = static_cast<size_t>(-1);
  size_t longest_ = 0;  // samples of the longest track left so far
};

}  // namespace

std::vector<OptionsProblem> Check(const TrackColumns& c) {
  OptionsChecker check;
  const std::vector<std::pair<const char*, const std::string*>> names = {
      {"frame", &c.frame}, {"subject", &c.subject}, {"run", &c.run}, {"x", &c.x},
      {"y", &c.y},         {"theta", &c.theta}};
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string& n = *names[i].second;
    const std::string field = Cat(std::string_view(names[i].first), "-column");
    if (n.empty() || n.find_first_of(",\n\r\"") != std::string::npos || Trim(n) != n) {
      check.Fail(field, Cat("--", field, " is ", Quoted(n),
                            "; expected a column name without comma, quote or surrounding blanks"));
    }
    for (size_t j = 0; j < i; ++j) {
      if (n == *names[j].second) {
        check.Fail(field, Cat("--", field, " and --", std::string_view(names[j].first),
                              "-column are both ", Quoted(n), "; expected different columns"));
      }
    }
  }
  return check.Take();
}

void Validate(const TrackColumns& columns) { ThrowFirstProblem(Check(columns)); }

namespace {

// The lines of one file, in order: the header, then the rows (blank and '#' lines skipped).
class LineParser {
 public:
  LineParser(const std::string& source, const TrackColumns& columns)
      : source_(source), columns_(columns) {
    Validate(columns);
  }

  void Line(std::string_view line) {
    ++line_number_;
    if (Skipped(line)) return;
    SplitCells(line, &cells_);
    if (!builder_) {
      idx_ = FindColumns(cells_, columns_, {source_, line_number_});
      builder_.emplace(source_, columns_, idx_);
      return;
    }
    builder_->AddRow(cells_, line_number_);
  }

  std::vector<MeasuredTrack> Take() {
    if (!builder_) {
      throw InputError(FileLoc{source_, 0},
                       "no header; expected a header row naming the columns, then one sample a "
                       "row");
    }
    std::vector<MeasuredTrack> tracks = builder_->Take();
    if (tracks.empty()) {
      throw InputError(FileLoc{source_, line_number_},
                       "no samples after the header; expected one sample a row");
    }
    return tracks;
  }

 private:
  const std::string& source_;
  const TrackColumns& columns_;
  std::vector<std::string_view> cells_;
  ColumnIndex idx_;
  std::optional<TrackBuilder> builder_;
  int line_number_ = 0;
};

}  // namespace

std::vector<MeasuredTrack> ParseTrackCsv(std::string_view text, const std::string& source_name,
                                         const TrackColumns& columns) {
  LineParser parser(source_name, columns);
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    parser.Line(text.substr(pos, end - pos));
    pos = end + 1;
  }
  return parser.Take();
}

// Read in blocks (no copy of the whole file in memory: 40 MB for a million samples).
std::vector<MeasuredTrack> ReadTrackCsv(const std::string& path, const TrackColumns& columns) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(
        Cat(EscapeForMessage(path), ": cannot open; expected a readable track CSV file"));
  }
  LineParser parser(path, columns);
  std::vector<char> buffer(size_t{1} << 20);
  size_t have = 0;  // bytes in buffer not yet parsed
  while (true) {
    in.read(buffer.data() + have, static_cast<std::streamsize>(buffer.size() - have));
    const auto got = static_cast<size_t>(in.gcount());
    if (in.bad()) {
      throw InputError(
          Cat(EscapeForMessage(path), ": cannot read; expected a readable track CSV file"));
    }
    have += got;
    const std::string_view block(buffer.data(), have);
    size_t pos = 0;
    for (size_t end = block.find('\n'); end != std::string_view::npos;
         end = block.find('\n', pos)) {
      parser.Line(block.substr(pos, end - pos));
      pos = end + 1;
    }
    if (got == 0) {
      if (pos < have) parser.Line(block.substr(pos));
      break;
    }
    std::memmove(buffer.data(), buffer.data() + pos, have - pos);
    have -= pos;
    if (have == buffer.size()) buffer.resize(buffer.size() * 2);  // a line longer than the block
  }
  return parser.Take();
}

}  // namespace patlab::sim
