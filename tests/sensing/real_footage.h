// Test helpers for the real table footage in ../shared/real: the hand-made labels
// (testdata/real_labels.txt), running the sensor over a clip, and scoring contacts against labels.
#pragma once

#include "test_paths.h"

#include "proxygrasp/sensing/calibration.h"
#include "proxygrasp/sensing/sensor.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace pg::real {

/// A circle in camera pixels.
struct Spot {
  double x = 0.0, y = 0.0, r = 0.0;
};

/// One labelled frame.
struct LabelledFrame {
  int index = 0;
  std::vector<Spot> tips;    // r unused
  std::vector<Spot> maybes;  // neither required nor false
  std::vector<Spot> hands;   // hand contacts other than fingertips: neither required nor false
};

/// One clip (video or still) and its labelled frames.
struct LabelledClip {
  std::string path;  // relative to the real data folder
  double cmPerPixel = 0.15;
  std::vector<Spot> hotspots;
  std::vector<std::pair<int, int>> clear;  // frame ranges [first, last] with nothing on the table
  std::vector<LabelledFrame> frames;
  bool IsClear(int frame) const {
    for (const auto& [first, last] : clear)
      if (frame >= first && frame <= last) return true;
    return false;
  }
  bool IsStill() const {
    const std::string ext = std::filesystem::path(path).extension().string();
    return ext == ".jpeg" || ext == ".jpg" || ext == ".png";
  }
  int LastFrame() const { return frames.empty() ? 0 : frames.back().index; }
};

/// The real footage folder: $PROXYGRASP_REAL_DATA, else ../shared/real beside the project, else
/// /work/shared/real; "" when none exists.
inline std::string RealDataDir() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("PROXYGRASP_REAL_DATA")) candidates.push_back(env);
  candidates.push_back(std::string(pg::test::SourceDir()) + "/../shared/real");
  candidates.push_back(std::string(pg::test::SourceDir()) + "/../../shared/real");
  for (const std::string& c : candidates)
    if (std::filesystem::is_directory(c)) return c;
  return "";
}

/// Reads testdata/real_labels.txt (format in its header).
inline std::vector<LabelledClip> ReadLabels(const std::string& file) {
  std::vector<LabelledClip> clips;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    std::string key;
    if (!(words >> key)) continue;
    // a circle's line: X Y R (a tip's: X Y, r unused)
    const auto spot = [&words](bool withRadius) {
      Spot s;
      words >> s.x >> s.y;
      if (withRadius) words >> s.r;
      return s;
    };
    if (key == "clip") {
      clips.emplace_back();
      words >> clips.back().path;
    } else if (key == "scale") {
      words >> clips.back().cmPerPixel;
    } else if (key == "hotspot") {
      clips.back().hotspots.push_back(spot(true));
    } else if (key == "clear") {
      std::pair<int, int> range;
      words >> range.first >> range.second;
      clips.back().clear.push_back(range);
    } else if (key == "frame") {
      clips.back().frames.emplace_back();
      words >> clips.back().frames.back().index;
    } else if (key == "tip") {
      clips.back().frames.back().tips.push_back(spot(false));
    } else if (key == "maybe") {
      clips.back().frames.back().maybes.push_back(spot(true));
    } else if (key == "hand") {
      clips.back().frames.back().hands.push_back(spot(true));
    }
  }
  return clips;
}

/// The table a clip's camera sees: the linear calibration of an image whose pixels are
/// cmPerPixel wide (the scale of each table, read from its fingertip size; see real_labels.txt).
inline TableParams ClipTable(const LabelledClip& clip, cv::Size size) {
  TableParams t;
  t.width = size.width * clip.cmPerPixel;
  t.height = size.height * clip.cmPerPixel;
  return t;
}

