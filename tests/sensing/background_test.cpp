// The background a sensor starts from (src/sensing/background.cpp) and what it gives from the
// first frame: real clips started at every 5 s mark, each still on its own, and the synthetic
// camera started with hands down, with a first touch on a dim table, and with the shadows and
// dark spots that must leave no contact (docs/sensing.md, "From the first frame").
#include "test_paths.h"

#include "proxygrasp/core/units.h"
#include "proxygrasp/sensing/sensor.h"
#include "proxygrasp/sensing/synthetic_camera.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "sensing/real_footage.h"

namespace pg {
namespace {

// ---- the synthetic camera started with hands down, a dim table's first touch, shadows ----

// Camera seeds 1 to 6 (issue 45); under the sanitizers, ten times slower, seed 1 alone: the code
// it runs is the same for every seed, and the sanitizer phase of CI is near its time budget.
#if defined(__SANITIZE_ADDRESS__)
constexpr int kLastSeed = 1;
#else
constexpr int kLastSeed = 6;
#endif

// a sensor on a synthetic camera with its true calibration and no background: estimated
struct Start {
  explicit Start(const SyntheticCameraParams& p) : camera(p, table) {
    EXPECT_FALSE(sensor.Configure(SensingParams(), table, CalibrationFromModel(camera.model())));
  }
  TableParams table;
  SyntheticCamera camera;
  Sensor sensor;
};

ContactShape Shape(ShapeKind kind, Vec2 pos, double radius = 0.8) {
  ContactShape s;
  s.kind = kind;
  s.pose.pos = pos;
  s.radius = radius;
  return s;
}

// true when some contact's outline holds the table point
bool Covered(const ContourFrame& f, Vec2 p) {
  for (const Blob& b : f.blobs) {
    std::vector<cv::Point2f> outline;
    for (Eigen::Index k = 0; k < b.contour.cols(); ++k)
      outline.emplace_back(static_cast<float>(b.contour(0, k)),
                           static_cast<float>(b.contour(1, k)));
    if (cv::pointPolygonTest(
            outline, cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y())), false) >= 0)
      return true;
  }
  return false;
}

// Hands down at the start (a flat hand and a five-finger hand on the table from the first frame),
// lying still for 0.5 s, then sliding away at `speed`, to 2.5 s: the frames each hand's centre is
// in no contact, from 0.2 s on, and the contacts off both hands.
struct HandsDown {
  int firstFlat = -1, firstFive = -1;  // the first frame each is found
  int missed = 0;                      // hand-frames missed after 0.2 s
  int phantoms = 0;
};
HandsDown RunHandsDown(int seed, double speed, int frames) {
  SyntheticCameraParams p;
  p.seed = seed;
  Start s(p);
  HandsDown h;
  const Vec2 flat0(18.0, 20.0), five0(40.0, 20.0);
  for (int i = 0; i < frames; ++i) {
    const double t = i / 60.0;
    const double shift = std::max(0.0, t - 0.5) * speed;  // cm
    ContactShape flat = Shape(ShapeKind::kHandFlat, flat0 + Vec2(shift, 0.0));
    ContactShape five = Shape(ShapeKind::kHandFive, five0 + Vec2(shift, 0.0));
    flat.scale = five.scale = 0.8;
    const ContactShape shapes[] = {flat, five};
    Result<ContourFrame> r = s.sensor.Step(s.camera.Render(shapes), i, t);
    EXPECT_TRUE(r) << r.error().Format();
    if (!r) return h;
    const bool flatSeen = Covered(r.value(), flat.pose.pos);
    const bool fiveSeen = Covered(r.value(), five.pose.pos);
    if (flatSeen && h.firstFlat < 0) h.firstFlat = i;
    if (fiveSeen && h.firstFive < 0) h.firstFive = i;
    if (t > 0.2) h.missed += (flatSeen ? 0 : 1) + (fiveSeen ? 0 : 1);
    for (const Blob& b : r.value().blobs)
      h.phantoms += ShapeDistance(flat, b.centroid) > 1.0 && ShapeDistance(five, b.centroid) > 1.0;
  }
  return h;
}

