// Reading track CSV files for `patlab analyze` (analyze.h).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include "patlab/analysis/analyze.h"
#include "patlab/analysis/analyze_internal.h"
#include "patlab/core/error.h"
#include "patlab/io/csv.h"

namespace patlab::analysis {

namespace {

using detail::Cat;
using detail::Quoted;

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

// Adds the samples of the rows to their tracks.
class TrackBuilder {
 public:
  TrackBuilder(const std::string& source, const TrackColumns& columns, const ColumnIndex& idx)
      : source_(source), columns_(columns), idx_(idx) {}

  void AddRow(const io::CsvRecord& record) {
    const std::vector<std::string_view>& cells = record.cells;
    const int line = record.line;
    const FileLoc loc = record.Loc();
    if (static_cast<int>(cells.size()) < idx_.needed) {
      throw InputError(loc,
                       Cat("row has ", std::to_string(cells.size()), " cells; expected at least ",
                           std::to_string(idx_.needed), " as the header names them"));
    }
    MeasuredTrack& t = TrackOf(cells, line);
    const int64_t frame =
        io::CsvInteger(record, idx_.frame, columns_.frame, "an integer frame number");
    if (!t.frame.empty() && frame <= t.frame.back()) {
      throw InputError(
          loc, Cat(columns_.frame, " ", std::to_string(frame), " of subject ", Quoted(t.subject),
                   " run ", Quoted(t.run), " is not after ", std::to_string(t.frame.back()),
                   " (line ", std::to_string(last_line_[current_]),
                   "); expected increasing frame numbers within a subject and run"));
    }
    t.frame.push_back(frame);
    t.x.push_back(io::CsvNumber(record, idx_.x, columns_.x));
    t.y.push_back(io::CsvNumber(record, idx_.y, columns_.y));
    if (idx_.theta >= 0) t.theta.push_back(io::CsvNumber(record, idx_.theta, columns_.theta));
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
      // Subjects and runs reach the JSON manifest, whose writer throws on invalid UTF-8.
      for (const auto& [what, text] : {std::pair{"subject", subject}, std::pair{"run", run}}) {
        if (!IsValidUtf8(text)) {
          throw InputError(FileLoc{source_, line}, Cat(what, " ", Quoted(text),
                                                       " is not valid UTF-8; expected UTF-8 text"));
        }
      }
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
    if (n.empty() || n.find_first_of(",\n\r\"") != std::string::npos || io::CsvNeedsQuotes(n)) {
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

// The records of one file, in order: the header, then the rows. A track file may hold blank
// lines, '#' comment lines and blanks around its cells (docs/file-formats.md).
class TrackRecords {
 public:
  TrackRecords(const std::string& source, const TrackColumns& columns)
      : source_(source),
        columns_(columns),
        parser_(source, Options(), [this](const io::CsvRecord& r) { Record(r); }) {
    Validate(columns);
  }

  void Feed(std::string_view bytes) { parser_.Feed(bytes); }

  std::vector<MeasuredTrack> Take() {
    parser_.Finish();
    if (!builder_) {
      throw InputError(FileLoc{source_, 0},
                       "no header; expected a header row naming the columns, then one sample a "
                       "row");
    }
    std::vector<MeasuredTrack> tracks = builder_->Take();
    if (tracks.empty()) {
      throw InputError(FileLoc{source_, last_line_},
                       "no samples after the header; expected one sample a row");
    }
    return tracks;
  }

 private:
  static io::CsvReadOptions Options() {
    io::CsvReadOptions o;
    o.skip_blank_lines = o.skip_comment_lines = o.trim_blanks = true;
    return o;
  }

  void Record(const io::CsvRecord& record) {
    last_line_ = record.line;
    if (!builder_) {
      idx_ = FindColumns(record.cells, columns_, record.Loc());
      builder_.emplace(source_, columns_, idx_);
      return;
    }
    builder_->AddRow(record);
  }

  const std::string& source_;
  const TrackColumns& columns_;
  io::CsvParser parser_;
  ColumnIndex idx_;
  std::optional<TrackBuilder> builder_;
  int last_line_ = 0;
};

}  // namespace

std::vector<MeasuredTrack> ParseTrackCsv(std::string_view text, const std::string& source_name,
                                         const TrackColumns& columns) {
  TrackRecords records(source_name, columns);
  records.Feed(text);
  return records.Take();
}

// Read in blocks (no copy of the whole file in memory: 40 MB for a million samples).
std::vector<MeasuredTrack> ReadTrackCsv(const std::string& path, const TrackColumns& columns) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(
        Cat(EscapeForMessage(path), ": cannot open; expected a readable track CSV file"));
  }
  TrackRecords records(path, columns);
  std::vector<char> buffer(size_t{1} << 20);
  while (true) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto got = static_cast<size_t>(in.gcount());
    if (in.bad()) {
      throw InputError(
          Cat(EscapeForMessage(path), ": cannot read; expected a readable track CSV file"));
    }
    if (got == 0) break;
    records.Feed(std::string_view(buffer.data(), got));
  }
  return records.Take();
}

}  // namespace patlab::analysis