/// Runs the sensor with `params` over a clip from its first frame to `lastFrame` (a still: its
/// one frame), calling `each(index, frame, sensor)` after every frame. The clip's frames come as
/// the camera delivered them (colour for videos and JPEG stills). A `background` (CV_8UC1 of the
/// clip's size) is the calibration's clear-table frame; without one the sensor estimates it.
/// False when the clip cannot be read.
inline bool RunClip(const std::string& dir, const LabelledClip& clip, const SensingParams& params,
                    int lastFrame,
                    const std::function<void(int, const ContourFrame&, const Sensor&)>& each,
                    const cv::Mat& background = cv::Mat()) {
  const std::string path = dir + "/" + clip.path;
  Sensor sensor;
  if (clip.IsStill()) {
    // a still is sensed on its own (SensingParams::stills)
    const cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
    if (image.empty()) return false;
    SensingParams still = params;
    still.stills = true;
    if (sensor.Configure(still, ClipTable(clip, image.size()),
                         LinearCalibration(image.size(), ClipTable(clip, image.size())), path))
      return false;
    Result<ContourFrame> r = sensor.Step(image, 0, 0.0);
    if (!r) return false;
    each(0, r.value(), sensor);
    return true;
  }
  cv::VideoCapture video(path);
  if (!video.isOpened()) return false;
  double fps = video.get(cv::CAP_PROP_FPS);
  if (!(fps > 0.0)) fps = 30.0;
  cv::Mat frame;
  for (int i = 0; i <= lastFrame && video.read(frame); ++i) {
    if (i == 0) {
      Calibration calibration = LinearCalibration(frame.size(), ClipTable(clip, frame.size()));
      calibration.background = background;
      if (sensor.Configure(params, ClipTable(clip, frame.size()), calibration, path)) return false;
    }
    Result<ContourFrame> r = sensor.Step(frame, i, i / fps);
    if (!r) return false;
    each(i, r.value(), sensor);
  }
  return true;
}

/// Runs one sensor for each of `starts` (frame indices, ascending) over a video clip, in one pass
/// over its frames: the sensor started at a frame sees no frame before it, as a sensor switched
/// on then would, and runs to `lastFrame`, working the high-pass out only where a contact can be,
/// as the pipeline's sensor does. Calls `each(k, index, frame, sensor)` for sensor k
/// after each of its frames. A still is one frame: every start but 0 is passed over. False when
/// the clip cannot be read.
inline bool RunClipFromStarts(
    const std::string& dir, const LabelledClip& clip, const SensingParams& params,
    const std::vector<int>& starts, int lastFrame,
    const std::function<void(size_t, int, const ContourFrame&, const Sensor&)>& each) {
  const std::string path = dir + "/" + clip.path;
  if (clip.IsStill()) {
    return RunClip(dir, clip, params, 0, [&](int i, const ContourFrame& f, const Sensor& s) {
      for (size_t k = 0; k < starts.size(); ++k)
        if (starts[k] == 0) each(k, i, f, s);
    });
  }
  cv::VideoCapture video(path);
  if (!video.isOpened()) return false;
  double fps = video.get(cv::CAP_PROP_FPS);
  if (!(fps > 0.0)) fps = 30.0;
  std::vector<Sensor> sensors(starts.size());
  for (Sensor& s : sensors) s.SetWholeStages(false);  // as the pipeline's (the same contours)
  cv::Mat frame;
  for (int i = 0; i <= lastFrame && video.read(frame); ++i) {
    for (size_t k = 0; k < starts.size(); ++k) {
      if (i < starts[k]) continue;
      if (i == starts[k]) {
        const TableParams table = ClipTable(clip, frame.size());
        if (sensors[k].Configure(params, table, LinearCalibration(frame.size(), table), path))
          return false;
      }
      Result<ContourFrame> r = sensors[k].Step(frame, i, i / fps);
      if (!r) return false;
      each(k, i, r.value(), sensors[k]);
    }
  }
  return true;
}

/// The frame rate of a video clip (30 when it does not say; 0 when it cannot be opened).
inline double ClipFrameRate(const std::string& dir, const LabelledClip& clip) {
  cv::VideoCapture video(dir + "/" + clip.path);
  if (!video.isOpened()) return 0.0;
  const double fps = video.get(cv::CAP_PROP_FPS);
  return fps > 0.0 ? fps : 30.0;
}