// Hands down at the start, still for 0.5 s, then sliding away at 10 cm/s: each is found from the
// first frame, against the spatial estimate. The warm-up (0.2 s) takes them in as it does a hot
// spot, but each ends in fingertips (HoldOutHandLike: the five-finger hand's five, the flat
// hand's finger ends and thumb, 3 or more 1.5 cm apart, each a hand-sized piece): held out from
// the frame after the warm-up, each stays a contact while it lies still (to 0.7 s, the warm-up
// and background_still) and from 0.5 s its motion keeps it out (TrackStillRegions), its centre
// too, which still lies where it lay. So no frame misses either: 0 of the 2 x 138 hand-frames
// after 0.2 s. Before the fingertips were looked for, the 36 of (0.2, 0.5] s were missed.
TEST(FirstFrames, HandsDownAtTheStartAreFoundAtOnce) {
  for (int seed = 1; seed <= kLastSeed; ++seed) {
    const HandsDown h = RunHandsDown(seed, 10.0, 150);
    std::printf(
        "seed %d: flat hand first found at frame %d, five-finger hand at %d; after 0.2 s %d of "
        "276 hand-frames missed; %d contacts off the hands\n",
        seed, h.firstFlat, h.firstFive, h.missed, h.phantoms);
    // "found within 0.2 s" (12 frames at 60 Hz)
    EXPECT_GE(h.firstFlat, 0);
    EXPECT_LE(h.firstFlat, 12);
    EXPECT_GE(h.firstFive, 0);
    EXPECT_LE(h.firstFive, 12);
    EXPECT_EQ(h.missed, 0) << "seed " << seed;
    EXPECT_EQ(h.phantoms, 0) << "seed " << seed;
  }
}

// The same hands sliding away slowly, at 2 cm/s: a slow hand shows the table first only in its
// blurred edge, where the region that moved read too little of the hand's contrast and kept
// its inside in (84 to 151 of 212 hand-frames missed before the fingertips were looked for).
// Held out from the warm-up with its fingertips' contrast, it is found on every frame.
TEST(FirstFrames, SlowHandsDownAtTheStartAreFound) {
  for (int seed = 1; seed <= kLastSeed; ++seed) {
    const HandsDown h = RunHandsDown(seed, 2.0, 150);
    std::printf("seed %d: after 0.2 s %d of 276 hand-frames missed; %d contacts off the hands\n",
                seed, h.missed, h.phantoms);
    EXPECT_EQ(h.missed, 0) << "seed " << seed;
    EXPECT_EQ(h.phantoms, 0) << "seed " << seed;
  }
}

// A bright glow of the table's own (an illuminator's hot spot, 60 grey, deviation 2 cm) added to
// a frame.
cv::Mat WithHotSpot(const Start& s, cv::Mat frame, Vec2 at) {
  for (int v = 0; v < frame.rows; ++v) {
    for (int u = 0; u < frame.cols; ++u) {
      const Vec2 t = s.camera.model().CameraToTable(Vec2(u, v));
      uint8_t& g = frame.at<uint8_t>(v, u);
      g = cv::saturate_cast<uint8_t>(g + 60.0 * std::exp(-(t - at).squaredNorm() / 8.0));
    }
  }
  return frame;
}

