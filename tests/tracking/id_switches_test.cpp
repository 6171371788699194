#include "proxygrasp/tracking/id_switches.h"

#include "test_paths.h"

#include "proxygrasp/sensing/types.h"
#include "proxygrasp/tracking/tracker.h"

#include <gtest/gtest.h>
#include <opencv2/videoio.hpp>

#include <cstdio>
#include <filesystem>

#include "sensing/real_footage.h"

namespace pg {
namespace {

Contact ContactAt(ContactId id, ContactState state, double x, double y) {
  Contact c;
  c.id = id;
  c.state = state;
  c.blob.centroid = Vec2(x, y);
  c.blob.area = 2.0;
  return c;
}

ContactSet Set(int64_t frame, std::vector<Contact> contacts) {
  ContactSet s;
  s.frame = frame;
  s.time = frame / 30.0;
  s.contacts = std::move(contacts);
  return s;
}

constexpr ContactState kNew = ContactState::kNew;
constexpr ContactState kOn = ContactState::kContinuing;
constexpr ContactState kLifted = ContactState::kLifted;

TEST(IdSwitchCounter, ATrackThatLiftsAndReappearsCountsOne) {
  IdSwitchCounter counter;
  counter.Add(Set(0, {ContactAt(1, kNew, 10, 10)}));
  counter.Add(Set(1, {ContactAt(1, kOn, 10.2, 10)}));
  counter.Add(Set(2, {ContactAt(1, kLifted, 10.2, 10)}));  // gone for frames 2 and 3
  counter.Add(Set(3, {}));
  counter.Add(Set(4, {ContactAt(2, kNew, 10.6, 10.3)}));  // 0.5 cm from where it lifted
  counter.Add(Set(5, {ContactAt(2, kOn, 10.6, 10.3)}));
  EXPECT_EQ(counter.count().switches, 1);
  EXPECT_EQ(counter.count().frames, 6);
  EXPECT_EQ(counter.count().contactFrames, 4);  // frames 0, 1, 4, 5
  // 4 contact frames at 30 fps: 4 / 30 / 60 min
  EXPECT_DOUBLE_EQ(counter.count().MinutesOfTouch(30.0), 4.0 / 30.0 / 60.0);
  EXPECT_DOUBLE_EQ(counter.count().PerMinuteOfTouch(30.0), 1.0 / (4.0 / 30.0 / 60.0));
}

TEST(IdSwitchCounter, AKeptContactCountsFromTheFrameItWasFirstMissing) {
  // the tracker kept id 1 where it was for 3 frames (missed 1 to 3) and listed it lifted in
  // frame 4 (missed 3): the counter takes the lift as of frame 1, and the kept frames are no touch
  auto kept = [](int64_t frame, int missed, ContactState state) {
    Contact c = ContactAt(1, state, 10, 10);
    c.missed = missed;
    return Set(frame, {c});
  };
  IdSwitchCounter within;  // maxGapFrames 3
  within.Add(Set(0, {ContactAt(1, kNew, 10, 10)}));
  for (int f = 1; f <= 3; ++f) within.Add(kept(f, f, kOn));
  Contact lifted = ContactAt(1, kLifted, 10, 10);
  lifted.missed = 3;
  Contact back = ContactAt(2, kNew, 10.3, 10);
  within.Add(Set(4, {back, lifted}));  // 3 frames after frame 1
  EXPECT_EQ(within.count().switches, 1);
  EXPECT_EQ(within.count().contactFrames, 2);  // frames 0 and 4
  IdSwitchCounter after;
  after.Add(Set(0, {ContactAt(1, kNew, 10, 10)}));
  for (int f = 1; f <= 3; ++f) after.Add(kept(f, f, kOn));
  after.Add(Set(4, {lifted}));
  after.Add(Set(5, {back}));  // 4 frames after frame 1: a new touch
  EXPECT_EQ(after.count().switches, 0);
}

TEST(IdSwitchCounter, TwoFarApartFingersCountNone) {
  IdSwitchCounter counter;
  // one finger lifts at (10, 10) while another, 20 cm away (beyond a hand's span), lands and stays
  counter.Add(Set(0, {ContactAt(1, kNew, 10, 10)}));
  counter.Add(Set(1, {ContactAt(1, kOn, 10, 10)}));
  counter.Add(Set(2, {ContactAt(2, kNew, 30, 10), ContactAt(1, kLifted, 10, 10)}));
  // and a third lands 5 cm from where the first lifted, after it
  counter.Add(Set(3, {ContactAt(2, kOn, 30, 10), ContactAt(3, kNew, 10, 15)}));
  counter.Add(Set(4, {ContactAt(2, kOn, 30, 10), ContactAt(3, kOn, 10, 15)}));
  EXPECT_EQ(counter.count().switches, 0);
  EXPECT_EQ(counter.count().contactFrames, 7);
}

TEST(IdSwitchCounter, FingersThatJumpFartherThanTheTrackersReachCountOneEach) {
  IdSwitchCounter counter;
  // two fingers spread apart by 5.5 cm each in one frame (a recording with dropped frames): the
  // tracker lists both as lifted and two new ones
  counter.Add(Set(0, {ContactAt(1, kNew, 46, 33), ContactAt(2, kNew, 69, 33)}));
  counter.Add(Set(1, {ContactAt(3, kNew, 40.5, 33), ContactAt(4, kNew, 74.5, 33),
                      ContactAt(1, kLifted, 46, 33), ContactAt(2, kLifted, 69, 33)}));
  ASSERT_EQ(counter.count().switches, 2);
  EXPECT_EQ(counter.count().jumps, 2);
  ASSERT_EQ(counter.switches().size(), 2u);
  EXPECT_EQ(counter.switches()[0].kind, IdSwitchKind::kJump);
  EXPECT_NEAR(counter.switches()[0].distance, 5.5, 1e-9);
  // the pairs are the near ones, not across the hands
  EXPECT_EQ(counter.switches()[0].lifted + 2, counter.switches()[0].next);
  EXPECT_EQ(counter.switches()[1].lifted + 2, counter.switches()[1].next);
}

TEST(IdSwitchCounter, MoreFingersLandingThanLiftingIsNoJump) {
  IdSwitchCounter counter;
  // a hand lands (three new contacts) as one finger lifts 5 cm away: not the same fingers
  counter.Add(Set(0, {ContactAt(1, kNew, 10, 10)}));
  counter.Add(Set(1, {ContactAt(2, kNew, 15, 10), ContactAt(3, kNew, 17, 10),
                      ContactAt(4, kNew, 19, 10), ContactAt(1, kLifted, 10, 10)}));
  EXPECT_EQ(counter.count().switches, 0);
}

TEST(IdSwitchCounter, AReturnAfterTheGapIsANewTouch) {
  IdSwitchCounter counter;  // maxGapFrames 3
  counter.Add(Set(0, {ContactAt(1, kNew, 10, 10)}));
  counter.Add(Set(1, {ContactAt(1, kLifted, 10, 10)}));
  for (int64_t f = 2; f <= 4; ++f) counter.Add(Set(f, {}));
  counter.Add(Set(5, {ContactAt(2, kNew, 10, 10)}));  // 4 frames after the lift
  EXPECT_EQ(counter.count().switches, 0);

  // the same with the return on the last frame of the gap counts
  IdSwitchCounter inTime;
  inTime.Add(Set(0, {ContactAt(1, kNew, 10, 10)}));
  inTime.Add(Set(1, {ContactAt(1, kLifted, 10, 10)}));
  for (int64_t f = 2; f <= 3; ++f) inTime.Add(Set(f, {}));
  inTime.Add(Set(4, {ContactAt(2, kNew, 10, 10)}));
  EXPECT_EQ(inTime.count().switches, 1);
}

TEST(IdSwitchCounter, EachLiftIsContinuedOnce) {
  IdSwitchCounter counter;
  // one finger flickers out and two new blobs start beside where it was: one switch, the other
  // blob is a new contact
  counter.Add(Set(0, {ContactAt(1, kNew, 10, 10)}));
  counter.Add(Set(1, {ContactAt(1, kLifted, 10, 10)}));
  counter.Add(Set(2, {ContactAt(2, kNew, 10.5, 10), ContactAt(3, kNew, 9.5, 10)}));
  EXPECT_EQ(counter.count().switches, 1);
}

TEST(IdSwitchCounter, NoTouchGivesZeroPerMinute) {
  IdSwitchCounter counter;
  counter.Add(Set(0, {}));
  EXPECT_EQ(counter.count().MinutesOfTouch(30.0), 0.0);
  EXPECT_EQ(counter.count().PerMinuteOfTouch(30.0), 0.0);
  EXPECT_EQ(counter.count().PerMinuteOfTouch(0.0), 0.0);
}

// ---- real table footage (../shared/real) ----

// Issue 14: "a finger held on the table keeps one id". A continuous clip run through the real
// table sensing settings and the default tracker (what `play` and `sense` use): its id switches,
// printed with why each was counted. Empty with `skip` set when the clip cannot be run here.
struct Measured {
  IdSwitchCount count;
  double fps = 0.0;
  std::string skip;
};

Measured MeasureClip(const std::string& name, const IdSwitchParams& window = IdSwitchParams()) {
  Measured m;
  const std::string dir = real::RealDataDir();
  if (dir.empty()) {
    m.skip =
        "../shared/real is absent (a clone of the project alone): no real footage to measure "
        "id switches on; set PROXYGRASP_REAL_DATA to its folder";
    return m;
  }
  if (!std::filesystem::exists(dir + "/" + name)) {
    m.skip = dir + "/" + name + " is absent on this machine: no id switches measured on it";
    return m;
  }
  const std::vector<real::LabelledClip> clips = real::ReadLabels(
      std::string(pg::test::SourceDir()) + "/tests/sensing/testdata/real_labels.txt");
  const real::LabelledClip* clip = nullptr;
  for (const real::LabelledClip& c : clips)
    if (c.path == name) clip = &c;
  if (clip == nullptr) {
    ADD_FAILURE() << name << " has no scale in tests/sensing/testdata/real_labels.txt";
    return m;
  }
  m.fps = cv::VideoCapture(dir + "/" + name).get(cv::CAP_PROP_FPS);
  EXPECT_GT(m.fps, 0.0) << name;

  Tracker tracker;
  IdSwitchCounter counter(window);
  EXPECT_TRUE(real::RunClip(
      dir, *clip, SensingParams(), 1 << 30,
      [&](int, const ContourFrame& f, const Sensor&) { counter.Add(tracker.Step(f)); }))
      << "cannot read " << dir << "/" << name;
  m.count = counter.count();
  const IdSwitchCount& n = m.count;
  std::printf(
      "%s: %lld frames at %.1f fps, %.2f min of touch, %d id switches (%d flickers, %d "
      "jumps), %.1f per minute of touch\n",
      name.c_str(), static_cast<long long>(n.frames), m.fps, n.MinutesOfTouch(m.fps), n.switches,
      n.switches - n.jumps, n.jumps, n.PerMinuteOfTouch(m.fps));
  for (const IdSwitch& s : counter.switches())
    std::printf(
        "  frame %lld: %s, id %d -> %d after %d frames, %.2f cm away, lifted area %.2f "
        "cm^2\n",
        static_cast<long long>(s.frame), kIdSwitchKindNames[static_cast<int>(s.kind)], s.lifted,
        s.next, s.gapFrames, s.distance, s.liftedArea);
  return m;
}

// The acceptance bound: at most one id switch per minute of touch, i.e. a finger held on the
// table keeps its id for a minute on average. It allows for the rare false count of the
// definition (another finger landing where one just lifted); on hard-5point.avi's 0.4 minutes of
// touch a single switch (2.5 per minute) fails it.
constexpr double kMaxSwitchesPerMinuteOfTouch = 1.0;

TEST(RealFootage, AHeldFingerKeepsItsIdOnHard5Point) {
  const Measured m = MeasureClip("touchlib/hard-5point.avi");
  if (!m.skip.empty()) GTEST_SKIP() << m.skip;
  EXPECT_GT(m.count.MinutesOfTouch(m.fps), 0.1) << "the clip's fingers were not found";
  EXPECT_LE(m.count.PerMinuteOfTouch(m.fps), kMaxSwitchesPerMinuteOfTouch);
}

// seth_tests.avi: 0 switches in 2.2 minutes of touch with the default tracker. Before
// tracking.max_speed it had 23 jumps (the recording moves in steps of 4.4 to 6.4 cm a frame at
// 20 fps, beyond a fixed 4 cm reach); before tracking.keep_lost (3 frames) 10 flickers, mostly
// faint fingertips at about min_area (0.5 cm^2) dropping out for 1 to 3 frames. keep_lost bridges
// exactly the gaps the counter calls flickers (maxGapFrames 3), so here 0 says that every
// returning blob was matched back to its kept contact; the test below watches longer gaps.
TEST(RealFootage, AHeldFingerKeepsItsIdOnSethTests) {
  const Measured m = MeasureClip("ccv-hand/seth_tests.avi");
  if (!m.skip.empty()) GTEST_SKIP() << m.skip;
  EXPECT_GT(m.count.MinutesOfTouch(m.fps), 1.0) << "the clip's fingers were not found";
  EXPECT_LE(m.count.PerMinuteOfTouch(m.fps), kMaxSwitchesPerMinuteOfTouch);
}

// Gaps of 4 to 6 frames (0.2 to 0.3 s at 20 fps), which keep_lost does not bridge and the
// acceptance's counter calls new touches: counted with a 6-frame window, seth_tests.avi has 11
// (5.0 per minute of touch; 24 without keep_lost). Whether they are the same finger cannot be told
// from the tracker's output. They must not get more frequent: at most the measured 5.0 plus one.
TEST(RealFootage, SethTestsLongerGapsGetNoMoreFrequent) {
  IdSwitchParams window;
  window.maxGapFrames = 6;
  const Measured m = MeasureClip("ccv-hand/seth_tests.avi", window);
  if (!m.skip.empty()) GTEST_SKIP() << m.skip;
  EXPECT_GT(m.count.MinutesOfTouch(m.fps), 1.0) << "the clip's fingers were not found";
  EXPECT_LE(m.count.PerMinuteOfTouch(m.fps), 6.0);
}

}  // namespace
}  // namespace pg
