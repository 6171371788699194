#include "proxygrasp/run/tuio_output.h"

#include "test_paths.h"

#include "proxygrasp/run/overrides.h"
#include "proxygrasp/run/tuio_input.h"
#include "proxygrasp/tuio/decoder.h"
#include "proxygrasp/tuio/touchlib_xml.h"
#include "proxygrasp/tuio/transport.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>
#include <unistd.h>

namespace pg {
namespace {

using ::testing::HasSubstr;

// what a contour may move on its way through TUIO and back: the encoder's 0.02 cm simplification
// plus float32 coordinates (docs/tuio.md, the acceptance figure)
constexpr double kRoundTripTol = 0.05;  // cm
// how long a test waits for loopback datagrams before it gives up, s
constexpr double kWait = 3.0;

// four fingertips squeeze two boxes; two lift at 1.6 s, the others at 3 s; 210 frames at 60 Hz
const std::string kLevel = std::string(pg::test::SourceDir()) + "/levels/release.toml";

// a frame as the simulation tracked it
struct SentContact {
  ContactId id = kNoId;
  ContactState state = ContactState::kNew;
  Contour contour;
  Vec2 centroid = Vec2::Zero();
};
struct SentFrame {
  int64_t frame = 0;
  double time = 0.0;  // s
  std::vector<SentContact> contacts;
};

SentFrame Snapshot(const Simulation& sim) {
  SentFrame f;
  f.frame = sim.stats().frame;
  f.time = sim.stats().time;
  for (const Contact& c : sim.contacts().contacts)
    f.contacts.push_back({c.id, c.state, c.blob.contour, c.blob.centroid});
  return f;
}

// the level's script through sensing and tracking, as `sense` runs it
class LevelRun {
 public:
  LevelRun() {
    Result<Level> level = LoadLevel(kLevel);
    EXPECT_TRUE(level.ok()) << level.error().Format();
    if (level.ok()) m_level = std::move(level.value());
    Start();
  }
  void Start() {
    SimulationOptions options;
    options.stages = RunStages::kThroughTracking;
    EXPECT_FALSE(m_sim.Start(m_level, m_level.params, options));
  }
  // one frame of the script; false when the script has ended
  bool Step() {
    if (m_sim.Time() >= m_level.script.duration - 1e-9) return false;
    MaybeError e = m_sim.StepScript();
    EXPECT_FALSE(e) << e->Format();
    return !e;
  }
  const Simulation& sim() const { return m_sim; }
  const Level& level() const { return m_level; }
  // the decoder's parameters for the level's table
  TuioParams Params() const {
    TuioParams p;
    p.table = m_level.params.table;
    return p;
  }

 private:
  Level m_level;
  Simulation m_sim;
};

std::unique_ptr<TuioOutput> OpenOutput(const std::string& spec,
                                       const TuioEncoderParams& params = {}) {
  Result<std::unique_ptr<TuioOutput>> out = TuioOutput::Open(spec, params);
  EXPECT_TRUE(out.ok()) << (out.ok() ? "" : out.error().Format());
  return out.ok() ? std::move(out.value()) : nullptr;
}

std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("pg_tuio_output_" + std::to_string(getpid()) + "_" + name))
      .string();
}

// a received frame holds the simulation's contacts of that frame: the same ids, new and lifted
// alike, and outlines within the round-trip tolerance of the tracked ones
void ExpectSameContacts(const TuioFrame& got, const SentFrame& sent) {
  SCOPED_TRACE("frame " + std::to_string(sent.frame));
  std::vector<TuioSessionId> live, lifted;
  for (const SentContact& c : sent.contacts)
    (c.state == ContactState::kLifted ? lifted : live).push_back(c.id);
  std::vector<TuioSessionId> gotLive, gotLifted = got.lifted;
  for (const TuioContact& c : got.contacts) gotLive.push_back(c.id);
  std::sort(live.begin(), live.end());
  std::sort(lifted.begin(), lifted.end());
  std::sort(gotLive.begin(), gotLive.end());
  std::sort(gotLifted.begin(), gotLifted.end());
  EXPECT_EQ(gotLive, live);
  EXPECT_EQ(gotLifted, lifted);
  for (const TuioContact& c : got.contacts) {
    auto s = std::find_if(sent.contacts.begin(), sent.contacts.end(),
                          [&](const SentContact& x) { return x.id == c.id; });
    if (s == sent.contacts.end()) continue;  // reported above
    SCOPED_TRACE("contact " + std::to_string(c.id));
    EXPECT_EQ(c.isNew, s->state == ContactState::kNew);
    EXPECT_EQ(c.shape, TuioShape::kContour);
    // the received outline is the simplified one: every point of each within the tolerance of
    // the other's boundary
    EXPECT_LE(HausdorffDistance(ToContour(c.contour), s->contour), kRoundTripTol);
  }
}