// A hand that lay still through the warm-up, moved 2 cm (0.2 s at 10 cm/s) and stopped, on the
// table until 7 s (past the settling, 5.2 s): found on every frame from the one it starts to move
// on, its centre too (which lies where it lay); the part still over where it lay stays out of the
// background, as the hand covers clear table beyond it. A hot spot beside it, static from the
// start, never gives a contact.
TEST(FirstFrames, AHandThatMovedAndStoppedStaysFound) {
  for (int seed = 1; seed <= kLastSeed; ++seed) {
    SyntheticCameraParams p;
    p.seed = seed;
    Start s(p);
    const Vec2 start(20.0, 20.0), spot(45.0, 25.0);
    int missed = 0, phantoms = 0, frames = 0;
    for (int i = 0; i / 30.0 < 7.0; ++i) {
      const double t = i / 30.0;
      const double shift = std::clamp(t - 0.5, 0.0, 0.2) * 10.0;  // cm
      ContactShape flat = Shape(ShapeKind::kHandFlat, start + Vec2(shift, 0.0));
      flat.scale = 0.8;
      const ContactShape shapes[] = {flat};
      Result<ContourFrame> r = s.sensor.Step(WithHotSpot(s, s.camera.Render(shapes), spot), i, t);
      ASSERT_TRUE(r) << r.error().Format();
      if (t > 0.5) {
        ++frames;
        missed += Covered(r.value(), flat.pose.pos) ? 0 : 1;
      }
      for (const Blob& b : r.value().blobs) phantoms += ShapeDistance(flat, b.centroid) > 1.0;
    }
    std::printf("seed %d: %d of %d frames from 0.5 s missed the hand; %d contacts off it\n", seed,
                missed, frames, phantoms);
    EXPECT_EQ(missed, 0) << "seed " << seed;
    EXPECT_EQ(phantoms, 0) << "seed " << seed;
  }
}

// A hand lying perfectly still from the start, with a hot spot beside it: the warm-up takes both
// in; the hand ends in fingertips and is held out (HoldOutHandLike), the spot (a round glow, no
// finger end on it) is not. So the hand is found on every frame until background_still (0.5 s)
// after the warm-up (0.2 s), and the spot never. Then, not having moved, the hand goes back in as
// any still region does (a hand-shaped mark of the table would otherwise stay a contact for good):
// the limit docs/sensing.md names.
TEST(FirstFrames, AStillHandIsFoundUntilBackgroundStill) {
  for (int seed = 1; seed <= kLastSeed; ++seed) {
    SyntheticCameraParams p;
    p.seed = seed;
    Start s(p);
    const Vec2 spot(45.0, 25.0);
    ContactShape five = Shape(ShapeKind::kHandFive, {20.0, 20.0});
    five.scale = 0.9;
    const ContactShape shapes[] = {five};
    int missed = 0, phantoms = 0, lastFound = -1;
    for (int i = 0; i < 90; ++i) {
      const double t = i / 60.0;
      Result<ContourFrame> r = s.sensor.Step(WithHotSpot(s, s.camera.Render(shapes), spot), i, t);
      ASSERT_TRUE(r) << r.error().Format();
      const bool seen = Covered(r.value(), five.pose.pos);
      if (seen) lastFound = i;
      if (t < 0.7 - 1e-9) missed += seen ? 0 : 1;
      for (const Blob& b : r.value().blobs) phantoms += ShapeDistance(five, b.centroid) > 1.0;
    }
    std::printf(
        "seed %d: %d of 42 frames to 0.7 s missed the hand, last found at frame %d; %d "
        "contacts off it\n",
        seed, missed, lastFound, phantoms);
    EXPECT_EQ(missed, 0) << "seed " << seed;
    EXPECT_EQ(phantoms, 0) << "seed " << seed;
  }
}

// A dim table: camera noise 0.7 grey, touches `contrast` grey above the table, no halo.
SyntheticCameraParams DimTable(int seed, double contrast) {
  SyntheticCameraParams p;
  p.seed = seed;
  p.noise = 0.7;
  p.contactLevel = p.background + contrast;
  p.haloLevel = 0.0;
  return p;
}

