// Holding robot IDs through short ambiguities (id_hold.h).
#include "patlab/live/id_hold.h"

#include <algorithm>
#include <tuple>

namespace patlab::live {

std::vector<OptionsProblem> Check(const IdHoldOptions& options) {
  return OptionsChecker()
      .Positive("radius_mm", options.radius_mm, "mm")
      .IntegerInRange("stable_frames", options.stable_frames, 1, 1 << 20)
      .IntegerInRange("switch_frames", options.switch_frames, 1, 1 << 20)
      .Take();
}

void Validate(const IdHoldOptions& options) { ThrowFirstProblem(Check(options)); }

IdHolder::IdHolder(const IdHoldOptions& options) : options_(options) { Validate(options); }

namespace {

// Each robot's track (index into `tracks`, or -1): nearest pairs within `radius_mm` first, ties by
// index, so the result does not depend on the sort.
std::vector<int> NearestMatches(const std::vector<SslRobot>& robots,
                                const std::vector<Vec2>& tracks, double radius_mm) {
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t i = 0; i < robots.size(); ++i) {
    const Vec2 p(robots[i].x_mm, robots[i].y_mm);
    for (size_t j = 0; j < tracks.size(); ++j) {
      const double d = (p - tracks[j]).norm();
      if (d <= radius_mm) pairs.emplace_back(d, i, j);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> track_of(robots.size(), -1);
  std::vector<bool> matched(tracks.size(), false);
  for (const auto& [d, i, j] : pairs) {
    if (track_of[i] >= 0 || matched[j]) continue;
    track_of[i] = static_cast<int>(j);
    matched[j] = true;
  }
  return track_of;
}

}  // namespace

int IdHolder::Apply(SslDetection* detection) {
  if (!options_.enabled) return 0;
  return ApplyTeam(&detection->robots_yellow, &yellow_) +
         ApplyTeam(&detection->robots_blue, &blue_);
}

int IdHolder::ApplyTeam(std::vector<SslRobot>* robots, std::vector<Track>* tracks) const {
  std::vector<Vec2> positions;
  for (const Track& t : *tracks) positions.push_back(t.position_mm);
  const std::vector<int> track_of = NearestMatches(*robots, positions, options_.radius_mm);
  std::vector<bool> matched(tracks->size(), false);
  for (const int j : track_of) {
    if (j >= 0) matched[static_cast<size_t>(j)] = true;
  }
  // IDs this frame reads or has given: a held ID never duplicates one of them.
  std::vector<int> taken;
  for (const SslRobot& r : *robots) {
    if (r.robot_id >= 0) taken.push_back(r.robot_id);
  }
  const auto is_taken = [&taken](int id) {
    return std::find(taken.begin(), taken.end(), id) != taken.end();
  };
  int held = 0;
  const size_t old_tracks = tracks->size();
  for (size_t i = 0; i < robots->size(); ++i) {
    SslRobot& robot = (*robots)[i];
    const int read = robot.robot_id;
    if (track_of[i] < 0) {
      Track track;
      track.position_mm = Vec2(robot.x_mm, robot.y_mm);
      track.id = read;
      track.reads = read >= 0 ? 1 : 0;
      tracks->push_back(track);
      continue;
    }
    Track& t = (*tracks)[static_cast<size_t>(track_of[i])];
    t.position_mm = Vec2(robot.x_mm, robot.y_mm);
    t.unmatched = 0;
    if (read >= 0 && read == t.id) {
      ++t.reads;
      t.missed = 0;
      t.other_id = -1;
      t.other_reads = 0;
      continue;
    }
    ++t.missed;
    if (read >= 0) {
      t.other_reads = read == t.other_id ? t.other_reads + 1 : 1;
      t.other_id = read;
    }
    const bool stable = t.id >= 0 && t.reads >= options_.stable_frames;
    if (stable && t.missed < options_.switch_frames && !is_taken(t.id)) {
      robot.robot_id = t.id;
      robot.id_held = true;
      taken.push_back(t.id);
      ++held;
      continue;
    }
    // The frame's own reading goes out and the track takes it up: another ID with the frames it
    // was read in since the track's ID was last read; an unknown one once the track's ID has been
    // missed switch_frames times, or while it was not yet stable.
    if (read >= 0) {
      t = Track{t.position_mm, read, t.other_reads, 0, -1, 0, 0};
    } else if (t.missed >= options_.switch_frames || !stable) {
      t = Track{t.position_mm, stable ? -1 : t.id, stable ? 0 : t.reads, 0, -1, 0, 0};
    }
  }
  // Tracks not seen in this frame age; after switch_frames such frames they are forgotten.
  size_t kept = 0;
  for (size_t j = 0; j < tracks->size(); ++j) {
    Track& t = (*tracks)[j];
    if (j < old_tracks && !matched[j] && ++t.unmatched >= options_.switch_frames) continue;
    (*tracks)[kept++] = t;
  }
  tracks->resize(kept);
  return held;
}

}  // namespace patlab::live