// polls until the frame with this id completes (or kWait passes)
std::optional<TuioFrame> WaitForFrame(TuioReceiver& r, int64_t frame) {
  const double start = TuioClock();
  while (TuioClock() - start < kWait) {
    r.Poll(TuioClock());
    for (TuioFrame& f : r.TakeFrames())
      if (f.frame == frame) return std::move(f);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return std::nullopt;
}

TEST(TuioOutput, UdpLoopbackReproducesTheContactsOfALevelRun) {
  LevelRun run;
  Result<std::unique_ptr<TuioReceiver>> receiver = TuioReceiver::Open(0, run.Params());
  ASSERT_TRUE(receiver.ok()) << receiver.error().Format();
  const std::string spec = "127.0.0.1:" + std::to_string(receiver.value()->port());
  std::unique_ptr<TuioOutput> out = OpenOutput(spec);
  ASSERT_TRUE(out);
  EXPECT_FALSE(out->IsFile());

  // every frame of the script, each checked as it arrives
  int frames = 0, news = 0, lifts = 0;
  while (run.Step()) {
    const SentFrame sent = Snapshot(run.sim());
    ASSERT_FALSE(out->Send(run.sim()));
    std::optional<TuioFrame> got = WaitForFrame(*receiver.value(), sent.frame);
    ASSERT_TRUE(got) << "frame " << sent.frame << " did not arrive";
    ExpectSameContacts(*got, sent);
    for (const SentContact& c : sent.contacts) {
      news += c.state == ContactState::kNew;
      lifts += c.state == ContactState::kLifted;
    }
    ++frames;
  }
  // the whole script: four fingertips come, two lift at 1.6 s and two at 3 s
  EXPECT_EQ(frames, 210);
  EXPECT_EQ(news, 4);
  EXPECT_EQ(lifts, 4);
  EXPECT_EQ(receiver.value()->stats().TotalDropped(), 0u) << receiver.value()->stats().Summary();
  EXPECT_EQ(out->encodeStats().coarsened, 0u);
  EXPECT_EQ(out->frames(), 210);
  EXPECT_EQ(out->Status(), "tuio out " + spec + ": 210 frames, 0 send errors");
}

// a blob's mean height over its outline, cm
double MeanHeight(const Blob& b) {
  double sum = 0.0;
  for (double h : b.heights) sum += h;
  return sum / static_cast<double>(b.heights.size());
}

TEST(TuioOutput, ADepthCamerasHeightsArriveOverTheLoopback) {
  // side_push on the synthetic depth camera (--set camera.kind=depth), through tracking, sent
  // over UDP and received as `--input tuio:PORT` receives it
  Result<Level> loaded = LoadLevel(std::string(pg::test::SourceDir()) + "/levels/side_push.toml");
  ASSERT_TRUE(loaded.ok()) << loaded.error().Format();
  Level level = std::move(loaded.value());
  ASSERT_FALSE(ApplyOverrides(level, {"camera.kind=depth"}));
  Simulation sim;
  SimulationOptions options;
  options.stages = RunStages::kThroughTracking;
  ASSERT_FALSE(sim.Start(level, level.params, options));
  TuioParams params;
  params.table = level.params.table;
  Result<std::unique_ptr<TuioReceiver>> receiver = TuioReceiver::Open(0, params);
  ASSERT_TRUE(receiver.ok()) << receiver.error().Format();
  std::unique_ptr<TuioOutput> out =
      OpenOutput("127.0.0.1:" + std::to_string(receiver.value()->port()));
  ASSERT_TRUE(out);
  // and a recording of the same frames (--tuio-out file:PATH)
  const std::string path = TempPath("depth.xml");
  std::unique_ptr<TuioOutput> recording = OpenOutput("file:" + path);
  ASSERT_TRUE(recording);
  std::vector<double> sentHeights;  // the contact's mean height in each frame, cm
  TuioTracker tracker;

  // 60 frames: the level gives the depth chain the clear table as its surface, so the fingertip
  // touching from the first frame is one contact in each
  int withHeights = 0;
  for (int frame = 0; frame < 60; ++frame) {
    ASSERT_FALSE(sim.StepScript());
    ASSERT_FALSE(out->Send(sim));
    ASSERT_FALSE(recording->Send(sim));
    std::optional<TuioFrame> got = WaitForFrame(*receiver.value(), sim.stats().frame);
    ASSERT_TRUE(got) << "frame " << frame << " did not arrive";
    const ContactSet received = tracker.Step(&*got, level.params.sensing.spacing);
    for (const Contact& c : sim.contacts().contacts) {
      if (c.state == ContactState::kLifted) continue;
      SCOPED_TRACE("frame " + std::to_string(frame) + ", contact " + std::to_string(c.id));
      ASSERT_FALSE(c.blob.heights.empty()) << "the depth chain gives every contact heights";
      auto it = std::find_if(got->contacts.begin(), got->contacts.end(),
                             [&](const TuioContact& t) { return t.id == c.id; });
      ASSERT_NE(it, got->contacts.end());
      ASSERT_TRUE(it->height) << "no p3d arrived";
      // z is float32 of height / 61 cm: 2 cm * 2^-24 = 1.2e-7 cm; 1e-6 allows the division and
      // multiplication around it
      EXPECT_NEAR(*it->height, MeanHeight(c.blob), 1e-6);
      // and the pipeline's contact made from it carries that height at every outline point
      auto tracked = std::find_if(received.contacts.begin(), received.contacts.end(),
                                  [&](const Contact& t) { return t.id == c.id; });
      ASSERT_NE(tracked, received.contacts.end());
      ASSERT_EQ(tracked->blob.heights.size(), static_cast<size_t>(tracked->blob.contour.cols()));
      EXPECT_NEAR(MeanHeight(tracked->blob), *it->height, 1e-9);
      sentHeights.push_back(MeanHeight(c.blob));
      ++withHeights;
    }
  }
  EXPECT_EQ(withHeights, 60);
  EXPECT_EQ(receiver.value()->stats().TotalDropped(), 0u) << receiver.value()->stats().Summary();

  // the recording replays with the same heights (its floats are written with 9 digits, so they
  // read back to the same bits: the same 1e-6 cm as over UDP)
  ASSERT_FALSE(recording->Close());
  Result<std::vector<OscBundle>> bundles = ReadTouchlibXml(path);
  std::remove(path.c_str());
  ASSERT_TRUE(bundles.ok()) << bundles.error().Format();
  const std::vector<TuioFrame> replayed = ReplayTuio(bundles.value(), params);
  ASSERT_EQ(replayed.size(), 60u);
  ASSERT_EQ(sentHeights.size(), 60u);
  for (size_t k = 0; k < replayed.size(); ++k) {
    ASSERT_EQ(replayed[k].contacts.size(), 1u) << k;
    ASSERT_TRUE(replayed[k].contacts[0].height) << k;
    EXPECT_NEAR(*replayed[k].contacts[0].height, sentHeights[k], 1e-6) << k;
  }
}

TEST(TuioOutput, FileRecordingReplaysAsTheSameContactsAtTheSimulationTime) {
  LevelRun run;
  const std::string path = TempPath("run.xml");
  TuioEncoderParams params;
  params.cursors11 = true;
  std::unique_ptr<TuioOutput> out = OpenOutput("file:" + path, params);
  ASSERT_TRUE(out);
  EXPECT_TRUE(out->IsFile());
  std::vector<SentFrame> sent;
  while (run.Step()) {
    sent.push_back(Snapshot(run.sim()));
    ASSERT_FALSE(out->Send(run.sim()));
  }
  ASSERT_FALSE(out->Close());
  EXPECT_EQ(out->Status(), "tuio out file:" + path + ": 210 frames, 0 write errors");

  Result<std::vector<OscBundle>> bundles = ReadTouchlibXml(path);
  std::remove(path.c_str());
  ASSERT_TRUE(bundles.ok()) << bundles.error().Format();
  // every bundle's time tag, and frm's, is its frame's simulation time
  ASSERT_GE(bundles.value().size(), 2 * sent.size());  // TUIO 2.0 and 2Dcur
  for (const OscBundle& b : bundles.value()) {
    ASSERT_FALSE(b.messages.empty());
    const OscMessage& first = b.messages.front();
    int64_t frame = -1;
    if (first.address == "/tuio2/frm") {
      frame = first.args[0].i;
      EXPECT_EQ(first.args[1].t, b.time);
      EXPECT_EQ(first.args[2].i, (640 << 16) | 480) << "dim: the level's camera size";
    } else {
      // the 2Dcur bundle: source, alive, set..., fseq
      frame = b.messages.back().args[1].i;
    }
    ASSERT_GE(frame, 0);
    ASSERT_LT(frame, static_cast<int64_t>(sent.size()));
    EXPECT_EQ(b.time, OscTimeTag::FromSeconds(sent[frame].time)) << "frame " << frame;
  }
  EXPECT_EQ(bundles.value().front().time, (OscTimeTag{0, 0}));
  EXPECT_EQ(bundles.value().back().time, OscTimeTag::FromSeconds(209.0 / 60.0));
  // so a replay on the time tags (ReplayArrivals, what [script] tuio uses) places each bundle at
  // its frame's time; 1e-9 s is the time tag's resolution (2^-32 s) with room to spare
  const std::vector<double> arrivals = ReplayArrivals(bundles.value(), 1.0);
  ASSERT_EQ(arrivals.size(), bundles.value().size());
  for (size_t k = 0; k < arrivals.size(); ++k)
    EXPECT_NEAR(arrivals[k], bundles.value()[k].time.ToSeconds(), 1e-9) << "bundle " << k;
  EXPECT_NEAR(arrivals.back(), 209.0 / 60.0, 1e-9);

  // replayed: the TUIO 2.0 frames are the simulation's frames, the 2Dcur frames its centroids
  std::vector<OscBundle> tuio2Bundles, cursorBundles;
  for (const OscBundle& b : bundles.value())
    (b.messages.front().address == "/tuio2/frm" ? tuio2Bundles : cursorBundles).push_back(b);
  const std::vector<TuioFrame> tuio2 = ReplayTuio(tuio2Bundles, run.Params());
  const std::vector<TuioFrame> cursors = ReplayTuio(cursorBundles, run.Params());
  ASSERT_EQ(tuio2.size(), sent.size());
  ASSERT_EQ(cursors.size(), sent.size());
  for (size_t k = 0; k < sent.size(); ++k) {
    EXPECT_EQ(tuio2[k].frame, sent[k].frame);
    ExpectSameContacts(tuio2[k], sent[k]);
    EXPECT_EQ(cursors[k].frame, sent[k].frame);
    for (const TuioContact& c : cursors[k].contacts) {
      auto s = std::find_if(sent[k].contacts.begin(), sent[k].contacts.end(),
                            [&](const SentContact& x) { return x.id == c.id; });
      ASSERT_NE(s, sent[k].contacts.end()) << "cursor " << c.id << " in frame " << k;
      EXPECT_NE(s->state, ContactState::kLifted);
      // float32 normalised coordinates on a 61 cm table are good to about 4e-6 cm
      EXPECT_NEAR((c.centroid - s->centroid).norm(), 0.0, 1e-4);
    }
    EXPECT_EQ(cursors[k].contacts.size(), tuio2[k].contacts.size());
  }
}

TEST(TuioOutput, ARestartedRunLiftsTheOldContactsAndCountsOn) {
  LevelRun run;
  const std::string path = TempPath("restart.xml");
  std::unique_ptr<TuioOutput> out = OpenOutput("file:" + path);
  ASSERT_TRUE(out);
  for (int k = 0; k < 20; ++k) {
    ASSERT_TRUE(run.Step());
    ASSERT_FALSE(out->Send(run.sim()));
  }
  const std::vector<ContactId> before = [&] {
    std::vector<ContactId> ids;
    for (const Contact& c : run.sim().contacts().contacts) ids.push_back(c.id);
    std::sort(ids.begin(), ids.end());
    return ids;
  }();
  ASSERT_EQ(before.size(), 4u);
  // the app's script loop and reload start the simulation again: frame 0, time 0, the same ids
  run.Start();
  for (int k = 0; k < 10; ++k) {
    ASSERT_TRUE(run.Step());
    ASSERT_FALSE(out->Send(run.sim()));
  }
  ASSERT_FALSE(out->Close());
  EXPECT_EQ(out->frames(), 31) << "20 frames, the lifting frame, 10 frames";

  Result<std::vector<OscBundle>> bundles = ReadTouchlibXml(path);
  std::remove(path.c_str());
  ASSERT_TRUE(bundles.ok()) << bundles.error().Format();
  const std::vector<TuioFrame> frames = ReplayTuio(bundles.value(), run.Params());
  ASSERT_EQ(frames.size(), 31u);
  // frame ids and time tags go on from the old run's
  for (size_t k = 0; k < frames.size(); ++k) EXPECT_EQ(frames[k].frame, static_cast<int64_t>(k));
  const double dt = 1.0 / 60.0;
  for (const OscBundle& b : bundles.value()) {
    const int64_t frame = b.messages.front().args[0].i;
    EXPECT_NEAR(b.time.ToSeconds(), frame * dt, 1e-9) << "frame " << frame;
  }
  // they never run backwards, so a replay on the time tags keeps them
  const std::vector<double> arrivals = ReplayArrivals(bundles.value(), 1.0);
  EXPECT_NEAR(arrivals.back(), 30 * dt, 1e-9);
  // frame 20 lifts the old run's contacts; frame 21 has the new run's, new again
  EXPECT_TRUE(frames[20].contacts.empty());
  std::vector<TuioSessionId> lifted = frames[20].lifted;
  std::sort(lifted.begin(), lifted.end());
  EXPECT_EQ(lifted, std::vector<TuioSessionId>(before.begin(), before.end()));
  // the new run's tracker numbers its contacts from the start again: without the lifting frame a
  // receiver would take them for the old ones
  ASSERT_EQ(frames[21].contacts.size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(frames[21].contacts[k].id, before[k]);
    EXPECT_TRUE(frames[21].contacts[k].isNew);
  }
}

TEST(TuioOutput, BadSpecsAreErrorsSayingWhy) {
  struct Case {
    std::string spec;
    std::string message;
  };
  const std::string file = TempPath("a_file");
  std::FILE* f = std::fopen(file.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fclose(f);
  const Case cases[] = {
      {"nohost", "TUIO output must be HOST:PORT or file:PATH (got \"nohost\")"},
      {"", "TUIO output must be HOST:PORT or file:PATH (got \"\")"},
      {"host:0", "TUIO output port must be 1 to 65535 (got \"0\")"},
      {"localhost:99999", "TUIO output port must be 1 to 65535 (got \"99999\")"},
      {":3333", "TUIO output must be HOST:PORT (got \":3333\")"},
      {"nosuchhost.invalid:3333", "cannot send TUIO to \"nosuchhost.invalid:3333\": "},
      {"file:", "a TUIO recording needs a path: file:PATH (got \"file:\")"},
      {"file:/nonexistent/folder/out.xml",
       "/nonexistent/folder/out.xml: cannot create the TUIO recording: No such file or directory"},
      // a folder that cannot hold files (root may write to any folder that exists)
      {"file:" + file + "/out.xml", file + "/out.xml: cannot create the TUIO recording: "},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.spec);
    Result<std::unique_ptr<TuioOutput>> out = TuioOutput::Open(c.spec);
    ASSERT_FALSE(out.ok());
    EXPECT_THAT(out.error().Format(), HasSubstr(c.message));
  }
  std::remove(file.c_str());
  EXPECT_TRUE(TuioOutput::Open("localhost:3333").ok());
}

TEST(TuioOutput, FailedWritesAreCountedAndTheRunGoesOn) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full to fail writes";
  LevelRun run;
  std::unique_ptr<TuioOutput> out = OpenOutput("file:/dev/full");
  ASSERT_TRUE(out);
  int failed = 0;
  for (int k = 0; k < 60 && run.Step(); ++k) {
    MaybeError e = out->Send(run.sim());
    if (!e) continue;
    ++failed;
    EXPECT_THAT(e->Format(),
                HasSubstr("/dev/full: cannot write the TUIO recording: No space left"));
  }
  // the file's buffer fills after a few frames; from then on every bundle fails, and is counted
  EXPECT_GT(failed, 30);
  EXPECT_EQ(out->frames(), 60);
  EXPECT_GE(out->sendErrors(), static_cast<uint64_t>(failed));
  EXPECT_THAT(out->Status(), HasSubstr("file:/dev/full: 60 frames, "));
  EXPECT_THAT(out->Status(), HasSubstr(" write errors"));
  MaybeError closed = out->Close();
  ASSERT_TRUE(closed);
  EXPECT_THAT(closed->Format(), HasSubstr("/dev/full: cannot complete the TUIO recording"));
}

}  // namespace
}  // namespace pg