// A dim table like t2.avi's (camera noise 0.7 grey), clear for its first second, then one
// fingertip lands with a contrast of 8 grey: found within 0.2 s of landing, and every frame after;
// no contact before it. The level then: 5 noise deviations (sigma reads about 0.86, see
// Sensor.AdaptiveLevelFindsADimTablesTouchesAndKeepsTheThresholdOnABrightOne) = 4.3 grey, under
// the touch's high-passed peak of 8 x 0.84 = 6.7 grey; 0.3 of that is 2 grey, under the floor.
TEST(FirstFrames, FirstTouchOnADimTableIsFoundAtOnce) {
  for (int seed = 1; seed <= kLastSeed; ++seed) {
    Start s(DimTable(seed, 8.0));
    const ContactShape tip = Shape(ShapeKind::kCircle, {30.0, 22.0});
    int first = -1, missedAfter = 0, phantoms = 0;
    for (int i = 0; i < 180; ++i) {
      const bool down = i >= 60;
      const std::vector<ContactShape> shapes =
          down ? std::vector<ContactShape>{tip} : std::vector<ContactShape>{};
      Result<ContourFrame> r = s.sensor.Step(s.camera.Render(shapes), i, i / 60.0);
      ASSERT_TRUE(r);
      const bool seen = Covered(r.value(), tip.pose.pos);
      if (down && seen && first < 0) first = i;
      if (down && first >= 0 && !seen) ++missedAfter;
      for (const Blob& b : r.value().blobs)
        phantoms += !down || (b.centroid - tip.pose.pos).norm() > 1.0;
    }
    std::printf(
        "seed %d: the touch at frame 60 first found at frame %d (%.3f s); %d frames "
        "missed after; %d other contacts; level %.2f\n",
        seed, first, (first - 60) / 60.0, missedAfter, phantoms, s.sensor.LastThreshold());
    EXPECT_GE(first, 60) << "seed " << seed;
    EXPECT_LE(first, 72) << "seed " << seed;
    EXPECT_EQ(missedAfter, 0) << "seed " << seed;
    EXPECT_EQ(phantoms, 0) << "seed " << seed;
  }
}

// A shadow or dark spot: `depth` grey darker over a disc `diameter` cm across (edges blurred over
// 0.3 cm), from `from` to `to` s; the frame `t` s in.
cv::Mat Shadowed(const cv::Mat& frame, const cv::Mat& mask, double depth) {
  cv::Mat f;
  frame.convertTo(f, CV_32F);
  f -= depth * mask;
  cv::Mat out;
  f.convertTo(out, CV_8UC1);
  return out;
}
// a mask over the camera image, `profile` of each pixel's table distance (cm) from `at`
template <typename Profile>
cv::Mat MaskAround(const Start& s, Vec2 at, Profile profile) {
  cv::Mat mask(s.camera.params().height, s.camera.params().width, CV_32F);
  for (int v = 0; v < mask.rows; ++v) {
    for (int u = 0; u < mask.cols; ++u) {
      const double d = (s.camera.model().CameraToTable(Vec2(u, v)) - at).norm();
      mask.at<float>(v, u) = static_cast<float>(profile(d));
    }
  }
  return mask;
}
cv::Mat DiscMask(const Start& s, Vec2 at, double diameter) {
  return MaskAround(s, at,
                    [&](double d) { return 0.5 * (1.0 - std::tanh((d - 0.5 * diameter) / 0.3)); });
}