/// True when the contact's outline holds the camera point, or passes within `slackPx` of it.
inline bool Holds(const Blob& blob, const Sensor& sensor, const Spot& at, double slackPx) {
  const Vec2 p = sensor.model().CameraToTable(Vec2(at.x, at.y));
  std::vector<cv::Point2f> outline;
  outline.reserve(static_cast<size_t>(blob.contour.cols()));
  for (Eigen::Index k = 0; k < blob.contour.cols(); ++k)
    outline.emplace_back(static_cast<float>(blob.contour(0, k)),
                         static_cast<float>(blob.contour(1, k)));
  const double cmPerPx = sensor.model().CmPerPixel(Vec2(at.x, at.y));
  return cv::pointPolygonTest(outline,
                              cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y())),
                              true) >= -slackPx * cmPerPx;
}

/// The camera pixel of a contact's centroid.
inline Vec2 CentroidPixel(const Blob& blob, const Sensor& sensor) {
  return sensor.model().TableToCamera(blob.centroid);
}

/// Scores of labelled frames.
struct Score {
  int frames = 0;
  int tips = 0;        // labelled fingertips
  int found = 0;       // labelled fingertips some contact holds
  int contacts = 0;    // contacts in labelled frames
  int unmatched = 0;   // contacts that hold no fingertip and lie in no "maybe" or "hand" circle
  int offTips = 0;     // contacts that hold no fingertip and lie in no "maybe" circle (hands not
                       // counted: the figure of the labels before their hand circles)
  std::string misses;  // where, for messages
};

/// Label reading precision (real_labels.txt), px: a contact passing within this of a fingertip
/// label holds it, and a centroid within this outside a circle's radius lies in the circle.
inline constexpr double kLabelSlackPx = 3.0;

/// True when a camera point lies in a maybe or hand circle. The circles were read off the same
/// exports and grid as the fingertips, so their edge is known to the same precision: a centroid
/// within kLabelSlackPx outside the drawn radius lies in the circle.
inline bool InCircle(const Vec2& point, const Spot& circle) {
  return std::hypot(point.x() - circle.x, point.y() - circle.y) <= circle.r + kLabelSlackPx;
}

/// Scores one labelled frame's contacts.
inline void ScoreFrame(const LabelledClip& clip, const LabelledFrame& labels,
                       const ContourFrame& frame, const Sensor& sensor, Score& score) {
  ++score.frames;
  for (const Spot& tip : labels.tips) {
    ++score.tips;
    bool found = false;
    for (const Blob& b : frame.blobs) found = found || Holds(b, sensor, tip, kLabelSlackPx);
    if (found)
      ++score.found;
    else
      score.misses += " missed " + clip.path + "@" + std::to_string(labels.index) + "(" +
                      std::to_string(static_cast<int>(tip.x)) + "," +
                      std::to_string(static_cast<int>(tip.y)) + ")";
  }
  for (const Blob& b : frame.blobs) {
    ++score.contacts;
    bool matched = false;
    for (const Spot& tip : labels.tips) matched = matched || Holds(b, sensor, tip, kLabelSlackPx);
    const Vec2 c = CentroidPixel(b, sensor);
    for (const Spot& m : labels.maybes) matched = matched || InCircle(c, m);
    if (!matched) ++score.offTips;
    for (const Spot& h : labels.hands) matched = matched || InCircle(c, h);
    if (!matched) {
      ++score.unmatched;
      score.misses += " extra " + clip.path + "@" + std::to_string(labels.index) + "(" +
                      std::to_string(static_cast<int>(c.x())) + "," +
                      std::to_string(static_cast<int>(c.y())) + ")";
    }
  }
}

/// Scores the labelled frames of one clip as RunClip delivers its frames in order: call it with
/// each frame; unlabelled frames are passed over.
struct ClipScorer {
  explicit ClipScorer(const LabelledClip& scored) : clip(scored) {}
  const LabelledClip& clip;
  Score score;
  size_t next = 0;
  void operator()(int index, const ContourFrame& frame, const Sensor& sensor) {
    while (next < clip.frames.size() && clip.frames[next].index < index) ++next;
    if (next < clip.frames.size() && clip.frames[next].index == index)
      ScoreFrame(clip, clip.frames[next], frame, sensor, score);
  }
};

}  // namespace pg::real
