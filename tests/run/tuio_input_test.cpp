#include "proxygrasp/run/tuio_input.h"

#include "real_data.h"

#include "proxygrasp/run/frame_input.h"
#include "proxygrasp/run/simulation.h"
#include "proxygrasp/run/trace.h"
#include "proxygrasp/run/tuio_output.h"
#include "proxygrasp/tuio/decoder.h"
#include "proxygrasp/tuio/encoder.h"
#include "proxygrasp/tuio/transport.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <thread>
#include <unistd.h>

#include "run/test_levels.h"

namespace pg {
namespace {

using ::testing::HasSubstr;

// a square of side 2 cm at (x, y), wound clockwise (as a sender may wind it)
std::vector<Vec2> SquareCw(double x, double y) {
  return {Vec2(x - 1, y - 1), Vec2(x - 1, y + 1), Vec2(x + 1, y + 1), Vec2(x + 1, y - 1)};
}

TuioContact Received(TuioSessionId id, double x, double y, bool isNew) {
  TuioContact c;
  c.id = id;
  c.isNew = isNew;
  c.contour = SquareCw(x, y);
  c.centroid = Vec2(x, y);
  return c;
}

const Contact* Find(const ContactSet& set, ContactId id) {
  for (const Contact& c : set.contacts)
    if (c.id == id) return &c;
  return nullptr;
}

TEST(TuioInput, AnOutlineBecomesABlobAsSensingMakesThem) {
  const Blob b = BlobFromOutline(SquareCw(10, 20), 0.3);
  EXPECT_NEAR(b.area, 4.0, 1e-12);
  EXPECT_NEAR((b.centroid - Vec2(10, 20)).norm(), 0.0, 1e-12);
  EXPECT_GT(SignedArea(b.contour), 0.0) << "counter-clockwise";
  // perimeter 8 cm at 0.3 cm: round(26.7) = 27 points, each on the square's edge
  EXPECT_EQ(b.contour.cols(), 27);
  EXPECT_NEAR((b.boundsMin - Vec2(9, 19)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((b.boundsMax - Vec2(11, 21)).norm(), 0.0, 1e-12);
}

TEST(TuioInput, SessionIdsAreContactIdsAndNewAndLiftedComeFromTheStream) {
  TuioTracker tracker;
  TuioFrame f1;
  f1.contacts = {Received(5, 10, 10, true), Received(9, 20, 10, true)};
  ContactSet s1 = tracker.Step(&f1, 0.3);
  ASSERT_EQ(s1.contacts.size(), 2u);
  EXPECT_EQ(s1.contacts[0].id, 5);
  EXPECT_EQ(s1.contacts[0].state, ContactState::kNew);
  EXPECT_EQ(s1.contacts[1].id, 9);

  // nothing arrived: both continue where they were
  ContactSet s2 = tracker.Step(nullptr, 0.3);
  ASSERT_EQ(s2.contacts.size(), 2u);
  for (const Contact& c : s2.contacts) EXPECT_EQ(c.state, ContactState::kContinuing);

  // 5 moves, 9 leaves alive (lifted with its last blob), 7 arrives: below an id handed out, so
  // it gets the next free id, 10
  TuioFrame f3;
  f3.contacts = {Received(5, 12, 10, false), Received(7, 30, 30, true)};
  f3.lifted = {9};
  ContactSet s3 = tracker.Step(&f3, 0.3);
  ASSERT_EQ(s3.contacts.size(), 3u);
  EXPECT_EQ(s3.contacts[0].id, 5);
  EXPECT_EQ(s3.contacts[0].state, ContactState::kContinuing);
  EXPECT_NEAR(s3.contacts[0].blob.centroid.x(), 12.0, 1e-12);
  EXPECT_EQ(s3.contacts[1].id, 10);
  EXPECT_EQ(s3.contacts[1].state, ContactState::kNew);
  EXPECT_EQ(tracker.IdOf(7), 10);
  EXPECT_EQ(s3.contacts[2].id, 9);
  EXPECT_EQ(s3.contacts[2].state, ContactState::kLifted);
  EXPECT_NEAR(s3.contacts[2].blob.centroid.x(), 20.0, 1e-12) << "its last blob";

  // a live session the frame no longer lists has lifted even when the frame does not say so
  TuioFrame f4;
  f4.contacts = {Received(7, 30, 30, false)};
  ContactSet s4 = tracker.Step(&f4, 0.3);
  ASSERT_EQ(s4.contacts.size(), 2u);
  EXPECT_EQ(s4.contacts[1].id, 5);
  EXPECT_EQ(s4.contacts[1].state, ContactState::kLifted);
  EXPECT_EQ(tracker.LiveCount(), 1);
}

TEST(TuioInput, SessionIdsNoContactIdCanHoldGetFreshIdsThatAreNeverReused) {
  TuioTracker tracker;
  TuioFrame f;
  const TuioSessionId huge = int64_t{std::numeric_limits<ContactId>::max()} + 5;
  f.contacts = {Received(0, 10, 10, true), Received(3, 20, 10, true), Received(huge, 30, 10, true),
                Received(-4, 40, 10, true)};
  ContactSet s = tracker.Step(&f, 0.3);
  std::vector<ContactId> ids;
  for (const Contact& c : s.contacts) ids.push_back(c.id);
  // in the frame's order: 0 -> 1 (first free), 3 -> 3, huge -> 4, -4 -> 5
  EXPECT_EQ(ids, (std::vector<ContactId>{1, 3, 4, 5}));
  // all lift, and session 3 comes back: id 3 was used, so it gets 6
  TuioFrame empty;
  tracker.Step(&empty, 0.3);
  TuioFrame back;
  back.contacts = {Received(3, 20, 10, true)};
  EXPECT_EQ(tracker.Step(&back, 0.3).contacts.at(0).id, 6);
}

TEST(TuioInput, ARecordingArrivesAtItsTimeTagsOrAtTheFrameRate) {
  std::vector<OscBundle> bundles(3);
  // "immediately" (as touchlib writes): k * interval
  EXPECT_EQ(ReplayArrivals(bundles, 0.5), (std::vector<double>{0.0, 0.5, 1.0}));
  // times: less the first
  bundles[0].time = OscTimeTag::FromSeconds(100.0);
  bundles[1].time = OscTimeTag::FromSeconds(100.25);
  bundles[2].time = OscTimeTag::FromSeconds(101.0);
  const std::vector<double> timed = ReplayArrivals(bundles, 0.5);
  EXPECT_NEAR(timed[1], 0.25, 1e-9);
  EXPECT_NEAR(timed[2], 1.0, 1e-9);
  // a tag that runs backwards: the tags are not trusted
  bundles[2].time = OscTimeTag::FromSeconds(99.0);
  EXPECT_EQ(ReplayArrivals(bundles, 0.5), (std::vector<double>{0.0, 0.5, 1.0}));
}

// the TUIO 2.0 bundles of contacts at frame k, time t
std::vector<OscBundle> Encoded(TuioEncoder& encoder, int64_t k, double t,
                               const std::vector<TuioOutContact>& contacts) {
  return encoder.Encode(k, OscTimeTag::FromSeconds(t), contacts);
}

TuioOutContact Out(TuioSessionId id, double x, double y) {
  TuioOutContact c;
  c.id = id;
  c.contour = SquareCw(x, y);
  c.centroid = Vec2(x, y);
  return c;
}

TEST(TuioInput, AReplayGivesEachSimulationFrameWhatArrivedBeforeItsMiddleAndLiftsAtTheEnd) {
  TuioEncoderParams ep;
  TuioEncoder encoder(ep);
  // frames at 0, 1/150 and 2/150 s (faster than the simulation's 60 Hz), then silence
  std::vector<OscBundle> bundles;
  for (int k = 0; k < 3; ++k)
    for (OscBundle& b : Encoded(encoder, k, k / 150.0, {Out(4, 10 + k, 10)})) bundles.push_back(b);
  std::unique_ptr<TuioStream> stream = TuioStream::Replay(bundles, "test.xml");
  EXPECT_EQ(stream->Describe(), "tuio file test.xml");
  TuioParams params;
  const double dt = 1.0 / 60.0;
  // frame 0 [0, 1/60): arrivals up to its middle, 1/120 s -> sender frames 0 and 1 merged, x = 11
  std::optional<TuioFrame> f0 = stream->Next(0.0, dt, params);
  ASSERT_TRUE(f0);
  ASSERT_EQ(f0->contacts.size(), 1u);
  EXPECT_TRUE(f0->contacts[0].isNew);
  EXPECT_NEAR(f0->contacts[0].centroid.x(), 11.0, 1e-4);
  // frame 1: sender frame 2
  std::optional<TuioFrame> f1 = stream->Next(dt, dt, params);
  ASSERT_TRUE(f1);
  EXPECT_NEAR(f1->contacts.at(0).centroid.x(), 12.0, 1e-4);
  // then nothing until the timeout (0.5 s) after the last bundle lifts it
  int frame = 2;
  std::optional<TuioFrame> next;
  for (; frame < 120 && !next; ++frame) next = stream->Next(frame * dt, dt, params);
  ASSERT_TRUE(next);
  EXPECT_EQ(next->lifted, (std::vector<TuioSessionId>{4}));
  // the lift arrives at last arrival + timeout + one interval, 2/150 + 0.5 + 1/60 s, and lands in
  // the frame whose middle follows it
  const double liftAt = (frame - 1) * dt;
  EXPECT_NEAR(liftAt, 2 / 150.0 + 0.5 + dt, dt) << "lifted at " << liftAt;
  EXPECT_THAT(stream->Status(), HasSubstr("none dropped"));
}

TEST(TuioInput, ABadPortSpecIsAnErrorThatSaysWhatIsExpected) {
  for (const char* spec : {"tuio:", "tuio:abc", "tuio:70000", "tuio::3333", "tuio:1.2.3.4:x"}) {
    Result<FrameInput> opened = FrameInput::Open(spec);
    ASSERT_FALSE(opened.ok()) << spec;
    EXPECT_THAT(opened.error().Format(), HasSubstr("expected tuio:PORT or tuio:ADDRESS:PORT"));
  }
  // an address this machine does not have cannot be listened on
  Result<FrameInput> foreign = FrameInput::Open("tuio:192.0.2.1:0");
  ASSERT_FALSE(foreign.ok());
  EXPECT_THAT(foreign.error().Format(), HasSubstr("192.0.2.1"));
}

// a fingertip pushing a box 2 cm over half a second
Level Push() {
  return test::ParseOrFail(
      test::BoxToml("box", 30, 23) + test::FingerToml("finger", 26, 23, 0, 29.2, 23, 0.5),
      "tuio_input.toml");
}

TEST(TuioInput, OurSenderToOurReceiverReproducesALevelsContactsFrameForFrame) {
  // one run sensed through the camera, its contacts sent each frame over UDP on the loopback; a
  // second run of the same level takes them from tuio:127.0.0.1:PORT. The contacts match frame
  // for frame: same ids and states, outlines within 0.05 cm (the encoder simplifies outlines by
  // 0.02 cm; float32 normalised coordinates add 61 cm * 2^-24 = 4e-6 cm; resampling at 0.3 cm
  // puts points on the simplified outline, so each outline is within 0.02 cm of the other)
  const Level level = Push();
  Simulation sensed;
  Simulation given;
  ASSERT_FALSE(sensed.Start(level, level.params));
  ASSERT_FALSE(given.Start(level, level.params));
  Result<FrameInput> opened = FrameInput::Open("tuio:127.0.0.1:0");
  ASSERT_TRUE(opened.ok()) << opened.error().Format();
  FrameInput& input = opened.value();
  ASSERT_EQ(input.kind(), FrameInput::Kind::kTuio);
  ASSERT_TRUE(input.Imageless());
  TuioStream* stream = input.tuio();
  ASSERT_NE(stream, nullptr);
  stream->SetWait(1.0);  // the sender is this thread: a frame is there or lost
  EXPECT_EQ(input.Describe(), "tuio:127.0.0.1:" + std::to_string(stream->port()));
  TuioEncoderParams ep;
  ep.table = level.params.table;
  Result<std::unique_ptr<TuioSender>> sender =
      TuioSender::Open("127.0.0.1:" + std::to_string(stream->port()), ep);
  ASSERT_TRUE(sender.ok()) << sender.error().Format();

  FrameInput script = FrameInput::Script();
  const int frames = 45;  // the push and 15 frames after the finger lifts at 0.5 s
  int compared = 0;
  for (int i = 0; i < frames; ++i) {
    ASSERT_TRUE(script.Step(sensed).ok());
    ASSERT_FALSE(sender.value()->Send(i, ToTuioOutContacts(sensed.contacts())));
    Result<FrameStatus> stepped = input.Step(given);
    ASSERT_TRUE(stepped.ok());
    ASSERT_EQ(stepped.value(), FrameStatus::kOk);
    const ContactSet& a = sensed.contacts();
    const ContactSet& b = given.contacts();
    ASSERT_EQ(a.contacts.size(), b.contacts.size()) << "frame " << i;
    for (const Contact& ca : a.contacts) {
      const Contact* cb = Find(b, ca.id);
      ASSERT_NE(cb, nullptr) << "frame " << i << " id " << ca.id;
      EXPECT_EQ(cb->state, ca.state) << "frame " << i;
      EXPECT_LT(HausdorffDistance(ca.blob.contour, cb->blob.contour), 0.05) << "frame " << i;
      ++compared;
    }
  }
  EXPECT_GE(compared, 30);
  EXPECT_TRUE(given.cameraImage().empty()) << "TUIO brings no camera image";
  EXPECT_EQ(stream->stats().TotalDropped(), 0u);
  // and the box went the same way: both runs pushed it by the same contacts, so its pose agrees
  // within the outline tolerance (0.05 cm)
  EXPECT_NEAR(given.world().Object(0).pose.pos.x(), sensed.world().Object(0).pose.pos.x(), 0.05);
  EXPECT_GT(given.world().Object(0).pose.pos.x(), 30.5) << "the push moved the box";
}

TEST(TuioInput, AFloodOfTenThousandPacketsASecondForTwoSecondsIsCountedAndSurvived) {
  // 10,000 datagrams a second for 2 s, paced, into tuio:127.0.0.1:PORT while a simulation steps
  // at its 60 Hz from it: good frames with a fresh session each, unknown addresses, NaN
  // coordinates and contours of 5,000 points (more than maxContourPoints; 10,000 points do not fit
  // one UDP datagram, the decoder's own test feeds those). Every frame steps; what is bad is
  // counted; memory stays flat
  const Level level = Push();
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  Result<FrameInput> opened = FrameInput::Open("tuio:127.0.0.1:0");
  ASSERT_TRUE(opened.ok()) << opened.error().Format();
  FrameInput& input = opened.value();
  const int port = input.tuio()->port();
  TuioEncoderParams ep;
  ep.table = level.params.table;
  Result<std::unique_ptr<TuioSender>> sender =
      TuioSender::Open("127.0.0.1:" + std::to_string(port), ep);
  ASSERT_TRUE(sender.ok());
  // a good frame: frame id k, a session that lasts 64 frames, moving
  TuioEncoder encoder(ep);
  const auto good = [&](int k) {
    return Encoded(encoder, k, 0.0, {Out(k / 64 + 1, 20 + 0.01 * (k % 64), 20)}).front();
  };
  // a frame whose outline has NaN coordinates
  const auto nan = [&](int k) {
    OscBundle b = good(k);
    for (OscMessage& m : b.messages)
      if (m.address == "/tuio2/ocg")
        for (size_t a = 1; a < m.args.size(); ++a) m.args[a].f = std::nan("");
    return b;
  };
  // a frame whose outline has 5,000 points: 40 KB, in one datagram
  const auto huge = [&](int k) {
    OscBundle b = good(k);
    for (OscMessage& m : b.messages)
      if (m.address == "/tuio2/ocg") {
        m.args.resize(1);
        for (int p = 0; p < 5000; ++p) {
          m.args.push_back(OscArg::Float(0.5f + 0.1f * std::cos(p * 6.283f / 5000)));
          m.args.push_back(OscArg::Float(0.5f + 0.1f * std::sin(p * 6.283f / 5000)));
        }
      }
    return b;
  };
  const auto rss = [] {
    long pages = 0, resident = 0;
    std::ifstream("/proc/self/statm") >> pages >> resident;
    return resident * sysconf(_SC_PAGESIZE);
  };

  constexpr double kRate = 10000.0;  // datagrams per second
  constexpr double kSeconds = 2.0;
  const int total = static_cast<int>(kRate * kSeconds);
  const double start = TuioClock();
  int sent = 0;
  int steps = 0;
  long rssAfterWarmup = 0;
  while (sent < total) {
    const double now = TuioClock() - start;
    // the datagrams due by now, a few at a time so that a slow machine (or a sanitizer) still
    // steps the simulation, and so reads the socket, every frame
    for (int burst = 0; sent < total && sent < now * kRate && burst < 20; ++sent, ++burst) {
      switch (sent % 8) {
        case 3:
          sender.value()->SendBundle(nan(sent + 1));
          break;
        case 5: {
          OscBundle b;
          OscMessage m;
          m.address = "/garbage/" + std::to_string(sent);
          b.messages.push_back(m);
          sender.value()->SendBundle(b);
          break;
        }
        case 7:
          if (sent % 80 == 7)
            sender.value()->SendBundle(huge(sent + 1));
          else
            sender.value()->SendBundle(good(sent + 1));
          break;
        default:
          sender.value()->SendBundle(good(sent + 1));
      }
    }
    // the simulation's frames, on time
    if (now >= steps * sim.FrameDuration()) {
      Result<FrameStatus> stepped = input.Step(sim);
      ASSERT_TRUE(stepped.ok());
      ASSERT_EQ(stepped.value(), FrameStatus::kOk);
      ++steps;
    }
    if (rssAfterWarmup == 0 && sent >= total / 5) rssAfterWarmup = rss();
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
  const double elapsed = TuioClock() - start;
  const TuioStats& s = input.tuio()->stats();
  std::printf("flood: %d datagrams in %.2f s, %d simulation frames; %s\n", sent, elapsed, steps,
              input.tuio()->Status().c_str());
  // the sends are paced never faster than kRate; how many frames the simulation stepped and how
  // many datagrams the kernel kept depend on the machine's load (and on sanitizers), so they are
  // printed, not bounded: this test is about surviving and counting, not speed
  EXPECT_GT(steps, 0);
  EXPECT_GT(s.packets, 0u);
  EXPECT_GT(s[TuioDrop::kNonFinite], 0u);
  EXPECT_GT(s[TuioDrop::kUnknownAddress], 0u);
  EXPECT_GT(s[TuioDrop::kTooManyPoints], 0u);
  EXPECT_THAT(input.tuio()->Status(), HasSubstr("non-finite"));
  EXPECT_LE(sim.contacts().contacts.size(), 2u) << "one session at a time, and the one it ends";
#if !defined(__SANITIZE_ADDRESS__)
  // flat: allocator slack only (not under AddressSanitizer, whose quarantine keeps freed memory)
  EXPECT_LT(rss() - rssAfterWarmup, 8L << 20);
#else
  (void)rssAfterWarmup;
#endif
}

// sessions of the touchlib recordings in ../shared/real/touchlib, read from the XML by hand: the
// packet it first appears in alive, the last such packet, the packet whose alive it has left, and
// its first and last normalised position (the sessions tests/tuio/touchlib_xml_test.cpp checks)
struct CheckedSession {
  TuioSessionId id;
  int first, last, lift;
  double x0, y0, x1, y1;
};
struct TouchlibRecording {
  const char* file;
  size_t packets;
  std::vector<CheckedSession> sessions;
};
const TouchlibRecording kTouchlib[] = {
    {"touchlib/tuio_test.xml",
     546,
     {{1847, 0, 187, 188, 0.32171196, 0.55886567, 0.32262605, 0.566776},
      {1848, 35, 137, 138, 0.3724041, 0.4086407, 0.45380107, 0.5567726},
      {1865, 203, 234, 235, 0.2541643, 0.65127295, 0.35481566, 0.6140836},
      {1879, 248, 375, 376, 0.424013, 0.3762815, 0.3059682, 0.6268407},
      {1887, 309, 377, 378, 0.26926112, 0.68964726, 0.2704469, 0.6914832}}},
    {"touchlib/tuio_tableData.xml",
     373,
     {{9, 2, 42, 43, 0.31734723, 0.3147611, 0.32947665, 0.59706515},
      {10, 85, 132, 133, 0.5076447, 0.20842105, 0.52693856, 0.6198044},
      {16, 203, 229, 230, 0.29515514, 0.49067765, 0.4307044, 0.6411433},
      {17, 205, 229, 230, 0.75292563, 0.46972466, 0.5867385, 0.6402787}}},
};

// names the recording in test failures instead of dumping its bytes
void PrintTo(const TouchlibRecording& r, std::ostream* os) {
  *os << r.file;
}

class TouchlibPipeline : public ::testing::TestWithParam<TouchlibRecording> {};

TEST_P(TouchlibPipeline, EveryCursorIsAContactWithItsSessionIdPathAndLift) {
  const TouchlibRecording& rec = GetParam();
  // a real table's TUIO 1.0 stream as a level's input: packet k arrives at k frames (its time
  // tags are all "immediately"), so simulation frame k holds packet k's cursors. Each cursor is
  // a contact whose id is its session id, new in the frame it first appears, at the XML's
  // position (a 0.8 cm circle of 16 points, resampled at 0.3 cm: its centroid is the cursor's
  // within 1e-3 cm), lifted in the frame whose alive has left it, and it gets particles
  const std::string dir = test::RealDataDir();
  if (dir.empty()) GTEST_SKIP() << test::kNoRealData;
  const std::string file = dir + "/" + rec.file;
  const Level level =
      test::ParseOrFail("[script]\ntuio = \"" + file + "\"\n", "touchlib_level.toml");
  ASSERT_TRUE(level.script.tuioBundles);
  ASSERT_EQ(level.script.tuioBundles->size(), rec.packets);
  Simulation sim;
  ASSERT_FALSE(sim.Start(level, level.params));
  Result<FrameInput> opened = FrameInput::ForLevel(level);
  ASSERT_TRUE(opened.ok());
  FrameInput& input = opened.value();
  ASSERT_EQ(input.kind(), FrameInput::Kind::kTuio);
  const TableParams& table = level.params.table;
  const auto onTable = [&](double x, double y) {
    return Vec2(x * table.width, (1.0 - y) * table.height);
  };
  int withParticles = 0;
  for (int k = 0; k < static_cast<int>(rec.packets); ++k) {
    ASSERT_EQ(input.Step(sim).value(), FrameStatus::kOk);
    const ContactSet& set = sim.contacts();
    // every set message of packet k is a contact of frame k, at its position
    for (const OscMessage& m : (*level.script.tuioBundles)[static_cast<size_t>(k)].messages) {
      if (m.args.size() < 4 || m.args[0].s != "set") continue;
      const Contact* c = Find(set, static_cast<ContactId>(m.args[1].i));
      ASSERT_NE(c, nullptr) << "session " << m.args[1].i << " in frame " << k;
      EXPECT_NE(c->state, ContactState::kLifted);
      EXPECT_NEAR((c->blob.centroid - onTable(m.args[2].f, m.args[3].f)).norm(), 0.0, 1e-3);
    }
    for (const CheckedSession& s : rec.sessions) {
      const Contact* c = Find(set, static_cast<ContactId>(s.id));
      if (k < s.first || k > s.lift) {
        EXPECT_EQ(c, nullptr) << s.id << " frame " << k;
        continue;
      }
      ASSERT_NE(c, nullptr) << s.id << " frame " << k;
      const ContactState want = k == s.first  ? ContactState::kNew
                                : k == s.lift ? ContactState::kLifted
                                              : ContactState::kContinuing;
      EXPECT_EQ(c->state, want) << s.id << " frame " << k;
      if (k == s.first) {
        EXPECT_NEAR((c->blob.centroid - onTable(s.x0, s.y0)).norm(), 0.0, 1e-3) << s.id;
      }
      if (k == s.last) {
        EXPECT_NEAR((c->blob.centroid - onTable(s.x1, s.y1)).norm(), 0.0, 1e-3) << s.id;
      }
    }
    if (sim.stats().contacts > 0 && sim.stats().particles > 0) ++withParticles;
  }
  EXPECT_GT(withParticles, 100) << "the proxies took the contacts";
  EXPECT_EQ(input.tuio()->stats().TotalDropped(), 0u) << input.tuio()->Status();
}

INSTANTIATE_TEST_SUITE_P(Recordings, TouchlibPipeline, ::testing::ValuesIn(kTouchlib),
                         [](const ::testing::TestParamInfo<TouchlibRecording>& info) {
                           return info.index == 0 ? std::string("test") : std::string("tableData");
                         });

}  // namespace
}  // namespace pg