// A hand hovering over a dim table from the first frame (noise 0.7 grey, as in
// FirstTouchOnADimTableIsFoundAtOnce), its glow 10 grey at its centre and falling off as a
// Gaussian of deviation 8 cm: wider than a hand, so the spatial estimate keeps most of it under
// its 10 cm opening (at least e^(-5^2 / 2 / 8^2) = 0.82 of it, 8.2 grey). The hand lifts away
// from 1 to 2 s, hovers there again to 3 s and then leaves; at 3.2 s a fingertip lands where it
// hovered, 12 grey above the table. While the background settles it comes down where the frame
// reads more than 3 noise deviations darker, to within them of the frame (2.1 grey): over the
// table the hand uncovered, 2 grey above it. Before 2026-11-30 never below the first frame's
// spatial estimate less 2 deviations: 5 grey above the table there (seed 1, measured), and the
// touch's high-passed peak (about 0.84 of 12 - 5 = 5.9) stood under the level (6.3), missed to the
// end of the run. The floor now comes down with the spatial estimates of the settling's frames
// (every 0.25 s, LowerSettleFloor): the touch stands about 0.84 x 10 = 8.4 over the background
// and is found on the frame it lands (within 0.2 s asked), with no contact before it or
// elsewhere (the glow's high-passed rest is well under the level).
TEST(FirstFrames, AHoveringHandsGlowAtTheStartIsLeftWhereTheTableShowsWhileItSettles) {
  for (int seed = 1; seed <= kLastSeed; ++seed) {
    Start s(DimTable(seed, 12.0));
    const Vec2 at(30.0, 22.0);
    const cv::Mat glow =
        MaskAround(s, at, [](double d) { return std::exp(-d * d / (2.0 * 8.0 * 8.0)); });
    const ContactShape tip = Shape(ShapeKind::kCircle, at);
    int first = -1, phantoms = 0;
    for (int i = 0; i < 240; ++i) {
      const double t = i / 60.0;
      const bool hovering = t < 1.0 || (t >= 2.0 && t < 3.0), down = t >= 3.2;
      const std::vector<ContactShape> shapes =
          down ? std::vector<ContactShape>{tip} : std::vector<ContactShape>{};
      cv::Mat frame = s.camera.Render(shapes);
      if (hovering) frame = Shadowed(frame, glow, -10.0);
      Result<ContourFrame> r = s.sensor.Step(frame, i, t);
      ASSERT_TRUE(r);
      if (down && first < 0 && Covered(r.value(), tip.pose.pos)) first = i;
      for (const Blob& b : r.value().blobs) phantoms += !down || (b.centroid - at).norm() > 1.0;
    }
    std::printf("seed %d: the touch at frame 192 first found at frame %d; %d other contacts\n",
                seed, first, phantoms);
    EXPECT_GE(first, 192) << "seed " << seed;
    EXPECT_LE(first, 204) << "seed " << seed;
    EXPECT_EQ(phantoms, 0) << "seed " << seed;
  }
}

// The empty table, hovering hands' shadows and dark spots, from the start, seeds 1 to 6: no
// contact at any frame. The shadows: 60 grey deep and 2 cm across for 2 s (a hand hovering in
// ambient light; it made the faster dark learning of 2026-11-27 fail), 20 grey for 2 s, present
// from the first frame or landing at 1 s (while the background settles, when it comes down fast
// where the frame is darker: never below the first frame's spatial estimate) or at 8 s; wider
// dark spots (4 cm, 30 and 60 grey, 2 s) and a shallow one (20 grey, 10 s). Each run lasts until
// 3 s after the shadow goes: a spot learned darker than the table reads as a touch when it goes.
TEST(FirstFrames, EmptyTableShadowsAndDarkSpotsLeaveNoContact) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "too slow under the sanitizers (48 runs, 11 s in Release): run in Release";
#endif
  struct Case {
    double depth, diameter, from, duration;
  };
  const Case cases[] = {{0.0, 2.0, 0.0, 0.0},  {60.0, 2.0, 0.0, 2.0}, {60.0, 2.0, 1.0, 2.0},
                        {60.0, 2.0, 8.0, 2.0}, {20.0, 2.0, 1.0, 2.0}, {30.0, 4.0, 1.0, 2.0},
                        {60.0, 4.0, 1.0, 2.0}, {20.0, 2.0, 1.0, 10.0}};
  int runs = 0;
  for (const Case& c : cases) {
    // the spot's mask is the same for every seed (the camera's geometry is)
    const cv::Mat mask = DiscMask(Start(SyntheticCameraParams()), {30.0, 22.0}, c.diameter);
    for (int seed = 1; seed <= kLastSeed; ++seed) {
      SyntheticCameraParams p;
      p.seed = seed;
      Start s(p);
      const double end = c.from + c.duration + 3.0;
      int contacts = 0;
      // 20 Hz keeps the test short; the learning is paced by time, not frames
      for (int i = 0; i / 20.0 < end; ++i) {
        const double t = i / 20.0;
        cv::Mat frame = s.camera.Render({});
        if (c.depth > 0.0 && t >= c.from && t < c.from + c.duration)
          frame = Shadowed(frame, mask, c.depth);
        Result<ContourFrame> r = s.sensor.Step(frame, i, t);
        ASSERT_TRUE(r);
        contacts += static_cast<int>(r.value().blobs.size());
      }
      EXPECT_EQ(contacts, 0) << "seed " << seed << ": " << c.depth << " grey, " << c.diameter
                             << " cm, from " << c.from << " s for " << c.duration << " s";
      ++runs;
    }
  }
  EXPECT_EQ(runs, 8 * kLastSeed);
}

// ---- real table footage (../shared/real), started at every 5 s mark ----

constexpr const char* kNoRealData =
    "../shared/real is absent (a clone of the project alone): no real footage to test on; set "
    "PROXYGRASP_REAL_DATA to its folder";

// the scores of one clip started at its 5 s marks
struct MarkScores {
  int hotClearHits = 0;     // contacts at a hot spot on clear frames, 1 s or more after a start
  int hotLongest = 0;       // frames, the longest a contact stayed at a hot spot after 1 s
  std::vector<int> starts;  // frames
  std::vector<real::Score> scores;  // per start
  real::Score total;
};

// Starts a sensor at every `every`-th 5 s mark of the clip (from mark `first`) that has a labelled
// frame at least 0.2 s after it, and scores each on the labelled frames from 0.2 s after its
// start to the end.
MarkScores ScoreFromMarks(const std::string& dir, const real::LabelledClip& clip,
                          const SensingParams& params, int every = 1, int first = 0) {
  MarkScores m;
  const double fps = clip.IsStill() ? 30.0 : real::ClipFrameRate(dir, clip);
  EXPECT_GT(fps, 0.0) << clip.path;
  if (!(fps > 0.0)) return m;
  const int settle = static_cast<int>(std::ceil(0.2 * fps));
  for (int mark = first;; mark += every) {
    const int start = static_cast<int>(std::lround(5.0 * mark * fps));
    if (clip.IsStill() && start > 0) break;
    if (start + settle > clip.LastFrame() && !(clip.IsStill() && start == 0)) break;
    m.starts.push_back(start);
  }
  m.scores.resize(m.starts.size());
  std::vector<size_t> next(m.starts.size(), 0);
  // t2.avi's hot spots, as RealFootage.DefaultsFindNoContactAtTheHotSpotsOfT2AfterTheFirstSecond
  // reads them (a contact's centroid within half the spot's radius), to the clip's end
  std::vector<std::vector<int>> run(m.starts.size(), std::vector<int>(clip.hotspots.size(), 0));
  const int last = clip.hotspots.empty() ? clip.LastFrame() : 1 << 30;
  const bool read = real::RunClipFromStarts(
      dir, clip, params, m.starts, last,
      [&](size_t k, int i, const ContourFrame& f, const Sensor& sensor) {
        if ((i - m.starts[k]) / fps > 1.0) {
          for (size_t h = 0; h < clip.hotspots.size(); ++h) {
            const real::Spot& spot = clip.hotspots[h];
            bool at = false;
            for (const Blob& b : f.blobs) {
              const Vec2 c = real::CentroidPixel(b, sensor);
              at = at || std::hypot(c.x() - spot.x, c.y() - spot.y) < 0.5 * spot.r;
            }
            run[k][h] = at ? run[k][h] + 1 : 0;
            m.hotLongest = std::max(m.hotLongest, run[k][h]);
            if (at && clip.IsClear(i)) ++m.hotClearHits;
          }
        }
        const int first = clip.IsStill() ? 0 : m.starts[k] + settle;
        if (i < first) return;
        size_t& n = next[k];
        while (n < clip.frames.size() && clip.frames[n].index < i) ++n;
        if (n < clip.frames.size() && clip.frames[n].index == i)
          real::ScoreFrame(clip, clip.frames[n], f, sensor, m.scores[k]);
      });
  EXPECT_TRUE(read) << "cannot read " << dir << "/" << clip.path;
  for (const real::Score& s : m.scores) {
    m.total.frames += s.frames;
    m.total.tips += s.tips;
    m.total.found += s.found;
    m.total.contacts += s.contacts;
    m.total.unmatched += s.unmatched;
    m.total.offTips += s.offTips;
    m.total.misses += s.misses;
  }
  return m;
}

// Issue 45: every clip started at 5 s marks with no earlier frames (the stills on their own),
// scored on its labelled frames from 0.2 s after the start to the end of the clip: at least 95% of
// the fingertips found, at most one unmatched contact per 20 labelled frames. A labelled frame
// counts once for every start before it. The sensors work as the pipeline's do, the high-pass only
// where a contact can be (the same contours). Every mark of every clip is some 6 s of sensing in
// Release (one pass over each clip's frames, all the starts' sensors on it): the test does not run
// under the sanitizers, ten times slower (the chain it checks runs there in the other real-footage
// tests).
TEST(RealFootage, StartedAtEvery5SecondMarkAndStillsAlone) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "too slow under the sanitizers (about 10 s in Release): run in Release";
#endif
  const std::string dir = real::RealDataDir();
  if (dir.empty()) GTEST_SKIP() << kNoRealData;
  const std::vector<real::LabelledClip> clips =
      real::ReadLabels(std::string(pg::test::TestDataDir()) + "/real_labels.txt");
  real::Score all;
  for (const real::LabelledClip& clip : clips) {
    const MarkScores m = ScoreFromMarks(dir, clip, SensingParams());
    std::printf("%s:", clip.path.c_str());
    for (size_t k = 0; k < m.starts.size(); ++k)
      std::printf(" from %d: %d of %d (%d unmatched) [%s];", m.starts[k], m.scores[k].found,
                  m.scores[k].tips, m.scores[k].unmatched, m.scores[k].misses.c_str());
    std::printf(" in all %d of %d, %d unmatched in %d frames\n", m.total.found, m.total.tips,
                m.total.unmatched, m.total.frames);
    // from the clip's own start, as the defaults' figures (sensor_test.cpp) have it
    if (!m.starts.empty() && m.starts[0] == 0) {
      EXPECT_GE(m.scores[0].found, 0.95 * m.scores[0].tips) << clip.path << m.scores[0].misses;
    }
    if (!clip.hotspots.empty()) {
      // 1 s after any start: none on the clear frames, none staying 2 s (a hand moves on)
      std::printf("%s hot spots after 1 s: %d contacts on clear frames, longest stay %d frames\n",
                  clip.path.c_str(), m.hotClearHits, m.hotLongest);
      EXPECT_EQ(m.hotClearHits, 0) << clip.path;
      EXPECT_LT(m.hotLongest, 117) << clip.path;
    }
    all.frames += m.total.frames;
    all.tips += m.total.tips;
    all.found += m.total.found;
    all.unmatched += m.total.unmatched;
    all.misses += m.total.misses;
  }
  std::printf("all: %d of %d fingertips (%.1f%%), %d unmatched in %d frames (%.2f per 20)\n",
              all.found, all.tips, 100.0 * all.found / all.tips, all.unmatched, all.frames,
              20.0 * all.unmatched / all.frames);
  ASSERT_GT(all.tips, 700);
  EXPECT_GE(all.found, 0.95 * all.tips) << all.misses;
  EXPECT_LE(all.unmatched * 20, all.frames) << all.misses;
}

}  // namespace
}  // namespace pg
